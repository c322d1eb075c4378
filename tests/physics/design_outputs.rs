//! Design outputs (issue 11 item 5): the sensors' velocity and
//! acceleration, checked against the state they are read from.

use crate::common;
use common::paper_scene;
use guideway::beam::Beam;
use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::{Advance, Simulation};

/// Every output row of `scene` at each internal step up to the exit or
/// `end_time`, and the output names.
fn rows(scene: &Scene, end_time: f64) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut sim = Simulation::new(scene).expect("scene builds");
    rows_of(&mut sim, scene.solver.step, end_time)
}

fn rows_of(sim: &mut Simulation, step: f64, end_time: f64) -> (Vec<String>, Vec<Vec<f64>>) {
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    let mut rows = vec![values.clone()];
    let mut k = 1;
    while k as f64 * step <= end_time {
        let advance = sim.advance_to(k as f64 * step).expect("step converges");
        sim.output_values(&mut values);
        rows.push(values.clone());
        if matches!(advance, Advance::Exited { .. }) {
            break;
        }
        k += 1;
    }
    (names, rows)
}

fn column(names: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = names.iter().position(|n| n == name).expect(name);
    rows.iter().map(|r| r[k]).collect()
}

#[test]
fn free_vibration_in_mode_one_has_acceleration_minus_omega_squared_deflection() {
    // The paper's beam, 20 elements, undamped, started in mode 1's shape;
    // the wheel waits on a rigid approach. In a pure mode a = −ω² w at
    // every instant, whatever the integrator does to the amplitude.
    let mut scene = paper_scene(BodyKind::Wheel, 0.0, 1e-3);
    scene.beam.elements = 20;
    scene.track.approach = 5.0;
    scene.vehicles[0].initial_position = -3.0;
    scene.solver.integrator = IntegratorKind::Hht;
    let beam = Beam::new(&scene.beam).unwrap();
    let modes = beam.modes(1).unwrap();
    let omega = modes.omega[0];
    let shape = modes.shapes.column(0).into_owned()
        * (0.01 / beam.deflection(&modes.shapes.column(0).into_owned(), 12.0));
    let mut sim = Simulation::new(&scene).unwrap();
    let mut state = sim.state();
    state.dynamic.beam_displacement = shape.clone();
    state.dynamic.beam_acceleration = &shape * (-omega * omega);
    sim.restore(&state).unwrap();
    let (names, rows) = rows_of(&mut sim, 1e-3, 0.5);
    let w = column(&names, &rows, "sensor.midspan.deflection");
    let a = column(&names, &rows, "sensor.midspan.acceleration");
    let v = column(&names, &rows, "sensor.midspan.velocity");
    assert!(rows.len() > 400);
    let peak_v = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // A quarter period in, the velocity is near its amplitude ω · 1 cm.
    assert!(
        (peak_v / (omega * 0.01) - 1.0).abs() < 0.01,
        "peak velocity {peak_v}"
    );
    for (k, (w, a)) in w.iter().zip(&a).enumerate() {
        assert!(
            (a + omega * omega * w).abs() <= 1e-6 * omega * omega * 0.01,
            "row {k}: a = {a}, −ω² w = {}",
            -omega * omega * w
        );
    }
}

#[test]
fn velocity_and_acceleration_outputs_integrate_to_the_deflection() {
    // The paper's wheel at 10 m/s on 8 elements, HHT-α with α = 0 (the
    // trapezoidal rule): w_{n+1} − w_n = Δt (v_n + v_{n+1}) / 2 holds to
    // round-off, and v_{n+1} − v_n = Δt (a_n + a_{n+1}) / 2 to the
    // contact iteration's tolerance (the integrator's acceleration takes
    // the load at the predicted configuration, the output the converged one).
    let step = 1e-3;
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, step);
    scene.beam.elements = 8;
    scene.solver.integrator = IntegratorKind::Hht;
    let (names, rows) = rows(&scene, 10.0);
    let w = column(&names, &rows, "sensor.midspan.deflection");
    let v = column(&names, &rows, "sensor.midspan.velocity");
    let a = column(&names, &rows, "sensor.midspan.acceleration");
    let scale = |x: &[f64]| x.iter().fold(0.0f64, |m, y| m.max(y.abs()));
    let (peak_v, peak_a) = (scale(&v), scale(&a));
    assert!(peak_a > 1.0, "peak acceleration {peak_a}");
    // The last row is the exit, after a shortened step.
    let n = rows.len() - 1;
    let mut worst = [0.0f64; 2];
    for k in 0..n - 1 {
        let dw = (w[k + 1] - w[k]) / step - 0.5 * (v[k] + v[k + 1]);
        let dv = (v[k + 1] - v[k]) / step - 0.5 * (a[k] + a[k + 1]);
        worst[0] = worst[0].max(dw.abs() / peak_v);
        worst[1] = worst[1].max(dv.abs() / peak_a);
    }
    println!("peak |v| {peak_v} m/s, |a| {peak_a} m/s²; relative mismatches {worst:?}");
    assert!(worst[0] < 1e-9, "velocity vs deflection: {}", worst[0]);
    assert!(worst[1] < 1e-4, "acceleration vs velocity: {}", worst[1]);
}

