//! Steps of the paper's scene on a given mesh, for instruction counts:
//! `valgrind --tool=callgrind target/release/examples/step_cost 1024 hht 20`
//! run at two step counts; the difference divided by the difference of the
//! counts is the cost of one step, start-up excluded (callgrind's counts do
//! not depend on the machine's load).
//!
//! With a fourth argument, `contacts`, the scene is that of
//! `contacts_scaling`: that many paper wheels (3000 kg, gravity, 200 kN
//! each) spread over a three-span continuous beam of 3 × 25 m at 150 km/h,
//! Δt = 1 ms, on `elements` elements.
#[path = "common/three_spans.rs"]
mod three_spans;

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: step_cost <elements> <rk4|hht> <steps> [contacts]";
    let elements: usize = args.get(1).and_then(|a| a.parse().ok()).expect(usage);
    let integrator = match args.get(2).map(String::as_str) {
        Some("rk4") => IntegratorKind::Rk4,
        Some("hht") => IntegratorKind::Hht,
        _ => panic!("{usage}"),
    };
    let steps: u32 = args.get(3).and_then(|a| a.parse().ok()).expect(usage);
    if let Some(contacts) = args.get(4) {
        let contacts: usize = contacts.parse().expect(usage);
        return many_contacts(elements, integrator, steps, contacts);
    }
    // RK4 at the largest stable step 0.0025 s / 2^k, HHT at the paper's.
    let mut step = 0.0025;
    let mut sim = loop {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
        scene.beam.elements = elements;
        scene.vehicles[0].initial_position = 6.0;
        scene.solver.integrator = integrator;
        if let Ok(sim) = Simulation::new(&scene) {
            break sim;
        }
        step /= 2.0;
    };
    for k in 1..=steps {
        sim.advance_to(k as f64 * step).expect("converges");
    }
    let (steps, integrations) = sim.counters();
    println!("{elements} elements, step {step:e} s: {steps} steps, {integrations} integrations");
}

/// `contacts` paper wheels 50 m / contacts apart from x = 0.5 m on a 3 × 25 m
/// continuous beam (EI = 1e10 N m², 5000 kg/m), 150 km/h, Δt = 1 ms (RK4
/// halves it until stable).
fn many_contacts(elements: usize, integrator: IntegratorKind, steps: u32, contacts: usize) {
    let mut step = 0.001;
    let mut sim = loop {
        let scene = three_spans::wheels_on_three_spans(contacts, elements, integrator, step);
        if let Ok(sim) = Simulation::new(&scene) {
            break sim;
        }
        step /= 2.0;
    };
    for k in 1..=steps {
        sim.advance_to(k as f64 * step).expect("converges");
    }
    let (steps, integrations) = sim.counters();
    println!(
        "{contacts} contacts, {elements} elements, step {step:e} s: {steps} steps, \
         {integrations} integrations"
    );
}
