//! Solver speed: the paper's 10 m/s case end to end, and the cost of one
//! step against the number of elements (it must grow linearly).
//!
//! `cargo bench --bench solver`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use guideway::scene::{BodyKind, Scene};
use guideway::{Advance, Simulation};
use std::hint::black_box;
use std::time::{Duration, Instant};

fn paper_case(c: &mut Criterion) {
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    c.bench_function("lee1994-wheel-10 end to end (910 steps)", |b| {
        b.iter(|| {
            let mut sim = Simulation::new(&scene).expect("valid scene");
            let advance = sim.advance_to(10.0).expect("converges");
            assert!(matches!(advance, Advance::Exited { .. }));
            black_box(sim.time())
        })
    });
}

/// The paper's scene on `elements` elements at the largest stable step of
/// the form 0.0025 s / 2^k.
fn stable_simulation(elements: usize) -> (Simulation, f64) {
    let mut step = 0.0025;
    loop {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
        scene.beam.elements = elements;
        // Start mid-beam so that the measured steps are typical ones.
        scene.body.initial_position = 6.0;
        if let Ok(sim) = Simulation::new(&scene) {
            return (sim, step);
        }
        step /= 2.0;
    }
}

fn cost_per_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("cost per step");
    for elements in [2usize, 16, 128, 1024] {
        let (mut sim, step) = stable_simulation(elements);
        let start_state = sim.state();
        group.bench_with_input(BenchmarkId::from_parameter(elements), &elements, |b, _| {
            b.iter_custom(|iterations| {
                let start = Instant::now();
                for _ in 0..iterations {
                    if sim.exit_time().is_some() {
                        sim.restore(&start_state).expect("same model");
                    }
                    let target = sim.time() + step;
                    black_box(sim.advance_to(target).expect("converges"));
                }
                start.elapsed()
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = paper_case, cost_per_step
}
criterion_main!(benches);
