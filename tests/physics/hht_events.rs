//! HHT-α across changes of contact state: lift-off (located inside the
//! step), landing, entry onto the beam and exit from it. The scheme carries
//! each step's end force and accelerations into the next; at every such
//! change it restarts from a consistent state (`src/solver/events/switch.rs`).

use crate::common;

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::simulation::EventKind;
use guideway::{Advance, Simulation};

/// What a run gives step by step: the balance's drift after every grid
/// step, the smallest normal force output, and the simulation.
struct Run {
    sim: Simulation,
    drift: Vec<f64>,
    least_force: f64,
}

fn run(scene: &Scene) -> Run {
    let mut sim = Simulation::new(scene).expect("builds");
    let dt = scene.solver.step;
    let end = scene.solver.end_time.expect("an end time");
    let e0 = sim.initial_energy();
    let forces: Vec<usize> = (sim.outputs().iter().enumerate())
        .filter(|(_, o)| o.name.ends_with("normal_force"))
        .map(|(i, _)| i)
        .collect();
    let mut values = vec![0.0; sim.outputs().len()];
    let (mut drift, mut least_force) = (Vec::new(), f64::INFINITY);
    for k in 1..=(end / dt).round() as u64 {
        match sim.advance_to(k as f64 * dt) {
            Ok(Advance::Reached) => {}
            other => panic!("t = {}: {other:?}", sim.time()),
        }
        drift.push(sim.energy_balance() - e0);
        sim.output_values(&mut values);
        least_force = forces.iter().fold(least_force, |m, &i| m.min(values[i]));
    }
    Run {
        sim,
        drift,
        least_force,
    }
}

fn kinds(sim: &Simulation) -> Vec<EventKind> {
    sim.events().iter().map(|e| e.kind).collect()
}

fn hht(mut scene: Scene, alpha: f64) -> Scene {
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = -alpha;
    scene.validate().expect("valid");
    scene
}

/// The paper's wheel (600 kN on 3000 kg, gravity off) at 10 m/s from a 5 m
/// approach over the beam on `elements` elements onto a run-off.
fn wheel_crossing(elements: usize, step: f64) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
    scene.beam.elements = elements;
    scene.track.approach = 5.0;
    scene.track.run_off = 10.0;
    scene.vehicles[0].initial_position = -2.0;
    scene.solver.end_time = Some(2.8);
    scene
}

#[test]
fn undamped_hht_rolls_a_wheel_onto_the_beam_and_off_it_compressed() {
    // α = 0 damps nothing: a force carried inconsistently across the
    // entry or the exit alternated from step to step for ever and pulled
    // (before: 1168 lift-offs at Δt = 0.1 ms, 16 elements; 11 at 2.5 ms).
    for (elements, step) in [(2, 1e-4), (16, 1e-4), (16, 2.5e-3)] {
        let run = run(&hht(wheel_crossing(elements, step), 0.0));
        let worst = run.drift.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let total = run.sim.initial_energy();
        eprintln!(
            "{elements} elements, {step} s: least force {:.4e} N, drift {worst:.3e} J of {total:.4e} J",
            run.least_force
        );
        assert_eq!(
            kinds(&run.sim),
            [EventKind::Entry, EventKind::Exit],
            "{elements}, {step}"
        );
        // The wheel turning about the beam's ends needs m v²/(r + h) =
        // 33 kN less than the 600 kN load.
        assert!(run.least_force > 5.5e5, "{}", run.least_force);
        assert!(worst < 1e-5 * total, "drift {worst} J of {total} J");
    }
}

/// A coach on rolling wheelsets (r = 0.45 m) at 5 m/s from the approach
/// onto Yang & Yau's 25 m beam, its first two wheelsets entering (the
/// second one 2.5 m behind, at 0.6 s), HHT-α at α = 0.
fn coach_entry(step: f64) -> Scene {
    let bogie = common::coach_bogie(0.0, 0.0);
    Scene::from_toml_str(&format!(
        r#"
name = "coach-entry"
gravity = 9.81
[beam]
length = 25.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 10
[track]
approach = 25.0
run_off = 25.0
[body]
name = "coach"
kind = "bogie_vehicle"
mass = 38884.0
initial_position = -10.5
initial_speed = 5.0
{bogie}
[solver]
step = {step:?}
start = "static"
integrator = "hht"
numerical_damping = 0.0
end_time = 0.7
"#
    ))
    .expect("valid")
}

