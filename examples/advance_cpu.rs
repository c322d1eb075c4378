//! The in-process CPU time of a scene's run, `Simulation::advance_to` from
//! the start to the run's end and nothing else (no outputs, rows or
//! summary): the measure issue 29 states its time targets in.
//!
//! `cargo run --release --example advance_cpu -- SCENE [ROUNDS]` prints
//! the median and least of ROUNDS runs (default 11), each on a new
//! `Simulation` (its construction not timed). Compare two builds by
//! running their binaries alternately, not one after the other.
#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;

use cpu_clock::thread_cpu_time;
use guideway::report::stop_time;
use guideway::scene::Scene;
use guideway::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: advance_cpu SCENE [ROUNDS]";
    let scene = Scene::load(args.get(1).expect(usage)).unwrap_or_else(|e| panic!("{e}"));
    let rounds: usize = args.get(2).map_or(11, |r| r.parse().expect(usage));
    assert!(rounds > 0, "{usage}");
    let end = stop_time(&scene).unwrap_or_else(|e| panic!("{e}"));
    let mut times: Vec<f64> = (0..rounds)
        .map(|_| {
            let mut sim = Simulation::new(&scene).unwrap_or_else(|e| panic!("{e}"));
            let start = thread_cpu_time();
            sim.advance_to(end).unwrap_or_else(|e| panic!("{e}"));
            (thread_cpu_time() - start).as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let (median, least) = (times[rounds / 2], times[0]);
    println!(
        "{}: advance_to median {median:.2} ms, least {least:.2} ms ({rounds} rounds)",
        scene.name
    );
}
