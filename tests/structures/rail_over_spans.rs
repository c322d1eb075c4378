//! The rail over several spans (`[track.on_deck]` on a deck with
//! intermediate supports or joints): static loads against the two-span
//! beam written here by the three-moment equation, in the limit of a stiff
//! track layer over a continuous deck (rail and deck one beam of EI_d +
//! EI_r) and of a soft one over a continuous deck and over two simply
//! supported spans (the infinite rail on its layer, P β / 2k, plus the
//! deck under the rail-seat load that the layer spreads over the pier).

use guideway::scene::{BeamSpec, EndSupport, JointKind, JointSpec, SupportsSpec};
use guideway::structure::rail_on_deck::{RailOnDeck, StaticSolution};
use nalgebra::{Matrix3, Vector3};

/// Two spans of 20 m and 24 m, in elements of 0.5 m.
const SPANS: [f64; 2] = [20.0, 24.0];
const H: f64 = 0.5;
const DECK_EI: f64 = 3.8e10;
/// A UIC 60 rail and the ballasted preset's ground (docs/structures.md).
const RAIL_EI: f64 = 6.4e6;
const GROUND: f64 = 3.3e7;
const LOAD: f64 = 100e3;

/// How the two spans meet at the pier.
#[derive(Clone, Copy, Debug)]
enum Pier {
    /// One beam over an intermediate support.
    Continuous,
    /// Two simply supported beams meeting at the pier (a separate joint of
    /// gap 0).
    Separate,
}

fn deck(pier: Pier) -> BeamSpec {
    let (intermediate, joints) = match pier {
        Pier::Continuous => (vec![SPANS[0]], Vec::new()),
        Pier::Separate => (
            Vec::new(),
            vec![JointSpec {
                at: SPANS[0],
                kind: JointKind::Separate,
                gap: 0.0,
            }],
        ),
    };
    let length = SPANS[0] + SPANS[1];
    BeamSpec {
        length,
        mass_per_length: 12_000.0,
        bending_stiffness: DECK_EI,
        surface_offset: 0.0,
        elements: (length / H).round() as usize,
        supports: SupportsSpec {
            left: EndSupport::Pinned,
            right: EndSupport::Pinned,
            intermediate,
            springs: Vec::new(),
        },
        joints,
        ..BeamSpec::default()
    }
}

fn layout(track_stiffness: f64, approach: f64) -> RailOnDeck {
    RailOnDeck {
        deck_length: SPANS[0] + SPANS[1],
        deck_bending_stiffness: DECK_EI,
        rail_bending_stiffness: RAIL_EI,
        track_stiffness,
        ground_stiffness: GROUND,
        approach,
        run_off: approach,
        element_length: H,
        sleepers: None,
    }
}

/// The two-span beam of bending stiffness `ei` on three pinned supports,
/// its ends restrained by rotational springs `end_spring` (N m/rad), by
/// the three-moment equation: support moments (sagging positive) from
/// slope continuity over the pier and M = ∓K θ at the ends, deflections
/// of each span as a simply supported beam under its load and its end
/// moments.
struct TwoSpan {
    ei: f64,
    end_spring: f64,
}

/// Slopes (δ' at both ends, δ down positive) of a simply supported span
/// of length `l` under a downward `p` at `a` from its left end.
fn point_load_slopes(p: f64, a: f64, l: f64, ei: f64) -> [f64; 2] {
    let b = l - a;
    [
        p * b * (l * l - b * b) / (6.0 * l * ei),
        -p * a * (l * l - a * a) / (6.0 * l * ei),
    ]
}

/// Downward deflection at `x` of a simply supported span of length `l`
/// under a downward `p` at `a`.
fn point_load_deflection(p: f64, a: f64, l: f64, x: f64, ei: f64) -> f64 {
    if x > a {
        return point_load_deflection(p, l - a, l, l - x, ei);
    }
    let b = l - a;
    p * b * x * (l * l - b * b - x * x) / (6.0 * l * ei)
}

