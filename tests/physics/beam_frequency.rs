//! `beam.frequency` (issue 26 item 8): a bridge given by its first natural
//! frequency gets the bending stiffness whose model has exactly that
//! frequency, checked by the modes code and, for a simply supported span,
//! against the closed form EI = m (2 f1 L²/π)².

use guideway::beam::HermiteBeam;
use guideway::scene::Scene;
use std::f64::consts::{PI, TAU};

/// A 25 m bridge under one moving force, with `beam` lines added to [beam].
fn scene_text(beam: &str) -> String {
    format!(
        "name = \"f1\"\n\
         [beam]\n\
         length = 25.0\n\
         mass_per_length = 15000.0\n\
         surface_offset = 0.0\n\
         elements = 40\n\
         {beam}\n\
         [body]\n\
         name = \"axle\"\n\
         kind = \"moving_force\"\n\
         mass = 1.0\n\
         force_y = -170e3\n\
         initial_position = 0.0\n\
         initial_speed = 50.0\n"
    )
}

/// The first natural frequency (Hz) of the scene's built beam, by the
/// modes code the simulation uses.
fn model_f1(scene: &Scene) -> f64 {
    let beam = HermiteBeam::new(&scene.beam).expect("beam builds");
    beam.modes(1).expect("modes").omega[0] / TAU
}

fn assert_f1(beam_lines: &str, f1: f64) -> Scene {
    let scene = Scene::from_toml_str(&scene_text(beam_lines)).expect("scene with frequency");
    assert_eq!(
        scene.beam.frequency, None,
        "the frequency is turned into EI"
    );
    let got = model_f1(&scene);
    assert!(
        (got - f1).abs() <= 1e-6 * f1,
        "{beam_lines}: model f1 {got} Hz, asked {f1} Hz"
    );
    scene
}

#[test]
fn simply_supported_span_gets_the_frequency_asked_for() {
    let scene = assert_f1("frequency = 4.0", 4.0);
    // Closed form of the continuous beam; the 40-element Hermite mesh's
    // first frequency is within 1e-6 of it, so EI must be too.
    let (l, m) = (25.0_f64, 15000.0);
    let closed = m * (2.0 * 4.0 * l * l / PI).powi(2);
    let ratio = scene.beam.bending_stiffness / closed;
    assert!(
        (ratio - 1.0).abs() < 1e-6,
        "EI {} vs closed form {closed}: ratio {ratio}",
        scene.beam.bending_stiffness
    );
}

#[test]
fn other_supports_get_the_frequency_asked_for() {
    assert_f1("frequency = 6.5\nsupports = { left = \"clamped\" }", 6.5);
    assert_f1("frequency = 3.0\nsupports = { intermediate = [10.0] }", 3.0);
}

#[test]
fn elastic_supports_get_the_frequency_asked_for() {
    // The springs' stiffness does not scale with EI: the secant steps.
    let springs = "frequency = 3.5\n\
                   supports = { left = \"free\", springs = [{ at = 0.0, vertical = 2e8 }] }";
    assert_f1(springs, 3.5);
}

#[test]
fn both_or_neither_is_refused_naming_both_fields() {
    let both = Scene::from_toml_str(&scene_text("frequency = 4.0\nbending_stiffness = 3.8e10"))
        .unwrap_err()
        .to_string();
    assert!(
        both.contains("beam.frequency") && both.contains("beam.bending_stiffness"),
        "{both}"
    );
    let neither = Scene::from_toml_str(&scene_text(""))
        .unwrap_err()
        .to_string();
    assert!(
        neither.contains("beam.frequency") && neither.contains("beam.bending_stiffness"),
        "{neither}"
    );
    let bad = Scene::from_toml_str(&scene_text("frequency = -1.0"))
        .unwrap_err()
        .to_string();
    assert!(bad.contains("beam.frequency = -1"), "{bad}");
}

#[test]
fn a_scene_given_by_frequency_writes_and_reads_back() {
    let scene = assert_f1("frequency = 4.0", 4.0);
    let again = Scene::from_toml_str(&scene.to_toml_string()).expect("reads back");
    assert_eq!(again, scene);
}
