//! Mesh and step convergence of the lift-off and of the landing on the
//! rigid run-off of the paper's wheel at 150 m/s (the last one: its largest), as a Markdown table for
//! README's "Lift-off and landing": `cargo run --release --example
//! lift_off_convergence`.

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::simulation::EventKind;
use guideway::Simulation;

fn main() {
    println!(
        "| elements | Δt (s) | integrator | first lift-off t (s) | flights | run-off landing t (s) | x at the grid point after it (m) | normal impulse (N s) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (elements, step) in [
        (8, 1e-4),
        (16, 1e-4),
        (16, 5e-5),
        (16, 2.5e-5),
        (32, 2.5e-5),
    ] {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 150.0, step);
        scene.beam.elements = elements;
        scene.solver.integrator = IntegratorKind::Auto;
        scene.track.run_off = 30.0;
        scene.solver.end_time = Some(0.24);
        scene.validate().expect("valid");
        let mut sim = Simulation::new(&scene).expect("builds");
        let mut landing = (f64::NAN, f64::NAN, f64::NAN);
        let mut landings = 0;
        let mut k = 0u64;
        while sim.time() < 0.24 - 1e-9 {
            k += 1;
            sim.advance_to(k as f64 * step).expect("runs");
            let count = sim
                .events()
                .iter()
                .filter(|e| e.kind == EventKind::Landing)
                .count();
            if count > landings {
                landings = count;
                // The landing ends its (shortened) step: the state after it is
                // the one at the event unless the grid step went on.
                let event = sim.events().iter().rfind(|e| e.kind == EventKind::Landing);
                let x = sim.state().dynamic.contact_x[0];
                let impulse = sim.contact_statuses()[0].impulse[1];
                landing = (event.map_or(f64::NAN, |e| e.time), x, impulse);
            }
        }
        let lift_offs: Vec<f64> = sim
            .events()
            .iter()
            .filter(|e| e.kind == EventKind::LiftOff)
            .map(|e| e.time)
            .collect();
        let (t, x, p) = landing;
        let integrator = sim.integrator_choice().split(' ').next().unwrap_or("");
        println!(
            "| {elements} | {step:.1e} | {integrator} | {:.5} | {} | {t:.6} | {x:.4} | {p:.1} |",
            lift_offs.first().copied().unwrap_or(f64::NAN),
            lift_offs.len()
        );
    }
}
