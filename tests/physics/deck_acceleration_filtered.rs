//! The run summary's deck acceleration as EN 1991-2 §6.4.6.5(4) counts it
//! (issue 24 item 5): an analytic acceleration record, a sine below the
//! cut-off max(30 Hz, 1.5 f1, f3) plus a larger one above it, must keep
//! the first at the Butterworth prototype's gain and lose the second; the
//! cut-off stated is the simply supported beam's f3 = 9 f1 in closed form.

use guideway::report::{RunSummary, SummaryBuilder};
use guideway::scene::{builtin, Scene};
use guideway::study::deck_filter::zero_phase_gain;
use std::f64::consts::PI;

const LENGTH: f64 = 20.0;
const MASS: f64 = 12_000.0;
/// First natural frequency (Hz) the beam is given: EI from
/// f1 = (π / 2L²) √(EI / m).
const F1: f64 = 5.0;
const STEP: f64 = 1e-3;

fn scene() -> Scene {
    let mut scene = builtin("lee1994-wheel-10").expect("built-in");
    scene.beam.length = LENGTH;
    scene.beam.mass_per_length = MASS;
    scene.beam.bending_stiffness = MASS * (2.0 * LENGTH * LENGTH * F1 / PI).powi(2);
    scene.beam.elements = 20;
    scene.sensors[0].position = LENGTH / 2.0;
    scene.solver.step = STEP;
    scene
}

/// A passage's envelope over the 4 s record: sin²(π t / 4), quiet at
/// both ends as a run starting from rest is.
fn envelope(t: f64) -> f64 {
    libm::sin(PI * t / 4.0).powi(2)
}

/// The summary of a made-up run whose midspan acceleration is the
/// envelope times `below` sin(2π 10 t) + `above` sin(2π 150 t + 0.3) for
/// 4 s, with a last row off the step grid (a run's exit row).
fn summary_of(below: f64, above: f64) -> RunSummary {
    let scene = scene();
    let names = vec!["sensor.midspan.acceleration".to_string()];
    let mut builder = SummaryBuilder::new(&scene, &names);
    let signal = |t: f64| {
        envelope(t)
            * (below * libm::sin(2.0 * PI * 10.0 * t)
                + above * libm::sin(2.0 * PI * 150.0 * t + 0.3))
    };
    for k in 0..=4000 {
        let t = k as f64 * STEP;
        builder.push(t, &[signal(t)]);
    }
    builder.push(4.0004, &[1e3]);
    builder.finish(None, 0.0)
}

#[test]
fn filtered_peak_keeps_what_is_below_the_cut_off_and_drops_what_is_above() {
    let (below, above) = (1.0, 2.0);
    let summary = summary_of(below, above);
    let cut_off = summary
        .acceleration_cut_off_hz
        .expect("a cut-off is stated");
    // max(30, 1.5 × 5, 9 × 5) = 45 Hz; the 20-element beam's f3 is within
    // 1e-5 of the continuous beam's.
    assert!((cut_off - 9.0 * F1).abs() < 1e-3 * F1, "cut-off {cut_off}");
    let filtered = summary.peak_design["sensor.midspan.acceleration_filtered"];
    // The 10 Hz sine at the zero-phase gain, the 150 Hz one at its gain
    // (1.6e-4 of it); sampling a 10 Hz peak at 1 kHz costs 5e-5 of it.
    // (The envelope widens the lines by 0.25 Hz: no change in gain.)
    let expected = (0..=4000)
        .map(|k| k as f64 * STEP)
        .map(|t| below * zero_phase_gain(10.0, 45.0) * envelope(t) * libm::sin(2.0 * PI * 10.0 * t))
        .fold(0.0, |m: f64, x| m.max(x.abs()));
    let leak = above * zero_phase_gain(150.0, 45.0);
    assert!(leak < 1e-3, "{leak}");
    assert!(
        (filtered.abs() - expected).abs() <= leak + 1e-4 * below,
        "filtered {filtered} against {expected} ± {leak}"
    );
    // The raw peak beside it holds both sines (the exit row off the grid
    // counts there, not in the filtered record).
    assert_eq!(summary.peak_design["sensor.midspan.acceleration"], 1e3);
}
