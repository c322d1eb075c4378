//! The `maglev_vehicle` preset: a car body (bounce, pitch) over eight
//! magnets (gliders) on spring–dampers, 3 m apart, on the beam section of
//! Yang & Yau (1997) (EI = 2.943e10 N/m² × 2.90 m⁴, m̄ = 2303 kg/m).

use guideway::{Advance, Scene, Simulation};

use crate::common::{largest_acceleration, GRAVITY};

/// A maglev car on a beam of `spans` continuous 25 m spans.
fn scene(spans: usize, position: f64, speed: f64, damping: f64, end_time: f64) -> Scene {
    let length = 25.0 * spans as f64;
    let intermediate: Vec<f64> = (1..spans).map(|i| 25.0 * i as f64).collect();
    Scene::from_toml_str(&format!(
        r#"
name = "maglev"
gravity = {GRAVITY:?}
[beam]
length = {length:?}
mass_per_length = 2303.0
bending_stiffness = {:?}
surface_offset = 0.0
elements = {}
[beam.supports]
intermediate = {intermediate:?}
[body]
name = "car"
kind = "maglev_vehicle"
mass = 30000.0
initial_position = {position:?}
initial_speed = {speed:?}
[body.maglev]
car_inertia = 1.5e6
magnets = 8
magnet_spacing = 3.0
magnet_mass = 600.0
stiffness = 8.0e5
damping = {damping:?}
[[sensors]]
name = "midspan"
position = 12.5
[solver]
step = 5e-5
start = "static"
end_time = {end_time:?}
"#,
        2.943e10 * 2.90,
        10 * spans,
    ))
    .expect("valid scene")
}

#[test]
fn maglev_vehicle_has_a_car_body_and_its_magnets() {
    let sim = Simulation::new(&scene(1, 12.5, 0.0, 0.0, 1.0)).expect("builds");
    let system = sim.system();
    assert_eq!(system.bodies.len(), 9);
    assert_eq!(system.contacts.len(), 8);
    // A vertical suspension and a longitudinal guide per magnet.
    assert_eq!(system.force_elements.len(), 16);
    let names: Vec<&str> = system.contacts.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names[0], "car_magnet1");
    assert_eq!(names[7], "car_magnet8");
}

#[test]
fn maglev_vehicle_at_rest_on_the_deflected_beam_stays_at_rest() {
    let step = 5e-5;
    let mut sim = Simulation::new(&scene(1, 12.5, 0.0, 1.5e4, 1.0)).expect("builds");
    let mut worst = largest_acceleration(&sim);
    for k in 1..=200 {
        assert_eq!(sim.advance_to(k as f64 * step).unwrap(), Advance::Reached);
        worst = worst.max(largest_acceleration(&sim));
    }
    eprintln!("largest acceleration {worst:.3e} g over 200 steps");
    assert!(worst < 1e-9, "largest body acceleration {worst:e} g");
}

/// Largest |balance − initial| over the run, the largest |work| gravity
/// did and the energy the dampers dissipated by the end.
fn energy_drift(scene: &Scene) -> (f64, f64, f64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (balance, gravity) = (at("energy.balance"), at("energy.gravity_work"));
    let dissipated = at("energy.dissipated");
    let mut values = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let (mut drift, mut work): (f64, f64) = (0.0, 0.0);
    let end = scene.solver.end_time.expect("an end time");
    let steps = (end / scene.solver.step).round() as usize;
    for k in 1..=steps {
        let advance = sim.advance_to(k as f64 * scene.solver.step).unwrap();
        assert_eq!(advance, Advance::Reached);
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs());
        work = work.max(values[gravity].abs());
    }
    (drift, work, values[dissipated])
}

#[test]
fn energy_balance_holds_as_a_maglev_vehicle_crosses_two_spans() {
    // Over a two-span continuous beam (the surface is smooth over the
    // middle support, so the gliders pass it) at 100 km/h, from the rear
    // magnet 0.5 m into the beam to the front one 1 m before its end;
    // undamped, then with dampers whose dissipation the balance counts.
    let speed = 100.0 / 3.6;
    let (start, reach) = (11.0, 10.5);
    let end_time = (50.0 - 1.0 - reach - start) / speed;
    for damping in [0.0, 1.5e4] {
        let (drift, work, dissipated) = energy_drift(&scene(2, start, speed, damping, end_time));
        eprintln!(
            "damping {damping}: drift {drift:.3e} J, gravity work {work:.4e} J, \
             dissipated {dissipated:.4e} J"
        );
        assert!(work > 100.0, "{work}");
        if damping > 0.0 {
            // The dampers' energy is far above the balance's error.
            assert!(dissipated > 1e3 * drift, "{dissipated} J");
        }
        assert!(drift < 1e-5 * work, "drift {drift} J of {work} J");
    }
}
