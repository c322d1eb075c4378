//! Unilateral contact: lift-off, flight, landing with Newton's restitution.

use guideway::scene::{BodyKind, DampingSpec, Scene};
use guideway::simulation::{EventKind, SimState};
use guideway::{Advance, Simulation};

/// A body dropped from `height` onto rigid ground (the approach), rolling
/// (a wheel) or gliding at 10 m/s under gravity alone.
fn drop_scene(kind: BodyKind, height: f64, restitution: f64) -> Scene {
    let mut scene = Scene::lee1994(kind, 10.0, 0.001);
    scene.gravity = 9.81;
    scene.vehicles[0].force_y = 0.0;
    scene.track.approach = 100.0;
    scene.vehicles[0].initial_position = -90.0;
    scene.vehicles[0].initial_height = height;
    scene.vehicles[0].restitution = restitution;
    scene.solver.end_time = Some(1.0);
    scene.validate().expect("valid");
    scene
}

/// Run to `end` on the grid of the scene's step, calling `each` after
/// every step.
fn run(scene: &Scene, end: f64, mut each: impl FnMut(&Simulation)) -> Simulation {
    let mut sim = Simulation::new(scene).expect("builds");
    let dt = scene.solver.step;
    for k in 1..=(end / dt).round() as u64 {
        match sim.advance_to(k as f64 * dt) {
            Ok(Advance::Reached) => each(&sim),
            Ok(Advance::Exited { .. }) => break,
            Err(e) => panic!("{e}"),
        }
    }
    sim
}

/// Height of the body's centre above its place on the ground at the apex of
/// its free flight now (m): y + v_y²/2g − (r + h).
fn ballistic_height(state: &SimState, rest: f64) -> f64 {
    let b = &state.dynamic.bodies[0];
    b.position.y + b.velocity.y * b.velocity.y / (2.0 * 9.81) - rest
}

fn landings(sim: &Simulation) -> usize {
    sim.events()
        .iter()
        .filter(|e| e.kind == EventKind::Landing)
        .count()
}

/// The ballistic height after the first landing, and the landings.
fn bounce(kind: BodyKind, restitution: f64) -> (f64, usize, Simulation) {
    let height = 0.1;
    let scene = drop_scene(kind, height, restitution);
    let rest = scene.vehicles[0].radius.unwrap_or(0.0) + scene.beam.surface_offset;
    let mut after = None;
    // First landing at t = √(2h/g) = 0.143 s; the next at 0.143 (1 + 2e) s.
    let sim = run(&scene, 0.2, |sim| {
        if landings(sim) == 1 && sim.contact_statuses()[0].open {
            after = Some(ballistic_height(&sim.state(), rest));
        }
    });
    (after.unwrap_or(f64::NAN), landings(&sim), sim)
}

#[test]
fn elastic_wheel_and_glider_bounce_back_to_their_height() {
    for kind in [BodyKind::Wheel, BodyKind::Glider] {
        let (height, landings, sim) = bounce(kind, 1.0);
        eprintln!(
            "{kind:?} e=1: {height} {landings} loss {}",
            sim.impact_loss()
        );
        assert_eq!(landings, 1);
        assert!((height - 0.1).abs() <= 1e-6 * 0.1, "{kind:?}: {height}");
        assert!(sim.impact_loss().abs() <= 1e-9, "{}", sim.impact_loss());
    }
}

#[test]
fn half_elastic_bounce_reaches_e_squared_of_the_height() {
    for kind in [BodyKind::Wheel, BodyKind::Glider] {
        let (height, landings, sim) = bounce(kind, 0.5);
        eprintln!(
            "{kind:?} e=0.5: {height} {landings} loss {}",
            sim.impact_loss()
        );
        assert_eq!(landings, 1);
        assert!((height - 0.025).abs() <= 1e-6 * 0.025, "{kind:?}: {height}");
        // The impact removes (1 − e²) of the kinetic energy of the fall.
        let m = 3000.0;
        let lost = m * 9.81 * 0.1 * (1.0 - 0.25);
        assert!((sim.impact_loss() - lost).abs() <= 1e-6 * lost);
    }
}

