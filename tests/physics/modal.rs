//! Modal reduction (`solver.structure = "modal"`, issue 14 item 4): the
//! beam in its lowest k modes reproduces the full model when every mode
//! is kept, converges to it as k grows, and keeps the energy balance.

use crate::common;
use common::{paper_scene, run_to_exit, RunFigures};
use guideway::scene::{BodyKind, DampingSpec, IntegratorKind, JointKind, JointSpec, StructureKind};
use guideway::{Scene, Simulation};

fn modal(mut scene: Scene, modes: usize) -> Scene {
    scene.solver.structure = StructureKind::Modal;
    scene.solver.modes = Some(modes);
    scene
}

/// Relative difference, against the larger magnitude.
fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

fn assert_same_run(full: &RunFigures, reduced: &RunFigures, tolerance: f64) {
    assert_eq!(full.steps, reduced.steps);
    for (name, (a, b)) in full
        .names
        .iter()
        .zip(full.final_values.iter().zip(&reduced.final_values))
    {
        let scale = full
            .final_values
            .iter()
            .zip(&full.names)
            .filter(|(_, n)| n.split('.').next() == name.split('.').next())
            .fold(a.abs(), |m, (v, _)| m.max(v.abs()));
        assert!(
            (a - b).abs() <= tolerance * scale.max(1e-12),
            "{name}: full {a:e}, modal {b:e}"
        );
    }
    assert!(relative(full.exit_nominal_speed, reduced.exit_nominal_speed) < tolerance);
    assert!(
        relative(
            full.peak_midspan_deflection,
            reduced.peak_midspan_deflection
        ) < tolerance
    );
    assert!(relative(full.exit_time, reduced.exit_time) < tolerance);
}

#[test]
fn every_mode_kept_reproduces_the_papers_10_m_s_case() {
    // 2 elements, 4 free DOFs, the paper's step and RK4.
    let scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    let full = run_to_exit(&scene);
    let reduced = run_to_exit(&modal(scene, 4));
    assert_same_run(&full, &reduced, 1e-10);
}

#[test]
fn every_mode_kept_reproduces_hht_on_a_damped_mesh() {
    // HHT-α's effective matrix projected onto all 32 modes of 16 elements,
    // Rayleigh damping included.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 16;
    scene.beam.damping = Some(DampingSpec::Modes {
        ratio: 0.02,
        modes: [1, 3],
    });
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = 0.1;
    let full = run_to_exit(&scene);
    let reduced = run_to_exit(&modal(scene, 32));
    assert_same_run(&full, &reduced, 1e-9);
}

/// The paper's 10 m/s case on 8 elements (16 DOFs) with RK4 at 0.5 ms,
/// inside the full model's stability limit.
fn eight_elements() -> Scene {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0005);
    scene.beam.elements = 8;
    scene
}

#[test]
fn sensor_deflection_and_exit_speed_converge_as_modes_are_added() {
    let full = run_to_exit(&eight_elements());
    println!("modes | midspan peak error (m) | exit speed error (m/s) | energy drift");
    let mut errors = Vec::new();
    for k in [1, 2, 3, 4, 6, 8, 12, 16] {
        let run = run_to_exit(&modal(eight_elements(), k));
        let deflection = (run.peak_midspan_deflection - full.peak_midspan_deflection).abs();
        let speed = (run.exit_nominal_speed - full.exit_nominal_speed).abs();
        println!(
            "{k:5} | {deflection:22.3e} | {speed:22.3e} | {:.3e}",
            run.max_energy_drift
        );
        // The energy balance holds on the reduced structure too (the full
        // model's drift at this step is 1.3e-6).
        assert!(
            run.max_energy_drift < 2e-6,
            "{k} modes: {:e}",
            run.max_energy_drift
        );
        errors.push((k, deflection, speed));
    }
    let at = |k: usize| *errors.iter().find(|e| e.0 == k).expect("k in the table");
    // Symmetric modes carry the midspan deflection: each pair of modes
    // that adds one cuts the error.
    for pair in [1, 3, 6, 12].windows(2) {
        let (coarse, fine) = (at(pair[0]), at(pair[1]));
        assert!(fine.1 < 0.5 * coarse.1, "{coarse:?} → {fine:?}");
    }
    for pair in [1, 2, 3, 6].windows(2) {
        let (coarse, fine) = (at(pair[0]), at(pair[1]));
        assert!(fine.2 < coarse.2, "{coarse:?} → {fine:?}");
    }
    assert!(at(12).1 < 1e-5 * full.peak_midspan_deflection.abs());
    assert!(at(8).2 < 2e-3);
    // All 16 modes: the full model to round-off.
    assert!(at(16).1 < 1e-12 && at(16).2 < 1e-11, "{:?}", at(16));
}