impl TwoSpan {
    /// The load of `p` at `xi` as (span, distance from its left end).
    fn in_span(xi: f64) -> (usize, f64) {
        if xi <= SPANS[0] {
            (0, xi)
        } else {
            (1, xi - SPANS[0])
        }
    }

    /// Support moments M0, M1, M2 (sagging positive) under `p` at `xi`.
    fn moments(&self, p: f64, xi: f64) -> [f64; 3] {
        let (ei, k) = (self.ei, self.end_spring);
        let [l1, l2] = SPANS;
        let (span, a) = Self::in_span(xi);
        let mut free = [[0.0; 2]; 2];
        free[span] = point_load_slopes(p, a, SPANS[span], ei);
        let matrix = Matrix3::new(
            1.0 + k * l1 / (3.0 * ei),
            k * l1 / (6.0 * ei),
            0.0,
            l1 / (6.0 * ei),
            (l1 + l2) / (3.0 * ei),
            l2 / (6.0 * ei),
            0.0,
            k * l2 / (6.0 * ei),
            1.0 + k * l2 / (3.0 * ei),
        );
        let rhs = Vector3::new(-k * free[0][0], free[0][1] - free[1][0], k * free[1][1]);
        let m = matrix.lu().solve(&rhs).expect("a regular system");
        [m[0], m[1], m[2]]
    }

    /// Downward deflection at `x` under `p` at `xi`.
    fn deflection(&self, p: f64, xi: f64, x: f64) -> f64 {
        let moments = self.moments(p, xi);
        let (span, local) = Self::in_span(x);
        let (load_span, a) = Self::in_span(xi);
        let (l, ei) = (SPANS[span], self.ei);
        let [left, right] = [moments[span], moments[span + 1]];
        let load = if span == load_span {
            point_load_deflection(p, a, l, local, ei)
        } else {
            0.0
        };
        load + left * local * (l - local) * (2.0 * l - local) / (6.0 * ei * l)
            + right * local * (l - local) * (l + local) / (6.0 * ei * l)
    }

    /// Upward reactions of the end supports under `p` at `xi`.
    fn end_reactions(&self, p: f64, xi: f64) -> [f64; 2] {
        let [m0, m1, m2] = self.moments(p, xi);
        let (span, a) = Self::in_span(xi);
        let [l1, l2] = SPANS;
        let (to_right, to_left) = if span == 0 {
            (p * (l1 - a), 0.0)
        } else {
            (0.0, p * a)
        };
        [(m1 - m0 + to_right) / l1, (m1 - m2 + to_left) / l2]
    }
}

fn at_node(solution: &StaticSolution, x: f64) -> usize {
    let at = solution.node_x.iter().position(|&n| (n - x).abs() < 1e-9);
    at.unwrap_or_else(|| panic!("no node at {x} m"))
}

fn assert_within(found: f64, expected: f64, tolerance: f64, what: &str) {
    let error = (found - expected).abs() / expected.abs();
    println!("{what}: {found:.6e} vs {expected:.6e} ({error:.2e})");
    assert!(
        error <= tolerance,
        "{what}: {found:e} vs {expected:e} (relative error {error:.2e} > {tolerance:e})"
    );
}

/// Loads in the first span, at the pier's side of the second and near
/// its far end; deflections read at the load, in the other span and at
/// the pier's neighbours.
const LOADS: [f64; 3] = [7.0, 26.0, 38.5];
const READ: [f64; 4] = [5.0, 10.0, 21.0, 32.0];

