//! The contact iteration's unit-load response cache stays linear in the
//! elements (issue 29). Up to 256 elements it used to keep a response
//! block for every pair of elements (65,536 blocks, 57 MiB of peak memory
//! at 256 elements against 6.7 MiB at 300); these crossings fail if the
//! cache grows with the square of the elements again.

use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::{Advance, Simulation};

/// The paper's wheel at 10 m/s over `elements` elements, HHT-α at 2.5 ms,
/// run to its exit; the cache's peak footprint.
fn crossing(elements: usize) -> guideway::iteration::Footprint {
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
    sim.response_cache_peak()
}

#[test]
fn a_crossing_of_4096_elements_keeps_the_response_cache_linear_in_the_elements() {
    let elements = 4096;
    let peak = crossing(elements);
    // The cache was used: one block at least, for the element under the
    // wheel.
    assert!(peak.pairs >= 1 && peak.loaded_elements >= 1, "{peak:?}");
    // A wheel loads one element at a time and is measured on one: the
    // blocks of the last few builds (swept when they pass 64 and double),
    // not one per pair of the 4,096² the crossing visits.
    assert!(peak.pairs <= 256, "{peak:?}");
    // Whole responses (8 vectors of 8,192 entries, 512 kB an element):
    // the one under the wheel and the 4 MiB of the last ones it left.
    assert!(peak.loaded_elements <= 10, "{peak:?}");
    // O(elements): 2 kB an element, where the pair blocks of every element
    // pair would take 1 MB an element.
    assert!(peak.bytes <= 2048 * elements, "{peak:?}");
}

#[test]
fn at_256_elements_the_cache_no_longer_holds_every_element_pair() {
    let elements = 256;
    let peak = crossing(elements);
    assert!(peak.pairs >= 1, "{peak:?}");
    // Was 65,536 blocks (every pair) from the crossing's end on.
    assert!(peak.pairs <= 256, "{peak:?}");
    // Whole responses of 512 entries (32 kB): the 4 MiB kept for elements
    // left hold at most 128 of them, and at most 160 before a sweep.
    assert!(
        peak.bytes <= (4 << 20) + 32 * 32 * 1024 + 256 * 512,
        "{peak:?}"
    );
}