#[test]
fn plastic_landing_stays_on_the_ground() {
    for kind in [BodyKind::Wheel, BodyKind::Glider] {
        let scene = drop_scene(kind, 0.1, 0.0);
        let rest = scene.vehicles[0].radius.unwrap_or(0.0) + scene.beam.surface_offset;
        let sim = run(&scene, 0.5, |_| {});
        let events: Vec<_> = sim.events().iter().map(|e| e.kind).collect();
        assert_eq!(events, [EventKind::Landing], "{kind:?}");
        let landing = sim.events()[0].time;
        assert!((landing - (0.2f64 / 9.81).sqrt()).abs() < 1e-9, "{landing}");
        let status = sim.contact_statuses()[0];
        assert!(!status.open);
        let body = &sim.state().dynamic.bodies[0];
        assert!((body.position.y - rest).abs() < 1e-5, "{}", body.position.y);
        assert!(body.velocity.y.abs() < 1e-6, "{}", body.velocity.y);
        // All the fall's kinetic energy is lost; the balance holds.
        let lost = 3000.0 * 9.81 * 0.1;
        assert!((sim.impact_loss() - lost).abs() <= 1e-6 * lost);
        assert!((status.impulse[1] - 3000.0 * (2.0 * 9.81 * 0.1f64).sqrt()).abs() < 1e-3);
        let drift = sim.energy_balance() - sim.initial_energy();
        assert!(drift.abs() <= 1e-6 * lost, "{drift}");
    }
}

/// The paper's wheel on a 16-element beam at `speed`, `integrator = "auto"`.
fn paper_scene(speed: f64, elements: usize, step: f64) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, speed, step);
    scene.beam.elements = elements;
    scene.solver.integrator = guideway::scene::IntegratorKind::Auto;
    scene.validate().expect("valid");
    scene
}

/// The paper's wheel crossing at `speed` onto a run-off of rigid ground,
/// until `after` seconds past the beam's end.
fn crossing_scene(speed: f64, step: f64, after: f64) -> Scene {
    let mut scene = paper_scene(speed, 16, step);
    scene.track.run_off = 30.0;
    scene.solver.end_time = Some(24.0 / speed + after);
    scene
}

/// The crossing of `crossing_scene`, with the balance's drift after
/// every step.
fn crossing(speed: f64, step: f64, after: f64) -> (Scene, Simulation, Vec<f64>) {
    let scene = crossing_scene(speed, step, after);
    let end = scene.solver.end_time.unwrap();
    let mut drift = Vec::new();
    let sim = run(&scene, end, |sim| {
        drift.push(sim.energy_balance() - sim.initial_energy())
    });
    (scene, sim, drift)
}

fn first(sim: &Simulation, kind: EventKind) -> Option<f64> {
    sim.events().iter().find(|e| e.kind == kind).map(|e| e.time)
}

/// The step from which the bilateral contact (the model before unilateral
/// contact, at commit 3c85ea0) stopped with a tensile force on the paper's
/// wheel, 16 elements, `integrator = "auto"`: (speed, step, start of the
/// step). Measured with `guideway run` on 2026-11-22: "the normal contact
/// force would become tensile ... in the step from t = 0.155 s at x =
/// 23.651085 m" (150 m/s, Δt = 2.5 ms) and likewise.
const BILATERAL_TENSILE: [(f64, f64, f64); 4] = [
    (150.0, 0.0025, 0.155),
    (250.0, 0.0025, 0.0625),
    (150.0, 1e-4, 0.1572),
    (250.0, 1e-4, 0.0942),
];

#[test]
fn paper_wheel_on_sixteen_elements_lifts_off_flies_and_lands() {
    for (speed, step, tensile) in BILATERAL_TENSILE {
        let (scene, sim, _) = crossing(speed, step, 0.08);
        let end = scene.solver.end_time.unwrap();
        assert!(
            sim.time() > end - step,
            "{speed} m/s stopped at {}",
            sim.time()
        );
        let lift_off = first(&sim, EventKind::LiftOff).expect("lifts off");
        assert!(
            (lift_off - tensile).abs() <= step * (1.0 + 1e-9),
            "{speed} m/s, {step} s: lift-off at {lift_off}, bilateral {tensile}"
        );
        let landing = first(&sim, EventKind::Landing).expect("lands");
        assert!(landing > lift_off);
        assert!(!sim.contact_statuses()[0].open, "ends in contact");
        assert!(sim.impact_loss() > 0.0);
    }
}

