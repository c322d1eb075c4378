//! Elastic supports and tracks of several beams (issue 11 item 2): static
//! deflections and frequencies against closed forms, and the energy
//! balance with support dampers.

use crate::common;
use common::{paper_scene, run_to_exit};
use guideway::beam::Beam;
use guideway::scene::{
    BeamSpec, BodyKind, EndSupport, IntegratorKind, JointKind, JointSpec, SpringSpec, StartKind,
};
use nalgebra::DVector;

const EI: f64 = 1e9;
const MU: f64 = 1250.0;
const P: f64 = 600e3;

fn beam(length: f64, elements: usize) -> BeamSpec {
    let mut spec = paper_scene(BodyKind::Wheel, 10.0, 1e-3).beam;
    spec.length = length;
    spec.elements = elements;
    spec
}

/// Static deflections at `measure` under a downward point load P at `load`.
fn static_deflections(spec: &BeamSpec, load: f64, measure: &[f64]) -> Vec<f64> {
    let beam = Beam::new(spec).expect("beam builds");
    let mut f = DVector::zeros(beam.free_dofs());
    let shape = beam.shape(beam.element_at(load), load);
    shape.scatter(&shape.n, -P, &mut f);
    let u = beam.static_deflection(&f).expect("static deflection");
    measure.iter().map(|&x| beam.deflection(&u, x)).collect()
}

fn assert_close(found: f64, expected: f64, tolerance: f64, what: &str) {
    println!("{what}: {found:.9e} vs closed form {expected:.9e}");
    assert!(
        (found / expected - 1.0).abs() <= tolerance,
        "{what}: {found} vs closed form {expected}"
    );
}

fn spring(at: f64) -> SpringSpec {
    SpringSpec {
        at,
        ..SpringSpec::default()
    }
}

#[test]
fn beam_on_vertical_end_springs_deflects_as_the_closed_form() {
    // Free ends on springs k: each spring carries P/2, so midspan goes
    // down by P L³/48EI + P/2k.
    let (length, k) = (24.0, 2e8);
    let mut spec = beam(length, 8);
    spec.supports.left = EndSupport::Free;
    spec.supports.right = EndSupport::Free;
    spec.supports.springs = vec![
        SpringSpec {
            vertical: k,
            ..spring(0.0)
        },
        SpringSpec {
            vertical: k,
            ..spring(length)
        },
    ];
    let w = static_deflections(&spec, 12.0, &[12.0, 0.0]);
    let bending = P * length.powi(3) / (48.0 * EI);
    assert_close(
        w[0],
        -(bending + P / (2.0 * k)),
        1e-10,
        "midspan on end springs",
    );
    assert_close(w[1], -P / (2.0 * k), 1e-10, "end on its spring");
}

#[test]
fn beam_with_rotational_end_springs_deflects_as_the_closed_form() {
    // Pinned ends restrained by rotational springs k_r: the end moment
    // M = k_r θ with θ (1 + k_r L / 2EI) = P L² / 16EI, and midspan goes
    // down by P L³/48EI − M L²/8EI.
    let (length, kr) = (24.0, 5e8);
    let mut spec = beam(length, 6);
    spec.supports.springs = vec![
        SpringSpec {
            rotational: kr,
            ..spring(0.0)
        },
        SpringSpec {
            rotational: kr,
            ..spring(length)
        },
    ];
    let w = static_deflections(&spec, 12.0, &[12.0]);
    let theta = P * length.powi(2) / (16.0 * EI) / (1.0 + kr * length / (2.0 * EI));
    let moment = kr * theta;
    let expected = P * length.powi(3) / (48.0 * EI) - moment * length.powi(2) / (8.0 * EI);
    assert_close(w[0], -expected, 1e-10, "midspan with rotational springs");
}

#[test]
fn a_stiff_intermediate_spring_approaches_a_pinned_support() {
    let mut pinned = beam(24.0, 8);
    pinned.supports.intermediate = vec![12.0];
    let mut elastic = beam(24.0, 8);
    elastic.supports.springs = vec![SpringSpec {
        vertical: 1e15,
        ..spring(12.0)
    }];
    let a = static_deflections(&pinned, 6.0, &[6.0])[0];
    let b = static_deflections(&elastic, 6.0, &[6.0])[0];
    assert_close(b, a, 1e-5, "stiff spring vs pinned support");
}

