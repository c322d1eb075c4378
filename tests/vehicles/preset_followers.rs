//! Massless followers as the contact points of the `bogie_vehicle`
//! (`wheelset_mass = 0`) and `maglev_vehicle` (`magnet_mass = 0`) presets,
//! on the beam section of Yang & Yau (1997) (EI = 2.943e10 N/m² × 2.90 m⁴,
//! m̄ = 2303 kg/m), with the coach and maglev data of
//! `tests/vehicles/bogie_vehicle.rs` and `tests/vehicles/maglev_vehicle.rs`.

use guideway::scene::{IntegratorKind, StartKind};
use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

use crate::common::yang_yau::EI;
use crate::common::{largest_acceleration, largest_difference, peak, GRAVITY};

/// The coach: car body, bogie, axle and bogie half distances.
const CAR: f64 = 38884.0;
const BOGIE: f64 = 2400.0;
const LC: f64 = 8.75;
const LT: f64 = 1.25;

/// The `[beam]` table of `spans` continuous 25 m spans of the Yang & Yau
/// section, 10 elements per span.
fn continuous_beam(spans: usize) -> String {
    let length = 25.0 * spans as f64;
    let intermediate: Vec<f64> = (1..spans).map(|i| 25.0 * i as f64).collect();
    format!(
        r#"[beam]
length = {length:?}
mass_per_length = 2303.0
bending_stiffness = {EI:?}
surface_offset = 0.0
elements = {}
[beam.supports]
intermediate = {intermediate:?}
"#,
        10 * spans
    )
}

/// The scenes' midspan sensor and solver: RK4 at 50 µs from the static
/// start to `end_time`.
fn static_start_solver(end_time: f64) -> String {
    format!(
        r#"[[sensors]]
name = "midspan"
position = 12.5
[solver]
step = 5e-5
start = "static"
end_time = {end_time:?}
"#
    )
}

/// A coach whose wheelsets weigh `wheelset_mass` (0: followers) on `spans`
/// continuous 25 m spans, 10 elements per span, with rigid ground of 25 m
/// before and after.
fn coach(wheelset_mass: f64, spans: usize, position: f64, speed: f64, end_time: f64) -> Scene {
    let beam = continuous_beam(spans);
    Scene::from_toml_str(&format!(
        r#"
name = "coach"
gravity = {GRAVITY:?}
{beam}[track]
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
{}"#,
        static_start_solver(end_time)
    ))
    .expect("valid scene")
}

/// A maglev car of 30 t over eight magnets 3 m apart weighing
/// `magnet_mass` (0: followers), on `spans` continuous 25 m spans.
fn maglev(magnet_mass: f64, spans: usize, position: f64, speed: f64, end_time: f64) -> Scene {
    let beam = continuous_beam(spans);
    Scene::from_toml_str(&format!(
        r#"
name = "maglev"
gravity = {GRAVITY:?}
{beam}[body]
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
{}"#,
        static_start_solver(end_time)
    ))
    .expect("valid scene")
}

fn with_hht(mut scene: Scene, step: f64) -> Scene {
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = 0.0;
    scene.solver.step = step;
    scene
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
    for name in [
        "coach_wheelset4.normal_force",
        "coach_wheelset4.state",
        "coach_bogie2.ay",
    ] {
        index(&all, name);
    }
    assert!(!all.iter().any(|n| n.starts_with("coach_wheelset1.y")));
    assert_unique(&all);

    let sim = Simulation::new(&maglev(0.0, 1, 12.5, 0.0, 1.0)).expect("builds");
    let system = sim.system();
    assert_eq!(system.bodies.len(), 1);
    assert!(system.force_elements.is_empty());
    let contacts: Vec<&str> = system.contacts.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(contacts[0], "car_magnet1");
    assert_eq!(contacts[7], "car_magnet8");
    assert!(system.contacts.iter().all(|c| c.body == 0));
    assert_eq!(system.contacts[0].follower.unwrap().attachment.x, 10.5);
    let all = names(&sim);
    index(&all, "car_magnet8.nominal_speed");
    assert_unique(&all);
}

