//! A wheel crossing a rail joint (issue 11 item 2): two simply supported
//! spans with a gap between them. While the rim spans the gap the wheel
//! turns about the end corner of the first span, then about the start
//! corner of the second, then rolls on; no penalty springs. The same with
//! the paper's RK4 and with HHT-α (which restarts from consistent loads and
//! accelerations where the contact switches surfaces).

use crate::common;
use common::paper_scene;
use guideway::scene::{BodyKind, IntegratorKind, IrregularitySpec, JointKind, JointSpec, Scene};
use guideway::{Advance, Simulation};

const SPAN: f64 = 24.0;

/// The paper's wheel (r = 0.3 m, h = 0.6 m, 600 kN) at `speed` over two
/// 24 m spans of the paper's beam with a joint of width `gap` between
/// them, `elements` per span.
fn two_spans(gap: f64, elements: usize, step: f64, integrator: IntegratorKind) -> Scene {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, step);
    scene.name = "rail-gap".into();
    scene.beam.length = 2.0 * SPAN + gap;
    scene.beam.elements = 2 * elements;
    scene.beam.joints = vec![JointSpec {
        at: SPAN,
        kind: JointKind::Separate,
        gap,
    }];
    scene.solver.integrator = integrator;
    scene
}

/// One run's history: time, centre height, normal force, energy balance.
struct Crossing {
    time: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    vy: Vec<f64>,
    normal: Vec<f64>,
    balance: Vec<f64>,
    impact_loss: f64,
    initial_energy: f64,
    exited: bool,
    impacts: Vec<guideway::simulation::JointImpact>,
    exit_speed: f64,
}

fn cross(scene: &Scene) -> Crossing {
    let mut sim = Simulation::new(scene).expect("scene builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| {
        names
            .iter()
            .position(|x| x == n)
            .unwrap_or_else(|| panic!("no {n} in {names:?}"))
    };
    let (x, y, vy, normal, balance) = (
        at("wheel.x"),
        at("wheel.y"),
        at("wheel.vy"),
        at("contact.normal_force"),
        at("energy.balance"),
    );
    let mut values = vec![0.0; names.len()];
    let mut run = Crossing {
        time: vec![],
        x: vec![],
        y: vec![],
        vy: vec![],
        normal: vec![],
        balance: vec![],
        impact_loss: 0.0,
        initial_energy: sim.initial_energy(),
        exited: false,
        impacts: vec![],
        exit_speed: f64::NAN,
    };
    let dt = scene.solver.step;
    for k in 1..2_000_000u64 {
        let advance = match sim.advance_to(k as f64 * dt) {
            Ok(a) => a,
            Err(e) => {
                println!("{e}");
                break;
            }
        };
        sim.output_values(&mut values);
        run.time.push(sim.time());
        run.x.push(values[x]);
        run.y.push(values[y]);
        run.vy.push(values[vy]);
        run.normal.push(values[normal]);
        run.balance.push(values[balance]);
        if let Advance::Exited { .. } = advance {
            run.exited = true;
            run.exit_speed = values[at("wheel.nominal_speed")];
            break;
        }
    }
    run.impacts = sim.joint_impacts().to_vec();
    run.impact_loss = sim.impact_loss();
    run
}

/// The largest drift of the energy balance (which counts the impacts'
/// losses), relative to the initial energy.
fn drift(run: &Crossing) -> f64 {
    let e0 = run.initial_energy;
    run.balance
        .iter()
        .fold(0.0f64, |m, e| m.max((e - e0).abs()))
        / e0
}

const MASS: f64 = 3000.0;
const GAP: f64 = 0.05;
/// r + h: the wheel turns about the neutral axis's end at this distance.
const REACH: f64 = 0.9;