#[test]
fn a_frequency_cut_off_keeps_the_modes_below_it() {
    // The 8-element beam's modes: 2.44, 9.8, 22, 39, 61, 88 Hz, ...
    let mut by_frequency = eight_elements();
    by_frequency.solver.structure = StructureKind::Modal;
    by_frequency.solver.max_frequency = Some(50.0);
    let sim = Simulation::new(&by_frequency).expect("builds");
    let basis = sim.system().beam.modal().expect("modal");
    assert_eq!(basis.modes(), 4);
    assert!(basis.omega()[3] / std::f64::consts::TAU < 50.0);
    let a = run_to_exit(&by_frequency);
    let b = run_to_exit(&modal(eight_elements(), 4));
    assert_eq!(a.final_values, b.final_values);
}

#[test]
fn a_long_mesh_is_reduced_without_a_dense_eigenproblem() {
    // 1000 elements (1998 free DOFs, beyond the dense limit): 12 modes by
    // subspace iteration; the run at the paper's step stays on RK4.
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 1000;
    scene.solver.integrator = IntegratorKind::Auto;
    let reduced = run_to_exit(&modal(scene.clone(), 12));
    let mut coarse = scene;
    coarse.beam.elements = 32;
    let dense = run_to_exit(&modal(coarse, 12));
    // The lowest 12 modes of 32 and 1000 elements differ by the mesh's
    // discretisation error only (≈ 1e-6 for mode 12 on 32 elements).
    assert!(
        relative(
            reduced.peak_midspan_deflection,
            dense.peak_midspan_deflection
        ) < 1e-4,
        "{} vs {}",
        reduced.peak_midspan_deflection,
        dense.peak_midspan_deflection
    );
    assert!((reduced.exit_nominal_speed - dense.exit_nominal_speed).abs() < 1e-4);
    assert!(
        reduced.max_energy_drift < 1e-4,
        "{}",
        reduced.max_energy_drift
    );
}

#[test]
fn the_modal_fields_are_validated_by_name() {
    let problem = |edit: fn(&mut Scene)| {
        let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
        edit(&mut scene);
        scene.validate().expect_err("invalid").to_string()
    };
    let text = problem(|s| s.solver.modes = Some(3));
    assert!(
        text.contains("solver.modes") && text.contains("structure = \"modal\""),
        "{text}"
    );
    let text = problem(|s| s.solver.structure = StructureKind::Modal);
    assert!(
        text.contains("solver.structure") && text.contains("needs solver.modes"),
        "{text}"
    );
    let text = problem(|s| {
        s.solver.structure = StructureKind::Modal;
        s.solver.modes = Some(0);
    });
    assert!(
        text.contains("solver.modes") && text.contains("between 1 and"),
        "{text}"
    );
    let text = problem(|s| {
        s.solver.structure = StructureKind::Modal;
        s.solver.modes = Some(2);
        s.solver.max_frequency = Some(10.0);
    });
    assert!(
        text.contains("solver.max_frequency") && text.contains("choose one"),
        "{text}"
    );
    let text = problem(|s| {
        s.solver.structure = StructureKind::Modal;
        s.solver.max_frequency = Some(f64::NAN);
    });
    assert!(
        text.contains("solver.max_frequency") && text.contains("finite"),
        "{text}"
    );
    let text = problem(|s| {
        *s = modal(s.clone(), 2);
        s.beam.length = 48.0;
        s.beam.elements = 4;
        s.beam.supports.intermediate = vec![24.0];
        s.beam.joints = vec![JointSpec {
            at: 24.0,
            kind: JointKind::Hinge,
            gap: 0.0,
        }];
    });
    assert!(
        text.contains("solver.structure") && text.contains("rail joints"),
        "{text}"
    );
    let text = problem(|s| {
        *s = modal(s.clone(), 2);
        s.vehicles[0].kind = BodyKind::MovingForce;
    });
    assert!(
        text.contains("solver.structure") && text.contains("moving_force"),
        "{text}"
    );
    // What only the mesh can tell is refused when the simulation is built.
    let scene = modal(paper_scene(BodyKind::Wheel, 10.0, 0.0025), 5);
    let error = Simulation::new(&scene).err().expect("refused");
    assert!(
        error.contains("solver.modes = 5") && error.contains("4 free DOFs"),
        "{error}"
    );
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 0.0025);
    scene.solver.structure = StructureKind::Modal;
    scene.solver.max_frequency = Some(1.0);
    let error = Simulation::new(&scene).err().expect("refused");
    assert!(
        error.contains("solver.max_frequency = 1.0") && error.contains("keeps no mode"),
        "{error}"
    );
    // The subspace iteration's memory is bounded up front.
    let mut scene = modal(paper_scene(BodyKind::Wheel, 10.0, 0.0025), 500);
    scene.beam.elements = 20_000;
    let error = Simulation::new(&scene).err().expect("refused");
    assert!(
        error.contains("solver.modes: 500 modes") && error.contains("at most"),
        "{error}"
    );
    // Beyond 4096 shortest elements per length the band stiffness cannot
    // fix the low modes (mode 1 of 8192 elements came out 0.17 % high).
    let mut scene = modal(paper_scene(BodyKind::Wheel, 10.0, 0.0025), 8);
    scene.beam.elements = 8192;
    let error = Simulation::new(&scene).err().expect("refused");
    assert!(
        error.contains("solver.modes: ") && error.contains("beyond 4096"),
        "{error}"
    );
}

