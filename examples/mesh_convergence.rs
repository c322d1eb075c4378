//! Mesh convergence of the paper's 10 m/s wheel case: prints the table of docs/verification.md.
//!
//! `cargo run --release --example mesh_convergence`
//!
//! Each mesh runs at a stable RK4 step (the largest of 0.0025 s / 2^k under
//! the mesh's stability limit, which `Simulation::new` checks).

use guideway::report::{run_scene, RunError};
use guideway::scene::{builtin, DEFAULT_SCENE};

fn main() {
    println!("| elements | Δt (s) | exit V (m/s) | peak midspan deflection / 0.1728 m | max energy drift | steps | iterations | wall time (s) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for elements in [2usize, 4, 8, 16] {
        let mut scene = builtin(DEFAULT_SCENE).expect("the default scene is built in");
        scene.beam.elements = elements;
        let run = loop {
            match run_scene(&scene, |_| {}) {
                // Refused before running: beyond RK4's stability limit.
                Err(RunError::Setup(_)) => scene.solver.step /= 2.0,
                other => break other.expect("the run converges"),
            }
        };
        let summary = run.summary(&scene);
        println!(
            "| {elements} | {:.3e} | {:.4} | {:.4} | {:.2e} | {} | {} | {:.4} |",
            scene.solver.step,
            summary.exit_nominal_speed.unwrap_or(f64::NAN),
            -summary.peak_sensor_deflection["midspan"] / 0.1728,
            summary.max_energy_drift.unwrap_or(f64::NAN),
            summary.steps,
            summary.iterations.unwrap_or(0),
            summary.wall_time_s,
        );
    }
}
