//! The paper's examples (METHOD.md, "The paper's examples"): our public
//! acceptance figures. Each tolerance is the one the acceptance criteria
//! state, or says why it is what it is.

use crate::common;
use common::{paper_scene, run_to_exit};
use guideway::scene::BodyKind;

/// Static midspan deflection P L³ / (48 EI) of the paper's beam (m).
const STATIC_DEFLECTION: f64 = 0.1728;

#[test]
fn wheel_at_10_m_per_s_matches_the_paper() {
    let run = run_to_exit(&paper_scene(BodyKind::Wheel, 10.0, 0.0025));
    // Paper: exit speed 9.96 m/s (acceptance ± 0.01).
    assert!(
        (run.exit_nominal_speed - 9.96).abs() <= 0.01,
        "exit V = {}",
        run.exit_nominal_speed
    );
    // Paper: peak nominal speed about 10 % above the initial (acceptance 10-12 %).
    let rise = run.peak_nominal_speed / 10.0 - 1.0;
    assert!((0.10..=0.12).contains(&rise), "peak rise = {rise}");
    // Paper: energy balance varies at most 0.0029 % at this step.
    assert!(
        run.max_energy_drift <= 2.9e-5,
        "drift = {}",
        run.max_energy_drift
    );
    // Paper: 913 steps; the exit is when the contact point reaches L, which
    // we locate inside the step, so allow 1 % for the paper's exit criterion.
    assert!(
        (run.steps as f64 / 913.0 - 1.0).abs() < 0.01,
        "steps = {}",
        run.steps
    );
    // The midspan dips below the static deflection (dynamic amplification).
    let amplification = -run.peak_midspan_deflection / STATIC_DEFLECTION;
    assert!((1.0..1.2).contains(&amplification), "{amplification}");
}

#[test]
fn energy_error_of_the_held_force_is_second_order_in_the_step() {
    // Holding the contact force over a step leaves an energy error of order
    // Δt² (the bounded, telescoping work of the in-step velocity error);
    // halving the step must divide it by about four (3 to 5 allows for the
    // beam's vibration phase at the maxima).
    let coarse = run_to_exit(&paper_scene(BodyKind::Wheel, 10.0, 0.0025));
    let fine = run_to_exit(&paper_scene(BodyKind::Wheel, 10.0, 0.00125));
    let ratio = coarse.max_energy_drift / fine.max_energy_drift;
    assert!((3.0..5.0).contains(&ratio), "ratio = {ratio}");
}

#[test]
fn wheel_at_100_m_per_s_leaves_energy_in_the_beam() {
    let run = run_to_exit(&paper_scene(BodyKind::Wheel, 100.0, 0.0025));
    // Paper: exit speed 99.30 m/s (acceptance ± 0.02).
    assert!(
        (run.exit_nominal_speed - 99.30).abs() <= 0.02,
        "exit V = {}",
        run.exit_nominal_speed
    );
    // Paper: 96 steps.
    assert!((95..=97).contains(&run.steps), "steps = {}", run.steps);
    // The wheel leaves with less kinetic energy than it entered with ...
    let ke_in = run.initial("energy.body_kinetic");
    let ke_out = run.value("energy.body_kinetic");
    assert!(ke_out < ke_in, "{ke_out} >= {ke_in}");
    // ... and the beam holds the difference (plus the work of the 600 kN
    // force), to within the energy drift.
    let beam = run.value("energy.beam_kinetic") + run.value("energy.beam_strain");
    let lost = ke_in - ke_out + run.value("energy.external_work");
    assert!(
        (beam - lost).abs() <= 1e-5 * ke_in,
        "beam {beam} vs lost {lost}"
    );
    // V is the rate of the contact point, not the centre's horizontal speed:
    // they differ by about 0.3 % at exit.
    let difference = run.exit_vx / run.exit_nominal_speed - 1.0;
    assert!((0.002..0.004).contains(&difference), "{difference}");
}

#[test]
fn wheel_at_1_m_per_s_speeds_up_to_about_five() {
    let run = run_to_exit(&paper_scene(BodyKind::Wheel, 1.0, 0.005));
    // Quasi-static energy balance gives 4.90 m/s (acceptance 4.8 to 5.0).
    assert!(
        (4.8..=5.0).contains(&run.peak_nominal_speed),
        "peak V = {}",
        run.peak_nominal_speed
    );
    // Travel time between 1/3 and 0.4 of the rigid-beam time of 24 s.
    let ratio = run.exit_time / 24.0;
    assert!((1.0 / 3.0..=0.4).contains(&ratio), "time ratio = {ratio}");
}

#[test]
fn glider_at_30_m_per_s_conserves_energy_without_tangential_force() {
    let run = run_to_exit(&paper_scene(BodyKind::Glider, 30.0, 0.005));
    // Same order as the wheel: within the paper's 0.0029 %.
    assert!(
        run.max_energy_drift <= 2.9e-5,
        "drift = {}",
        run.max_energy_drift
    );
    assert_eq!(run.max_abs_tangential_force, 0.0);
    // No wheel-only outputs.
    for name in [
        "glider.angular_velocity",
        "contact.tangential_force",
        "wheel.x",
    ] {
        assert!(!run.names.iter().any(|n| n == name), "{name} present");
    }
    // Smooth horizontal speed of the body: it changes by well under 1 %.
    assert!((run.exit_vx / 30.0 - 1.0).abs() < 0.01);
}