#[test]
fn springs_where_a_support_holds_the_dof_are_refused() {
    let mut spec = beam(24.0, 4);
    spec.supports.springs = vec![SpringSpec {
        vertical: 1e8,
        ..spring(0.0)
    }];
    let error = Beam::new(&spec).err().expect("refused");
    assert!(error.contains("beam.supports.springs[0]"), "{error}");
    assert!(error.contains("deflection"), "{error}");
}

/// The paper's wheel at 10 m/s on a beam whose left end stands on a
/// spring and damper, the right end pinned with a rotational spring and
/// damper, and an elastic support with a damper at x = 16 m.
fn elastic_scene(damping: f64) -> guideway::Scene {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 1e-3);
    scene.beam.elements = 12;
    scene.beam.supports.left = EndSupport::Free;
    scene.beam.supports.springs = vec![
        SpringSpec {
            vertical: 5e8,
            vertical_damping: damping,
            ..spring(0.0)
        },
        SpringSpec {
            rotational: 1e9,
            rotational_damping: damping * 10.0,
            ..spring(24.0)
        },
        SpringSpec {
            vertical: 2e8,
            vertical_damping: damping,
            ..spring(16.0)
        },
    ];
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = 0.0;
    // Loaded suddenly at the soft end the wheel would bounce off.
    scene.solver.start = StartKind::Static;
    scene
}

#[test]
fn energy_balance_holds_with_support_dampers() {
    let undamped = run_to_exit(&elastic_scene(0.0));
    let damped = run_to_exit(&elastic_scene(2e7));
    let dissipated = damped.value("energy.beam_damping");
    let initial = damped.initial("energy.balance");
    println!(
        "support dampers dissipated {dissipated} J of {initial} J; drift {:e} (undamped {:e})",
        damped.max_energy_drift, undamped.max_energy_drift
    );
    assert!(
        dissipated > 2e-3 * initial,
        "dissipated {dissipated} J of {initial} J"
    );
    assert!(
        damped.max_energy_drift <= 1e-5,
        "drift {}",
        damped.max_energy_drift
    );
    // Left out of the balance, the dampers' share would show as a drift
    // of dissipated / initial (3e-3), a hundred times the bound.
    assert!(dissipated / initial > 100.0 * 1e-5);
}

fn two_spans(span: f64, kind: JointKind, gap: f64, elements: usize) -> BeamSpec {
    let mut spec = beam(2.0 * span + gap, elements);
    spec.joints = vec![JointSpec {
        at: span,
        kind,
        gap,
    }];
    spec
}

#[test]
fn continuous_two_span_beam_deflects_as_the_closed_form() {
    // Two equal spans L, load P at the middle of the first: 23 P L³ / 1536 EI
    // under the load (three-moment equation).
    let span = 12.0;
    let spec = two_spans(span, JointKind::Continuous, 0.0, 8);
    let w = static_deflections(&spec, span / 2.0, &[span / 2.0, span]);
    let expected = 23.0 * P * span.powi(3) / (1536.0 * EI);
    assert_close(w[0], -expected, 1e-10, "continuous beam under the load");
    assert_eq!(w[1], 0.0, "the joint's support holds");
    // The same as an intermediate support.
    let mut intermediate = beam(2.0 * span, 8);
    intermediate.supports.intermediate = vec![span];
    let v = static_deflections(&intermediate, span / 2.0, &[span / 2.0]);
    assert_eq!(w[0], v[0]);
}

#[test]
fn continuous_two_span_beam_has_the_closed_form_frequencies() {
    // Two equal spans: mode 1 is one span's simply supported mode
    // (λL = π), mode 2 the propped cantilever's (λL = 3.9266); ω = λ² √(EI/μ).
    let span = 12.0;
    let spec = two_spans(span, JointKind::Continuous, 0.0, 40);
    let omega = Beam::new(&spec).unwrap().modes(2).unwrap().omega;
    let exact = |lambda_l: f64| (lambda_l / span).powi(2) * (EI / MU).sqrt();
    // Consistent-mass Hermite elements bound each frequency from above
    // and converge as ℓ⁴: at 20 elements a span, mode 2 is 1e-6 high.
    let modes = [
        (omega[0], exact(std::f64::consts::PI)),
        (omega[1], exact(3.926_602_312_047_919)),
    ];
    for (i, (found, closed)) in modes.into_iter().enumerate() {
        assert!(found >= closed * (1.0 - 1e-12), "mode {}", i + 1);
        assert_close(found, closed, 1e-5, &format!("mode {}", i + 1));
    }
}

