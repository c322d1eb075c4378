//! The many-contact scene both cost examples measure: `contacts` paper
//! wheels (3000 kg, gravity on, 200 kN applied load each) 50 m / contacts
//! apart from x = 0.5 m on a three-span continuous beam (3 × 25 m,
//! EI = 1e10 N m², 5000 kg/m) with 100 m of run-off, at 150 km/h.

use guideway::scene::{BodyKind, IntegratorKind, Scene};

pub fn wheels_on_three_spans(
    contacts: usize,
    elements: usize,
    integrator: IntegratorKind,
    step: f64,
) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 150.0 / 3.6, step);
    scene.gravity = 9.81;
    scene.beam.length = 75.0;
    scene.beam.bending_stiffness = 1e10;
    scene.beam.mass_per_length = 5000.0;
    scene.beam.elements = elements;
    scene.beam.supports.intermediate = vec![25.0, 50.0];
    scene.track.run_off = 100.0;
    scene.solver.integrator = integrator;
    scene.solver.numerical_damping = 0.1;
    scene.sensors[0].position = 37.5;
    let spacing = 50.0 / contacts as f64;
    let template = scene.vehicles[0].clone();
    let wheels = (0..contacts).map(|i| {
        let mut body = template.clone();
        body.name = format!("wheel{}", i + 1);
        body.force_y = -2e5;
        body.initial_position = 0.5 + spacing * i as f64;
        body
    });
    scene.vehicles = wheels.collect();
    assert!(!scene.vehicles.is_empty(), "at least one contact");
    scene
}