#[test]
fn through_a_stiff_layer_rail_and_deck_bend_as_one_two_span_beam() {
    // No approach: the rail ends with the deck, so the composite beam is
    // pinned at both ends without restraint.
    let composite = TwoSpan {
        ei: DECK_EI + RAIL_EI,
        end_spring: 0.0,
    };
    for pier in [Pier::Continuous] {
        for xi in LOADS {
            let solution = layout(1e13, 0.0)
                .static_solution_over(&deck(pier), xi, LOAD)
                .expect("solves");
            for x in READ.into_iter().chain([xi]) {
                let found = -solution.deck[at_node(&solution, x)];
                let what = format!("{pier:?}, load at {xi} m, deck at {x} m");
                assert_within(found, composite.deflection(LOAD, xi, x), 1e-4, &what);
            }
            let [left, right] = composite.end_reactions(LOAD, xi);
            let reactions = &solution.reactions;
            assert_eq!(reactions.len(), 3, "{reactions:?}");
            assert_within(reactions[0].1, left, 1e-4, "left bearing");
            assert_within(reactions[2].1, right, 1e-4, "right bearing");
            let pier_force = LOAD - left - right;
            assert_within(reactions[1].1, pier_force, 1e-4, "pier");
        }
    }
}

#[test]
fn a_stiff_layer_with_approaches_adds_the_rail_on_the_ground_at_the_ends() {
    // The rail runs on for 10 m on the ground at each end. Tied to the
    // held deck at the abutment, it is there a semi-infinite beam on a
    // Winkler foundation with w(0) = 0: w = B e^(−βx) sin βx, whose end
    // moment per rotation is 2 EI_r β with β = (k_g / 4EI_r)^(1/4).
    let beta = libm::pow(GROUND / (4.0 * RAIL_EI), 0.25);
    let restrained = TwoSpan {
        ei: DECK_EI + RAIL_EI,
        end_spring: 2.0 * RAIL_EI * beta,
    };
    for pier in [Pier::Continuous] {
        for xi in LOADS {
            let solution = layout(1e13, 10.0)
                .static_solution_over(&deck(pier), xi, LOAD)
                .expect("solves");
            for x in READ.into_iter().chain([xi]) {
                let found = -solution.deck[at_node(&solution, x)];
                let what = format!("{pier:?}, load at {xi} m, deck at {x} m");
                assert_within(found, restrained.deflection(LOAD, xi, x), 2e-4, &what);
            }
            let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
            assert_within(bearings + solution.ground_force, LOAD, 1e-9, "balance");
        }
    }
}

/// The rail-seat load per metre at distance `r` from a load `p` on an
/// infinite rail on a layer of modulus `k` over a rigid base: k w with w
/// = P β / 2k e^(−β|r|) (cos β|r| + sin β|r|).
fn seat_load(p: f64, beta: f64, r: f64) -> f64 {
    let r = (beta * r).abs();
    0.5 * p * beta * libm::exp(-r) * (libm::cos(r) + libm::sin(r))
}