#[test]
fn energy_balance_with_impacts_holds_within_rk4s_limit() {
    // `auto` picks RK4 at Δt = 1e-4 s (its limit is 1.417e-4 s on 16
    // elements); at the paper's step it picks HHT-α with α = −0.1, whose
    // numerical damping is not part of the balance.
    for speed in [150.0, 250.0] {
        let (_, sim, drift) = crossing(speed, 1e-4, 0.08);
        assert!(sim.integrator_choice().starts_with("rk4"));
        let s = sim.state();
        let total = sim.initial_energy().abs()
            + s.external_work.abs()
            + s.gravity_work.abs()
            + sim.impact_loss();
        let worst = drift.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        assert!(
            worst <= 1e-5 * total,
            "{speed} m/s: drift {worst} J of {total} J"
        );
        // What the flights and landings add to the drift is small against
        // the energy the impacts take out.
        let lift_off = first(&sim, EventKind::LiftOff).unwrap();
        let before = drift[(lift_off / 1e-4).round() as usize - 1];
        let added = (drift.last().unwrap() - before).abs();
        assert!(added <= 1e-5 * sim.impact_loss(), "{speed} m/s: {added} J");
    }
}

#[test]
fn energy_balance_with_impacts_holds_at_the_papers_step_under_auto() {
    // At Δt = 2.5 ms `auto` picks HHT-α with α = −0.1; its numerical
    // dissipation, from the scheme's discrete energy identity step by step,
    // is a term of the balance. Measured on 2026-11-22 (largest drift over
    // the run, with D and without, of the total): 150 m/s 333 J and 694 J
    // of 5.07e7 J (6.6e-6, 1.4e-5), D = 346 J; 250 m/s 2.9e3 J and
    // 4.4e3 J of 1.41e8 J (2.0e-5, 3.1e-5), D = 2.9e3 J: at 250 m/s the
    // balance does not hold to 1e-5. What is left is the
    // same at α = −0.05, −0.1 and −0.2 (2.1e3, 2.9e3, 2.7e3 J): not the
    // numerical damping but the contact forces' work at the coarse step,
    // while the force alternates from step to step near the beam's end.
    let scene = crossing_scene(150.0, 0.0025, 0.08);
    let end = scene.solver.end_time.unwrap();
    let (mut drift, mut numerical_history) = (Vec::new(), Vec::new());
    let sim = run(&scene, end, |sim| {
        drift.push(sim.energy_balance() - sim.initial_energy());
        numerical_history.push(sim.state().dynamic.numerical_dissipation);
    });
    assert!(sim.integrator_choice().starts_with("hht"));
    let s = sim.state();
    let total = sim.initial_energy().abs()
        + s.external_work.abs()
        + s.gravity_work.abs()
        + sim.impact_loss();
    let worst = drift.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let numerical = s.dynamic.numerical_dissipation;
    let without = drift
        .iter()
        .zip(&numerical_history)
        .fold(0.0f64, |m, (d, n)| m.max((d - n).abs()));
    eprintln!("150 m/s: drift {worst} J (without D {without} J) of {total} J, D {numerical} J");
    assert!(worst <= 1e-5 * total, "drift {worst} J of {total} J");
    // Left out of the balance, the numerical damping would break it.
    assert!(numerical > 0.0 && without > 1e-5 * total, "{without} J");
}

/// The paper's wheel crossing the undamped paper beam on `elements` at
/// 100 m/s (`auto`, step `step`) and a glider (the paper's 600 kN load on
/// 3000 kg) released 0.2 m above midspan, plastic (e = 0), until 0.2 s.
fn glider_over_vibrating_beam(elements: usize, step: f64) -> Scene {
    let mut scene = paper_scene(100.0, elements, step);
    scene.solver.end_time = Some(0.2);
    let mut glider = Scene::lee1994(BodyKind::Glider, 0.0, step).vehicles[0].clone();
    glider.name = "glider".into();
    glider.initial_position = 12.0;
    glider.initial_height = 0.2;
    scene.vehicles.push(glider);
    scene.validate().expect("valid");
    scene
}

