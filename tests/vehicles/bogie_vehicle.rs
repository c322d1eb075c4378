//! The `bogie_vehicle` preset (10-DOF half vehicle: car body and two bogies
//! in bounce and pitch, four glider wheelsets) on the simply supported beam
//! of Yang & Yau (1997) (L = 25 m, EI = 2.943e10 N/m² × 2.90 m⁴,
//! m̄ = 2303 kg/m), with vehicle data of the order of a passenger coach.

use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

use crate::common::{coach_bogie_on_gliders, largest_acceleration, GRAVITY};

fn scene(length: f64, position: f64, speed: f64, start: &str, step: f64, end_time: f64) -> Scene {
    let bogie = coach_bogie_on_gliders("body", 0.0, 0.0);
    Scene::from_toml_str(&format!(
        r#"
name = "bogie"
gravity = {GRAVITY:?}
[beam]
length = {length:?}
mass_per_length = 2303.0
bending_stiffness = {:?}
surface_offset = 0.0
elements = {}
[track]
approach = 25.0
run_off = 25.0
[body]
name = "coach"
kind = "bogie_vehicle"
mass = 38884.0
initial_position = {position:?}
initial_speed = {speed:?}
{bogie}
[[sensors]]
name = "midspan"
position = {:?}
[solver]
step = {step:?}
start = "{start}"
end_time = {end_time:?}
"#,
        2.943e10 * 2.90,
        (length / 2.5).round(),
        length / 2.0
    ))
    .expect("valid scene")
}

#[test]
fn bogie_vehicle_at_rest_on_the_deflected_beam_stays_at_rest() {
    // Centred at midspan, speed 0, static start: the beam carries the
    // vehicle's weight in its static deflection and nothing moves.
    let step = 5e-5;
    let mut sim = Simulation::new(&scene(25.0, 12.5, 0.0, "static", step, 1.0)).expect("builds");
    let midspan = sim
        .outputs()
        .iter()
        .position(|o| o.name == "sensor.midspan.deflection");
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    let deflection = values[midspan.expect("midspan sensor")];
    // The static deflection of the beam under the weight is present.
    assert!(deflection < -1e-4, "midspan deflection {deflection} m");
    let mut worst = largest_acceleration(&sim);
    eprintln!("at t = 0: {worst:.3e} g");
    for k in 1..=200 {
        assert_eq!(sim.advance_to(k as f64 * step).unwrap(), Advance::Reached);
        worst = worst.max(largest_acceleration(&sim));
    }
    eprintln!("midspan {deflection:.4e} m; largest acceleration {worst:.3e} g over 200 steps");
    assert!(worst < 1e-9, "largest body acceleration {worst:e} g");
}

#[test]
fn without_the_static_start_the_vehicle_at_rest_moves() {
    // The same vehicle on the undeformed beam is not in equilibrium: the
    // at-rest test above could fail.
    let step = 5e-5;
    let mut sim = Simulation::new(&scene(25.0, 12.5, 0.0, "rest", step, 1.0)).expect("builds");
    let mut worst: f64 = 0.0;
    for k in 1..=200 {
        sim.advance_to(k as f64 * step).unwrap();
        worst = worst.max(largest_acceleration(&sim));
    }
    assert!(worst > 1e-3, "largest body acceleration {worst:e} g");
}

/// Largest |balance − initial| over the run and the largest |work| gravity
/// did on the way.
fn energy_drift(scene: &Scene) -> (f64, f64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (balance, gravity) = (at("energy.balance"), at("energy.gravity_work"));
    let mut values = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let (mut drift, mut work): (f64, f64) = (0.0, 0.0);
    let end = scene.solver.end_time.expect("an end time");
    let steps = (end / scene.solver.step).round() as usize;
    for k in 1..=steps {
        let advance = sim.advance_to(k as f64 * scene.solver.step).unwrap();
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs());
        work = work.max(values[gravity].abs());
        if advance != Advance::Reached {
            break;
        }
    }
    (drift, work)
}

#[test]
fn energy_balance_holds_as_a_bogie_vehicle_crosses_the_beam() {
    // A 50 m span of the same section, from the static start with the rear
    // wheelset 0.5 m into the beam, at 100 km/h until the front wheelset is
    // 2.5 m before the end, undamped: gravity does work as the beam deflects
    // and the vehicle pitches over it. (Glider wheelsets cannot pass the
    // kink of the surface at a support: their normal velocity would jump.)
    let speed = 100.0 / 3.6;
    let end_time = 27.0 / speed;
    let crossing = scene(50.0, 10.5, speed, "static", 5e-5, end_time);
    let (drift, gravity_work) = energy_drift(&crossing);
    eprintln!("drift {drift:.3e} J, gravity work {gravity_work:.4e} J");
    assert!(gravity_work > 100.0, "{gravity_work}");
    assert!(
        drift < 1e-5 * gravity_work,
        "drift {drift} J of {gravity_work} J"
    );
}

/// The same coach on rolling wheelsets (r = 0.45 m, J = 700 kg m²).
fn on_wheels(mut scene: Scene) -> Scene {
    let bogie = scene.vehicles[0].bogie.as_mut().expect("a bogie vehicle");
    bogie.wheel_radius = Some(0.45);
    bogie.wheelset_inertia = Some(700.0);
    scene.validate().expect("valid scene");
    scene
}

#[test]
fn a_bogie_vehicle_on_wheels_rolls_from_the_approach_onto_the_run_off() {
    // From the approach (rear wheelset 1 m after the track's start) over
    // the 25 m beam onto the run-off, at 5 m/s, undamped, until the front
    // wheelset is 1 m before the track's end: every wheelset enters and
    // leaves the beam (glider wheelsets cannot: the slope jumps at the
    // beam's ends), and the energy balance holds over the events. Rolling
    // over the loaded beam's end (a corner) needs a normal force of
    // m v² / r towards it, so a bilateral wheel holds only while that is
    // below its static load: v below about 6 m/s here.
    // The drift is first order in the step (events and the first steps;
    // 2.5e-3 J at 5e-5 s, 1.0e-3 J at 2.5e-5 s).
    let (speed, step) = (5.0, 2.5e-5);
    let (approach, reach) = (25.0, 10.0);
    let start = -approach + reach + 1.0;
    let end_time = (25.0 + 25.0 - 1.0 - reach - start) / speed;
    let crossing = on_wheels(scene(25.0, start, speed, "static", step, end_time));
    let mut sim = Simulation::new(&crossing).expect("builds");
    let e0 = sim.initial_energy();
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (balance, gravity) = (at("energy.balance"), at("energy.gravity_work"));
    let mut values = vec![0.0; names.len()];
    let (mut drift, mut work): (f64, f64) = (0.0, 0.0);
    let steps = (end_time / step).round() as usize;
    for k in 1..=steps {
        let advance = sim.advance_to(k as f64 * step).expect("no lift-off");
        assert_eq!(advance, Advance::Reached);
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs());
        work = work.max(values[gravity].abs());
    }
    let events = sim.events();
    let (entries, exits) = (
        events.iter().filter(|e| e.kind == EventKind::Entry).count(),
        events.iter().filter(|e| e.kind == EventKind::Exit).count(),
    );
    eprintln!("{entries} entries, {exits} exits; drift {drift:.3e} J, gravity work {work:.4e} J");
    assert_eq!((entries, exits), (4, 4), "{events:?}");
    assert!(work > 100.0, "{work}");
    assert!(drift < 1e-5 * work, "drift {drift} J of {work} J");
}
