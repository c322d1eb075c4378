//! Mesh and step convergence of the lift-off and of the landing on the
//! rigid run-off of the paper's wheel at 150 m/s (the last one: its largest),
//! and of a glider's first landing on the beam, as Markdown tables for
//! docs/lift-off.md, "Lift-off and landing": `cargo run --release --example
//! lift_off_convergence`.

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::simulation::EventKind;
use guideway::Simulation;

fn main() {
    wheel_onto_the_run_off();
    println!();
    glider_onto_the_beam();
}

/// The glider of `tests/vehicles/lift_off.rs` released 0.2 m above midspan of the
/// undamped paper beam that the wheel crosses at 100 m/s: the instant of
/// its first landing and that impact's normal impulse.
fn glider_onto_the_beam() {
    println!("| elements | Δt (s) | integrator | first landing t (s) | normal impulse P (N s) | P × elements |");
    println!("|---|---|---|---|---|---|");
    for (elements, step) in [
        (8, 1e-4),
        (16, 1e-4),
        (16, 5e-5),
        (16, 2.5e-5),
        (32, 2.5e-5),
        (32, 1.25e-5),
        (64, 5e-6),
        (128, 1e-5),
    ] {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 100.0, step);
        scene.beam.elements = elements;
        scene.solver.integrator = IntegratorKind::Auto;
        let mut glider = Scene::lee1994(BodyKind::Glider, 0.0, step).vehicles[0].clone();
        glider.name = "glider".into();
        glider.initial_position = 12.0;
        glider.initial_height = 0.2;
        scene.vehicles.push(glider);
        scene.validate().expect("valid");
        let mut sim = Simulation::new(&scene).expect("builds");
        let mut k = 0u64;
        let landing = loop {
            k += 1;
            sim.advance_to(k as f64 * step).expect("runs");
            let event = sim
                .events()
                .iter()
                .find(|e| e.contact == 1 && e.kind == EventKind::Landing);
            if let Some(event) = event {
                break event.time;
            }
        };
        // The impulse of the grid step's first impact (a second one in the
        // same grid step would overwrite it: none here, checked).
        let landings = sim
            .events()
            .iter()
            .filter(|e| e.contact == 1 && e.kind == EventKind::Landing)
            .count();
        assert_eq!(landings, 1, "{elements} elements, {step} s");
        let p = sim.contact_statuses()[1].impulse[1];
        let integrator = sim.integrator_choice().split(' ').next().unwrap_or("");
        println!(
            "| {elements} | {step:.2e} | {integrator} | {landing:.7} | {p:.1} | {:.0} |",
            p * elements as f64
        );
    }
}

/// The paper's wheel at 150 m/s on the beam and onto a rigid run-off.
fn wheel_onto_the_run_off() {
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