/// The crossing of the 5 cm joint at 10 m/s, asserted: it completes, one
/// impact at the far corner with the closed-form plastic impulse and loss,
/// the energy balance holds, and the contact force shows the corners.
fn check_5_cm_crossing(run: &Crossing) {
    assert!(run.exited, "the wheel did not complete the crossing");
    // One impact at the far corner; the switch onto the next span after it
    // turns the normal continuously (its impulse is 10⁻⁴ of the corner's).
    let impact = run.impacts[0];
    assert!(
        run.impacts[1..]
            .iter()
            .all(|i| i.impulse.norm() < 1e-4 * impact.impulse.norm()),
        "{:?}",
        run.impacts
    );
    // The impact happens when the centre passes the middle of the gap,
    // where the rim touches both corners.
    let i = run.time.iter().position(|&t| t >= impact.time).unwrap();
    let middle = SPAN + GAP / 2.0;
    assert!(
        run.x[i - 1] <= middle + 1e-9 && run.x[i] >= middle,
        "impact at x = {} .. {}",
        run.x[i - 1],
        run.x[i]
    );
    // Plastic impact on the far corner: the centre's velocity turns from
    // the tangent of one corner's circle to the other's, 2θ with
    // sin θ = (w/2)/(r + h); the normal impulse takes the normal part.
    let speed = 10.0;
    let theta = libm::asin(GAP / 2.0 / REACH);
    let expected_impulse = MASS * speed * libm::sin(2.0 * theta);
    let impulse = impact.impulse.y;
    println!("impulse {impulse} N s (closed form {expected_impulse})");
    assert!(
        (impulse / expected_impulse - 1.0).abs() < 1e-3,
        "impulse {impulse} vs {expected_impulse}"
    );
    // The impact takes the plastic impact's J² / 2m; the balance, which
    // counts it, holds through the whole crossing.
    let loss = impulse * impulse / (2.0 * MASS);
    let drift = drift(run);
    println!(
        "impact loss {} J, J²/2m = {loss} J; drift {drift:e}",
        run.impact_loss
    );
    assert!(
        (run.impact_loss / loss - 1.0).abs() < 1e-3,
        "impact loss {} J vs {loss} J",
        run.impact_loss
    );
    assert!(drift < 1e-5, "drift {drift}");
    // While it turns about a corner the wheel presses with the load less
    // the centripetal force, 600 kN − m v² / (r + h), at every step (no
    // step-to-step alternation about it).
    let corner_force = 600e3 - MASS * speed * speed / REACH;
    let on_corner: Vec<f64> = (0..run.x.len())
        .filter(|&k| run.x[k] > SPAN + 0.005 && run.x[k] < SPAN + GAP - 0.005)
        .map(|k| run.normal[k])
        .collect();
    assert!(on_corner.len() > 10);
    for force in &on_corner {
        assert!(
            (force / corner_force - 1.0).abs() < 0.01,
            "normal force on the corner {force} N vs {corner_force} N"
        );
    }
    // Before the joint and on the next span the wheel presses with the
    // whole load, within the ±1 % the beam's vibration adds, and the force
    // does not alternate from step to step (undamped HHT-α without its
    // restart at the switches: ±82 kN about 600 kN on the next span).
    let rolls = |x: f64| {
        (x > SPAN - 0.3 && x < SPAN - 0.01) || (x > SPAN + GAP + 0.01 && x < SPAN + GAP + 0.3)
    };
    let rolling: Vec<usize> = (1..run.x.len())
        .filter(|&k| rolls(run.x[k]) && rolls(run.x[k - 1]))
        .collect();
    assert!(rolling.len() > 100);
    for &k in &rolling {
        let (force, jump) = (run.normal[k], run.normal[k] - run.normal[k - 1]);
        assert!(
            (force / 600e3 - 1.0).abs() < 0.02 && jump.abs() < 0.01 * 600e3,
            "normal force next to the joint {force} N (changed by {jump} N in a step)"
        );
    }
}

#[test]
fn wheel_crosses_a_5_cm_joint_with_rk4() {
    let run = cross(&two_spans(GAP, 8, 2.5e-4, IntegratorKind::Rk4));
    check_5_cm_crossing(&run);
}

