//! `guideway run` of moving forces (issue 26 item 4): the time history of
//! a crossing and of the free vibration after it, against Frýba's modal
//! series written here; a two-axle run against the sum of its one-axle
//! runs (the beam is linear); the sweep at one speed against the run's
//! peaks (the same crossing).
//!
//! The series: during the passage (0 ≤ t ≤ T = L/c) mode j of the simply
//! supported, undamped beam has, down positive and in units of
//! 2PL³/(π⁴EI),
//!
//!   q_j(t) = [sin jωt − (α/j) sin ω_j t] / (j²(j² − α²)),
//!
//! ω = πc/L = α ω₁, ω_j = j² ω₁; after it each mode vibrates freely from
//! its state at T: q_j(T) cos ω_j(t − T) + q̇_j(T)/ω_j sin ω_j(t − T).

use guideway::moving_load::ForceRun;
use guideway::report::{drive, Trace};
use guideway::scene::{BodyKind, Scene, SectionSpec};
use guideway::study::sweep::{sweep, Loads, SpeedUnit};
use std::f64::consts::PI;

use crate::common::fryba::{self, omega1, v0, FORCE, LENGTH};

const ALPHA: f64 = 1.5;

fn speed() -> f64 {
    fryba::speed(ALPHA)
}

fn exit() -> f64 {
    LENGTH / speed()
}

/// Midspan deflection over v₀ (down positive) at `t`, 200 modes.
fn series_midspan(t: f64) -> f64 {
    fryba::series_midspan_with_free_vibration(ALPHA, t)
}

/// The largest |series| over [from, to], sampled 20 000 times.
fn series_peak(from: f64, to: f64) -> f64 {
    (0..=20_000)
        .map(|k| series_midspan(from + (to - from) * k as f64 / 20_000.0).abs())
        .fold(0.0, f64::max)
}

/// One force of 600 kN at α = 1.5 on the paper's 24 m beam (40 elements,
/// 4000 steps a passage), with a midspan sensor and section, run to
/// `end_time`.
fn scene(end_time: Option<f64>) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::MovingForce, speed(), 0.0);
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    scene.vehicles[0].mass = 1.0; // no gravity: the force is force_y alone
    scene.vehicles[0].force_y = -FORCE;
    scene.beam.elements = 40;
    scene.beam.surface_offset = 0.0;
    scene.sensors[0].position = 0.5 * LENGTH;
    scene.sections.push(SectionSpec {
        name: "midspan".into(),
        position: 0.5 * LENGTH,
    });
    scene.solver.step = exit() / 4000.0;
    scene.solver.end_time = end_time;
    scene.validate().expect("valid");
    scene
}

fn run(scene: &Scene) -> (Trace, Option<f64>) {
    let mut forces = ForceRun::new(scene).expect("builds");
    let run = drive(scene, &mut forces, |_| {}).expect("runs");
    (run.trace, run.exit_time)
}

