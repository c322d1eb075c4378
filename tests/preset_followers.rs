//! Massless followers as the contact points of the `bogie_vehicle`
//! (`wheelset_mass = 0`) and `maglev_vehicle` (`magnet_mass = 0`) presets,
//! on the beam section of Yang & Yau (1997) (EI = 2.943e10 N/m² × 2.90 m⁴,
//! m̄ = 2303 kg/m), with the coach and maglev data of
//! `tests/bogie_vehicle.rs` and `tests/maglev_vehicle.rs`.

use guideway::scene::{IntegratorKind, StartKind};
use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

const GRAVITY: f64 = 9.81;
const EI: f64 = 2.943e10 * 2.90;
/// The coach: car body, bogie, axle and bogie half distances.
const CAR: f64 = 38884.0;
const BOGIE: f64 = 2400.0;
const LC: f64 = 8.75;
const LT: f64 = 1.25;

/// A coach whose wheelsets weigh `wheelset_mass` (0: followers) on `spans`
/// continuous 25 m spans, 10 elements per span, with rigid ground of 25 m
/// before and after.
fn coach(wheelset_mass: f64, spans: usize, position: f64, speed: f64, end_time: f64) -> Scene {
    let length = 25.0 * spans as f64;
    let intermediate: Vec<f64> = (1..spans).map(|i| 25.0 * i as f64).collect();
    Scene::from_toml_str(&format!(
        r#"
name = "coach"
gravity = {GRAVITY:?}
[beam]
length = {length:?}
mass_per_length = 2303.0
bending_stiffness = {EI:?}
surface_offset = 0.0
elements = {}
[beam.supports]
intermediate = {intermediate:?}
[track]
approach = 25.0
run_off = 25.0
[body]
name = "coach"
kind = "bogie_vehicle"
mass = {CAR:?}
initial_position = {position:?}
initial_speed = {speed:?}
[body.bogie]
car_inertia = 1.95e6
bogie_mass = {BOGIE:?}
bogie_inertia = 3200.0
wheelset_mass = {wheelset_mass:?}
bogie_half_distance = {LC:?}
axle_half_distance = {LT:?}
primary_stiffness = 1.18e6
secondary_stiffness = 5.3e5
[[sensors]]
name = "midspan"
position = 12.5
[solver]
step = 5e-5
start = "static"
end_time = {end_time:?}
"#,
        10 * spans,
    ))
    .expect("valid scene")
}

/// A maglev car of 30 t over eight magnets 3 m apart weighing
/// `magnet_mass` (0: followers), on `spans` continuous 25 m spans.
fn maglev(magnet_mass: f64, spans: usize, position: f64, speed: f64, end_time: f64) -> Scene {
    let length = 25.0 * spans as f64;
    let intermediate: Vec<f64> = (1..spans).map(|i| 25.0 * i as f64).collect();
    Scene::from_toml_str(&format!(
        r#"
name = "maglev"
gravity = {GRAVITY:?}
[beam]
length = {length:?}
mass_per_length = 2303.0
bending_stiffness = {EI:?}
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
magnet_mass = {magnet_mass:?}
stiffness = 8.0e5
[[sensors]]
name = "midspan"
position = 12.5
[solver]
step = 5e-5
start = "static"
end_time = {end_time:?}
"#,
        10 * spans,
    ))
    .expect("valid scene")
}

fn with_hht(mut scene: Scene, step: f64) -> Scene {
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = 0.0;
    scene.solver.step = step;
    scene
}

/// The largest component of any body's (ẍ, ÿ, θ̈), in units of g.
fn largest_acceleration(sim: &Simulation) -> f64 {
    sim.body_accelerations()
        .iter()
        .flat_map(|a| a.iter().map(|x| x.abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max)
        / GRAVITY
}

fn names(sim: &Simulation) -> Vec<String> {
    sim.outputs().iter().map(|o| o.name.clone()).collect()
}

fn index(names: &[String], name: &str) -> usize {
    names.iter().position(|x| x == name).expect(name)
}

/// Histories of the outputs `wanted` at every step to the scene's end.
fn histories(scene: &Scene, wanted: &[&str]) -> (Simulation, Vec<Vec<f64>>) {
    let mut sim = Simulation::new(scene).expect("builds");
    let all = names(&sim);
    let at: Vec<usize> = wanted.iter().map(|n| index(&all, n)).collect();
    let mut values = vec![0.0; all.len()];
    let mut out = vec![Vec::new(); wanted.len()];
    let dt = scene.solver.step;
    let steps = (scene.solver.end_time.expect("an end time") / dt).round() as usize;
    for k in 1..=steps {
        assert_eq!(sim.advance_to(k as f64 * dt).unwrap(), Advance::Reached);
        sim.output_values(&mut values);
        for (series, &i) in out.iter_mut().zip(&at) {
            series.push(values[i]);
        }
    }
    (sim, out)
}

#[test]
fn followers_replace_the_wheelsets_and_magnets_and_keep_their_names() {
    let sim = Simulation::new(&coach(0.0, 1, 12.5, 0.0, 1.0)).expect("builds");
    let system = sim.system();
    let bodies: Vec<&str> = system.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(bodies, ["coach", "coach_bogie1", "coach_bogie2"]);
    let contacts: Vec<(&str, usize)> = system
        .contacts
        .iter()
        .map(|c| (c.name.as_str(), c.body))
        .collect();
    assert_eq!(
        contacts,
        [
            ("coach_wheelset1", 1),
            ("coach_wheelset2", 1),
            ("coach_wheelset3", 2),
            ("coach_wheelset4", 2)
        ]
    );
    // Attached at the axles, ±l_t from the bogies' centres.
    let at: Vec<f64> = system
        .contacts
        .iter()
        .map(|c| c.follower.expect("a follower").attachment.x)
        .collect();
    assert_eq!(at, [LT, -LT, LT, -LT]);
    // Only the secondary suspensions and their guides are force elements.
    let elements: Vec<&str> = system
        .force_elements
        .iter()
        .map(|e| e.name.as_str())
        .collect();
    assert_eq!(
        elements,
        [
            "coach.secondary1",
            "coach.secondary1_guide",
            "coach.secondary2",
            "coach.secondary2_guide"
        ]
    );
    let all = names(&sim);
    for name in ["coach_wheelset4.normal_force", "coach_wheelset4.state", "coach_bogie2.ay"] {
        index(&all, name);
    }
    assert!(!all.iter().any(|n| n.starts_with("coach_wheelset1.y")));

    let sim = Simulation::new(&maglev(0.0, 1, 12.5, 0.0, 1.0)).expect("builds");
    let system = sim.system();
    assert_eq!(system.bodies.len(), 1);
    assert!(system.force_elements.is_empty());
    let names: Vec<&str> = system.contacts.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names[0], "car_magnet1");
    assert_eq!(names[7], "car_magnet8");
    assert!(system.contacts.iter().all(|c| c.body == 0));
    assert_eq!(system.contacts[0].follower.unwrap().attachment.x, 10.5);
}