#[test]
fn undamped_hht_passes_a_wheelsets_entry_without_lifting_off() {
    // Before: the second wheelset's entry began with a 0.4 µs step to the
    // grid point inside its 9 µs turn about the beam's start, and the end
    // force 2 × 43 − 121 kN pulled: a lift-off the exact solution does not
    // have. The restart now fits that step, and again the next full one.
    for step in [1e-4, 2.5e-3] {
        let run = run(&coach_entry(step));
        eprintln!("{step} s: least force {:.4e} N", run.least_force);
        assert_eq!(kinds(&run.sim), [EventKind::Entry, EventKind::Entry]);
        // The static wheel load is 121 kN.
        assert!(run.least_force > 1.1e5, "{step}: {}", run.least_force);
    }
}

/// The paper's wheel on 16 elements at `speed` crossing onto a 30 m
/// run-off, `auto` at `step` (HHT-α, α = −0.1, beyond RK4's 1.417e-4 s).
fn fast_crossing(speed: f64, step: f64) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, speed, step);
    scene.beam.elements = 16;
    scene.solver.integrator = IntegratorKind::Auto;
    scene.track.run_off = 30.0;
    scene.solver.end_time = Some(24.0 / speed + 0.08);
    scene.validate().expect("valid");
    scene
}

fn worst(drift: &[f64]) -> f64 {
    drift.iter().fold(0.0f64, |m, d| m.max(d.abs()))
}

#[test]
fn lift_offs_and_landings_under_undamped_hht_add_little_energy() {
    // 150 m/s at the paper's step, α = 0: the wheel lifts off and lands
    // again and again. Before, the start force carried into the step a contact
    // opened in did work on the separating bodies: +1.8 MJ.
    let run = run(&hht(fast_crossing(150.0, 2.5e-3), 0.0));
    let s = run.sim.state();
    let total = run.sim.initial_energy() + s.external_work.abs() + run.sim.impact_loss();
    let events = kinds(&run.sim);
    let count = |k| events.iter().filter(|&&e| e == k).count();
    eprintln!(
        "150 m/s, α = 0: drift {:.1} J of {total:.4e} J, {events:?}",
        worst(&run.drift)
    );
    assert!(count(EventKind::LiftOff) >= 2 && count(EventKind::Landing) >= 2);
    assert!(!run.sim.contact_statuses()[0].open);
    // Measured 1.4e-5 (2026-11-23): what is left comes from lift-offs that
    // open at a step's start (README "HHT-α at a change of contact state").
    assert!(worst(&run.drift) < 2e-5 * total, "{} J", worst(&run.drift));
}

#[test]
fn a_plastic_landing_under_hht_does_not_raise_the_balance() {
    // A glider (600 kN on 3000 kg) released 0.2 m above midspan of the
    // undamped 16-element beam, landing plastically, at the paper's step.
    // Before, the grid step of the landing added up to 913 J. (What the
    // rebounds that follow add is not bounded here: see README.)
    for alpha in [0.0, -0.1] {
        let mut scene = Scene::lee1994(BodyKind::Glider, 0.0, 2.5e-3);
        scene.beam.elements = 16;
        scene.vehicles[0].initial_position = 12.0;
        scene.vehicles[0].initial_height = 0.2;
        scene.solver.end_time = Some(0.2);
        let run = run(&hht(scene, alpha));
        let sim = &run.sim;
        let landing = sim.events()[0];
        assert_eq!(landing.kind, EventKind::Landing);
        // The fall's energy: 600 kN over 0.2 m.
        let fall = 6e5 * 0.2;
        let k = (landing.time / 2.5e-3).ceil() as usize - 1;
        let gain = run.drift[k] - if k > 0 { run.drift[k - 1] } else { 0.0 };
        eprintln!(
            "α = {alpha}: landing at {} s, balance change {gain:.3e} J in its step, \
             largest drift {:.3e} J, {} events",
            landing.time,
            worst(&run.drift),
            sim.events().len()
        );
        // Measured 2.9e-11 J (α = 0) and 0.75 J (α = −0.1) (2026-11-23).
        assert!(gain <= 1e-5 * fall, "{gain} J");
    }
}

#[test]
fn the_remaining_drift_at_250_ms_is_second_order_in_the_step() {
    // At 250 m/s and the paper's step the balance drifts by 1.9e-5 of the
    // total work, above the 1e-5 asked. Not at the events: in the closed
    // steps near the beam's end where the force is 2–3.6 MN and swings
    // from step to step; halving the step divides the drift by about four
    // (the contact force's work on the contact's relative motion, which
    // the exact constraint makes zero, is the trapezoidal rule's error).
    let mut drifts = Vec::new();
    for step in [2.5e-3, 1.25e-3, 6.25e-4] {
        let run = run(&fast_crossing(250.0, step));
        assert!(run.sim.integrator_choice().starts_with("hht"));
        let kinds = kinds(&run.sim);
        assert!(kinds.contains(&EventKind::LiftOff) && kinds.contains(&EventKind::Landing));
        drifts.push(worst(&run.drift));
    }
    eprintln!("250 m/s: largest drift {drifts:?} J at 2.5, 1.25, 0.625 ms");
    assert!(drifts[0] < 2e-5 * 1.407e8, "{drifts:?}");
    assert!(
        drifts[0] > 3.0 * drifts[1] && drifts[1] > 3.0 * drifts[2],
        "{drifts:?}"
    );
}