/// Every output named once (the FMU's variable names must be unique).
fn assert_unique(names: &[String]) {
    let mut sorted = names.to_vec();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len(), "duplicate output names");
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
    let contacts: Vec<String> = sim
        .system()
        .contacts
        .iter()
        .map(|c| c.name.clone())
        .collect();
    let at = |c: &String, what: &str| values[index(&all, &format!("{c}.{what}"))];
    let placed: Vec<(f64, f64)> = contacts
        .iter()
        .zip(nominal.iter().zip(loads))
        .map(|(c, (&x, &p))| {
            let foot = at(c, "position");
            assert!(
                (foot - x).abs() < 1e-3,
                "{label}: {c} at {foot} m, not {x} m"
            );
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
    assert!(
        worst < 1e-9,
        "{label}: largest body acceleration {worst:e} g"
    );
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

/// The coach from the static start, rear wheelset 0.5 m into a 2 × 25 m
/// continuous beam, at 100 km/h until the front one is 2.5 m before its
/// end (glider wheelsets pass the middle support, not the beam's ends).
fn crossing(wheelset_mass: f64) -> Scene {
    let speed = 100.0 / 3.6;
    coach(wheelset_mass, 2, 10.5, speed, 27.0 / speed)
}

#[test]
fn glider_wheelsets_of_vanishing_mass_converge_to_the_followers() {
    // Largest differences over the crossing, of the follower's peaks. The
    // midspan deflection, the bogie's pitch and the contact force converge
    // linearly in the wheelset mass; the car body's acceleration (a small
    // peak) levels off near 1e-3 of it at 1.4 kg: RK4's error on the light
    // wheelsets' fast modes (ω Δt = 0.46 for the guide), which halves with
    // the step; lighter wheelsets than 1.4 kg put it beyond ω Δt = 1.
    let wanted = [
        "sensor.midspan.deflection",
        "coach_bogie1.pitch",
        "coach_wheelset1.normal_force",
        "coach.ay",
    ];
    let (_, follower) = histories(&crossing(0.0), &wanted);
    let mut previous: Option<Vec<f64>> = None;
    for mass in [140.0, 14.0, 1.4] {
        let (_, glider) = histories(&crossing(mass), &wanted);
        let differences: Vec<f64> = glider
            .iter()
            .zip(&follower)
            .map(|(g, f)| largest_difference(g, f) / peak(f))
            .collect();
        let shown: Vec<String> = differences.iter().map(|d| format!("{d:.2e}")).collect();
        eprintln!(
            "wheelset mass {mass} kg: differences of the follower's peaks (deflection, bogie \
             pitch, contact force, car body ay) {}",
            shown.join(", ")
        );
        if let Some(previous) = &previous {
            // Linear in the mass: ten times lighter, about ten times closer.
            for (d, p) in differences.iter().zip(previous).take(3) {
                assert!(*d < 0.2 * p, "{d:e} after {p:e}");
            }
        }
        previous = Some(differences);
    }
    let lightest = previous.unwrap();
    for d in lightest.iter().take(3) {
        assert!(*d < 3e-4, "{d:e}");
    }
    assert!(lightest[3] < 2e-3, "{:e}", lightest[3]);
    // The car body's floor is the step's: at half the step it halves.
    let half = |mut scene: Scene| {
        scene.solver.step *= 0.5;
        histories(&scene, &wanted).1
    };
    let (follower, glider) = (half(crossing(0.0)), half(crossing(1.4)));
    let car = largest_difference(&glider[3], &follower[3]) / peak(&follower[3]);
    eprintln!("wheelset mass 1.4 kg, half the step: car body ay {car:.2e}");
    assert!(car < 0.5 * lightest[3], "{car:e} against {:e}", lightest[3]);
}

/// Largest |balance − initial| over `scene`, the largest |work| of
/// gravity, and what the dampers and the scheme dissipated by the end.
fn energy_drift(scene: &Scene) -> (f64, f64, f64) {
    let wanted = [
        "energy.balance",
        "energy.gravity_work",
        "energy.dissipated",
        "energy.numerical_dissipation",
    ];
    let e0 = Simulation::new(scene).expect("builds").initial_energy();
    let (_, out) = histories(scene, &wanted);
    let drift = out[0].iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
    let dissipated = out[2].last().unwrap() + out[3].last().unwrap();
    (drift, peak(&out[1]), dissipated)
}

#[test]
fn the_energy_balance_holds_for_followers_under_a_bogie_and_a_maglev_vehicle() {
    let speed = 100.0 / 3.6;
    let mut cases = Vec::new();
    for damping in [0.0, 2.0e4] {
        let mut scene = crossing(0.0);
        let bogie = scene.vehicles[0].bogie.as_mut().unwrap();
        bogie.primary_damping = damping;
        bogie.secondary_damping = damping;
        cases.push((format!("bogie, c = {damping}, RK4"), scene.clone()));
        cases.push((
            format!("bogie, c = {damping}, HHT-α"),
            with_hht(scene, 1e-4),
        ));
        let mut scene = maglev(0.0, 2, 11.0, speed, (50.0 - 1.0 - 10.5 - 11.0) / speed);
        scene.vehicles[0].maglev.as_mut().unwrap().damping = damping;
        cases.push((format!("maglev, c = {damping}, RK4"), scene));
    }
    for (label, scene) in cases {
        let (drift, work, dissipated) = energy_drift(&scene);
        eprintln!(
            "{label}: drift {drift:.3e} J, gravity work {work:.4e} J, dissipated {dissipated:.4e} J"
        );
        assert!(work > 1.0, "{label}: {work}");
        assert!(drift < 1e-5 * work, "{label}: drift {drift} J of {work} J");
        if !label.contains("c = 0") {
            assert!(dissipated > 1e3 * drift, "{label}: {dissipated} J");
        }
    }
}

#[test]
fn a_bogie_vehicle_on_followers_runs_from_the_approach_onto_the_run_off() {
    // Followers, unlike glider wheelsets, pass the beam's ends. Entering a
    // beam already deflected by the followers ahead, a follower leans on
    // the beam's start (a corner) until its attachment is h sin φ past it,
    // then on the sloped surface: its force turns by φ within a fraction
    // of a microsecond. The step ends there (located like a track event),
    // and likewise where it leaves the run-off's corner; inside a step
    // that turn cost the balance P φ v Δt / 6 (RK4) or / 2 (HHT-α) per
    // corner, first order in the step (1.7e-3 J at 50 µs).
    // Asserted: four entries and four exits; under RK4 a drift at the
    // balance's round-off (the step's own error lies below it), under
    // HHT-α one that falls by four when the step is halved.
    let speed = 100.0 / 3.6;
    let reach = LC + LT;
    let start = -25.0 + reach + 1.0;
    let end_time = (25.0 + 25.0 - 1.0 - reach - start) / speed;
    for (hht, step) in [(false, 5e-5), (true, 2e-4)] {
        let mut drifts = Vec::new();
        for step in [step, 0.5 * step] {
            let mut scene = coach(0.0, 1, start, speed, end_time);
            if hht {
                scene = with_hht(scene, step);
            }
            scene.solver.step = step;
            let (drift, work, _) = energy_drift(&scene);
            let mut sim = Simulation::new(&scene).expect("builds");
            let steps = (end_time / step).round() as usize;
            assert_eq!(
                sim.advance_to(steps as f64 * step).unwrap(),
                Advance::Reached
            );
            let kinds: Vec<EventKind> = sim.events().iter().map(|e| e.kind).collect();
            let count = |k: EventKind| kinds.iter().filter(|&&x| x == k).count();
            eprintln!(
                "approach to run-off, HHT {hht}, step {step:e}: {} entries, {} exits, drift \
                 {drift:.3e} J, gravity work {work:.4e} J",
                count(EventKind::Entry),
                count(EventKind::Exit)
            );
            assert_eq!((count(EventKind::Entry), count(EventKind::Exit)), (4, 4));
            assert!(work > 100.0, "{work}");
            if !hht {
                assert!(drift < 1e-8 * work, "drift {drift} J of {work} J");
            }
            drifts.push(drift);
        }
        if hht {
            let ratio = drifts[0] / drifts[1];
            assert!(
                (3.2..5.0).contains(&ratio),
                "drift ratio {ratio} at half the step"
            );
        }
    }
}

#[test]
fn slack_followers_under_a_dropped_bogie_vehicle_are_open_until_they_land() {
    // 0.2 m above its place on the beam: each primary suspension would
    // pull (k₁ × 0.2 m exceeds its preload), so its follower starts slack
    // and open, carries nothing while open, and lands without an impact;
    // undamped, the vehicle bounces and the followers lift off again.
    let mut scene = coach(0.0, 1, 12.5, 0.0, 0.4);
    scene.solver.start = StartKind::Rest;
    scene.vehicles[0].initial_height = 0.2;
    let contacts: Vec<String> = (1..=4).map(|i| format!("coach_wheelset{i}")).collect();
    let mut wanted: Vec<String> = Vec::new();
    for c in &contacts {
        wanted.push(format!("{c}.state"));
        wanted.push(format!("{c}.normal_force"));
    }
    wanted.extend(
        [
            "energy.balance",
            "energy.impact_loss",
            "energy.gravity_work",
        ]
        .map(String::from),
    );
    let wanted: Vec<&str> = wanted.iter().map(String::as_str).collect();
    let e0 = Simulation::new(&scene).expect("builds").initial_energy();
    let (sim, out) = histories(&scene, &wanted);
    let landings: Vec<usize> = sim
        .events()
        .iter()
        .filter(|e| e.kind == EventKind::Landing)
        .map(|e| e.contact)
        .collect();
    eprintln!("dropped coach on followers: events {:?}", sim.events());
    let lift_offs = sim.events().iter().filter(|e| e.kind == EventKind::LiftOff);
    // Undamped, the vehicle bounces: the followers go slack again.
    assert!(lift_offs.count() >= 4);
    for c in 0..4 {
        assert!(landings.contains(&c), "follower {c} never landed");
        assert_eq!(out[2 * c][0], 0.0, "follower {c} starts open");
        for (state, force) in out[2 * c].iter().zip(&out[2 * c + 1]) {
            if *state == 0.0 {
                assert_eq!(*force, 0.0);
            } else {
                assert!(*force > 0.0);
            }
        }
    }
    assert!(out[9].iter().all(|&loss| loss == 0.0), "no impact");
    let drift = out[8].iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
    let work = peak(&out[10]);
    eprintln!("drift {drift:.3e} J, gravity work {work:.4e} J");
    assert!(work > 1e3, "{work}");
    assert!(drift < 1e-5 * work, "drift {drift} J of {work} J");
}

#[test]
fn bad_follower_fields_are_refused_naming_field_and_value() {
    let refused = |scene: &Scene, field: &str, value: &str| {
        let message = scene.validate().unwrap_err().to_string();
        assert!(message.contains(field), "{message}");
        assert!(message.contains(value), "{message}");
        message
    };
    let mut scene = coach(0.0, 1, 12.5, 0.0, 1.0);
    scene.vehicles[0].bogie.as_mut().unwrap().wheelset_mass = -1.0;
    refused(&scene, "body.bogie.wheelset_mass", "-1");
    scene.vehicles[0].bogie.as_mut().unwrap().wheelset_mass = 1e-300;
    refused(&scene, "body.bogie.wheelset_mass", "1e-300");
    // A follower does not roll: no wheel wheelsets without mass.
    let bogie = scene.vehicles[0].bogie.as_mut().unwrap();
    bogie.wheelset_mass = 0.0;
    bogie.wheel_radius = Some(0.45);
    bogie.wheelset_inertia = Some(700.0);
    let message = refused(&scene, "body.bogie.wheelset_mass", "0");
    assert!(message.contains("does not roll"), "{message}");

    let mut scene = maglev(0.0, 1, 12.5, 0.0, 1.0);
    scene.vehicles[0].maglev.as_mut().unwrap().magnet_mass = f64::NAN;
    refused(&scene, "body.maglev.magnet_mass", "NaN");
    scene.vehicles[0].maglev.as_mut().unwrap().magnet_mass = -600.0;
    refused(&scene, "body.maglev.magnet_mass", "-600");
    // And through the scene text.
    let text = "name = \"m\"\n[body]\nname = \"car\"\nkind = \"maglev_vehicle\"\nmass = 1.0\n\
                initial_position = 12.5\ninitial_speed = 0.0\n[body.maglev]\n\
                car_inertia = 1.0\nmagnets = 2\nmagnet_spacing = 3.0\n\
                magnet_mass = -2.5\nstiffness = 1.0\n\
                [beam]\nlength = 25.0\nmass_per_length = 1.0\nbending_stiffness = 1.0\n\
                surface_offset = 0.0\nelements = 4\n[solver]\nstep = 1e-3\n";
    let message = Scene::from_toml_str(text).unwrap_err().to_string();
    assert!(
        message.contains("body.maglev.magnet_mass") && message.contains("-2.5"),
        "{message}"
    );
}
