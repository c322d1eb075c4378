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
    for vehicle in std::iter::once(&mut damped.body).chain(&mut damped.vehicles) {
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
    // step (tests/bogie_vehicle.rs): at the scene's step (2e-4 s) the
    // drift is 5.4e-5 of the work (2026-11-22).
    assert!(drift < 1e-4 * work, "drift {drift} J of {work} J");
}
