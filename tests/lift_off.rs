//! Unilateral contact: lift-off, flight, landing with Newton's restitution.

use guideway::scene::{BodyKind, Scene};
use guideway::simulation::{EventKind, SimState};
use guideway::{Advance, Simulation};

/// A body dropped from `height` onto rigid ground (the approach), rolling
/// (a wheel) or gliding at 10 m/s under gravity alone.
fn drop_scene(kind: BodyKind, height: f64, restitution: f64) -> Scene {
    let mut scene = Scene::lee1994(kind, 10.0, 0.001);
    scene.gravity = 9.81;
    scene.body.force_y = 0.0;
    scene.track.approach = 100.0;
    scene.body.initial_position = -90.0;
    scene.body.initial_height = height;
    scene.body.restitution = restitution;
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
    sim.events().iter().filter(|e| e.kind == EventKind::Landing).count()
}

/// The ballistic height after the first landing, and the landings.
fn bounce(kind: BodyKind, restitution: f64) -> (f64, usize, Simulation) {
    let height = 0.1;
    let scene = drop_scene(kind, height, restitution);
    let rest = scene.body.radius.unwrap_or(0.0) + scene.beam.surface_offset;
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
        eprintln!("{kind:?} e=1: {height} {landings} loss {}", sim.impact_loss());
        assert_eq!(landings, 1);
        assert!((height - 0.1).abs() <= 1e-6 * 0.1, "{kind:?}: {height}");
        assert!(sim.impact_loss().abs() <= 1e-9, "{}", sim.impact_loss());
    }
}

#[test]
fn half_elastic_bounce_reaches_e_squared_of_the_height() {
    for kind in [BodyKind::Wheel, BodyKind::Glider] {
        let (height, landings, sim) = bounce(kind, 0.5);
        eprintln!("{kind:?} e=0.5: {height} {landings} loss {}", sim.impact_loss());
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
        let rest = scene.body.radius.unwrap_or(0.0) + scene.beam.surface_offset;
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

#[test]
fn explore_paper() {
    for (integrator, damping) in [(guideway::scene::IntegratorKind::Auto, 0.0)] {
    for speed in [150.0, 250.0] {
        let dt: f64 = std::env::var("DT").unwrap().parse().unwrap();
        let mut scene = paper_scene(speed, 16, dt);
        scene.solver.integrator = integrator;
        scene.solver.numerical_damping = damping;
        scene.track.run_off = 30.0;
        scene.solver.end_time = Some(24.0 / speed + 0.08);
        let mut sim = Simulation::new(&scene).unwrap();
        eprintln!("{}", sim.integrator_choice());
        let mut first = true;
        let mut k = 0;
        loop {
            k += 1;
            let r = sim.advance_to(k as f64 * dt);
            if first && !sim.events().is_empty() { first = false; eprintln!("drift at first event {} t={}", sim.energy_balance() - sim.initial_energy(), sim.time()); }
            if !matches!(r, Ok(Advance::Reached)) { eprintln!("{r:?}"); break; }
            if k as f64 * dt >= 24.0 / speed + 0.08 - 1e-9 { break; }
        }
        eprintln!("{speed}: t={} events {:?}", sim.time(), sim.events().iter().map(|e| (e.time, e.kind)).collect::<Vec<_>>());
        eprintln!("loss {} drift {} ext {} steps {:?}", sim.impact_loss(), sim.energy_balance() - sim.initial_energy(), sim.state().external_work, sim.counters());
    }
    }
}
