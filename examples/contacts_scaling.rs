//! Cost per step against the number of contacts: 1, 4, 16 and 64 paper
//! wheels (3000 kg, gravity on, 200 kN applied load) spread over a three-span
//! continuous beam (3 × 25 m, 75 elements, EI = 1e10 N m², 5000 kg/m), HHT-α (α = −0.1) at Δt = 1 ms, 150 km/h.
//! Each line: the median over 5 runs of 200 steps, after the element-pair
//! responses are cached (a warm-up of 20 steps).
//!
//! `cargo run --release --example contacts_scaling`

#[path = "common/three_spans.rs"]
mod three_spans;

use guideway::scene::{IntegratorKind, Scene};
use guideway::Simulation;
use std::time::Instant;

fn scene(contacts: usize) -> Scene {
    let mut scene = three_spans::wheels_on_three_spans(contacts, 75, IntegratorKind::Hht, 0.001);
    scene.solver.end_time = Some(1.0);
    // All stay on the beam over the measured 0.22 s (9 m at 150 km/h).
    scene.validate().expect("valid scene");
    scene
}

fn main() {
    println!("| contacts | time per step (µs) | per contact (µs) |");
    println!("|---:|---:|---:|");
    for contacts in [1, 4, 16, 64] {
        let scene = scene(contacts);
        let mut times = Vec::new();
        for _ in 0..5 {
            let mut sim = Simulation::new(&scene).expect("builds");
            sim.advance_to(0.020).expect("warm-up");
            let started = Instant::now();
            sim.advance_to(0.220).expect("converges");
            times.push(started.elapsed().as_secs_f64() / 200.0);
        }
        times.sort_by(f64::total_cmp);
        let median = times[2] * 1e6;
        println!(
            "| {contacts} | {median:.1} | {:.2} |",
            median / contacts as f64
        );
    }
}
