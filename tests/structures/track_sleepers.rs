//! The rail on discrete supports (`[track.on_deck.sleepers]`): statics
//! against the infinite rail on discrete springs (its Fourier series,
//! written here) and, at close spacing, against the Winkler closed form
//! P β / 2k with k = k_eq / a within the derived leading difference
//! (β a)⁴ / 144; the rail seat's two-mass natural frequencies against the
//! closed-form 2-DOF eigenvalues by a free vibration; the scene's rules and
//! its rail-seat force.

use guideway::beam::Rayleigh;
use guideway::structure::rail_on_deck::RailOnDeck;
use guideway::structure::track_on_deck::{TrackAssembly, TrackOnDeck, TrackState};
use guideway::structure::track_sleepers::{SleeperPreset, Sleepers};
use std::f64::consts::PI;

/// A UIC 60 rail.
const RAIL_EI: f64 = 6.4e6;
const RAIL_MU: f64 = 60.0;
const LOAD: f64 = 100e3;

/// The ballasted preset at the spacing `spacing`.
fn ballasted(spacing: f64) -> Sleepers {
    Sleepers {
        spacing,
        ..SleeperPreset::Ballasted.values()
    }
}

/// A rail of EI `rail_ei` on `sleepers` from x = −`side` over a deck of one
/// spacing (its bearings under the sleepers at 0 and a, so that every
/// sleeper rests on fixed ground) to a + `side`, in elements of `h`.
fn rail_on_sleepers(sleepers: Sleepers, h: f64, side: f64, rail_ei: f64) -> TrackAssembly {
    TrackOnDeck {
        layout: RailOnDeck {
            deck_length: sleepers.spacing,
            deck_bending_stiffness: 1e9,
            rail_bending_stiffness: rail_ei,
            track_stiffness: 0.0,
            ground_stiffness: 0.0,
            approach: side,
            run_off: side,
            element_length: h,
            sleepers: Some(sleepers),
        },
        rail_mass_per_length: RAIL_MU,
        deck_mass_per_length: 1000.0,
        track_damping: 0.0,
        ground_damping: 0.0,
        deck_damping: Rayleigh::default(),
    }
    .assemble()
    .expect("assembles")
}

/// Deflection under a downward `load` at a support of the infinite rail
/// (EI) on springs `k` (N/m) at spacing `a`, by its Fourier series. With
/// w_j the support deflections, the rail's flexibility between supports
/// j a apart is g(j a), whose series over j is F(θ) = (a³/EI) Σₙ (θ +
/// 2πn)⁻⁴ = (a³/EI)(2 + cos θ) / (48 sin⁴(θ/2)); the supports' forces
/// −k w_j then give W(θ) = −P F / (1 + k F), and w₀ = (1/2π) ∫ W dθ over
/// [−π, π]. The integrand is smooth and periodic, so the trapezoid rule
/// converges geometrically.
fn discrete_support_deflection(load: f64, ei: f64, k: f64, a: f64) -> f64 {
    let n = 20_000;
    let sum: f64 = (0..n)
        .map(|i| {
            let theta = -PI + 2.0 * PI * i as f64 / n as f64;
            let inverse_f =
                ei / a.powi(3) * 48.0 * libm::sin(theta / 2.0).powi(4) / (2.0 + libm::cos(theta));
            1.0 / (inverse_f + k)
        })
        .sum();
    -load * sum / n as f64
}

/// The rail's deflection and the rail-seat force at `x` under a static
/// downward `load` there.
fn static_at(track: &TrackAssembly, x: f64, load: f64) -> (f64, f64) {
    let mut force = vec![0.0; track.free_dofs()];
    track
        .add_rail_force(x, -load, &mut force)
        .expect("on the rail");
    let u = track.static_deflection(&force).expect("solves");
    let zero = vec![0.0; u.len()];
    let rail = track.rail_deflection(x, &u).expect("on the rail");
    (rail, track.rail_seat_force(x, &u, &zero).expect("sleepers"))
}

fn relative(found: f64, expected: f64) -> f64 {
    (found - expected).abs() / expected.abs()
}

/// At any spacing the Hermite rail between supports is exact under point
/// forces, so the assembly meets the discrete series to the solver's
/// precision; the pad carries k_eq w (pad and ballast in series).
#[test]
fn a_load_at_a_sleeper_deflects_the_rail_as_the_discrete_support_series() {
    for (spacing, h) in [(0.55, 0.275), (0.6, 0.6), (1.2, 0.3)] {
        let sleepers = ballasted(spacing);
        let k = sleepers.series_stiffness();
        let side = 40.0 * spacing;
        let track = rail_on_sleepers(sleepers, h, side, RAIL_EI);
        let (rail, seat) = static_at(&track, -20.0 * spacing, LOAD);
        let expected = discrete_support_deflection(LOAD, RAIL_EI, k, spacing);
        println!(
            "a = {spacing} m: rail {rail:.9e} m against {expected:.9e} ({:.1e}); seat {seat:.6e} N \
             against k_eq w {:.6e}",
            relative(rail, expected),
            -k * expected
        );
        assert!(
            relative(rail, expected) < 1e-8,
            "a = {spacing}: {rail:e} vs {expected:e}"
        );
        assert!(
            relative(seat, -k * expected) < 1e-8,
            "a = {spacing}: seat {seat:e}"
        );
    }
}

