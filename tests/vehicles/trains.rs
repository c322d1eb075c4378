//! Trains of bogie vehicles on multi-span bridges: the built-in train
//! scenes run, and the energy balance holds over a two-span bridge.

use guideway::scene::{builtin, DampingSpec};
use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

/// Largest |balance − initial| over the run, the largest |work| gravity
/// did, and the energy dissipated (dampers and beam) by the end.
fn energy_drift(scene: &Scene) -> (f64, f64, f64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n);
    let (balance, gravity) = (
        at("energy.balance").unwrap(),
        at("energy.gravity_work").unwrap(),
    );
    let dissipated: Vec<usize> = ["energy.dissipated", "energy.beam_dissipated"]
        .iter()
        .filter_map(|n| at(n))
        .collect();
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
    let lost = dissipated.iter().map(|&i| values[i]).sum();
    (drift, work, lost)
}

#[test]
fn energy_balance_of_a_bogie_vehicle_train_over_a_two_span_bridge() {
    // Two coaches at 100 km/h over the middle pier of a 2 × 40 m
    // continuous bridge (the built-in scene), undamped, then with
    // suspension dampers and Rayleigh damping of the bridge: the balance counts what they dissipate.
    let undamped = builtin("train-2-coaches-2x40-100").expect("built-in");
    let mut damped = undamped.clone();
    // Mass-proportional (α = 0.6/s: about 2 % at the first mode), which
    // leaves explicit RK4's step limit as it is.
    damped.beam.damping = Some(DampingSpec::Coefficients {
        alpha: 0.6,
        beta: 0.0,
    });
    for vehicle in damped.vehicles.iter_mut() {
        let bogie = vehicle.bogie.as_mut().expect("coaches");
        bogie.primary_damping = 2.0e4;
        bogie.secondary_damping = 4.5e4;
    }
    damped.validate().expect("valid");
    for (which, scene) in [("undamped", undamped), ("damped", damped)] {
        let (drift, work, dissipated) = energy_drift(&scene);
        eprintln!(
            "{which}: drift {drift:.3e} J, gravity work {work:.4e} J ({:.2e}), dissipated \
             {dissipated:.4e} J",
            drift / work
        );
        assert!(work > 1e3, "{work}");
        if which == "damped" {
            // What the dampers took is far above the balance's error.
            assert!(dissipated > 1e3 * drift, "{dissipated} J");
        }
        assert!(drift < 1e-5 * work, "drift {drift} J of {work} J");
    }
}

#[test]
fn three_coaches_on_wheels_run_from_the_approach_onto_the_run_off() {
    // The built-in train at 5 m/s: every wheelset enters and leaves the
    // bridge, the run goes on to its end time (1 s of free vibration after
    // the last exit) and the energy balance holds.
    let scene = builtin("train-3-coaches-2x25-5").expect("built-in");
    let (drift, work, dissipated) = energy_drift(&scene);
    let mut sim = Simulation::new(&scene).expect("builds");
    let end = scene.solver.end_time.expect("an end time");
    assert_eq!(sim.advance_to(end).expect("runs"), Advance::Reached);
    let count = |kind| sim.events().iter().filter(|e| e.kind == kind).count();
    assert_eq!((count(EventKind::Entry), count(EventKind::Exit)), (12, 12));
    let last_exit = sim.events().iter().map(|e| e.time).fold(0.0, f64::max);
    assert!(end - last_exit > 0.9, "last exit at {last_exit} s");
    eprintln!(
        "drift {drift:.3e} J, gravity work {work:.4e} J ({:.2e}), dissipated {dissipated:.4e} J",
        drift / work
    );
    // The corners at the bridge's ends cost energy to first order in the
    // step (tests/vehicles/bogie_vehicle.rs): at the scene's step (2e-4 s) the
    // drift is 5.4e-5 of the work (2026-11-22).
    assert!(drift < 1e-4 * work, "drift {drift} J of {work} J");
}

/// What a run to its end time shows: the largest |balance − initial|, the
/// largest |work| gravity did, the impact losses, the entries and exits,
/// the last exit's time, the peak |deflection| at the sensor while the
/// train is on the bridge, and the largest |deflection| and beam energy
/// (kinetic + strain) in the first and the second half of the free
/// vibration after the last exit.
struct Crossing {
    initial_energy: f64,
    drift: f64,
    work: f64,
    impact_loss: f64,
    entries: usize,
    exits: usize,
    last_exit: f64,
    loaded_peak: f64,
    free: [(f64, f64); 2],
}

