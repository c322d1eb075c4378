//! The compliant contact laws' secant step under HHT-α (issue 29 item 2,
//! issue 24's speed): the eight Hertz coaches on the rail over the deck
//! converge in at most 4.5 integrations a step (8.0 with the plain fixed
//! point), to the same fixed point: the forces agree with a run whose
//! tolerance is 1e4 times tighter.

use guideway::{Scene, Simulation};

/// The built-in rail scene, cut at `end_time`, at `velocity_tolerance`.
fn rail_scene(end_time: f64, velocity_tolerance: f64) -> Scene {
    let text = include_str!("../../scenes/train-8-coaches-20m-300-rail.toml")
        .replace("end_time = 2.6", &format!("end_time = {end_time:?}"))
        .replace(
            "velocity_tolerance = 1e-7",
            &format!("velocity_tolerance = {velocity_tolerance:e}"),
        );
    Scene::from_toml_str(&text).expect("a valid scene")
}

/// Every wheelset's normal force at every grid point of a run, and the
/// integrations a step.
fn forces_and_iterations(scene: &Scene) -> (Vec<f64>, f64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let forces: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].ends_with(".normal_force"))
        .collect();
    assert_eq!(forces.len(), 32, "{names:?}");
    let mut values = vec![0.0; names.len()];
    let mut found = Vec::new();
    let dt = scene.solver.step;
    let end = (scene.solver.end_time.expect("an end time") / dt).round() as u64;
    for k in 1..=end {
        sim.advance_to(k as f64 * dt).expect("no solver error");
        sim.output_values(&mut values);
        found.extend(forces.iter().map(|&i| values[i]));
    }
    let (steps, iterations) = sim.counters();
    (found, iterations as f64 / steps as f64)
}

#[test]
fn hertz_coaches_on_the_rail_converge_in_few_integrations_to_the_fixed_point() {
    let (forces, per_step) = forces_and_iterations(&rail_scene(0.05, 1e-7));
    assert!(per_step <= 4.5, "{per_step} integrations a step");
    let (tight, _) = forces_and_iterations(&rail_scene(0.05, 1e-11));
    let largest = tight.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    assert!(largest > 1e5, "{largest}");
    let worst = forces
        .iter()
        .zip(&tight)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    // The tolerance 1e-7 m/s on a 1400 kg wheelset over 0.25 ms is a
    // force of about 1 N (1e-5 of the static wheel load, 120.9 kN).
    assert!(worst < 1e-5 * largest, "{worst} N of {largest} N");
}
