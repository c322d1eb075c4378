//! A moving force's free vibration after it has left the beam (issue 26
//! item 4): with `solver.end_time` past the exit, the sweep's peak
//! deflection is the largest of the passage and of the free vibration
//! that follows, against Frýba's modal series continued past the exit.
//!
//! During the passage (0 ≤ t ≤ T = L/c) mode j of the simply supported,
//! undamped beam has, down positive and in units of v₀ = 2PL³/(π⁴EI),
//!
//!   q_j(t) = [sin jωt − (α/j) sin ω_j t] / (j²(j² − α²)),
//!
//! ω = πc/L = α ω₁, ω_j = j² ω₁; after it, each mode vibrates freely from
//! its state at T: q_j(T) cos ω_j(t − T) + q̇_j(T)/ω_j sin ω_j(t − T).

use guideway::scene::Scene;
use guideway::study::sweep::{sweep, Loads, SpeedUnit};

use crate::common::fryba::{self, FORCE, LENGTH};
use std::f64::consts::PI;

const ALPHA: f64 = 1.5;

fn speed() -> f64 {
    fryba::speed(ALPHA)
}

/// Midspan deflection over v₀ (down positive) at `t`, 200 terms.
fn series_midspan(t: f64) -> f64 {
    fryba::series_midspan_with_free_vibration(ALPHA, t)
}

/// One force of 600 kN at α = 1.5 on the paper's 24 m beam (40 elements),
/// run to `end_time`.
fn scene(end_time: Option<f64>) -> Scene {
    let mut scene = Scene::lee1994(guideway::scene::BodyKind::MovingForce, speed(), 0.0);
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    scene.vehicles[0].mass = 1.0; // no gravity: the force is force_y alone
    scene.vehicles[0].force_y = -FORCE;
    scene.beam.elements = 40;
    scene.beam.surface_offset = 0.0;
    scene.solver.step = LENGTH / speed() / 4000.0;
    scene.solver.end_time = end_time;
    scene.validate().expect("valid");
    scene
}

/// The sweep's peak midspan deflection over v₀ at the one speed.
fn swept_peak(scene: &Scene) -> f64 {
    let rows = sweep(
        scene,
        &Loads::Scene,
        (&[speed()], SpeedUnit::MetresPerSecond),
        1,
        u64::MAX,
    )
    .expect("the sweep runs");
    rows[0].peak_deflection / fryba::v0()
}

/// The largest |series| over [0, end] sampled every 1/20 000 of it.
fn series_peak(end: f64) -> f64 {
    (0..=20_000)
        .map(|k| series_midspan(end * k as f64 / 20_000.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_sweep_runs_the_free_vibration_to_end_time_at_alpha_1_5() {
    let exit = LENGTH / speed();
    let period = 2.0 * PI / fryba::omega1();
    let end = exit + 1.5 * period;
    let (during, after) = (series_peak(exit), series_peak(end));
    eprintln!("series: {during:.5} v0 during the passage, {after:.5} v0 with the free vibration");
    // At α = 1.5 the largest deflection comes after the force has left.
    assert!(after > 1.1 * during, "{during} {after}");
    let without = swept_peak(&scene(None));
    let with = swept_peak(&scene(Some(end)));
    eprintln!("sweep: {without:.5} v0 to the exit, {with:.5} v0 to end_time");
    // 40 elements and 4000 steps a passage: within 0.1 % of the series.
    assert!(
        (without / during - 1.0).abs() < 5e-3,
        "{without} vs {during}"
    );
    assert!((with / after - 1.0).abs() < 1e-3, "{with} vs {after}");
}
