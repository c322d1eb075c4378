//! Several vehicles on one track: independence on rigid ground, coupling
//! through the beam.

use guideway::scene::{BodyKind, BodySpec};
use guideway::{Advance, Scene, Simulation};

fn paper_wheel(name: &str, position: f64, speed: f64) -> BodySpec {
    let mut spec = Scene::lee1994(BodyKind::Wheel, speed, 0.0025).vehicles[0].clone();
    spec.name = name.to_string();
    spec.initial_position = position;
    spec
}

fn ground_scene(bodies: &[BodySpec]) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.gravity = 9.81;
    scene.track.approach = 2000.0;
    scene.vehicles = bodies.to_vec();
    scene.solver.end_time = Some(2.0);
    scene.validate().expect("valid");
    scene
}

fn final_values(scene: &Scene, end: f64) -> (Vec<String>, Vec<f64>) {
    let mut sim = Simulation::new(scene).expect("builds");
    let dt = scene.solver.step;
    for k in 1..=(end / dt).round() as u64 {
        assert_eq!(sim.advance_to(k as f64 * dt).unwrap(), Advance::Reached);
    }
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    (names, values)
}

fn value(run: &(Vec<String>, Vec<f64>), name: &str) -> f64 {
    run.1[run.0.iter().position(|n| n == name).expect(name)]
}

#[test]
fn two_far_apart_wheels_on_rigid_ground_are_two_single_wheels() {
    let (a, b) = (
        paper_wheel("wheel", -1500.0, 10.0),
        paper_wheel("wheel", -500.0, 14.0),
    );
    let single_a = final_values(&ground_scene(std::slice::from_ref(&a)), 2.0);
    let single_b = final_values(&ground_scene(std::slice::from_ref(&b)), 2.0);
    let mut b2 = b.clone();
    b2.name = "second".into();
    let pair = final_values(&ground_scene(&[a, b2]), 2.0);
    for q in ["x", "y", "vx", "vy", "angular_velocity", "nominal_speed"] {
        let (alone, together) = (
            value(&single_a, &format!("wheel.{q}")),
            value(&pair, &format!("wheel.{q}")),
        );
        assert!(
            (alone - together).abs() <= 1e-12 * alone.abs().max(1.0),
            "wheel.{q}: {alone} vs {together}"
        );
        let (alone, together) = (
            value(&single_b, &format!("wheel.{q}")),
            value(&pair, &format!("second.{q}")),
        );
        assert!(
            (alone - together).abs() <= 1e-12 * alone.abs().max(1.0),
            "second.{q}: {alone} vs {together}"
        );
    }
    for (single, contact) in [(&single_a, "contact"), (&single_b, "second_contact")] {
        let alone = value(single, "contact.normal_force");
        let together = value(&pair, &format!("{contact}.normal_force"));
        assert!(
            (alone - together).abs() <= 1e-9 * alone,
            "{contact}: {alone} vs {together}"
        );
    }
    // The ground carries each wheel's load and weight.
    let load = 6e5 + 3000.0 * 9.81;
    assert!((value(&pair, "second_contact.normal_force") - load).abs() < 1e-6 * load);
}

#[test]
fn two_wheels_on_one_span_load_each_other_and_keep_the_energy_balance() {
    // The paper's wheel, and a second one 6 m ahead: both on the beam at
    // once, coupled through it (the block Delassus operator's off-diagonal
    // blocks).
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.vehicles.push(paper_wheel("second", 6.0, 10.0));
    // Without run-off the first wheel to leave the beam would leave the
    // track and end the run.
    scene.track.run_off = 30.0;
    scene.validate().unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).unwrap();
    let (balance, midspan) = (at("energy.balance"), at("sensor.midspan.deflection"));
    let mut values = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let (mut drift, mut peak): (f64, f64) = (0.0, 0.0);
    let mut ended = None;
    for k in 1..2000 {
        match sim.advance_to(k as f64 * 0.0025).expect("converges") {
            Advance::Reached => {}
            Advance::Exited { time } => {
                ended = Some(time);
                break;
            }
        }
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs() / e0);
        peak = peak.max(-values[midspan]);
    }
    // The run ends when the last contact (the first wheel) leaves the beam.
    let ended = ended.expect("both wheels left");
    let events = sim.events();
    // Both start on the beam: each has its exit only, the second first.
    assert_eq!(events.len(), 2, "{events:?}");
    assert_eq!(events[0].contact, 1);
    assert_eq!(events.last().unwrap().contact, 0);
    assert_eq!(events.last().unwrap().time, ended);
    // Two 600 kN loads deflect the beam more than one (1.093 × 0.1728 m).
    assert!(peak > 1.2 * 0.1889, "peak deflection {peak}");
    assert!(drift < 1e-4, "energy drift {drift}");
    eprintln!("two wheels: peak midspan {peak} m, energy drift {drift:.3e}, end {ended} s");
}