/// Against Winkler's P β / 2k with k = k_eq / a. Expanding the series in
/// β a: F = a³/(EI θ⁴) + R(θ) with R(0) = a³ / (720 EI) (2 ζ(4) / (2π)⁴);
/// the O((βa)³) parts (∫ R over [−π, π] against Winkler's integral beyond
/// ±π) cancel, and what is left is −R(0) k ∫ (1 + 2τ⁴)/(1 + τ⁴)² dτ /
/// ∫ dτ/(1 + τ⁴) = −(θ₀⁴/720)(5/4) with θ₀⁴ = 4 (βa)⁴: the discrete rail is
/// stiffer by (βa)⁴/144 to leading order. Asserted within 10 % of it (the
/// next order is (βa)⁶-small at these spacings: 2 % at βa = 0.16).
#[test]
fn at_close_spacing_the_sleepers_are_the_winkler_layer_to_beta_a_to_the_fourth() {
    for spacing in [0.1, 0.2] {
        let sleepers = ballasted(spacing);
        let k = sleepers.series_stiffness() / spacing;
        let beta = libm::pow(k / (4.0 * RAIL_EI), 0.25);
        let track = rail_on_sleepers(sleepers, spacing / 2.0, 40.0, RAIL_EI);
        let (rail, _) = static_at(&track, -20.0, LOAD);
        let winkler = -LOAD * beta / (2.0 * k);
        let difference = rail / winkler - 1.0;
        let leading = -(beta * spacing).powi(4) / 144.0;
        println!(
            "a = {spacing} m, βa = {:.3}: w/w_Winkler − 1 = {difference:.4e} against \
             −(βa)⁴/144 = {leading:.4e}",
            beta * spacing
        );
        assert!(
            (difference - leading).abs() <= 0.1 * leading.abs(),
            "a = {spacing}: {difference:e} vs {leading:e}"
        );
    }
}

/// The rail seat's two masses: m_r (the rail's mass per sleeper) on the
/// pad k_p over m_s on the ballast k_b. ω² solves m_r m_s ω⁴ −
/// (m_r (k_p + k_b) + m_s k_p) ω² + k_p k_b = 0; the mode's sleeper amplitude per
/// rail amplitude is k_p / (k_p + k_b − m_s ω²).
fn two_mass(m_r: f64, s: &Sleepers) -> [(f64, f64); 2] {
    let (kp, kb, ms) = (s.pad_stiffness, s.ballast_stiffness, s.sleeper_mass);
    let (a, b, c) = (m_r * ms, m_r * (kp + kb) + ms * kp, kp * kb);
    let root = (b * b - 4.0 * a * c).sqrt();
    [(b - root) / (2.0 * a), (b + root) / (2.0 * a)].map(|w2| (w2.sqrt(), kp / (kp + kb - ms * w2)))
}

/// Times of the upward zero crossings of `signal` sampled every `dt`
/// (linear interpolation).
fn upward_crossings(signal: &[f64], dt: f64) -> Vec<f64> {
    (1..signal.len())
        .filter(|&i| signal[i - 1] < 0.0 && signal[i] >= 0.0)
        .map(|i| dt * (i as f64 - 1.0 + signal[i - 1] / (signal[i - 1] - signal[i])))
        .collect()
}

/// A rigid rail (EI 1e12 N m²: the seat model takes the rail mass per
/// sleeper as rigid) on 22 undamped sleepers, every sleeper on fixed
/// ground, started in each closed-form mode: it oscillates at that
/// frequency and keeps its amplitude (HHT with α = 0, T/400 a step; its
/// period error (ωΔt)²/12 is 2e-5).
#[test]
fn a_sleeper_on_pad_and_ballast_vibrates_at_the_two_mass_frequencies() {
    let sleepers = Sleepers {
        pad_damping: 0.0,
        ballast_damping: 0.0,
        ..ballasted(0.6)
    };
    let track = rail_on_sleepers(sleepers, 0.3, 6.0, 1e12);
    let count = track.sleeper_dofs().len();
    let rail_mass = RAIL_MU * (track.node_x[track.node_x.len() - 1] - track.node_x[0]);
    assert_eq!(count, 22);
    for (omega, ratio) in two_mass(rail_mass / count as f64, &sleepers) {
        let amplitude = 1e-3;
        let mut u = track.nodal_field(&|_| [amplitude, 0.0], &|_| [0.0, 0.0]);
        for dof in track.sleeper_dofs() {
            u[dof] = ratio * amplitude;
        }
        let mut a = vec![0.0; u.len()];
        track.stiffness.mul_to(&u, &mut a);
        a.iter_mut().for_each(|x| *x = -*x);
        track.mass.ldlt().expect("definite").solve_in_place(&mut a);
        let n = u.len();
        let mut state = TrackState {
            u,
            v: vec![0.0; n],
            a,
        };
        let period = 2.0 * PI / omega;
        let dt = period / 400.0;
        let hht = track.hht(dt, 0.0).expect("stepper");
        let zero = vec![0.0; n];
        let mut rail = Vec::new();
        for _ in 0..2000 {
            hht.advance(&track, &mut state, (&zero, &zero));
            rail.push(track.rail_deflection(0.3, &state.u).expect("on the rail"));
        }
        let crossings = upward_crossings(&rail, dt);
        let found = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        println!(
            "two-mass mode {:.3} Hz: period {found:.6e} s against {period:.6e} s ({:.1e})",
            omega / (2.0 * PI),
            relative(found, period)
        );
        assert!(crossings.len() >= 4, "{} crossings", crossings.len());
        assert!(relative(found, period) < 0.01, "{found:e} vs {period:e}");
        let peak = rail.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(
            relative(peak, amplitude) < 0.01,
            "a pure mode keeps its amplitude: {peak:e}"
        );
    }
}