/// The paper's 600 kN wheel parked at midspan of 8 elements, started in
/// static equilibrium, with sections and the reactions reported.
fn parked_wheel() -> Scene {
    let mut scene = paper_scene(BodyKind::Wheel, 0.0, 1e-3);
    scene.beam.elements = 8;
    scene.vehicles[0].initial_position = 12.0;
    scene.solver.start = guideway::scene::StartKind::Static;
    scene.solver.end_time = Some(0.01);
    scene.solver.integrator = IntegratorKind::Hht;
    for (name, position) in [
        ("quarter", 6.0),
        ("midspan", 12.0),
        ("left_of_load", 11.9),
        ("right_of_load", 12.1),
    ] {
        scene.sections.push(guideway::scene::SectionSpec {
            name: name.into(),
            position,
        });
    }
    scene.reactions = true;
    scene
}

#[test]
fn static_load_at_midspan_gives_pl_over_4_shear_and_reactions_p_over_2() {
    let (p, l) = (600e3, 24.0);
    let (names, rows) = rows(&parked_wheel(), 0.01);
    assert_eq!(rows.len(), 11);
    let expected = [
        ("section.midspan.moment", p * l / 4.0),
        ("section.quarter.moment", p * l / 8.0),
        ("section.left_of_load.shear", p / 2.0),
        ("section.right_of_load.shear", -p / 2.0),
        ("support.left.reaction", p / 2.0),
        ("support.right.reaction", p / 2.0),
    ];
    for (name, value) in expected {
        for (k, found) in column(&names, &rows, name).iter().enumerate() {
            assert!(
                (found - value).abs() <= 1e-6 * value.abs(),
                "{name} at row {k}: {found} vs {value}"
            );
        }
    }
    // Pinned ends: no moment outputs; the scene asked for no more.
    assert!(!names
        .iter()
        .any(|n| n.ends_with(".moment") && n.starts_with("support.")));
}

#[test]
fn scenes_without_sections_keep_their_columns() {
    let scene = paper_scene(BodyKind::Wheel, 10.0, 1e-3);
    let sim = Simulation::new(&scene).unwrap();
    let names: Vec<&str> = sim.outputs().iter().map(|o| o.name.as_str()).collect();
    assert!(!names
        .iter()
        .any(|n| n.starts_with("section.") || n.starts_with("support.")));
    assert!(names.contains(&"sensor.midspan.acceleration"));
}

/// The run summary of `scene`, run to its exit.
fn summary(scene: &Scene) -> guideway::report::RunSummary {
    let run = guideway::report::run_scene(scene, |_| {}).expect("run");
    run.summary(scene)
}

fn with_design_outputs(mut scene: Scene) -> Scene {
    scene.beam.elements = 8;
    scene.solver.integrator = IntegratorKind::Hht;
    scene.sections.push(guideway::scene::SectionSpec {
        name: "midspan".into(),
        position: 12.0,
    });
    scene.reactions = true;
    scene
}

#[test]
fn a_very_slow_crossing_has_dynamic_amplification_one() {
    // The paper's wheel at 0.5 m/s: speed parameter α = v / (2 f₁ L) =
    // 0.5 / (2 · 2.44 Hz · 24 m) = 0.0043. The dynamic part of a moving
    // load's response is of order α times the static one (Frýba 1972,
    // ch. 1), so the amplification is within 2α ≈ 1 % of 1.
    let scene = with_design_outputs(paper_scene(BodyKind::Wheel, 0.5, 2.5e-3));
    let summary = summary(&scene);
    assert!(summary.exit_time.is_some());
    let daf = &summary.dynamic_amplification;
    for name in [
        "sensor.midspan.deflection",
        "section.midspan.moment",
        "section.midspan.shear",
        "support.left.reaction",
        "support.right.reaction",
    ] {
        let value = daf[name];
        println!("{name}: DAF {value}");
        assert!((value - 1.0).abs() < 0.01, "{name}: DAF {value}");
    }
    // The peaks are the static ones, P L / 4 and P.
    let peak = &summary.peak_design;
    assert!((peak["section.midspan.moment"] / (600e3 * 24.0 / 4.0) - 1.0).abs() < 0.01);
    assert!((peak["support.left.reaction"] / 600e3 - 1.0).abs() < 0.01);
}

#[test]
fn the_papers_crossing_amplifies_the_midspan_deflection_by_1_093() {
    // The paper's figure (10 m/s): peak midspan deflection 1.093 × P L³ / 48 EI,
    // the largest static deflection of a load crossing the simply supported beam.
    let scene = paper_scene(BodyKind::Wheel, 10.0, 2.5e-3);
    let daf = summary(&scene).dynamic_amplification["sensor.midspan.deflection"];
    assert!((daf - 1.093).abs() < 2e-3, "DAF {daf}");
}

/// The summary takes the static envelope from the simulation (no second
/// assembly): it must be the one the scene assembles to, also where the
/// static start has moved the bodies (a train) and on a modal beam.
#[test]
fn the_simulations_static_envelope_is_the_scenes() {
    let train = guideway::scene::builtin("train-2-coaches-2x40-100").expect("built-in");
    let mut modal = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    modal.beam.elements = 32;
    modal.solver.structure = guideway::scene::StructureKind::Modal;
    modal.solver.modes = Some(8);
    for scene in [
        train,
        with_design_outputs(paper_scene(BodyKind::Wheel, 10.0, 0.0025)),
        modal,
    ] {
        let sim = Simulation::new(&scene).expect("scene builds");
        let own = guideway::design::envelope_of_run(&sim, &scene).expect("envelope");
        let assembled = guideway::design::static_envelope(&scene).expect("envelope");
        assert!(!own.peaks.is_empty(), "{}", scene.name);
        assert_eq!(own.peaks, assembled.peaks, "{}", scene.name);
        assert_eq!(own.positions, assembled.positions, "{}", scene.name);
    }
}