#[test]
fn glider_released_above_a_vibrating_beam_lands_and_stays() {
    // The paper's wheel crosses at 100 m/s and sets the beam vibrating; a
    // glider (the paper's 600 kN load on 3000 kg) hangs 0.2 m above
    // midspan and falls onto it, plastically (e = 0).
    let mut scene = glider_over_vibrating_beam(16, 1e-4);
    // Undamped, the glider does not stay (see the next test); 5 % of
    // Rayleigh damping at the first two modes lets the beam's vibration die.
    scene.beam.damping = Some(DampingSpec::Modes {
        ratio: 0.05,
        modes: [1, 2],
    });
    scene.validate().expect("valid");
    let sim = run(&scene, 0.2, |sim| {
        let glider = sim.contact_statuses()[1];
        assert!(
            glider.gap >= -1e-5,
            "t = {}: gap {}",
            sim.time(),
            glider.gap
        );
    });
    let events: Vec<_> = sim
        .events()
        .iter()
        .filter(|e| e.contact == 1)
        .map(|e| e.kind)
        .collect();
    // It lands, rebounds twice within a millisecond (the beam under the
    // point of impact springs back) and then stays.
    assert_eq!(events.first(), Some(&EventKind::Landing));
    assert_eq!(events.last(), Some(&EventKind::Landing));
    assert!(events.len() <= 5, "{events:?}");
    let times: Vec<f64> = sim
        .events()
        .iter()
        .filter(|e| e.contact == 1)
        .map(|e| e.time)
        .collect();
    assert!(times.last().unwrap() - times[0] < 2e-3, "{times:?}");
    let landing = first(&sim, EventKind::Landing).unwrap();
    // Free fall at 200 m/s² from 0.2 m onto a beam already deflected by the
    // wheel: a little later than √(2 · 0.2 / 200) = 0.0447 s.
    assert!(landing > 0.0447 && landing < 0.06, "{landing}");
    assert!(!sim.contact_statuses()[1].open);
    assert!(sim.impact_loss() > 0.0);
}

/// A stress case from what the model has (irregular tracks are not yet
/// there): at 300 km/h the paper's wheel, bouncing (e = 0.9, dropped from
/// 5 cm), crosses a three-span continuous beam between rigid approach and
/// run-off, whose supports and ends are kinks it jumps at; `auto` at
/// Δt = 50 µs (RK4, whose limit is 63 µs on this mesh).
fn rough_scene() -> Scene {
    let speed = 300.0 / 3.6;
    Scene::from_toml_str(&format!(
        r#"
name = "rough"
gravity = 9.81
[beam]
length = 24.0
mass_per_length = 1250.0
bending_stiffness = 1e9
surface_offset = 0.6
elements = 24
supports = {{ intermediate = [8.0, 16.0] }}
[track]
approach = 30.0
run_off = 30.0
[body]
name = "wheel"
kind = "wheel"
mass = 3000.0
inertia = 135.0
radius = 0.3
initial_position = -2.0
initial_speed = {speed:?}
force_y = -6e5
restitution = 0.9
initial_height = 0.05
[solver]
step = 5e-5
integrator = "auto"
end_time = 0.6
"#
    ))
    .expect("valid")
}

#[test]
fn bouncing_wheel_on_a_rough_track_neither_fails_nor_grinds() {
    let scene = rough_scene();
    let grid = (0.6f64 / 5e-5).round() as u64;
    let sim = run(&scene, 0.6, |sim| {
        let mut values = vec![0.0; sim.outputs().len()];
        sim.output_values(&mut values);
        assert!(values.iter().all(|v| v.is_finite()), "t = {}", sim.time());
    });
    assert!(sim.time() > 0.6 - 1e-9, "stopped at {}", sim.time());
    let (steps, _) = sim.counters();
    let kinds: Vec<_> = sim.events().iter().map(|e| e.kind).collect();
    let count = |kind| kinds.iter().filter(|&&k| k == kind).count();
    let (landings, lift_offs) = (count(EventKind::Landing), count(EventKind::LiftOff));
    eprintln!(
        "steps {steps} of {grid}, events {}, landings {landings}, lift-offs {lift_offs}",
        kinds.len()
    );
    assert!(landings >= 10 && lift_offs >= 3, "{kinds:?}");
    // Every event shortens at most one step: no endless tiny steps.
    assert!(
        steps <= grid + kinds.len() as u64,
        "{steps} steps for {grid}"
    );
}

