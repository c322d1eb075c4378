//! Steps of the paper's scene on a given mesh, for instruction counts:
//! `valgrind --tool=callgrind target/release/examples/step_cost 1024 hht 20`
//! run at two step counts; the difference divided by the difference of the
//! counts is the cost of one step, start-up excluded (callgrind's counts do
//! not depend on the machine's load).
use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: step_cost <elements> <rk4|hht> <steps>";
    let elements: usize = args.get(1).and_then(|a| a.parse().ok()).expect(usage);
    let integrator = match args.get(2).map(String::as_str) {
        Some("rk4") => IntegratorKind::Rk4,
        Some("hht") => IntegratorKind::Hht,
        _ => panic!("{usage}"),
    };
    let steps: u32 = args.get(3).and_then(|a| a.parse().ok()).expect(usage);
    // RK4 at the largest stable step 0.0025 s / 2^k, HHT at the paper's.
    let mut step = 0.0025;
    let mut sim = loop {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
        scene.beam.elements = elements;
        scene.body.initial_position = 6.0;
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
