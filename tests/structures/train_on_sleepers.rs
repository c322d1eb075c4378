//! A train on sleepers (issue 24): the eight Hertz coaches of
//! `scenes/train-8-coaches-20m-300-sleepers.toml` on two rails over
//! ballasted sleepers at 0.5 m, cut when the first two coaches have crossed
//! the deck, at two rail elements a sleeper bay (with one, the Hermite
//! rail misses its bending under a wheel between sleepers and the wheel
//! force moves by 1.8 % at the first doubling: docs/structures.md, "A
//! train on sleepers"). The issue's criteria for a well-posed model: the
//! peak filtered deck acceleration, the peak wheel force and the peak
//! rail-seat force move by less than 2 % at half the step and at twice the
//! elements, no wheelset lifts off, and no wheel force exceeds twice the
//! static wheel load (the track is smooth).

use crate::common;

use guideway::report::{drive, RunSummary, SummaryEvent};
use guideway::Scene;
use guideway::Simulation;

/// The shipped scene, cut at 0.6 s (the first two coaches past the deck),
/// at two elements a sleeper bay.
fn sleeper_scene() -> Scene {
    let text = include_str!("../../scenes/train-8-coaches-20m-300-sleepers.toml")
        .replace("end_time = 2.6", "end_time = 0.6");
    let mut scene = Scene::from_toml_str(&text).expect("a valid scene");
    scene.beam.elements *= 2;
    scene
}

/// The run's summary and its lift-off count.
fn run(scene: &Scene) -> (RunSummary, usize) {
    let mut simulation = Simulation::new(scene).expect("scene builds");
    let run = drive(scene, &mut simulation, |_| {}).expect("run succeeds");
    let lift_offs = SummaryEvent::list(&simulation)
        .iter()
        .filter(|e| e.kind == "lift_off")
        .count();
    (run.summary(scene), lift_offs)
}

/// Peak |filtered deck acceleration|, peak wheel force and peak rail-seat
/// force over the sensors and contacts.
fn peaks(summary: &RunSummary) -> [f64; 3] {
    let design = |suffix: &str| {
        (summary.peak_design.iter())
            .filter(|(name, _)| name.ends_with(suffix))
            .map(|(_, v)| v.abs())
            .fold(0.0, f64::max)
    };
    let force = (summary.peak_contact_force.values()).fold(0.0, |m: f64, v| m.max(*v));
    [
        design(".acceleration_filtered"),
        force,
        design(".rail_seat_force"),
    ]
}

#[test]
fn eight_coaches_on_ballasted_sleepers_converge_without_lift_off() {
    let scene = sleeper_scene();
    let mut half = scene.clone();
    half.solver.step *= 0.5;
    let mut finer = scene.clone();
    finer.beam.elements *= 2;
    let static_load = common::static_wheelset_load(&scene);
    let (base, base_lifts) = run(&scene);
    let base_peaks = peaks(&base);
    println!("Δt: {base_peaks:?} (filtered deck acceleration, wheel force, rail-seat force)");
    assert_eq!(base_lifts, 0, "lift-offs at the scene's step");
    assert!(base_peaks.iter().all(|p| *p > 0.0), "{base_peaks:?}");
    assert!(
        base_peaks[1] < 2.0 * static_load,
        "{} N against {static_load} N",
        base_peaks[1]
    );
    for (what, refined) in [("Δt/2", &half), ("2n elements", &finer)] {
        let (summary, lifts) = run(refined);
        let found = peaks(&summary);
        let change: Vec<f64> = (found.iter().zip(&base_peaks))
            .map(|(f, b)| f / b - 1.0)
            .collect();
        println!("{what}: {found:?}, relative changes {change:?}, {lifts} lift-offs");
        assert_eq!(lifts, 0, "lift-offs at {what}");
        for (name, c) in [
            "filtered deck acceleration",
            "wheel force",
            "rail-seat force",
        ]
        .iter()
        .zip(&change)
        {
            assert!(c.abs() < 0.02, "{name} at {what}: {c:+e}");
        }
    }
}
