//! Solver speed: the paper's 10 m/s case end to end, the cost of one step
//! against the number of elements (it must grow linearly), the cost per
//! element and integration, and the start-up.
//!
//! `cargo bench --bench solver`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use guideway::scene::{BodyKind, IntegratorKind, Scene};
use guideway::{Advance, Simulation};
use std::hint::black_box;
use std::time::Duration;

#[path = "common/cpu_clock.rs"]
mod cpu_clock;
use cpu_clock::thread_cpu_time;

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
        scene.vehicles[0].initial_position = 6.0;
        scene.solver.integrator = integrator;
        if let Ok(sim) = Simulation::new(&scene) {
            return (sim, step);
        }
        step /= 2.0;
    }
}

/// The measured steps end here, 1.5 s after the start (the wheel at 21 m of
/// 24), and start again from the start: the exit step (a shortened step,
/// its own factorization and Delassus operator) costs about eight typical
/// steps, and a sample of a few steps that held it was an outlier.
const LAST_TYPICAL_TIME: f64 = 1.5;

/// Time `n` steps from the current state (back to the start before the
/// exit); the thread's CPU time and the integrations they took.
fn timed_steps(
    sim: &mut Simulation,
    start: &guideway::SimState,
    step: f64,
    n: u64,
) -> (Duration, u64) {
    // The counters go back with the state: count from each restore.
    let mut counted_from = sim.counters().1;
    let mut integrations = 0;
    let clock = thread_cpu_time();
    for _ in 0..n {
        if sim.time() + step > LAST_TYPICAL_TIME || sim.exit_time().is_some() {
            integrations += sim.counters().1 - counted_from;
            sim.restore(start).expect("same model");
            counted_from = sim.counters().1;
        }
        let target = sim.time() + step;
        black_box(sim.advance_to(target).expect("converges"));
    }
    let elapsed = thread_cpu_time().saturating_sub(clock);
    (elapsed, integrations + sim.counters().1 - counted_from)
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
            // Not 100,000: started mid-beam, its fourth step refactorizes
            // for a shortened step and the band LDLᵀ fails (docs/performance-log.md, Speed).
            &[2usize, 16, 128, 1024, 8192, 65_536][..],
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

/// Element-integrations in a step, about (4 to 5 integrations of 1024
/// elements with HHT-α, 2 to 3 with RK4).
const ELEMENT_INTEGRATIONS_PER_STEP: u64 = 4 * 1024;

/// Time per element and per integration (one pass of the integrator over
/// the beam inside the contact iteration) at 1024 elements: the steps'
/// time divided by their integrations and by the number of elements. An
/// iteration of criterion is one element-integration, so a sample of `n`
/// runs about n / 4096 steps (at least one): criterion plans its samples
/// from the time it is told, and running `n` whole steps made them 4096
/// times longer than planned.
fn per_element_integration(c: &mut Criterion) {
    let mut group = c.benchmark_group("per element-integration, 1024 elements");
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Hht] {
        let (mut sim, step) = simulation(1024, integrator);
        let start = sim.state();
        group.bench_function(format!("{integrator:?}"), |b| {
            b.iter_custom(|n| {
                let steps = n.div_ceil(ELEMENT_INTEGRATIONS_PER_STEP);
                let (elapsed, integrations) = timed_steps(&mut sim, &start, step, steps);
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
