//! Where the error of a coarse step comes from on the paper's 10 m/s case:
//! the local error of each step of Δt along the run, each step taken from
//! the fine reference's state (`guideway::study::local_error`).
//!
//! `cargo run --release --example local_error [Δt] [held|linear|quadratic] [elements]`
//!
//! Prints per step: time, contact abscissa, the local errors of the nominal
//! speed V and of the energy balance (per initial energy); then the step
//! that straddles the midspan node against its neighbours, the frequency
//! the errors follow, and RMS values over the run.

use guideway::scene::{builtin, ForceProfile, IntegratorKind};
use guideway::study::local_error::{dominant_frequency, local_errors, StepError};

/// Fine steps per coarse step in the reference.
const FINE: usize = 64;

fn profile(name: &str) -> ForceProfile {
    match name {
        "held" => ForceProfile::Held,
        "linear" => ForceProfile::Linear,
        _ => ForceProfile::Quadratic,
    }
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0), |(s, n), v| (s + v * v, n + 1));
    (sum / n as f64).sqrt()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dt: f64 = args.get(1).map_or(0.0025, |a| a.parse().expect("a step"));
    let shape = profile(args.get(2).map_or("quadratic", String::as_str));
    let elements: usize = args.get(3).map_or(2, |a| a.parse().expect("a count"));
    let mut scene = builtin("lee1994-wheel-10").expect("built in");
    scene.beam.elements = elements;
    scene.solver.integrator = IntegratorKind::Rk4;
    scene.solver.velocity_tolerance = 1e-12;
    scene.solver.force_profile = shape;
    scene.solver.step = dt;
    let rows = local_errors(&scene, FINE).expect("the runs complete");
    println!("# Δt = {dt} s, {shape:?}, {elements} elements; reference Δt/{FINE}");
    println!("# t (s), x (m), local V error (m/s), local energy error / E0");
    for r in &rows {
        println!(
            "{:.6} {:.4} {:+.3e} {:+.3e}",
            r.time, r.position, r.speed, r.energy
        );
    }
    let midspan = 0.5 * scene.beam.length;
    if let Some(i) = rows.iter().position(|r| r.position >= midspan) {
        let near = |r: &&StepError| (r.position - midspan).abs() < 0.5;
        let others = rows.iter().enumerate().filter(|&(j, r)| j != i && near(&r));
        let (v, e) = others.fold((0.0f64, 0.0f64), |(v, e), (_, r)| {
            (v.max(r.speed.abs()), e.max(r.energy.abs()))
        });
        println!(
            "# the step straddling x = {midspan} m: V {:.3e}, energy {:.3e}; \
             largest of the other steps within 0.5 m: V {v:.3e}, energy {e:.3e}",
            rows[i].speed.abs(),
            rows[i].energy.abs()
        );
    }
    let speeds: Vec<f64> = rows.iter().map(|r| r.speed).collect();
    println!(
        "# {} steps: RMS local V error {:.3e} m/s, energy {:.3e}; sum of energy errors {:.3e}; \
         V errors follow ω = {:.0} rad/s",
        rows.len(),
        rms(speeds.iter().copied()),
        rms(rows.iter().map(|r| r.energy)),
        rows.iter().map(|r| r.energy).sum::<f64>(),
        dominant_frequency(&speeds, dt)
    );
}