#[test]
fn wheel_crosses_a_5_cm_joint_with_undamped_hht() {
    // α = 0: the trapezoidal rule, which damps nothing, the hardest case
    // for the force jumps at the corners.
    let mut scene = two_spans(GAP, 8, 2.5e-4, IntegratorKind::Hht);
    scene.solver.numerical_damping = 0.0;
    check_5_cm_crossing(&cross(&scene));
}

#[test]
fn wheel_crosses_a_5_cm_joint_with_auto_choosing_hht() {
    // 32 elements per span: the paper's step is beyond RK4's limit, auto
    // takes HHT-α with its least damping.
    let scene = two_spans(GAP, 32, 2.5e-4, IntegratorKind::Auto);
    let sim = Simulation::new(&scene).unwrap();
    assert!(
        sim.integrator_choice().starts_with("hht"),
        "{}",
        sim.integrator_choice()
    );
    check_5_cm_crossing(&cross(&scene));
}

#[test]
fn hht_and_rk4_cross_alike() {
    // The same crossing on the same mesh and step: the exit speeds agree
    // to the schemes' error, far below the impact's loss of speed.
    let rk4 = cross(&two_spans(GAP, 8, 1.25e-4, IntegratorKind::Rk4));
    let hht = cross(&two_spans(GAP, 8, 1.25e-4, IntegratorKind::Hht));
    let difference = (rk4.exit_speed - hht.exit_speed).abs();
    println!(
        "exit speeds {} (RK4), {} (HHT-α)",
        rk4.exit_speed, hht.exit_speed
    );
    assert!(difference < 0.05 * (10.0 - rk4.exit_speed), "{difference}");
}

#[test]
fn wheel_crosses_a_joint_without_gap_with_no_impact_loss_beyond_the_kink() {
    // Two separate spans end to end: one corner, the normal turns
    // continuously while the wheel turns about it.
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Hht] {
        let run = cross(&two_spans(0.0, 8, 2.5e-4, integrator));
        assert!(run.exited);
        let drift = drift(&run);
        println!("{integrator:?}: drift {drift:e}, impacts {:?}", run.impacts);
        assert!(drift < 1e-5, "drift {drift}");
        // The kink is concave here (the first span bulges up towards its
        // end): the impact onto the second span is small but present.
        assert!(!run.impacts.is_empty());
        assert!(run.impacts.iter().all(|i| i.impulse.norm() < 100.0));
    }
}

#[test]
fn a_wheel_moving_left_over_joints_is_refused_before_the_run() {
    // Joints are crossed moving right only: the mirrored scene (from the
    // right end at −10 m/s) is refused up front, naming the field and the
    // way out.
    let mut scene = two_spans(GAP, 8, 2.5e-4, IntegratorKind::Rk4);
    scene.vehicles[0].initial_position = 2.0 * SPAN;
    scene.vehicles[0].initial_speed = -10.0;
    let message = scene.validate().unwrap_err().to_string();
    println!("{message}");
    assert!(message.contains("body.initial_speed = -10"), "{message}");
    assert!(message.contains("mirror the scene"), "{message}");
    // Without joints (a continuous support) the same start is valid.
    scene.beam.joints[0].kind = JointKind::Continuous;
    scene.beam.joints[0].gap = 0.0;
    scene.validate().expect("leftwards without joints");
}

/// Over the joint the centre keeps r + h from the corner it turns about,
/// and the corners are the beam ends raised by the profile `r` (the ends
/// are pinned: w = 0 there). Returns the largest error (m) over the
/// samples on the two corners.
fn corner_distance_error(run: &Crossing, r: impl Fn(f64) -> f64) -> f64 {
    let mut worst = 0.0f64;
    let mut samples = 0;
    for k in 0..run.x.len() {
        let x = run.x[k];
        let corner = if x > SPAN + 0.001 && x < SPAN + GAP / 2.0 - 0.001 {
            SPAN
        } else if x > SPAN + GAP / 2.0 + 0.001 && x < SPAN + GAP - 0.001 {
            SPAN + GAP
        } else {
            continue;
        };
        let distance = (x - corner).hypot(run.y[k] - r(corner));
        worst = worst.max((distance - REACH).abs());
        samples += 1;
    }
    assert!(samples > 10, "{samples} samples on the corners");
    worst
}

