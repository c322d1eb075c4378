//! The FMU's per-step overhead: the paper's 10 m/s scene stepped with
//! communication steps of one internal step (2.5 ms, where the overhead
//! weighs most), every real output read after each step, three ways:
//!
//! - `native`: `Simulation::advance_to`, `output_values` and the check that
//!   every output is finite, as `guideway run` does after every step
//!   (`report::drive_into`);
//! - `model`: the FMU's model layer (`Model::do_step` and `get_reals`)
//!   in-process;
//! - `fmu`: the exported FMU loaded by the `fmi` crate (an independent
//!   importer), `fmi2DoStep` and `fmi2GetReal`.
//!
//! Criterion times each (wall clock); `paired` alternates the three crossing
//! by crossing (native, model, FMU, native, ...) and prints the median of
//! the per-round ratios of the thread's CPU time, the figure docs/performance-log.md quotes
//! (on a loaded machine the wall clock mostly measures the waits for a
//! core, which CPU time leaves out).
//!
//! `cargo bench --bench fmu`
//!
//! With `FMU_BENCH_CROSSINGS=native:N` (or `model:N`, `fmu:N`) the bench
//! runs N crossings of that kind and nothing else, for callgrind:
//! `scripts/fmu_overhead.sh` counts the instructions of the crossings'
//! stepping loops alone (`native_steps`, `model_steps`, `fmu_steps`), so
//! set-up (building, exporting, loading, instantiating) is left out.

use criterion::{criterion_group, Criterion};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use guideway::model::{Model, VarType};
use guideway::report::non_finite_output;
use guideway::scene::{BodyKind, Scene};
use guideway::simulation::Steppable;
use guideway::Simulation;
use std::hint::black_box;
use std::time::{Duration, Instant};

#[path = "common/cpu_clock.rs"]
mod cpu_clock;
use cpu_clock::thread_cpu_time;

/// Communication step: the scene's internal step.
const H: f64 = 0.0025;
/// Steps per crossing: to 2.25 s, before the wheel leaves the beam.
const STEPS: usize = 900;
/// Rounds of the paired measurement.
const ROUNDS: usize = 31;

fn scene() -> Scene {
    Scene::lee1994(BodyKind::Wheel, 10.0, H)
}

/// A clock: the wall clock, or the CPU time of this thread.
#[derive(Clone, Copy)]
enum Clock {
    Wall,
    ThreadCpu,
}

impl Clock {
    /// Time `f`.
    fn time(self, f: impl FnOnce()) -> Duration {
        match self {
            Clock::Wall => {
                let start = Instant::now();
                f();
                start.elapsed()
            }
            Clock::ThreadCpu => {
                let start = thread_cpu_time();
                f();
                thread_cpu_time().saturating_sub(start)
            }
        }
    }
}

/// One crossing natively: advance, then every output.
fn native_crossing(scene: &Scene, clock: Clock) -> Duration {
    let mut sim = Simulation::new(scene).expect("valid scene");
    let mut values = vec![0.0; Steppable::outputs(&sim).len()];
    clock.time(|| native_steps(&mut sim, &mut values))
}

// The crossings' loops are functions of their own, never inlined, so that
// callgrind can count them alone (scripts/fmu_overhead.sh).
#[inline(never)]
fn native_steps(sim: &mut Simulation, values: &mut [f64]) {
    for k in 1..=STEPS {
        sim.advance_to(k as f64 * H).expect("converges");
        sim.output_values(values);
        let bad = non_finite_output(Steppable::outputs(sim), values);
        assert!(bad.is_none(), "finite outputs");
        black_box(&values);
    }
}

/// The real outputs' value references of the scene's FMU.
fn real_outputs(model: &Model<Simulation>) -> Vec<u32> {
    let table = model.table();
    table
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.value_reference)
        .collect()
}

/// One crossing through the model layer in-process.
fn model_crossing(scene: &Scene, clock: Clock) -> Duration {
    let mut model = Model::<Simulation>::new(scene.clone()).expect("valid scene");
    let outputs = real_outputs(&model);
    model.initialize().expect("initializes");
    let mut values = vec![0.0; outputs.len()];
    clock.time(|| model_steps(&mut model, &outputs, &mut values))
}

#[inline(never)]
fn model_steps(model: &mut Model<Simulation>, outputs: &[u32], values: &mut [f64]) {
    for k in 0..STEPS {
        model.do_step(k as f64 * H, H).expect("steps");
        model.get_reals(outputs, values).expect("outputs");
        black_box(&values);
    }
}

/// The exported FMU, loaded once, and its real outputs.
struct Fmu {
    _dir: tempfile::TempDir,
    import: Fmi2Import,
    outputs: Vec<u32>,
}