/// The stress case of `tests/vehicles/impacts.rs` (a coach on rolling wheelsets,
/// e = 0.9, at 300 km/h from the approach over Yang & Yau's 25 m bridge
/// onto the run-off) on an ISO 8608 class A profile (seed 3), with `auto`
/// at 50 µs: HHT-α (RK4's limit is 14.5 µs on this mesh).
fn stress_case() -> Scene {
    common::rough_coach_scene("rough-track-300-hht", "A", 3, 5e-5, "auto")
}

#[test]
fn the_bouncing_coach_under_hht_gains_no_energy() {
    // Before, a landing located 2.7e-11 s into a step left HHT-α an end
    // acceleration of that sliver's forces, and the run gained 10 % of its
    // energy in one step.
    let run = run(&stress_case());
    let sim = &run.sim;
    assert!(sim.integrator_choice().starts_with("hht"));
    let events = kinds(sim);
    let count = |k| events.iter().filter(|&&e| e == k).count();
    let (landings, lift_offs) = (count(EventKind::Landing), count(EventKind::LiftOff));
    let e0 = sim.initial_energy();
    let largest_gain = (run.drift.windows(2))
        .map(|w| w[1] - w[0])
        .fold(0.0f64, f64::max);
    eprintln!(
        "landings {landings}, lift-offs {lift_offs}, impact loss {:.1} J, numerical \
         dissipation {:.1} J, largest drift {:.2} J, largest gain in a step {largest_gain:.3} J, \
         of {e0:.4e} J",
        sim.impact_loss(),
        sim.state().dynamic.numerical_dissipation,
        worst(&run.drift)
    );
    assert!(landings >= 50 && lift_offs >= 10, "{events:?}");
    // Measured 4.4e-7 and 1.5e-7 (2026-11-23); before, 10 % in one step.
    assert!(worst(&run.drift) < 2e-6 * e0, "{}", worst(&run.drift));
    assert!(largest_gain < 1e-6 * e0, "{largest_gain}");
}

#[test]
fn a_state_naming_a_missing_contact_to_restart_is_refused() {
    let scene = hht(wheel_crossing(2, 2.5e-3), 0.0);
    let mut sim = Simulation::new(&scene).expect("builds");
    let mut state = sim.state();
    state.pending_restart = vec![1];
    let refused = sim.restore(&state).expect_err("refused");
    assert!(refused.contains("pending restarts"), "{refused}");
    state.pending_restart = vec![0];
    sim.restore(&state).expect("one contact, index 0");
}

/// Sixteen realizations of the rough track: every run ends, and none gains
/// energy beyond 1e-6 of it in a step. Before the landing locator bracketed
/// a just-bounced contact's return and checked the other landing contacts
/// (2026-11-27), seeds 1, 4 and 5 gained 1.4e-2, 5e-4 and 2e-4 of it in
/// one step (a contact left 14 µm below the track, a sliver step of
/// 4.8e-13 s) and seed 8 stopped with a solver error (on the profile grid
/// of the time). Seed 14 then still gained 4.1e-6 in the step at 0.2815 s,
/// where one contact lifted off at the step's start with its force in
/// HHT-α's start accelerations and another landed and left at once; with
/// the restart at those lift-offs every seed gains at most 1.5e-8 and
/// drifts at most 4.4e-8 (measured 2026-11-27 05:29 UTC).
#[test]
fn rough_tracks_under_hht_gain_no_energy_whatever_the_seed() {
    for seed in 1..=16u64 {
        let scene = common::rough_coach_scene("rough-track-300-hht", "A", seed, 5e-5, "auto");
        let run = run(&scene);
        let e0 = run.sim.initial_energy();
        let gain = (run.drift.windows(2).map(|w| w[1] - w[0])).fold(0.0f64, f64::max);
        eprintln!(
            "seed {seed}: drift {:.2e}, largest gain in a step {:.2e} of e0",
            worst(&run.drift) / e0,
            gain / e0
        );
        assert!(
            worst(&run.drift) < 1e-6 * e0 && gain < 1e-6 * e0,
            "seed {seed}"
        );
    }
}