/// The largest |value| of `column` over the rows with time in [from, to].
fn peak(trace: &Trace, column: &str, (from, to): (f64, f64)) -> f64 {
    let values = trace.column(column).expect("the column");
    trace
        .time
        .iter()
        .zip(values)
        .filter(|(&t, _)| t >= from && t <= to)
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_run_to_end_time_has_the_free_vibration_of_the_modal_series_at_alpha_1_5() {
    let end = exit() + 1.5 * 2.0 * PI / omega1();
    let (during, after) = (series_peak(0.0, exit()), series_peak(exit(), end));
    eprintln!("series: {during:.5} v0 during the passage, {after:.5} v0 after it");
    // The figures: 1.04 v0 during the passage, 1.18 v0 after it.
    assert!((during - 1.04).abs() < 0.01 && (after - 1.18).abs() < 0.01);
    let (trace, exit_time) = run(&scene(Some(end)));
    let deflection = "sensor.midspan.deflection";
    let run_during = peak(&trace, deflection, (0.0, exit())) / v0();
    let run_after = peak(&trace, deflection, (exit(), f64::INFINITY)) / v0();
    eprintln!("run: {run_during:.5} v0 during the passage, {run_after:.5} v0 after it");
    assert!(
        (run_during / during - 1.0).abs() < 5e-3,
        "{run_during} vs {during}"
    );
    assert!(
        (run_after / after - 1.0).abs() < 5e-3,
        "{run_after} vs {after}"
    );
    // The run went on to end_time (the last step may pass it).
    let last = *trace.time.last().expect("rows");
    assert!(last >= end && last < end + scene(None).solver.step * 1.001);
    assert_eq!(exit_time, None);
    // Without an end time it stops after the step in which the force left.
    let (trace, exit_time) = run(&scene(None));
    assert_eq!(exit_time, Some(exit()));
    let last = *trace.time.last().expect("rows");
    assert!(last >= exit() && last < exit() + scene(None).solver.step * 1.001);
}

/// Two axles, 7 m apart and of different loads, on a damped beam, against
/// two runs of one axle each: every linear output (not the energies) is their sum.
#[test]
fn a_two_axle_run_is_the_sum_of_its_one_axle_runs() {
    let end = 2.5 * exit();
    let mut both = scene(Some(end));
    both.beam.damping = Some(guideway::scene::DampingSpec::Modes {
        ratio: 0.02,
        modes: [1, 3],
    });
    both.vehicles[0].initial_position = 7.0;
    let mut second = both.vehicles[0].clone();
    second.name = "second".into();
    second.initial_position = 0.0;
    second.force_y = -0.4 * FORCE;
    both.vehicles.push(second.clone());
    both.validate().expect("valid");
    let mut first_alone = both.clone();
    first_alone.vehicles.truncate(1);
    let mut second_alone = first_alone.clone();
    second_alone.vehicles[0] = second;
    let (sum, a, b) = (run(&both).0, run(&first_alone).0, run(&second_alone).0);
    assert_eq!(sum.time, a.time);
    assert_eq!(sum.time, b.time);
    let mut checked = 0;
    for name in sum.names.iter().filter(|n| !n.starts_with("energy.")) {
        let (s, x, y) = (
            sum.column(name).unwrap(),
            a.column(name).unwrap(),
            b.column(name).unwrap(),
        );
        let scale = s.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(scale > 0.0, "{name} is never nonzero");
        for k in 0..s.len() {
            let error = (s[k] - (x[k] + y[k])).abs() / scale;
            assert!(
                error < 1e-9,
                "{name} at row {k}: {} vs {}",
                s[k],
                x[k] + y[k]
            );
        }
        checked += 1;
    }
    // deflection, velocity, acceleration, moment, shear, forces on beam
    assert_eq!(checked, 6);
}

/// `sweep` at the run's one speed with the same end time runs the same
/// crossing: its peaks are the run's.
#[test]
fn the_sweep_at_one_speed_has_the_peaks_of_the_run() {
    let end = exit() + 0.37 * 2.0 * PI / omega1();
    let scene = scene(Some(end));
    let (trace, _) = run(&scene);
    let rows = sweep(
        &scene,
        &Loads::Scene,
        (&[speed()], SpeedUnit::MetresPerSecond),
        1,
        u64::MAX,
    )
    .expect("the sweep runs");
    let mut compared = 0;
    for design in rows[0].design.iter() {
        let Some(column) = trace.column(&design.name) else {
            continue;
        };
        let largest = column
            .iter()
            .copied()
            .fold(0.0_f64, |p, v| if v.abs() > p.abs() { v } else { p });
        assert_eq!(largest, design.peak, "{}", design.name);
        compared += 1;
    }
    assert_eq!(compared, 5);
}

/// `guideway run` of the shipped HSLM bridge scene to an end time after
/// the train: CSV, summary and plot written; the summary's first and last
/// axle exits are the train's closed-form times (leading axle at x = 0 and
/// the last HSLM-A1 axle 397.525 m behind it, at 50 m/s on 25 m).
#[test]
fn the_cli_runs_a_train_of_moving_forces_with_its_free_vibration() {
    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string("scenes/bridge25_hslm.toml").unwrap();
    let scene = scene.replace("[solver]", "[solver]\nend_time = 9.5");
    let file = dir.path().join("bridge.toml");
    std::fs::write(&file, scene).unwrap();
    let (csv, json, png) = (
        dir.path().join("run.csv"),
        dir.path().join("run.json"),
        dir.path().join("run.png"),
    );
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args(["run", file.to_str().unwrap(), "--quiet", "--out"])
        .arg(&csv)
        .arg("--summary")
        .arg(&json)
        .arg("--plot")
        .arg(&png)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let vehicle = &summary["vehicles"][0];
    let length = guideway::moving_load::hslm("HSLM-A1").unwrap().length();
    assert_eq!(vehicle["contacts"], 50);
    assert!((vehicle["first_exit_time"].as_f64().unwrap() - 25.0 / 50.0).abs() < 1e-12);
    let last = (25.0 + length) / 50.0;
    assert!((vehicle["last_exit_time"].as_f64().unwrap() - last).abs() < 1e-12);
    assert!(
        summary["dynamic_amplification"]["sensor.midspan.deflection"]
            .as_f64()
            .unwrap()
            > 1.0
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().next().unwrap();
    assert!(header.contains("sensor.midspan.acceleration"), "{header}");
    assert!(header.contains("section.midspan.moment"), "{header}");
    let last_time: f64 = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((9.5..9.5 + 1.001e-3).contains(&last_time), "{last_time}");
    assert!(std::fs::metadata(&png).unwrap().len() > 10_000);
}
