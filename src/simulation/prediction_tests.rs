//! The first prediction of a step whose contacts are all followers under
//! HHT-α (bogie vehicles on massless wheelsets, their primary suspensions
//! the contact laws): from the start's accelerations it gives the outputs
//! of the velocity-only prediction to the iteration's tolerance, in fewer
//! integrations.

use super::coaches_tests::{every_step, two_coaches};
use super::Simulation;
use crate::scene::Scene;

/// Two coaches on massless wheelsets over a 20 m span from the approach.
fn coaches_on_followers() -> Scene {
    let track = "[track]\napproach = 60.0\nrun_off = 60.0";
    two_coaches((0.0, None), track, "end_time = 0.3")
}

/// Every output after every grid step, and the integrations spent.
fn run(scene: &Scene, accelerated: bool) -> (Vec<Vec<f64>>, u64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let integrator = sim.stepper.iteration_mut().integrator_mut();
    integrator.predict_with_accelerations(accelerated);
    every_step(sim, scene.solver.step, 0.3)
}

#[test]
fn followers_predicted_from_accelerations_settle_in_fewer_integrations_to_the_same_outputs() {
    let scene = coaches_on_followers();
    let sim = Simulation::new(&scene).expect("builds");
    assert!(sim.system.contacts.iter().all(|c| c.follower.is_some()));
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let (velocity, by_velocity) = run(&scene, false);
    let (accelerated, by_accelerations) = run(&scene, true);
    // Measured 2026-11-28: 3,304 → 2,400 integrations on the eight-coach
    // scene this one is cut from; here 3,322 → 2,418.
    eprintln!("integrations: {by_velocity} from velocities, {by_accelerations} from accelerations");
    assert!(
        (by_accelerations as f64) < 0.9 * by_velocity as f64,
        "{by_accelerations} against {by_velocity}"
    );
    let mut worst = (0.0f64, String::new());
    // The same fixed point to the tolerances: every output within 1e-5 of
    // its largest magnitude (the bodies' velocities settle to 1e-7 m/s, a
    // bogie's acceleration to 1e-7 / Δt = 4e-4 m/s²; measured: 2.5e-6 of
    // `coach1_bogie1.ay`'s peak, 2026-11-28).
    for (j, name) in names.iter().enumerate() {
        let column = |rows: &[Vec<f64>]| rows.iter().map(|r| r[j]).collect::<Vec<f64>>();
        let (a, b) = (column(&velocity), column(&accelerated));
        let peak = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let apart = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        if name.starts_with("solver.") {
            continue;
        }
        if apart > worst.0 * peak {
            worst = (apart / peak, name.clone());
        }
        assert!(apart <= 1e-5 * peak, "{name}: {apart} apart, peak {peak}");
    }
    eprintln!("largest difference: {:e} of {}'s peak", worst.0, worst.1);
}