#[test]
fn the_joints_corners_follow_the_irregularity() {
    // A track raised 2 mm everywhere (a constant table): the crossing is
    // the flat one raised by 2 mm.
    let flat = cross(&two_spans(GAP, 8, 2.5e-4, IntegratorKind::Rk4));
    let mut scene = two_spans(GAP, 8, 2.5e-4, IntegratorKind::Rk4);
    scene.track.irregularities = vec![IrregularitySpec::Table {
        file: None,
        points: vec![[0.0, 0.002], [2.0 * SPAN + GAP, 0.002]],
    }];
    scene
        .validate()
        .expect("irregularities with joints are valid");
    let raised = cross(&scene);
    check_5_cm_crossing(&raised);
    let (a, b) = (flat.impacts[0].impulse.y, raised.impacts[0].impulse.y);
    assert!((a / b - 1.0).abs() < 1e-6, "impulse {a} flat, {b} raised");
    let error = corner_distance_error(&raised, |_| 0.002);
    assert!(error < 2e-5, "centre to corner off r + h by {error} m");
    let k = raised.x.len() / 2;
    assert!((raised.y[k] - flat.y[k] - 0.002).abs() < 1e-6);
}

#[test]
fn a_wheel_crosses_a_joint_on_a_sine_profile_with_either_integrator() {
    // 1 mm, 4 m sine: at the joint the corners are 0.02 mm apart in height
    // and the surface slopes by 1.4 mrad.
    let (amplitude, wavelength, phase) = (0.001, 4.0, 0.7);
    let r = |x: f64| amplitude * libm::sin(2.0 * std::f64::consts::PI * x / wavelength + phase);
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Hht] {
        let mut scene = two_spans(GAP, 8, 2.5e-4, integrator);
        // From the approach, so that the wheel starts on the profile.
        scene.track.approach = 10.0;
        scene.vehicles[0].initial_position = -5.0;
        scene.track.irregularities = vec![IrregularitySpec::Sine {
            amplitude,
            wavelength,
            phase,
        }];
        let run = cross(&scene);
        assert!(run.exited, "{integrator:?}: the crossing did not complete");
        let drift = drift(&run);
        let error = corner_distance_error(&run, r);
        println!(
            "{integrator:?}: drift {drift:e}, corner distance error {error:e} m, impacts {:?}",
            run.impacts
        );
        assert!(drift < 1e-5, "{integrator:?}: drift {drift}");
        // One impact, at the far corner: the switches onto the corners and
        // onto the next span follow the sloped surface continuously.
        let (first, rest) = (run.impacts[0].impulse.norm(), &run.impacts[1..]);
        assert!(
            rest.iter().all(|i| i.impulse.norm() < 1e-3 * first),
            "{:?}",
            run.impacts
        );
        // The gap tolerance (1e-5 m) bounds the distance's error; the
        // profile moves the corners by up to 1 mm.
        assert!(
            error < 2e-5,
            "{integrator:?}: centre to corner off by {error} m"
        );
    }
}

/// Mesh and step convergence of the crossing (README's table).
#[test]
#[ignore = "a table for README: cargo test --release --test structures rail_gap:: -- --ignored --nocapture"]
fn convergence_table() {
    println!("| integrator | elements per span | step (s) | normal impulse (N s) | impact loss (J) | balance drift | exit speed (m/s) |");
    println!("|---|---|---|---|---|---|---|");
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Hht] {
        for (elements, step) in [
            (8, 2.5e-4),
            (8, 1.25e-4),
            (8, 6.25e-5),
            (16, 1.25e-4),
            (32, 3e-5),
        ] {
            let run = cross(&two_spans(GAP, elements, step, integrator));
            assert!(run.exited);
            println!(
                "| {integrator:?} | {elements} | {step:e} | {:.3} | {:.3} | {:.2e} | {:.6} |",
                run.impacts[0].impulse.y,
                run.impact_loss,
                drift(&run),
                run.exit_speed
            );
        }
    }
}
