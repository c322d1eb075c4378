//! The contact iteration's operator costs stay linear in the elements
//! (issue 29). Up to 256 elements the unit-load response cache used to keep
//! a block for every pair of elements (65,536 blocks, 57 MiB of peak memory
//! at 256 elements against 6.7 MiB at 300); HHT-α's operator on the full
//! mesh now comes from its effective matrix's inverse at the contacts'
//! DOFs (`iteration::condensed`), with no cache and no beam solve per
//! element. These crossings fail if either grows with the elements again.

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::{Advance, Simulation};

/// The paper's wheel at 10 m/s over `elements` elements, HHT-α at 2.5 ms,
/// run to its exit; the cache's peak footprint, the whole-beam solves for
/// operators and the condensed builds' work.
fn crossing(
    elements: usize,
) -> (
    guideway::iteration::Footprint,
    u64,
    guideway::iteration::CondensedWork,
) {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = elements;
    scene.solver.integrator = IntegratorKind::Hht;
    let mut sim = Simulation::new(&scene).expect("builds");
    let mut step = 0;
    loop {
        step += 1;
        assert!(step < 2000, "the wheel crosses in 909 steps");
        let advance = sim.advance_to(step as f64 * 0.0025).expect("converges");
        if matches!(advance, Advance::Exited { .. }) {
            break;
        }
    }
    let (solves, work) = sim.delassus_work();
    (sim.response_cache_peak(), solves, work)
}

#[test]
fn a_crossing_of_4096_elements_builds_its_operators_without_a_beam_solve_per_element() {
    let (peak, solves, work) = crossing(4096);
    // Was: four whole-beam solves per element the wheel entered (16,384),
    // and 512 kB of kept responses per element.
    assert_eq!(peak.bytes, 0, "{peak:?}");
    // Only the shortened exit step's operator (one solve per applied row,
    // two rows of a rolling wheel, two operators) integrates.
    assert!(solves <= 4, "{solves} whole-beam solves");
    // One band of A⁻¹ for the whole crossing.
    assert_eq!(work.bands, 1, "{work:?}");
    assert!(work.builds >= 900, "{work:?}");
    // The wheel moves 25 mm a step, four of these 6.1 mm elements: the
    // elements it is measured and loaded on are at most 5 apart, 8 DOFs
    // whose columns walk at most 2 × 5 + 3 rows each; on the whole beam
    // (8,192 DOFs) a column alone would walk thousands.
    assert!(work.rows_walked <= 8 * 13 * work.builds, "{work:?}");
}

#[test]
fn at_256_elements_no_pair_of_elements_is_kept() {
    let (peak, solves, work) = crossing(256);
    // Was 65,536 blocks (every pair) from the crossing's end on.
    assert_eq!((peak.pairs, peak.loaded_elements), (0, 0), "{peak:?}");
    assert!(solves <= 4, "{solves} whole-beam solves");
    assert_eq!(work.bands, 1, "{work:?}");
    // Elements of 98 mm: the wheel is measured and loaded on one element
    // or two neighbours (6 DOFs: 5 + 4 + 3 + 2 + 1 rows walked at most).
    assert!(work.rows_walked <= 15 * work.builds, "{work:?}");
}
