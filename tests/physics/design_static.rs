//! The static reference of the design outputs (issue 11): the static
//! envelope of moving forces and of a beam on elastic supports, against
//! closed forms.

use guideway::design::static_envelope;
use guideway::scene::Scene;

const L: f64 = 24.0;
const EI: f64 = 1e9;
const P: f64 = 600e3;

/// A moving force of P (a 600 kN "mass" under g = 10) crossing `beam`
/// (a TOML `[beam]` body with its supports), with a midspan sensor and
/// section and the reactions.
fn moving_force_scene(beam: &str) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "moving-force"
gravity = 10.0
reactions = true

[beam]
length = {L}
mass_per_length = 1250.0
bending_stiffness = {EI}
surface_offset = 0.0
elements = 8
{beam}

[body]
name = "force"
kind = "moving_force"
mass = 60000.0
initial_position = 0.0
initial_speed = 10.0

[[sensors]]
name = "midspan"
position = 12.0

[[sections]]
name = "midspan"
position = 12.0

[[sections]]
name = "quarter"
position = 6.0

[solver]
step = 0.001
"#
    ))
    .expect("scene is valid")
}

fn assert_close(found: f64, expected: f64, what: &str) {
    let error = (found - expected).abs() / expected.abs();
    assert!(
        error <= 1e-9,
        "{what}: {found} vs {expected} (error {error:e})"
    );
}

#[test]
fn a_moving_force_on_a_simple_span_peaks_at_pl_over_4_and_pl3_over_48ei() {
    let envelope = static_envelope(&moving_force_scene("")).unwrap();
    let peak = |name: &str| envelope.peaks[name];
    assert_close(
        peak("section.midspan.moment"),
        P * L / 4.0,
        "midspan moment",
    );
    // The quarter section's moment peaks with the force on it: 3PL/16.
    assert_close(
        peak("section.quarter.moment"),
        3.0 * P * L / 16.0,
        "quarter moment",
    );
    // Shear just right of a load at the quarter: P · 3/4 left, as a load on
    // the section counts as right of it.
    assert_close(peak("section.quarter.shear"), 0.75 * P, "quarter shear");
    let w = P * L.powi(3) / (48.0 * EI);
    assert_close(peak("sensor.midspan.deflection"), w, "midspan deflection");
    // A reaction peaks at P with the force over the support.
    assert_close(peak("support.left.reaction"), P, "left reaction");
    assert_close(peak("support.right.reaction"), P, "right reaction");
}

#[test]
fn a_span_on_elastic_supports_adds_the_settlement_and_reports_the_spring_forces() {
    // Free ends on vertical springs k: a load P at midspan settles each end
    // by P / 2k, and the midspan deflection is PL³/48EI + P/2k; the moment
    // is still PL/4 (the span is statically determinate).
    let k = 2e8;
    let springs = format!(
        "[beam.supports]\nleft = \"free\"\nright = \"free\"\n\
         [[beam.supports.springs]]\nat = 0.0\nvertical = {k}\n\
         [[beam.supports.springs]]\nat = {L}\nvertical = {k}\n"
    );
    let envelope = static_envelope(&moving_force_scene(&springs)).unwrap();
    let peak = |name: &str| envelope.peaks[name];
    let w = P * L.powi(3) / (48.0 * EI) + P / (2.0 * k);
    assert_close(peak("sensor.midspan.deflection"), w, "midspan deflection");
    assert_close(
        peak("section.midspan.moment"),
        P * L / 4.0,
        "midspan moment",
    );
    // The springs are the supports: P when the force is over one.
    assert_close(peak("support.left.reaction"), P, "left spring force");
    assert_close(peak("support.right.reaction"), P, "right spring force");
}

#[test]
fn a_rotational_spring_at_a_pinned_end_reports_its_moment() {
    // Pinned ends, a rotational spring k_r at the right one. With the force
    // at a, the end moment is that of a propped cantilever softened by the
    // spring; its largest magnitude over the crossing is found by sampling
    // the closed form (slope-deflection: M_B = −k_r θ_B, θ_B from the
    // simply supported rotation and the end moment's own rotation L/3EI).
    let kr = 5e9;
    let spring = format!("[[beam.supports.springs]]\nat = {L}\nrotational = {kr}\n");
    let envelope = static_envelope(&moving_force_scene(&spring)).unwrap();
    let closed_form = (0..=24_000)
        .map(|i| {
            let a = L * i as f64 / 24_000.0;
            // Rotation at B of a simple span under P at a: P a (L² − a²) / 6EIL.
            let theta_simple = P * a * (L * L - a * a) / (6.0 * EI * L);
            // M (hogging at B) = θ_simple / (L/3EI + 1/k_r).
            theta_simple / (L / (3.0 * EI) + 1.0 / kr)
        })
        .fold(0.0, f64::max);
    let found = envelope.peaks["support.right.moment"];
    let error = (found - closed_form).abs() / closed_form;
    // Sampled on both sides: the envelope's positions (4 per element) and
    // the closed form's differ near a flat maximum.
    assert!(
        error < 1e-6,
        "end moment {found} vs {closed_form} ({error:e})"
    );
}
