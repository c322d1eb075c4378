//! Solver speed: the paper's 10 m/s case end to end, the cost of one step
//! against the number of elements (it must grow linearly), the cost per
//! element and integration, and the start-up.
//!
//! `cargo bench --bench solver`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use guideway::scene::{BodyKind, IntegratorKind, Scene};
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

/// The paper's scene on `elements` elements, started mid-beam so that the
/// measured steps are typical ones: RK4 at the largest stable step of the
/// form 0.0025 s / 2^k, or HHT-α at the paper's step.
fn simulation(elements: usize, integrator: IntegratorKind) -> (Simulation, f64) {
    let mut step = 0.0025;
    loop {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
        scene.beam.elements = elements;
        scene.body.initial_position = 6.0;
        scene.solver.integrator = integrator;
        if let Ok(sim) = Simulation::new(&scene) {
            return (sim, step);
        }
        step /= 2.0;
    }
}

/// Time `iterations` steps from the current state (back to the start at
/// the exit); the elapsed time and the integrations they took.
fn timed_steps(
    sim: &mut Simulation,
    start: &guideway::SimState,
    step: f64,
    n: u64,
) -> (Duration, u64) {
    let before = sim.counters().1;
    let mut integrations = 0;
    let clock = Instant::now();
    for _ in 0..n {
        if sim.exit_time().is_some() {
            integrations += sim.counters().1 - before;
            sim.restore(start).expect("same model");
        }
        let target = sim.time() + step;
        black_box(sim.advance_to(target).expect("converges"));
    }
    let elapsed = clock.elapsed();
    (
        elapsed,
        integrations + sim.counters().1.saturating_sub(before),
    )
}

/// `GUIDEWAY_BENCH_MAX_ELEMENTS` caps the meshes measured (for quick runs,
/// or to compare with a version that cannot run the largest).
fn max_elements() -> usize {
    std::env::var("GUIDEWAY_BENCH_MAX_ELEMENTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(usize::MAX)
}

fn cost_per_step(c: &mut Criterion) {
    for (name, integrator, sizes) in [
        (
            "cost per step, rk4 at its stable step",
            IntegratorKind::Rk4,
            &[2usize, 16, 128, 1024, 8192, 65_536, 100_000][..],
        ),
        (
            "cost per step, hht at 2.5 ms",
            IntegratorKind::Hht,
            &[2usize, 16, 128, 1024, 8192][..],
        ),
    ] {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        for &elements in sizes.iter().filter(|&&e| e <= max_elements()) {
            let (mut sim, step) = simulation(elements, integrator);
            let start = sim.state();
            group.bench_with_input(BenchmarkId::from_parameter(elements), &elements, |b, _| {
                b.iter_custom(|n| timed_steps(&mut sim, &start, step, n).0)
            });
        }
        group.finish();
    }
}

/// Time per element and per integration (one pass of the integrator over
/// the beam inside the contact iteration) at 1024 elements: the step's time
/// divided by its integrations and by the number of elements.
fn per_element_integration(c: &mut Criterion) {
    let mut group = c.benchmark_group("per element-integration, 1024 elements");
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Hht] {
        let (mut sim, step) = simulation(1024, integrator);
        let start = sim.state();
        group.bench_function(format!("{integrator:?}"), |b| {
            b.iter_custom(|n| {
                let (elapsed, integrations) = timed_steps(&mut sim, &start, step, n);
                // Report the time of n element-integrations.
                elapsed.mul_f64(n as f64 / (integrations.max(1) as f64 * 1024.0))
            })
        });
    }
    group.finish();
}

/// From the scene to the first step: assembly, factorizations, the
/// stability limit, the integrator's choice.
fn start_up(c: &mut Criterion) {
    let mut group = c.benchmark_group("start-up");
    for elements in [2usize, 100, 1000] {
        for integrator in [IntegratorKind::Auto, IntegratorKind::Hht] {
            let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
            scene.beam.elements = elements;
            scene.solver.integrator = integrator;
            group.bench_function(format!("{elements} elements, {integrator:?}"), |b| {
                b.iter(|| black_box(Simulation::new(&scene).expect("builds")))
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = paper_case, cost_per_step, per_element_integration, start_up
}
criterion_main!(benches);
