//! Where the stress case's energy balance moves: per grid step, the jump of
//! `energy.balance`, summed by the events the step holds.
//! `cargo run --release --example stress_balance -- [step] [restitution] [flat]`

#[path = "../tests/common/mod.rs"]
mod common;

use guideway::simulation::{ContactEvent, EventKind};
use guideway::{Scene, Simulation};

/// The stress case's scene (the tests' own), with restitution `e`, and
/// without its irregularity unless `rough`.
fn scene(step: f64, e: f64, rough: bool) -> Scene {
    let mut scene = common::rough_coach_scene("rough-track-300", "C", 2026, step, "rk4");
    scene.vehicles[0].restitution = e;
    if !rough {
        scene.track.irregularities.clear();
    }
    scene.validate().expect("valid");
    scene
}

/// Which kind of step: 0 without events, 1 landings only, 2 lift-offs
/// only, 3 entries and exits only, 4 a mix.
fn class_of(events: &[ContactEvent]) -> usize {
    let all = |f: fn(EventKind) -> bool| events.iter().all(|e| f(e.kind));
    if events.is_empty() {
        0
    } else if all(|k| k == EventKind::Landing) {
        1
    } else if all(|k| k == EventKind::LiftOff) {
        2
    } else if all(|k| matches!(k, EventKind::Entry | EventKind::Exit)) {
        3
    } else {
        4
    }
}

/// One step's jump, its events, the contacts (o open, c closed) and the
/// track parts they are on.
fn print_step(sim: &Simulation, events: &[ContactEvent], jump: f64) {
    let desc: Vec<String> = events
        .iter()
        .map(|e| format!("{}:{:?}@{:.9}", e.contact, e.kind, e.time))
        .collect();
    let open: String = sim
        .contact_statuses()
        .iter()
        .map(|c| if c.open { 'o' } else { 'c' })
        .collect();
    let parts = &sim.state().parts;
    println!(
        "t {:.6} jump {jump:+.3} J {open} {parts:?} {}",
        sim.time(),
        desc.join(" ")
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let step: f64 = args.get(1).map_or(1.25e-5, |s| s.parse().expect("step"));
    let e: f64 = args.get(2).map_or(0.9, |s| s.parse().expect("e"));
    let rough = args.get(3).is_none_or(|s| s != "flat");
    let verbose = std::env::var("VERBOSE").is_ok();
    let scene = scene(step, e, rough);
    let mut sim = Simulation::new(&scene).expect("builds");
    let grid = (0.75 / step).round() as u64;
    let names = ["none", "landing", "lift-off", "entry/exit", "mixed"];
    let mut sums = [0.0f64; 5];
    let mut counts = [0u64; 5];
    let mut absum = [0.0f64; 5];
    let mut last = sim.energy_balance();
    let mut seen = 0;
    let mut worst: f64 = 0.0;
    for k in 1..=grid {
        sim.advance_to(k as f64 * step).expect("runs");
        let now = sim.energy_balance();
        let jump = now - last;
        worst = worst.max((now - sim.initial_energy()).abs());
        last = now;
        let new = &sim.events()[seen..];
        let class = class_of(new);
        sums[class] += jump;
        absum[class] += jump.abs();
        counts[class] += 1;
        if verbose && (class != 0 || jump.abs() > 1.0) {
            print_step(&sim, new, jump);
        }
        seen = sim.events().len();
    }
    println!(
        "step {step:e} e {e} rough {rough}: drift at the end {:.2} J, largest {worst:.2} J, \
         of {:.4e} J; impact loss {:.1} J, numerical dissipation {:.1} J, steps {}, events {}",
        sim.energy_balance() - sim.initial_energy(),
        sim.initial_energy(),
        sim.impact_loss(),
        sim.state().dynamic.numerical_dissipation,
        sim.counters().0,
        sim.events().len()
    );
    for c in 0..5 {
        println!(
            "  {:10} steps {:6} sum {:+12.3} J  |sum| {:12.3} J",
            names[c], counts[c], sums[c], absum[c]
        );
    }
}
