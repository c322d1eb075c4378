//! Mesh convergence of the paper's 10 m/s wheel case: prints the README table.
//!
//! `cargo run --release --example mesh_convergence`
//!
//! Each mesh runs at a stable RK4 step (the largest of 0.0025 s / 2^k under
//! the mesh's stability limit, which `Simulation::new` checks).

use guideway::scene::{BodyKind, Scene};
use guideway::{Advance, Simulation};

fn main() {
    println!("| elements | Δt (s) | exit V (m/s) | peak midspan deflection / 0.1728 m | max energy drift | steps | iterations | wall time (s) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for elements in [2usize, 4, 8, 16] {
        let mut step = 0.0025;
        let (scene, mut sim) = loop {
            let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
            scene.beam.elements = elements;
            match Simulation::new(&scene) {
                Ok(sim) => break (scene, sim),
                Err(_) => step /= 2.0,
            }
        };
        let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
        let at = |n: &str| names.iter().position(|x| x == n).unwrap();
        let (speed, balance, midspan) = (
            at("wheel.nominal_speed"),
            at("energy.balance"),
            at("sensor.midspan.deflection"),
        );
        let mut values = vec![0.0; names.len()];
        let e0 = sim.initial_energy();
        let (mut drift, mut deflection) = (0.0f64, 0.0f64);
        let start = std::time::Instant::now();
        let mut k = 0u64;
        let exit_speed = loop {
            k += 1;
            let advance = sim
                .advance_to(k as f64 * scene.solver.step)
                .expect("converges");
            sim.output_values(&mut values);
            drift = drift.max(((values[balance] - e0) / e0).abs());
            deflection = deflection.min(values[midspan]);
            if let Advance::Exited { .. } = advance {
                break values[speed];
            }
        };
        let wall = start.elapsed().as_secs_f64();
        let (steps, iterations) = sim.counters();
        println!(
            "| {elements} | {step:.3e} | {exit_speed:.4} | {:.4} | {drift:.2e} | {steps} | {iterations} | {wall:.4} |",
            -deflection / 0.1728
        );
    }
}