#[test]
fn the_work_precision_study_measures_the_modal_structure() {
    use guideway::study::work_precision::{cases, measure_modal, reference};
    let case = cases(true)
        .into_iter()
        .find(|c| c.scene.beam.elements == 32)
        .expect("the 32-element case");
    let reference = reference(&case).expect("reference runs");
    let points = measure_modal(&case, &reference, 1, |_| {});
    let finest = |scheme: &str| {
        points
            .iter()
            .filter(|p| p.scheme == scheme)
            .min_by(|a, b| a.step.total_cmp(&b.step))
            .unwrap_or_else(|| panic!("{scheme} measured"))
    };
    for scheme in ["modal-2", "modal-4", "modal-8", "modal-16"] {
        assert!(points
            .iter()
            .filter(|p| p.scheme == scheme)
            .all(|p| p.failure.is_none()));
    }
    // At the finest step the truncation error remains: it falls with k.
    let errors: Vec<f64> = ["modal-2", "modal-4", "modal-8", "modal-16"]
        .iter()
        .map(|s| finest(s).rms_deflection_error)
        .collect();
    for pair in errors.windows(2) {
        assert!(pair[1] < 0.5 * pair[0], "{errors:?}");
    }
}

#[test]
fn every_mode_kept_reproduces_support_springs_and_dampers() {
    // Elastic supports with dampers couple the modes (Φᵀ D Φ): RK4's
    // accelerations and HHT-α's k×k effective factor carry the coupling.
    // The tolerance of the contact iteration is tightened so that both
    // runs take the same iterations; the stiff springs (ω_max² / ω₁² about
    // 1e5) leave the accelerations equal to a few 1e-9 of the sensors'
    // largest output, hence 1e-8 here against 1e-9 without springs.
    let mut scene = eight_elements();
    scene.beam.supports.left = guideway::scene::EndSupport::Free;
    scene.beam.supports.springs = vec![
        guideway::scene::SpringSpec {
            at: 0.0,
            vertical: 5e8,
            vertical_damping: 2e6,
            ..Default::default()
        },
        guideway::scene::SpringSpec {
            at: 15.0,
            vertical: 1e8,
            rotational: 1e9,
            vertical_damping: 1e6,
            rotational_damping: 1e5,
        },
    ];
    scene.solver.step = 0.0003;
    scene.solver.velocity_tolerance = 1e-11;
    let full = run_to_exit(&scene);
    let free_dofs = Simulation::new(&scene)
        .expect("builds")
        .system()
        .beam
        .free_dofs();
    let reduced = run_to_exit(&modal(scene.clone(), free_dofs));
    assert_same_run(&full, &reduced, 1e-8);
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.step = 0.0025;
    let full = run_to_exit(&scene);
    let reduced = run_to_exit(&modal(scene, free_dofs));
    assert_same_run(&full, &reduced, 1e-8);
}

#[test]
fn the_state_is_the_modal_coordinates_and_fields_are_reconstructed_from_them() {
    // 1024 elements, 8 modes: the beam's state has 8 entries, and every
    // nodal field read from it (sensors, the nodes output, sections) is
    // Φ q evaluated by the element's shape functions.
    let mut scene = modal(paper_scene(BodyKind::Wheel, 10.0, 0.0025), 8);
    scene.beam.elements = 1024;
    scene.solver.end_time = Some(1.2);
    let mut sim = Simulation::new(&scene).expect("builds");
    sim.advance_to(1.2).expect("runs");
    let beam = &sim.system().beam;
    let state = sim.state();
    let q = &state.dynamic.beam_displacement;
    assert_eq!((beam.coordinates(), q.len()), (8, 8));
    assert_eq!(state.dynamic.beam_velocity.len(), 8);
    let nodal = beam.modal().expect("modal").shapes() * q;
    assert_eq!(nodal.len(), beam.free_dofs());
    for x in [0.3, 7.77, 12.0, 23.9] {
        let shape = beam.shape(beam.element_at(x), x);
        let expected = shape.dot(&shape.n, &nodal);
        let read = beam.deflection(q, x);
        assert!(
            (read - expected).abs() <= 1e-12 * expected.abs().max(1e-9),
            "x = {x}: {read} vs {expected}"
        );
        assert!(expected.abs() > 1e-4, "the beam is deflected at {x}");
    }
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    let midspan = names
        .iter()
        .position(|n| n == "sensor.midspan.deflection")
        .expect("sensor");
    let shape = beam.shape(beam.element_at(12.0), 12.0);
    assert!((values[midspan] - shape.dot(&shape.n, &nodal)).abs() < 1e-12);
    // The energies are those of the k modes: ½ q̇ᵀq̇ + ½ qᵀΩ²q.
    let v = &state.dynamic.beam_velocity;
    let omega = beam.modal().expect("modal").omega();
    let modal_energy: f64 = (0..8)
        .map(|j| 0.5 * v[j] * v[j] + 0.5 * (omega[j] * q[j]).powi(2))
        .sum();
    let beam_energy = beam.kinetic_energy(v) + beam.strain_energy(q);
    assert!((beam_energy - modal_energy).abs() <= 1e-12 * modal_energy);
}
