//! Communication steps of the paper's wheel through the FMU's model layer,
//! with or without the running error estimate, for instruction counts:
//! `valgrind --tool=callgrind target/release/examples/fmu_error_cost on 400`
//! run at two step counts, on and off; the difference of the counts over
//! the difference of the steps is the cost of one communication step
//! (start-up excluded), and on over off the estimate's cost ratio.

use guideway::model::{Model, VarType};
use guideway::scene::{BodyKind, Scene};
use guideway::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: fmu_error_cost <on|off> <communication steps> [communication step s]";
    let on = match args.get(1).map(String::as_str) {
        Some("on") => true,
        Some("off") => false,
        _ => panic!("{usage}"),
    };
    let steps: u32 = args.get(2).and_then(|a| a.parse().ok()).expect(usage);
    let h: f64 = args.get(3).map_or(0.01, |a| a.parse().expect(usage));
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.vehicles[0].initial_position = 1.0;
    scene.error_estimate = on;
    let mut model = Model::<Simulation>::new(scene).expect("the paper's scene builds");
    model.initialize().expect("it initializes");
    let reals: Vec<u32> = model
        .table()
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.value_reference)
        .collect();
    for _ in 0..steps {
        model.do_step(model.time(), h).expect("the step runs");
        std::hint::black_box(model.get(VarType::Real, &reals).expect("outputs read"));
    }
}
