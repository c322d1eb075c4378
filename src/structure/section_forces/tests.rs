//! Unit tests of the internal forces: section forces and reactions of
//! loaded beams against statics written by hand (P L / 4, lever rules).

use super::*;
use crate::structure::beam::{BeamSpec, EndSupport, SupportsSpec};

const L: f64 = 24.0;
const EI: f64 = 1e9;
const MU: f64 = 1250.0;
const P: f64 = 600e3;

fn beam(elements: usize, left: EndSupport, right: EndSupport) -> Beam {
    Beam::new(&BeamSpec {
        length: L,
        mass_per_length: MU,
        bending_stiffness: EI,
        surface_offset: 0.6,
        elements,
        supports: SupportsSpec {
            left,
            right,
            intermediate: Vec::new(),
            springs: Vec::new(),
        },
        ..BeamSpec::default()
    })
    .unwrap()
}

fn pinned(elements: usize) -> Beam {
    beam(elements, EndSupport::Pinned, EndSupport::Pinned)
}

/// P downward at `a` on `beam`, in static equilibrium.
fn static_load(beam: &Beam, a: f64) -> BeamDynamics<'static> {
    BeamDynamics::static_response(beam, vec![PointLoad::vertical(beam, a, -P)]).unwrap()
}

fn assert_close(found: f64, expected: f64, what: &str) {
    assert!(
        (found - expected).abs() <= 1e-9 * expected.abs().max(P),
        "{what}: {found} vs {expected}"
    );
}

#[test]
fn midspan_load_gives_pl_over_4_and_half_the_load_each_side() {
    // Midspan on a node (2, 4 elements) and inside an element (3, 5).
    for elements in [2, 3, 4, 5] {
        let beam = pinned(elements);
        let d = static_load(&beam, L / 2.0);
        let at = |x: f64| d.section_forces(&beam, x);
        assert_close(at(L / 2.0).moment, P * L / 4.0, "M(L/2)");
        assert_close(at(L / 4.0).moment, P * L / 8.0, "M(L/4)");
        assert_close(at(0.8 * L).moment, 0.2 * P * L / 2.0, "M(0.8 L)");
        for x in [0.1, L / 4.0, L / 2.0 - 1e-6] {
            assert_close(at(x).shear, P / 2.0, &format!("V({x})"));
        }
        for x in [L / 2.0 + 1e-6, 0.7 * L, L - 0.1] {
            assert_close(at(x).shear, -P / 2.0, &format!("V({x})"));
        }
        let supports = supports(&beam);
        assert_eq!(supports.len(), 2);
        for s in &supports {
            assert!(!s.has_moment);
            assert_close(d.reaction(&beam, s.node)[0], P / 2.0, &s.name);
        }
    }
}

#[test]
fn load_inside_an_element_gives_the_exact_moment_diagram() {
    // M(x) = P (L − a) x / L left of the load, P a (L − x) / L right of it,
    // exact on a coarse mesh with the load off the nodes.
    let beam = pinned(3);
    let a = 0.37 * L;
    let d = static_load(&beam, a);
    for k in 1..40 {
        let x = L * k as f64 / 40.0;
        let expected = if x < a {
            P * (L - a) * x / L
        } else {
            P * a * (L - x) / L
        };
        assert_close(
            d.section_forces(&beam, x).moment,
            expected,
            &format!("M({x})"),
        );
    }
    assert_close(d.reaction(&beam, 0)[0], P * (L - a) / L, "left");
    assert_close(d.reaction(&beam, 3)[0], P * a / L, "right");
}

#[test]
fn propped_cantilever_has_the_fixed_end_moment() {
    // Clamped left, pinned right, P at midspan: R_left = 11P/16, R_right =
    // 5P/16, the clamp's moment 3PL/16 counter-clockwise, M(0) = −3PL/16.
    let beam = beam(4, EndSupport::Clamped, EndSupport::Pinned);
    let d = static_load(&beam, L / 2.0);
    let supports = supports(&beam);
    assert!(supports[0].has_moment && !supports[1].has_moment);
    let left = d.reaction(&beam, 0);
    assert_close(left[0], 11.0 * P / 16.0, "R_left");
    assert_close(left[1], 3.0 * P * L / 16.0, "clamp moment");
    assert_close(d.reaction(&beam, 4)[0], 5.0 * P / 16.0, "R_right");
    assert_close(
        d.section_forces(&beam, 0.0).moment,
        -3.0 * P * L / 16.0,
        "M(0)",
    );
    assert_close(
        d.section_forces(&beam, L / 2.0).moment,
        5.0 * P * L / 32.0,
        "M(L/2)",
    );
}