#[test]
fn a_state_saved_in_flight_continues_identically_and_bad_ones_are_refused() {
    let scene = drop_scene(BodyKind::Wheel, 0.1, 0.5);
    let mut sim = Simulation::new(&scene).unwrap();
    sim.advance_to(0.1).unwrap();
    let saved = sim.state();
    assert!(saved.contacts[0].open);
    sim.advance_to(0.3).unwrap();
    let mut other = Simulation::new(&scene).unwrap();
    other.restore(&saved).unwrap();
    other.advance_to(0.3).unwrap();
    let (a, b) = (sim.state(), other.state());
    assert_eq!(a.dynamic.bodies, b.dynamic.bodies);
    assert_eq!(a.dynamic.beam_velocity, b.dynamic.beam_velocity);
    assert_eq!(
        (a.contacts, a.events, a.impact_loss),
        (b.contacts, b.events, b.impact_loss)
    );
    // At 0.143 s and, after a rebound to 0.025 m, at 0.286 s.
    assert_eq!(landings(&other), 2);
    let mut bad = saved.clone();
    bad.contacts.clear();
    assert!(other.restore(&bad).unwrap_err().contains("contact states"));
    let mut bad = saved.clone();
    bad.contacts[0].gap = f64::NAN;
    assert!(bad.check_values(scene.solver.step).is_err());
}

#[test]
fn glider_on_an_undamped_vibrating_beam_flies_again_and_again_in_bounded_steps() {
    // Undamped, the glider keeps leaving the beam and landing on it, and
    // that is the discrete model's physics, not a numerical artefact: the
    // landing's impulse goes to the point's effective mass on the
    // consistent-mass mesh, a fraction of an element (its impulse halves
    // as the mesh doubles: 6868, 3967, 2150 N s on 16, 32, 64 elements),
    // the rest of the 27 kN s is exchanged by the contact force after it,
    // and the vibration this puts into the beam's higher modes, never
    // damped, accelerates the surface under the glider faster than the
    // 200 m/s² that holds it down. The landings do not go away with the
    // step (51, 78, 74 on 16 elements at 100, 50, 25 µs) and grow with the
    // mesh (91 and 121 on 32 elements at 25 and 12.5 µs, 166 on 64 at
    // 5 µs), each a real flight (impulses up to 2.4 kN s, far above the
    // chattering threshold's 30 N s). What bounds the run is the rule
    // that a contact opens at most once and bounces at most once per grid
    // step: at most three events per contact per grid step, every event
    // shortening one step, so no run grinds to tiny steps.
    let mut drifts = Vec::new();
    for step in [1e-4, 5e-5] {
        let scene = glider_over_vibrating_beam(16, step);
        let mut sim = Simulation::new(&scene).expect("builds");
        let grid = (0.2 / step).round() as u64;
        let mut seen = 0;
        for k in 1..=grid {
            assert!(matches!(
                sim.advance_to(k as f64 * step),
                Ok(Advance::Reached)
            ));
            for c in 0..2 {
                let new = sim.events()[seen..].iter().filter(|e| e.contact == c);
                assert!(new.count() <= 3, "t = {}: {:?}", sim.time(), sim.events());
            }
            seen = sim.events().len();
        }
        let (steps, _) = sim.counters();
        let events = sim.events().len() as u64;
        assert!(steps <= grid + events, "{steps} steps for {grid}");
        let landings = sim
            .events()
            .iter()
            .filter(|e| e.contact == 1 && e.kind == EventKind::Landing)
            .count();
        assert!(landings >= 40, "Δt = {step}: {landings} landings");
        let drift = (sim.energy_balance() - sim.initial_energy()).abs();
        drifts.push(drift / sim.impact_loss());
    }
    // The energy balance, impact losses and RK4's numerical dissipation
    // included, holds to 5.3e-3 and 7.6e-4 of the impact losses (72 and
    // 77 kJ; measured 2026-11-23): what is left comes mostly from steps
    // without events (up to 110 J in one at 100 µs), the contact force's
    // work on the glider and on a beam whose excited higher modes the step
    // barely resolves; it falls faster than the step.
    assert!(drifts[0] < 1e-2, "{drifts:?}");
    assert!(drifts[1] < 0.5 * drifts[0], "{drifts:?}");
}