/// A scene with a 10 t glider at rest at midspan of a stiff deck on
/// ballasted sleepers at 0.5 m.
fn sleeper_scene(sleepers: &str) -> String {
    format!(
        r#"
name = "sleepers"
gravity = 9.81
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 1e13
surface_offset = 0.0
elements = 40
[beam.damping]
ratio = 0.02
modes = [1, 3]
[track]
approach = 10.0
run_off = 10.0
[track.on_deck]
rail_bending_stiffness = {RAIL_EI:?}
rail_mass_per_length = {RAIL_MU:?}
[track.on_deck.sleepers]
{sleepers}
[body]
name = "glider"
kind = "glider"
mass = 10000.0
initial_position = 10.0
initial_speed = 0.0
[[sensors]]
name = "mid"
position = 10.0
[solver]
step = 0.001
integrator = "hht"
start = "static"
end_time = 0.01
"#
    )
}

/// The outputs `names` after the first step.
fn first_step(scene: &str, names: &[&str]) -> Vec<f64> {
    let scene = guideway::Scene::from_toml_str(scene).expect("a valid scene");
    let mut sim = guideway::Simulation::new(&scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; all.len()];
    sim.advance_to(scene.solver.step).expect("steps");
    sim.output_values(&mut values);
    names
        .iter()
        .map(|n| values[all.iter().position(|x| x == n).expect(n)])
        .collect()
}

/// Under the glider the pad carries k_eq w of the infinite rail on
/// discrete supports, w the rail's deflection over the deck's; the deck
/// (PL³/48EI = 1.6e-6 m) moves the rail's base almost rigidly over the
/// rail's characteristic length 1/β ≈ 0.9 m.
#[test]
fn in_a_scene_the_rail_seat_under_a_glider_at_rest_carries_the_discrete_support_force() {
    let found = first_step(
        &sleeper_scene("preset = \"ballasted\"\nspacing = 0.5"),
        &[
            "sensor.mid.rail_deflection",
            "sensor.mid.rail_seat_force",
            "sensor.mid.deflection",
        ],
    );
    let sleepers = ballasted(0.5);
    let k = sleepers.series_stiffness();
    let weight = 10000.0 * 9.81;
    let expected = discrete_support_deflection(weight, RAIL_EI, k, 0.5);
    let rail = found[0] - found[2];
    println!(
        "rail over the deck {rail:.6e} m against {expected:.6e} m; seat {:.6e} N against \
         {:.6e} N",
        found[1],
        -k * expected
    );
    assert!(relative(rail, expected) < 2e-4, "{found:?}");
    assert!(relative(found[1], -k * expected) < 2e-4, "{found:?}");
}

#[test]
fn sleepers_that_the_model_cannot_hold_are_refused_naming_field_value_and_rule() {
    for (sleepers, path, words) in [
        (
            "preset = \"ballasted\"\nspacing = 0.3",
            "track.on_deck.sleepers.spacing",
            "whole number",
        ),
        (
            "preset = \"ballasted\"\npad_stiffness = -1.0",
            "track.on_deck.sleepers.pad_stiffness",
            "> 0",
        ),
        (
            "spacing = 0.5\npad_stiffness = 2e8\nsleeper_mass = 150.0",
            "track.on_deck.sleepers.ballast_stiffness",
            "preset",
        ),
        (
            "preset = \"ballasted\"\nballast_damping = -5.0",
            "track.on_deck.sleepers.ballast_damping",
            ">= 0",
        ),
    ] {
        let text = sleeper_scene(sleepers);
        let error = guideway::Scene::from_toml_str(&text)
            .expect_err(sleepers)
            .to_string();
        println!("{error}");
        assert!(
            error.contains(path) && error.contains(words),
            "{sleepers}: {error}"
        );
    }
    let layer_too = sleeper_scene("preset = \"ballasted\"")
        .replace("[track.on_deck]\n", "[track.on_deck]\nstiffness = 3.3e7\n");
    let error = guideway::Scene::from_toml_str(&layer_too)
        .expect_err("layer")
        .to_string();
    assert!(
        error.contains("track.on_deck.stiffness") && error.contains("on sleepers"),
        "{error}"
    );
}