#[test]
fn through_a_soft_layer_the_rail_bends_as_on_a_rigid_base_over_the_deck() {
    // A layer as soft as the ground: the rail sits on one Winkler modulus
    // k from the approach to the run-off and deflects by P β / 2k over
    // what the deck does under the seat load, which the layer spreads over
    // a few 1/β. The deck's part is the two-span beam's deflection
    // integrated against that load (Simpson, 2 mm steps); seat load that
    // falls off the deck goes to the ground. The two parts decouple to
    // O(EI_r w_d'''' / k), here far below 1e-3.
    let k = GROUND;
    let beta = libm::pow(k / (4.0 * RAIL_EI), 0.25);
    let continuous = TwoSpan {
        ei: DECK_EI,
        end_spring: 0.0,
    };
    // The deck's deflection at x under a unit load at s.
    let influence = |pier: Pier, s: f64, x: f64| match pier {
        Pier::Continuous => continuous.deflection(1.0, s, x),
        Pier::Separate => {
            let (span, a) = TwoSpan::in_span(s);
            let (other, local) = TwoSpan::in_span(x);
            let ss = point_load_deflection(1.0, a, SPANS[span], local, DECK_EI);
            if span == other {
                ss
            } else {
                0.0
            }
        }
    };
    let length = SPANS[0] + SPANS[1];
    let deck_under_seats = |pier: Pier, xi: f64, x: f64| {
        let (a, b) = ((xi - 12.0).max(0.0), (xi + 12.0).min(length));
        let n = ((b - a) / 0.002).round() as usize * 2;
        let step = (b - a) / n as f64;
        let f = |i: usize| {
            let s = a + i as f64 * step;
            seat_load(LOAD, beta, s - xi) * influence(pier, s, x)
        };
        let inner: f64 = (1..n)
            .map(|i| f(i) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        step / 3.0 * (f(0) + inner + f(n))
    };
    for (pier, xi) in [Pier::Continuous, Pier::Separate]
        .into_iter()
        .flat_map(|pier| LOADS.into_iter().chain([21.0]).map(move |xi| (pier, xi)))
    {
        let solution = layout(k, 10.0)
            .static_solution_over(&deck(pier), xi, LOAD)
            .expect("solves");
        let node = at_node(&solution, xi);
        let deck = deck_under_seats(pier, xi, xi);
        let what = format!("{pier:?}, load at {xi} m");
        assert_within(-solution.deck[node], deck, 3e-3, &format!("{what}: deck"));
        let rail = LOAD * beta / (2.0 * k) + deck;
        assert_within(-solution.rail[node], rail, 3e-3, &format!("{what}: rail"));
        if let Pier::Continuous = pier {
            let far = if xi < SPANS[0] { 32.0 } else { 10.0 };
            let found = -solution.deck[at_node(&solution, far)];
            let expected = deck_under_seats(pier, xi, far);
            assert_within(found, expected, 3e-3, &format!("{what}: other span"));
        }
    }
}

#[test]
fn over_a_gap_the_rail_rests_on_the_ground_and_the_loads_balance() {
    // Two simply supported spans 1 m apart (20 m and 23 m): the rail
    // crosses the gap on the ground. Bearings and ground carry the load.
    let mut spans = deck(Pier::Separate);
    spans.joints[0].gap = 1.0;
    spans.elements -= 2;
    for xi in [-3.0, 10.0, 20.5, 30.0] {
        let solution = layout(GROUND, 10.0)
            .static_solution_over(&spans, xi, LOAD)
            .expect("solves");
        assert_eq!(solution.reactions.len(), 4, "{:?}", solution.reactions);
        let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
        let what = format!("load at {xi} m: bearings + ground");
        assert_within(bearings + solution.ground_force, LOAD, 1e-9, &what);
        let gap = at_node(&solution, 20.5);
        assert_eq!(solution.deck[gap], 0.0, "no deck in the gap");
    }
}

/// A scene of the rail over the two-span deck: `supports` and `joints`
/// TOML for the pier, a 4 m approach and run-off on the ground, a layer
/// of `layer` (N/m²), a glider of 10 t from `start` at `speed`, HHT-α at
/// `step` with the deck damped at 5 % in modes 1 and 3 (a slow crossing
/// stays quasi-static); a sensor at 10 m and one at 32 m.
fn two_span_scene(pier: &str, layer: f64, (start, speed): (f64, f64), step: f64) -> String {
    let end = if speed > 0.0 {
        (46.0 - start) / speed
    } else {
        2.0 * step
    };
    format!(
        r#"
name = "rail-over-two-spans"
gravity = 9.81
[beam]
length = 44.0
mass_per_length = 12000.0
bending_stiffness = {DECK_EI:?}
surface_offset = 0.0
elements = {elements}
{pier}
[beam.damping]
ratio = 0.05
modes = [1, 3]
[track]
approach = 4.0
run_off = 4.0
[track.on_deck]
stiffness = {layer:?}
damping = 0.0
ground_stiffness = {GROUND:?}
rail_bending_stiffness = {RAIL_EI:?}
rail_mass_per_length = 60.0
[body]
name = "glider"
kind = "glider"
mass = 10000.0
initial_position = {start:?}
initial_speed = {speed:?}
[[sensors]]
name = "first"
position = 10.0
[[sensors]]
name = "second"
position = 32.0
[solver]
step = {step:?}
integrator = "hht"
numerical_damping = 0.05
start = "static"
end_time = {end:?}
"#,
        elements = if pier.contains("gap = 1.0") { 86 } else { 88 },
    )
}

/// The outputs `names` after every step of `scene` (TOML) up to its end.
fn run_scene(scene: &str, names: &[&str]) -> Vec<Vec<f64>> {
    let scene = guideway::Scene::from_toml_str(scene).expect("a valid scene");
    let mut sim = guideway::Simulation::new(&scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let index: Vec<usize> = names
        .iter()
        .map(|n| {
            let at = all.iter().position(|x| x == n);
            at.unwrap_or_else(|| panic!("no output {n} in {all:?}"))
        })
        .collect();
    let mut values = vec![0.0; all.len()];
    let mut rows = Vec::new();
    let dt = scene.solver.step;
    let steps = (scene.solver.end_time.expect("an end time") / dt).round() as u64;
    for k in 1..=steps {
        let advance = sim.advance_to(k as f64 * dt).expect("no solver error");
        assert_eq!(advance, guideway::Advance::Reached, "step {k}");
        sim.output_values(&mut values);
        rows.push(index.iter().map(|&i| values[i]).collect());
    }
    rows
}

const INTERMEDIATE: &str = "[beam.supports]\nintermediate = [20.0]";

#[test]
fn in_a_scene_a_slow_glider_over_two_continuous_spans_follows_their_influence_lines() {
    // Through a stiff layer the deck and the rail are one two-span beam
    // of EI_d + EI_r; the glider's weight at x deflects the sensors by
    // that beam's influence lines (Maxwell: the deflection at the sensor
    // under the load at x).
    let (speed, step) = (0.5, 0.02);
    let scene = two_span_scene(INTERMEDIATE, 1e11, (-3.0, speed), step);
    let names = [
        "glider.x",
        "sensor.first.deflection",
        "sensor.second.deflection",
    ];
    let rows = run_scene(&scene, &names);
    let composite = TwoSpan {
        ei: DECK_EI + RAIL_EI,
        end_spring: 0.0,
    };
    let weight = 10_000.0 * 9.81;
    let peak = composite.deflection(weight, 10.0, 10.0);
    let mut worst = 0.0f64;
    for row in rows.iter().filter(|r| r[0] > 2.0 && r[0] < 42.0) {
        for (k, sensor) in [10.0, 32.0].into_iter().enumerate() {
            let expected = -composite.deflection(weight, row[0], sensor);
            worst = worst.max((row[1 + k] - expected).abs() / peak);
        }
    }
    println!("largest departure from the influence lines: {worst:.3e} of the peak");
    assert!(worst < 5e-3, "{worst:e} of the peak");
}

#[test]
fn in_a_scene_a_glider_crosses_a_gap_between_two_spans_on_the_rail() {
    // Two simply supported spans 1 m apart under a ballasted track: the
    // glider (which the bare deck refuses at a gap) crosses it on the
    // rail, which rests there on the ground. Slow, the contact carries
    // the weight throughout: no impact where the rail leaves a span.
    let pier = "[[beam.joints]]\nat = 20.0\nkind = \"separate\"\ngap = 1.0";
    let scene = two_span_scene(pier, 6.0e7, (15.0, 0.5), 0.02);
    let rows = run_scene(&scene, &["glider.x", "contact.normal_force"]);
    let weight = 10_000.0 * 9.81;
    let crossing = rows.iter().filter(|r| r[0] > 19.0 && r[0] < 22.0);
    let worst = crossing
        .map(|r| (r[1] - weight).abs() / weight)
        .fold(0.0, f64::max);
    println!("largest departure of the contact force from the weight: {worst:.3e}");
    assert!(rows.iter().any(|r| r[0] > 22.0), "the glider crossed");
    assert!(worst < 1e-2, "{worst:e}");
}

#[test]
fn springs_under_the_deck_are_refused_naming_the_rule() {
    // Springs under the deck are not the track's layer.
    let springs = two_span_scene(
        "[beam.supports]\nintermediate = [20.0]\nsprings = [{ at = 30.0, vertical = 1e8 }]",
        1e8,
        (0.0, 0.0),
        1e-3,
    );
    let error = guideway::Scene::from_toml_str(&springs)
        .unwrap_err()
        .to_string();
    println!("{error}");
    assert!(
        error.contains("leave beam.supports.springs and beam.foundation out"),
        "{error}"
    );
}

/// The two continuous spans in 87 elements: 40 of 0.5 m over the first,
/// 47 of 24/47 m over the second; the rail's nodes are the deck's.
fn uneven_deck() -> BeamSpec {
    BeamSpec {
        elements: 87,
        ..deck(Pier::Continuous)
    }
}

/// The node of `solution` nearest `x`, and its abscissa.
fn nearest_node(solution: &StaticSolution, x: f64) -> (usize, f64) {
    let distance = |n: &f64| (n - x).abs();
    let (i, &at) = (solution.node_x.iter().enumerate())
        .min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
        .expect("nodes");
    (i, at)
}

#[test]
fn over_spans_of_unequal_elements_a_stiff_layer_bends_as_one_two_span_beam() {
    // Elements of 0.5 m and 0.5106 m; with approaches of 10 m and of
    // 10.3 m (not whole elements: 21 of 0.4905 m) the rail on the ground
    // restrains the ends by 2 EI_r β as in the uniform case.
    let beta = libm::pow(GROUND / (4.0 * RAIL_EI), 0.25);
    for (approach, end_spring, tolerance) in [
        (0.0, 0.0, 1e-4),
        (10.0, 2.0 * RAIL_EI * beta, 2e-4),
        (10.3, 2.0 * RAIL_EI * beta, 2e-4),
    ] {
        let beam = TwoSpan {
            ei: DECK_EI + RAIL_EI,
            end_spring,
        };
        for xi in LOADS {
            let probe = layout(1e13, approach)
                .static_solution_over(&uneven_deck(), xi, LOAD)
                .expect("solves");
            let (_, at) = nearest_node(&probe, xi);
            let solution = layout(1e13, approach)
                .static_solution_over(&uneven_deck(), at, LOAD)
                .expect("solves");
            for x in READ.into_iter().chain([at]) {
                let (node, x) = nearest_node(&solution, x);
                let found = -solution.deck[node];
                let what = format!("approach {approach} m, load at {at:.4} m, deck at {x:.4} m");
                assert_within(found, beam.deflection(LOAD, at, x), tolerance, &what);
            }
            let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
            assert_within(bearings + solution.ground_force, LOAD, 1e-9, "balance");
        }
    }
}

#[test]
fn in_a_scene_a_slow_glider_over_spans_of_unequal_elements_follows_their_influence_lines() {
    // As the uniform scene, in 87 elements (0.5 m and 0.5106 m), which the
    // rail's nodes follow.
    let (speed, step) = (0.5, 0.02);
    let scene = two_span_scene(INTERMEDIATE, 1e11, (-3.0, speed), step)
        .replace("elements = 88", "elements = 87");
    let rows = run_scene(
        &scene,
        &[
            "glider.x",
            "sensor.first.deflection",
            "sensor.second.deflection",
        ],
    );
    let composite = TwoSpan {
        ei: DECK_EI + RAIL_EI,
        end_spring: 0.0,
    };
    let weight = 10_000.0 * 9.81;
    let peak = composite.deflection(weight, 10.0, 10.0);
    let mut worst = 0.0f64;
    for row in rows.iter().filter(|r| r[0] > 2.0 && r[0] < 42.0) {
        for (k, sensor) in [10.0, 32.0].into_iter().enumerate() {
            let expected = -composite.deflection(weight, row[0], sensor);
            worst = worst.max((row[1 + k] - expected).abs() / peak);
        }
    }
    println!("largest departure from the influence lines: {worst:.3e} of the peak");
    assert!(worst < 5e-3, "{worst:e} of the peak");
}