#[test]
fn separate_spans_do_not_load_each_other() {
    for gap in [0.0, 0.05] {
        let span = 12.0;
        let spec = two_spans(span, JointKind::Separate, gap, 8);
        let far = span + gap + span / 2.0;
        let w = static_deflections(&spec, span / 2.0, &[span / 2.0, far, span, span + gap]);
        let expected = P * span.powi(3) / (48.0 * EI);
        assert_close(w[0], -expected, 1e-10, "loaded span at midspan");
        assert_eq!(w[1], 0.0, "the other span stays unloaded (gap {gap})");
        assert_eq!(w[2], 0.0);
        assert_eq!(w[3], 0.0);
        // Its frequencies are one span's, each twice.
        let omega = Beam::new(&spec).unwrap().modes(2).unwrap().omega;
        assert!((omega[1] / omega[0] - 1.0).abs() < 1e-9, "{omega:?}");
    }
}

#[test]
fn hinge_shares_the_deflection_but_not_the_rotation() {
    // A cantilever of length a, clamped at x = 0, carries at its tip a hinge
    // and a suspended span b pinned at its far end. A load P on the hinge
    // goes to the cantilever alone: P a³ / 3EI.
    let (a, b) = (6.0, 10.0);
    let mut spec = beam(a + b, 8);
    spec.supports.left = EndSupport::Clamped;
    spec.joints = vec![JointSpec {
        at: a,
        kind: JointKind::Hinge,
        gap: 0.0,
    }];
    let w = static_deflections(&spec, a, &[a, a - 1e-9, a + 1e-9]);
    let expected = P * a.powi(3) / (3.0 * EI);
    assert_close(w[0], -expected, 1e-10, "hinge deflection");
    assert_close(w[1], w[2], 1e-6, "deflection continuous across the hinge");
    // The suspended span stays straight: its midpoint halfway down.
    let mid = static_deflections(&spec, a, &[a + b / 2.0])[0];
    assert_close(
        mid,
        -expected / 2.0,
        1e-10,
        "suspended span is a straight link",
    );
}

/// The problems `validate` reports for a scene, as (path, value, rule).
fn problems(scene: &guideway::Scene) -> Vec<(String, String, String)> {
    match scene.validate() {
        Ok(()) => vec![],
        Err(e) => e
            .problems()
            .into_iter()
            .map(|p| (p.path, p.value, p.rule))
            .collect(),
    }
}

#[test]
fn scenes_with_joints_and_springs_are_validated() {
    let mut scene = paper_scene(BodyKind::Wheel, 10.0, 1e-3);
    scene.beam.length = 48.05;
    scene.beam.elements = 8;
    scene.beam.joints = vec![JointSpec {
        at: 24.0,
        kind: JointKind::Separate,
        gap: 0.05,
    }];
    assert_eq!(problems(&scene), vec![]);
    // The TOML round trip keeps joints and springs.
    scene.beam.supports.springs = vec![SpringSpec {
        rotational: 1e9,
        ..spring(48.05)
    }];
    let text = scene.to_toml_string();
    assert_eq!(guideway::Scene::from_toml_str(&text).unwrap(), scene);

    let mut wide = scene.clone();
    wide.beam.joints[0].gap = 0.3;
    wide.beam.length = 48.3;
    wide.beam.supports.springs.clear();
    let found = problems(&wide);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "beam.joints[0].gap");
    assert!(found[0].2.contains("radius"), "{found:?}");

    let glider = guideway::Scene {
        vehicles: paper_scene(BodyKind::Glider, 10.0, 1e-3).vehicles,
        ..scene.clone()
    };
    let found = problems(&glider);
    assert!(
        found
            .iter()
            .any(|p| p.0 == "beam.joints[0].gap" && p.2.contains("only wheels")),
        "{found:?}"
    );

    let mut in_gap = scene.clone();
    in_gap.sensors[0].position = 24.02;
    in_gap.beam.supports.springs[0].at = 24.01;
    in_gap.beam.supports.springs[0].vertical = -1.0;
    let paths: Vec<String> = problems(&in_gap).into_iter().map(|p| p.0).collect();
    for path in [
        "sensors[0].position",
        "beam.supports.springs[0].at",
        "beam.supports.springs[0].vertical",
    ] {
        assert!(paths.iter().any(|p| p == path), "{path} not in {paths:?}");
    }

    let mut hinge_gap = scene.clone();
    hinge_gap.beam.joints[0].kind = JointKind::Hinge;
    let found = problems(&hinge_gap);
    assert!(
        found.iter().any(|p| p.0 == "beam.joints[0].gap"),
        "{found:?}"
    );
}
