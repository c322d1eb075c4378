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

/// Deflection at `x` of a simply supported beam of length `l` under
/// downward point loads (position, force): the closed form of beam theory.
fn point_load_deflection(l: f64, loads: &[(f64, f64)], x: f64) -> f64 {
    loads
        .iter()
        .map(|&(a, p)| {
            // Mirror so that x lies left of the load.
            let (a, x) = if x <= a { (a, x) } else { (l - a, l - x) };
            let b = l - a;
            -p * b * x * (l * l - b * b - x * x) / (6.0 * EI * l)
        })
        .sum()
}

/// Run `scene` 200 steps from its static start; assert it stays at rest
/// (every body acceleration below 1e-9 g) and that the midspan deflection
/// is beam theory's under the followers' vertical loads `loads` (one per
/// contact, in order) at their foot points, which lie off their nominal
/// abscissae `nominal` by the attachment's height times the slope there.
/// Returns the largest acceleration.
fn stays_at_rest(scene: &Scene, nominal: &[f64], loads: &[f64], label: &str) -> f64 {
    let mut sim = Simulation::new(scene).expect("builds");
    let all = names(&sim);
    let midspan = index(&all, "sensor.midspan.deflection");
    let mut values = vec![0.0; all.len()];
    sim.output_values(&mut values);
    let contacts: Vec<String> = sim.system().contacts.iter().map(|c| c.name.clone()).collect();
    let at = |c: &String, what: &str| values[index(&all, &format!("{c}.{what}"))];
    let placed: Vec<(f64, f64)> = contacts
        .iter()
        .zip(nominal.iter().zip(loads))
        .map(|(c, (&x, &p))| {
            let foot = at(c, "position");
            assert!((foot - x).abs() < 1e-3, "{label}: {c} at {foot} m, not {x} m");
            (foot, p)
        })
        .collect();
    let expected = point_load_deflection(25.0, &placed, 12.5);
    let deflection = values[midspan];
    // The beam's own weight is not applied: only the vehicle's.
    assert!(
        (deflection - expected).abs() < 1e-9 * expected.abs(),
        "{label}: midspan {deflection} m, beam theory {expected} m"
    );
    // The followers' normal forces carry the weight: their vertical parts.
    let total: f64 = contacts.iter().map(|c| at(c, "normal_force")).sum();
    let weight: f64 = loads.iter().sum();
    assert!(
        total >= weight && total - weight < 1e-6 * weight,
        "{label}: {total} N"
    );
    let mut worst = largest_acceleration(&sim);
    for k in 1..=200 {
        let t = k as f64 * scene.solver.step;
        assert_eq!(sim.advance_to(t).unwrap(), Advance::Reached);
        worst = worst.max(largest_acceleration(&sim));
    }
    sim.output_values(&mut values);
    eprintln!(
        "{label}: midspan {deflection:.6e} m (beam theory {expected:.6e} m), largest \
         acceleration {worst:.3e} g over 200 steps"
    );
    assert!(worst < 1e-9, "{label}: largest body acceleration {worst:e} g");
    assert!((values[midspan] - deflection).abs() < 1e-9 * expected.abs());
    worst
}

#[test]
fn a_bogie_vehicle_on_followers_at_rest_on_the_deflected_beam_stays_at_rest() {
    // Each follower carries half its bogie's load: (M g / 2 + m_b g) / 2.
    let p = 0.5 * (0.5 * CAR + BOGIE) * GRAVITY;
    let at: Vec<f64> = [LC + LT, LC - LT, -LC + LT, -LC - LT]
        .iter()
        .map(|dx| 12.5 + dx)
        .collect();
    let loads = [p; 4];
    let scene = coach(0.0, 1, 12.5, 0.0, 1.0);
    stays_at_rest(&scene, &at, &loads, "bogie vehicle on followers, RK4");
    stays_at_rest(
        &with_hht(scene, 1e-3),
        &at,
        &loads,
        "bogie vehicle on followers, HHT-α",
    );
}

#[test]
fn a_maglev_vehicle_on_followers_at_rest_on_the_deflected_beam_stays_at_rest() {
    let p = 30000.0 * GRAVITY / 8.0;
    let at: Vec<f64> = (0..8).map(|i| 12.5 + 10.5 - 3.0 * i as f64).collect();
    let loads = [p; 8];
    let scene = maglev(0.0, 1, 12.5, 0.0, 1.0);
    stays_at_rest(&scene, &at, &loads, "maglev vehicle on followers, RK4");
    stays_at_rest(
        &with_hht(scene, 1e-3),
        &at,
        &loads,
        "maglev vehicle on followers, HHT-α",
    );
}

#[test]
fn without_the_static_start_the_bogie_vehicle_on_followers_moves() {
    // On the undeformed beam the followers' preloads do not balance the
    // beam: the at-rest test above could fail.
    let mut scene = coach(0.0, 1, 12.5, 0.0, 1.0);
    scene.solver.start = StartKind::Rest;
    let mut sim = Simulation::new(&scene).expect("builds");
    let mut worst: f64 = 0.0;
    for k in 1..=200 {
        sim.advance_to(k as f64 * 5e-5).unwrap();
        worst = worst.max(largest_acceleration(&sim));
    }
    assert!(worst > 1e-3, "largest body acceleration {worst:e} g");
}
