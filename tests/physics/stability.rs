//! The explicit scheme refuses steps beyond its stability limit, and the
//! solution converges with the mesh.

use crate::common;
use common::{paper_scene, run_to_exit};
use guideway::scene::{BodyKind, IntegratorKind, StructureKind};
use guideway::simulation::EventKind;
use guideway::Simulation;

#[test]
fn rk4_beyond_its_stability_limit_is_refused_before_running() {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 8;
    let message = Simulation::new(&scene).err().expect("refused");
    // Names the element length, the limit (0.0563 ℓ² √(μ/EI) = 0.57 ms) and the step.
    assert!(message.contains("3.0000 m"), "{message}");
    assert!(message.contains("5.6"), "{message}");
    assert!(message.contains("0.0025"), "{message}");
    scene.solver.step = 5e-4;
    assert!(Simulation::new(&scene).is_ok());
}

/// On a modal structure the limit is set by the highest mode kept, not
/// by the mesh: the refusal says so, and its limit is 2√2 / ω₄ with ω₄
/// the simply supported beam's closed form 16 (π/L)² √(EI/m).
#[test]
fn rk4_beyond_a_modal_structures_limit_names_the_modes_kept() {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 8;
    scene.solver.structure = StructureKind::Modal;
    scene.solver.modes = Some(4);
    let beam = &scene.beam;
    let omega1 = (std::f64::consts::PI / beam.length).powi(2)
        * (beam.bending_stiffness / beam.mass_per_length).sqrt();
    let closed = 2.0 * std::f64::consts::SQRT_2 / (16.0 * omega1);
    scene.solver.step = 2.0 * closed;
    let message = Simulation::new(&scene).err().expect("refused");
    assert!(message.contains("the 4 modes kept"), "{message}");
    assert!(message.contains("keep fewer modes"), "{message}");
    assert!(!message.contains("fewer elements"), "{message}");
    let limit: f64 = message
        .split("must not exceed ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|number| number.parse().ok())
        .expect("the message states the limit");
    // Eight Hermite elements overestimate ω₄ by well under 1 %.
    assert!((limit / closed - 1.0).abs() < 0.01, "{limit} vs {closed}");
    scene.solver.step = 0.9 * limit;
    assert!(Simulation::new(&scene).is_ok());
}

#[test]
fn exit_speed_converges_with_the_mesh() {
    // 2, 4 and 8 elements at stable steps: energy stays within the paper's
    // bound and the exit speed within its 9.96 ± 0.01 m/s on every mesh.
    let mut speeds = Vec::new();
    for (elements, step) in [(2, 0.0025), (4, 0.001), (8, 0.00025)] {
        let mut scene = paper_scene(BodyKind::Wheel, 10.0, step);
        scene.beam.elements = elements;
        let run = run_to_exit(&scene);
        assert!(
            run.max_energy_drift < 2.9e-5,
            "{elements}: {}",
            run.max_energy_drift
        );
        speeds.push(run.exit_nominal_speed);
    }
    for v in &speeds {
        assert!((v - 9.96).abs() <= 0.01, "{speeds:?}");
    }
}

#[test]
fn tensile_contact_force_lifts_the_wheel_off() {
    // Far above the beam's critical speed (about 117 m/s) the contact force
    // of a bilateral contact would turn tensile near the exit (from about
    // 150 m/s). Two elements are too coarse to show it; eight at a stable
    // step do: the contact opens instead (tests/vehicles/lift_off.rs follows the
    // flight), and no normal force is ever tensile.
    let mut scene = paper_scene(BodyKind::Wheel, 300.0, 1e-4);
    scene.beam.elements = 8;
    let mut sim = Simulation::new(&scene).unwrap();
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let normal = names
        .iter()
        .position(|n| n == "contact.normal_force")
        .unwrap();
    let mut values = vec![0.0; names.len()];
    let mut k = 0;
    while sim.exit_time().is_none() {
        k += 1;
        sim.advance_to(k as f64 * 1e-4).expect("no failure");
        sim.output_values(&mut values);
        assert!(values.iter().all(|v| v.is_finite()));
        assert!(
            values[normal] >= 0.0,
            "t = {}: {}",
            sim.time(),
            values[normal]
        );
    }
    let kinds: Vec<_> = sim.events().iter().map(|e| e.kind).collect();
    assert!(kinds.contains(&EventKind::LiftOff), "{kinds:?}");
}

#[test]
fn below_the_critical_speed_the_contact_stays_compressed() {
    let run = run_to_exit(&paper_scene(BodyKind::Wheel, 100.0, 0.0025));
    assert!(run.value("contact.normal_force") > 0.0);
}

#[test]
fn implicit_scheme_matches_the_paper_case_within_its_tolerances() {
    // HHT-α with α = 0 (average acceleration) at the paper's step: the same
    // acceptance figures as the paper's RK4.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.solver.integrator = IntegratorKind::Hht;
    let run = run_to_exit(&scene);
    assert!(
        (run.exit_nominal_speed - 9.96).abs() <= 0.01,
        "{}",
        run.exit_nominal_speed
    );
    assert!(
        run.max_energy_drift <= 2.9e-5,
        "drift = {}",
        run.max_energy_drift
    );
}

#[test]
fn auto_picks_the_implicit_scheme_for_a_fine_mesh_and_says_so() {
    // 32 elements: RK4 would need Δt ≤ 35 µs; at the paper's 2.5 ms it is
    // refused, `auto` runs HHT-α and completes with bounded energy drift.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 32;
    assert!(Simulation::new(&scene).is_err());
    scene.solver.integrator = IntegratorKind::Auto;
    let sim = Simulation::new(&scene).expect("auto builds");
    assert!(
        sim.integrator_choice().starts_with("hht"),
        "{}",
        sim.integrator_choice()
    );
    assert!(
        sim.integrator_choice().contains("3.5"),
        "{}",
        sim.integrator_choice()
    );
    let run = run_to_exit(&scene);
    assert!(
        run.max_energy_drift <= 2.9e-5,
        "drift = {}",
        run.max_energy_drift
    );
    assert!(
        (run.exit_nominal_speed - 9.96).abs() <= 0.01,
        "{}",
        run.exit_nominal_speed
    );
    // On the paper's mesh `auto` keeps RK4.
    let mut coarse = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    coarse.solver.integrator = IntegratorKind::Auto;
    let sim = Simulation::new(&coarse).unwrap();
    assert!(
        sim.integrator_choice().starts_with("rk4"),
        "{}",
        sim.integrator_choice()
    );
}

#[test]
fn numerical_damping_dissipates_energy() {
    // HHT-α's damping (−α) removes energy from the beam's high modes:
    // `energy.numerical_dissipation`, a term of the balance, is zero for
    // α = 0 and grows with the damping. (The paper's loading puts little
    // energy into high modes, so the effect is small: the physics is left
    // alone.)
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 16;
    scene.solver.integrator = IntegratorKind::Hht;
    let mut losses = Vec::new();
    for damping in [0.0, 0.1, 0.3] {
        scene.solver.numerical_damping = damping;
        let run = run_to_exit(&scene);
        let initial = run.initial("energy.balance");
        losses.push(run.value("energy.numerical_dissipation") / initial);
    }
    assert!(losses[0].abs() < 1e-12, "{losses:?}");
    assert!(losses[0] < losses[1] && losses[1] < losses[2], "{losses:?}");
}

#[test]
fn a_thousandfold_stiffer_beam_runs_with_auto_and_stays_conservative() {
    // EI × 1000: RK4 at the paper's step is refused (limit 0.29 ms), auto
    // runs HHT-α: the beam barely deflects and the wheel keeps its speed.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.bending_stiffness = 1e12;
    assert!(Simulation::new(&scene).is_err());
    scene.solver.integrator = IntegratorKind::Auto;
    let run = run_to_exit(&scene);
    assert!(
        (run.exit_nominal_speed - 10.0).abs() < 1e-3,
        "{}",
        run.exit_nominal_speed
    );
    assert!(run.max_energy_drift < 1e-6, "{}", run.max_energy_drift);
}

#[test]
fn a_tolerance_below_round_off_with_a_tight_cap_stops_with_a_diagnostic() {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.solver.velocity_tolerance = 1e-14;
    scene.solver.max_iterations = 5;
    let mut sim = Simulation::new(&scene).unwrap();
    let error = sim
        .advance_to(2.0)
        .expect_err("cannot converge below round-off in 5");
    assert!(
        error.message.contains("did not converge in 5 iterations"),
        "{error}"
    );
    assert!(error.message.contains("tolerance 1.000e-14"), "{error}");
    // The state is the last converged step's: finite, before the failure.
    assert!(sim.time() <= error.time && sim.time() > 0.0);
}

#[test]
fn the_implicit_scheme_takes_steps_far_beyond_rk4s_limit() {
    // Δt = 20 ms, twice RK4's limit on the paper's mesh: HHT-α completes with
    // the exit speed still within 0.02 m/s of the paper's.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.02);
    assert!(Simulation::new(&scene).is_err());
    scene.solver.integrator = IntegratorKind::Hht;
    let run = run_to_exit(&scene);
    assert!(
        (run.exit_nominal_speed - 9.96).abs() < 0.02,
        "{}",
        run.exit_nominal_speed
    );
    assert!(run.max_energy_drift < 1e-3, "{}", run.max_energy_drift);
}
