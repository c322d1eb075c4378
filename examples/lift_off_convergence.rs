//! Mesh and step convergence of the first lift-off and landing of the
//! paper's wheel at 150 m/s (onto a rigid run-off), as a Markdown table for
//! README's "Lift-off and landing": `cargo run --release --example
//! lift_off_convergence`.

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::simulation::EventKind;
use guideway::Simulation;

fn main() {
    println!("| elements | Δt (s) | integrator | lift-off t (s) | landing t (s) | landing x (m) | normal impulse (N s) |");
    println!("|---|---|---|---|---|---|---|");
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
        let mut landing = None;
        let mut k = 0u64;
        while landing.is_none() && sim.time() < 0.24 - 1e-9 {
            k += 1;
            sim.advance_to(k as f64 * step).expect("runs");
            let found = sim.events().iter().find(|e| e.kind == EventKind::Landing);
            landing = found.map(|e| {
                (
                    e.time,
                    sim.state().dynamic.contact_x[0],
                    sim.contact_statuses()[0].impulse[1],
                )
            });
        }
        let lift_off = sim
            .events()
            .iter()
            .find(|e| e.kind == EventKind::LiftOff)
            .map_or(f64::NAN, |e| e.time);
        let (t, x, p) = landing.unwrap_or((f64::NAN, f64::NAN, f64::NAN));
        let integrator = sim
            .integrator_choice()
            .split(' ')
            .next()
            .unwrap_or("")
            .to_string();
        println!(
            "| {elements} | {step:.1e} | {integrator} | {lift_off:.5} | {t:.6} | {x:.4} | {p:.1} |"
        );
    }
}