#[test]
fn continuous_beam_reactions() {
    // Two equal spans, P at the middle of the first: R = 13P/32, 11P/16, −3P/32.
    let mut spec = BeamSpec {
        length: L,
        mass_per_length: MU,
        bending_stiffness: EI,
        surface_offset: 0.6,
        elements: 6,
        ..BeamSpec::default()
    };
    spec.supports.intermediate = vec![L / 2.0];
    let beam = Beam::new(&spec).unwrap();
    let d = static_load(&beam, L / 4.0);
    let supports = supports(&beam);
    let names: Vec<&str> = supports.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["left", "intermediate1", "right"]);
    let r: Vec<f64> = supports
        .iter()
        .map(|s| d.reaction(&beam, s.node)[0])
        .collect();
    assert_close(r[0], 13.0 * P / 32.0, "left");
    assert_close(r[1], 11.0 * P / 16.0, "middle");
    assert_close(r[2], -3.0 * P / 32.0, "right");
}

/// Mode 1 of a pinned beam of `elements` elements, scaled to 1 cm at midspan,
/// in free vibration (no loads): the state at its largest deflection.
fn mode_one(beam: &Beam) -> (f64, BeamDynamics<'static>) {
    let modes = beam.modes(1).unwrap();
    let shape = modes.shapes.column(0).into_owned();
    let u = &shape * (0.01 / beam.deflection(&shape, L / 2.0));
    let zero = DVector::zeros(beam.free_dofs());
    (
        modes.omega[0],
        BeamDynamics::new(beam, (u, zero), Vec::new(), None),
    )
}

#[test]
fn free_mode_one_acceleration_is_minus_omega_squared_deflection() {
    let beam = pinned(20);
    let (omega, d) = mode_one(&beam);
    for x in [1.3, 6.0, 12.0, 17.7] {
        let w = d.deflection_at(&beam, x);
        let a = d.acceleration_at(&beam, x);
        // To the dense eigensolver's accuracy (its shape is good to ~1e-9).
        assert!(
            (a + omega * omega * w).abs() <= 1e-7 * omega * omega * w.abs(),
            "x = {x}: a = {a}, −ω² w = {}",
            -omega * omega * w
        );
    }
}

#[test]
fn free_mode_one_moment_converges_to_ei_w_second_derivative() {
    // The exact mode is sin(πx/L): M = EI w'' = −EI (π/L)² w. The recovered
    // moment converges with the mesh; EI w'' of the cubic would not reach
    // these errors (it is piecewise linear in x).
    let expected = -EI * (std::f64::consts::PI / L).powi(2) * 0.01;
    let mut errors = Vec::new();
    for elements in [4, 8, 16] {
        let beam = pinned(elements);
        let (_, d) = mode_one(&beam);
        let m = d.section_forces(&beam, 0.43 * L).moment;
        let exact = expected * libm::sin(0.43 * std::f64::consts::PI);
        errors.push(((m - exact) / exact).abs());
        // Dynamic equilibrium: the reactions carry the inertia forces.
        let inertia: f64 = (0..400)
            .map(|k| {
                let x = L * (k as f64 + 0.5) / 400.0;
                MU * d.acceleration_at(&beam, x) * L / 400.0
            })
            .sum();
        let reactions = d.reaction(&beam, 0)[0] + d.reaction(&beam, elements)[0];
        assert!(
            (reactions - inertia).abs() <= 1e-4 * inertia.abs(),
            "{elements} elements: reactions {reactions} vs ∫ μ a {inertia}"
        );
    }
    println!("relative moment errors at 4, 8, 16 elements: {errors:?}");
    assert!(errors[2] < 1e-4, "{errors:?}");
    assert!(
        errors[1] < errors[0] / 8.0 && errors[2] < errors[1] / 8.0,
        "{errors:?}"
    );
}

#[test]
fn shear_and_moment_are_continuous_across_nodes_in_motion() {
    let beam = pinned(8);
    let (_, d) = mode_one(&beam);
    for node in 1..8 {
        let x = beam.node_x[node];
        let (left, right) = (
            d.section_forces(&beam, x - 1e-9),
            d.section_forces(&beam, x + 1e-9),
        );
        let scale = d.section_forces(&beam, L / 2.0).moment.abs();
        assert!(
            (left.moment - right.moment).abs() < 1e-7 * scale,
            "M at node {node}"
        );
        assert!(
            (left.shear - right.shear).abs() < 1e-7 * scale / L,
            "V at node {node}: {} vs {}",
            left.shear,
            right.shear
        );
    }
}