fn cross(scene: &Scene, sensor: &str) -> Crossing {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let deflection = at(&format!("sensor.{sensor}.deflection"));
    let (balance, gravity, loss) = (
        at("energy.balance"),
        at("energy.gravity_work"),
        at("energy.impact_loss"),
    );
    let (kinetic, strain) = (at("energy.beam_kinetic"), at("energy.beam_strain"));
    let mut values = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let end = scene.solver.end_time.expect("an end time");
    let step = scene.solver.step;
    let mut history = Vec::new();
    let (mut drift, mut work): (f64, f64) = (0.0, 0.0);
    for k in 1..=(end / step).round() as usize {
        let advance = sim.advance_to(k as f64 * step).expect("runs to its end");
        assert_eq!(advance, Advance::Reached);
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs());
        work = work.max(values[gravity].abs());
        history.push((
            sim.time(),
            values[deflection],
            values[kinetic] + values[strain],
        ));
    }
    sim.output_values(&mut values);
    let count = |kind| sim.events().iter().filter(|e| e.kind == kind).count();
    let last_exit = sim
        .events()
        .iter()
        .filter(|e| e.kind == EventKind::Exit)
        .map(|e| e.time)
        .fold(0.0, f64::max);
    let half = 0.5 * (end + last_exit);
    let largest = |from: f64, to: f64| {
        history
            .iter()
            .filter(|(t, ..)| *t > from && *t <= to)
            .fold((0.0f64, 0.0f64), |(w, e), (_, d, energy)| {
                (w.max(d.abs()), e.max(*energy))
            })
    };
    Crossing {
        initial_energy: e0,
        drift,
        work,
        impact_loss: values[loss],
        entries: count(EventKind::Entry),
        exits: count(EventKind::Exit),
        last_exit,
        loaded_peak: largest(0.0, last_exit).0,
        free: [largest(last_exit, half), largest(half, end)],
    }
}

/// The train at speed: every wheelset from the approach over the bridge
/// onto the run-off, then the bridge's free vibration to the end time.
fn check_crossing(scene: &Scene, sensor: &str, contacts: usize) -> Crossing {
    let c = cross(scene, sensor);
    let end = scene.solver.end_time.unwrap();
    eprintln!(
        "{} at {} s: {} entries, {} exits, last at {:.4} s; drift {:.3e} J of {:.4e} J \
         initial energy ({:.2e}) and {:.4e} J gravity work ({:.2e}), impact losses {:.3e} J; \
         peak |w| {:.4e} m loaded, free {:.4e} m then {:.4e} m, beam energy {:.4e} J then \
         {:.4e} J",
        scene.name,
        scene.solver.step,
        c.entries,
        c.exits,
        c.last_exit,
        c.drift,
        c.initial_energy,
        c.drift / c.initial_energy,
        c.work,
        c.drift / c.work,
        c.impact_loss,
        c.loaded_peak,
        c.free[0].0,
        c.free[1].0,
        c.free[0].1,
        c.free[1].1
    );
    assert_eq!((c.entries, c.exits), (contacts, contacts));
    assert!(end - c.last_exit > 0.9, "last exit at {} s", c.last_exit);
    // The balance against the system's energy (the train's kinetic energy,
    // 1.4e9 J): HHT-α's numerical damping is not one of its terms, and
    // every entry and exit costs a few hundredths of a joule, so against
    // gravity's work (5e2 J on a level track) it is 3e-3 (README).
    assert!(
        c.drift < 1e-8 * c.initial_energy,
        "drift {} J of {} J",
        c.drift,
        c.initial_energy
    );
    // Free vibration present: a clear fraction of the loaded peak ...
    assert!(
        c.free[0].0 > 0.05 * c.loaded_peak,
        "{} m of {} m",
        c.free[0].0,
        c.loaded_peak
    );
    // ... and bounded: the beam's energy does not grow from the first half
    // of the free vibration to the second.
    assert!(c.free[1].0 < c.loaded_peak, "{} m", c.free[1].0);
    assert!(
        c.free[1].1 < 1.01 * c.free[0].1,
        "beam energy {} J after {} J",
        c.free[1].1,
        c.free[0].1
    );
    c
}

#[test]
fn eight_coaches_cross_a_three_span_bridge_at_300_km_h_and_leave_it_vibrating() {
    // The benchmark, built in: 32 glider wheelsets, HHT-α at 1 ms.
    // It stopped at t = 1.937 s ("no foot point") until the force guess
    // after a very short event step was bounded. A quarter of the step
    // gives the same free vibration: with α = 0 it did not (the contact
    // forces' step-to-step alternation grew into a 9 mm vibration).
    let scene = builtin("train-8-coaches-3x25-300").expect("built-in");
    let coarse = check_crossing(&scene, "midspan2", 32);
    let mut fine = scene.clone();
    fine.solver.step = 0.25 * scene.solver.step;
    let fine = check_crossing(&fine, "midspan2", 32);
    let (a, b) = (coarse.free[0].0, fine.free[0].0);
    assert!(
        (a - b).abs() < 0.2 * b,
        "free amplitude {a} m at 1 ms, {b} m at 0.25 ms"
    );
}

#[test]
fn the_same_train_on_rolling_wheelsets_crosses_too() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scripts/scenes/bench-8-coaches-3x25-300-wheels.toml"
    );
    let scene = Scene::from_toml_str(&std::fs::read_to_string(path).expect("the scene file"))
        .expect("valid scene");
    check_crossing(&scene, "midspan2", 32);
}