impl Fmu {
    fn new(scene: &Scene) -> Fmu {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let path = dir.path().join("scene.fmu");
        let cdylib = guideway::fmu::default_cdylib().expect("the cdylib is built with the bench");
        guideway::fmu::export(scene, &path, &cdylib).expect("exports");
        let import = fmi::import::from_path(&path).expect("the fmi crate loads it");
        let model = Model::<Simulation>::new(scene.clone()).expect("valid scene");
        Fmu {
            _dir: dir,
            import,
            outputs: real_outputs(&model),
        }
    }

    /// A fresh instance, initialized.
    fn instance(&self) -> InstanceCS {
        let mut inst = self
            .import
            .instantiate_cs("bench", false, false)
            .expect("instantiates");
        inst.setup_experiment(None, 0.0, None).expect("setup");
        inst.enter_initialization_mode().expect("init");
        inst.exit_initialization_mode().expect("init");
        inst
    }

    fn crossing(&self, clock: Clock) -> Duration {
        let mut inst = self.instance();
        let mut values = vec![0.0; self.outputs.len()];
        clock.time(|| fmu_steps(&mut inst, &self.outputs, &mut values))
    }
}

#[inline(never)]
fn fmu_steps(inst: &mut InstanceCS, outputs: &[u32], values: &mut [f64]) {
    for k in 0..STEPS {
        inst.do_step(k as f64 * H, H, true).expect("steps");
        inst.get_real(outputs, values).expect("outputs");
        black_box(&values);
    }
}

fn sum(n: u64, crossing: impl Fn() -> Duration) -> Duration {
    (0..n).map(|_| crossing()).sum()
}

fn each(c: &mut Criterion) {
    let scene = scene();
    let fmu = Fmu::new(&scene);
    let mut group = c.benchmark_group(format!("crossing, {STEPS} communication steps of {H} s"));
    group.sample_size(20);
    let wall = Clock::Wall;
    group.bench_function("native", |b| {
        b.iter_custom(|n| sum(n, || native_crossing(&scene, wall)))
    });
    group.bench_function("model", |b| {
        b.iter_custom(|n| sum(n, || model_crossing(&scene, wall)))
    });
    group.bench_function("fmu", |b| b.iter_custom(|n| sum(n, || fmu.crossing(wall))));
    group.finish();
}

/// Median, min and max.
fn spread(mut ratios: Vec<f64>) -> (f64, f64, f64) {
    ratios.sort_by(f64::total_cmp);
    (
        ratios[ratios.len() / 2],
        ratios[0],
        ratios[ratios.len() - 1],
    )
}

fn paired(_: &mut Criterion) {
    let scene = scene();
    let fmu = Fmu::new(&scene);
    // One of each first, unmeasured: caches, the loader, the allocator.
    let cpu = Clock::ThreadCpu;
    let _ = (
        native_crossing(&scene, cpu),
        model_crossing(&scene, cpu),
        fmu.crossing(cpu),
    );
    let (mut model, mut through_fmu) = (Vec::new(), Vec::new());
    for _ in 0..ROUNDS {
        let native = native_crossing(&scene, cpu).as_secs_f64();
        model.push(model_crossing(&scene, cpu).as_secs_f64() / native);
        through_fmu.push(fmu.crossing(cpu).as_secs_f64() / native);
    }
    for (name, ratios) in [("model", model), ("fmu", through_fmu)] {
        let (median, min, max) = spread(ratios);
        println!(
            "paired, {name} / native (thread CPU time) over {ROUNDS} rounds: \
             median {median:.3} [{min:.3}, {max:.3}]"
        );
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = paired, each
}

/// `FMU_BENCH_CROSSINGS=kind:N`: N crossings of one kind, untimed.
fn crossings_only(spec: &str) {
    let (kind, n) = spec
        .split_once(':')
        .and_then(|(k, n)| Some((k, n.parse::<usize>().ok()?)))
        .expect("FMU_BENCH_CROSSINGS=native|model|fmu:N");
    let scene = scene();
    let fmu = (kind == "fmu").then(|| Fmu::new(&scene));
    for _ in 0..n {
        match (kind, &fmu) {
            ("native", _) => native_crossing(&scene, Clock::Wall),
            ("model", _) => model_crossing(&scene, Clock::Wall),
            (_, Some(fmu)) => fmu.crossing(Clock::Wall),
            _ => panic!("unknown kind {kind}: native, model or fmu"),
        };
    }
}

fn main() {
    match std::env::var("FMU_BENCH_CROSSINGS") {
        Ok(spec) => crossings_only(&spec),
        Err(_) => {
            benches();
            Criterion::default().configure_from_args().final_summary();
        }
    }
}
