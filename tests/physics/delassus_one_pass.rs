//! The contact operator of all contacts in one pass (issue 29): on HHT-α's
//! grid steps the eight-coach train's operator needs no whole-beam solve
//! per contact, and its work per build depends on the contacts and their
//! spread, not on the bridge's length. These fail if the operator's cost
//! becomes contacts × elements again (as with a response per contact).

use guideway::{Scene, Simulation};

/// The eight coaches (32 glider wheelsets on rigid contacts, HHT-α at
/// 1 ms: the benchmark as it was built in before its wheelsets took the
/// Hertz contact, whose forces need no operator) over `spans` continuous
/// spans of 25 m, run to `until`: the whole-beam solves for operators and
/// the condensed builds' work.
fn train_over(spans: usize, until: f64) -> (u64, guideway::iteration::CondensedWork) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scripts/scenes/bench-8-coaches-3x25-300-rigid.toml"
    );
    let text = std::fs::read_to_string(path).expect("the scene file");
    let mut scene = Scene::from_toml_str(&text).expect("a valid scene");
    scene.beam.length = 25.0 * spans as f64;
    scene.beam.elements = 25 * spans;
    scene.beam.supports.intermediate = (1..spans).map(|k| 25.0 * k as f64).collect();
    let mut sim = Simulation::new(&scene).expect("builds");
    let dt = scene.solver.step;
    let steps = (until / dt).round() as usize;
    for step in 1..=steps {
        sim.advance_to(step as f64 * dt).expect("converges");
    }
    sim.delassus_work()
}

#[test]
fn the_trains_operator_costs_the_same_on_a_bridge_three_times_as_long() {
    // At 2.7 s every coach is on both bridges (its front at 214 m, its
    // back at 46 m): the contacts sit on the same elements of each.
    let (short, long) = (train_over(12, 2.7), train_over(36, 2.7));
    for (solves, work) in [short, long] {
        // Grid steps integrate no beam for their operators; the shortened
        // steps of events (a wheelset landing, the end) solve one column
        // per row on the beam. A response per contact and step would be
        // 32 solves a build.
        assert!(solves <= work.builds / 2, "{solves} solves, {work:?}");
        // One sweep over the beam (the band of A⁻¹) for the whole run.
        assert_eq!(work.bands, 1, "{work:?}");
        assert!(work.builds >= 2700, "{work:?}");
    }
    let per_build = |w: guideway::iteration::CondensedWork| w.rows_walked as f64 / w.builds as f64;
    let (a, b) = (per_build(short.1), per_build(long.1));
    assert!(
        (a - b).abs() <= 0.2 * a,
        "rows walked per build: {a} on 12 spans, {b} on 36"
    );
    // 32 wheelsets on at most 32 elements (128 DOFs), each column walked
    // at most over the train's 190 m (380 DOFs of 1 m elements) and the
    // contacts before it: far below a walk over the 36 spans' 1,800 DOFs
    // per column.
    assert!(b <= 128.0 * 400.0, "rows walked per build: {b}");
}
