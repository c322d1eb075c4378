//! Magnitude fuzzing of `guideway run` (issue 13): every numeric field of a
//! scene set to subnormal, tiny, huge and near-limit values, one to three at
//! a time, and the scene *run* by the binary, each case within a budget of
//! CPU time and memory. A case passes when the run
//!
//! - ends with 0 (done), 1 (the solver stopped, with a diagnostic) or 2
//!   (refused before running, naming the field or the limit), and nothing
//!   else: no panic, no abort, no signal;
//! - writes no non-finite number: the CSV of a finished run and the
//!   `.incomplete` rows of a stopped one hold finite values only, and a
//!   refused run writes nothing;
//! - stays within `CPU_BUDGET` of CPU time and `MEMORY_BUDGET` of peak
//!   resident memory (the process is killed after `WALL_LIMIT`).
//!
//! Each case runs with `--max-steps` = `ELEMENT_STEPS / beam.elements`, so
//! that the work it may do is the same whatever the mesh: the budget checks
//! that the step limit and the scene limits together bound every run.
//!
//! `GUIDEWAY_MAGNITUDE_FUZZ_CASES` sets the number of cases (default 60);
//! `scripts/fuzz_scene.sh --magnitudes [CASES]` is the long run.

use guideway::scene::{
    builtin, builtins, Scene, MAX_ELEMENTS, MAX_ITERATIONS, MAX_MAGNITUDE, MIN_MAGNITUDE,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};
use std::time::{Duration, Instant};

/// CPU time (user + system) one case may take.
const CPU_BUDGET: Duration = Duration::from_secs(30);
/// Peak resident memory one case may use.
const MEMORY_BUDGET_KB: i64 = 1024 * 1024;
/// Wall time after which a case is killed as a hang.
const WALL_LIMIT: Duration = Duration::from_secs(120);
/// Steps × elements a case may run (`--max-steps` is this / elements).
const ELEMENT_STEPS: u64 = 2_000_000;

fn seeds() -> Vec<Scene> {
    let mut scenes: Vec<Scene> = builtins()
        .iter()
        .map(|(name, _)| builtin(name).unwrap())
        .collect();
    let mut rich = builtin("lee1994-glider-30").unwrap();
    rich.beam.supports.intermediate = vec![8.0, 16.0];
    rich.sensors.push(guideway::scene::SensorSpec {
        name: "quarter".into(),
        position: 6.0,
    });
    rich.solver.end_time = Some(0.5);
    rich.solver.integrator = guideway::scene::IntegratorKind::Hht;
    scenes.push(rich);
    scenes
}

/// Values aimed at the edges: subnormal, tiny, around the magnitude limits,
/// huge, and each of these negative.
fn magnitude() -> impl Strategy<Value = f64> {
    let up = |x: f64| x * (1.0 + f64::EPSILON);
    let down = |x: f64| x * (1.0 - f64::EPSILON);
    let edges = vec![
        5e-324,
        2.2250738585072014e-308,
        1e-300,
        1e-30,
        1e-16,
        down(MIN_MAGNITUDE),
        MIN_MAGNITUDE,
        up(MIN_MAGNITUDE),
        1e-9,
        1e-3,
        0.0,
        1e3,
        1e9,
        down(MAX_MAGNITUDE),
        MAX_MAGNITUDE,
        up(MAX_MAGNITUDE),
        1e16,
        1e30,
        1e300,
        f64::MAX,
    ];
    (prop::sample::select(edges), any::<bool>())
        .prop_map(|(x, negative)| if negative { -x } else { x })
}

/// Whole numbers around the limits of `beam.elements` and
/// `solver.max_iterations`.
fn count(limit: u64) -> impl Strategy<Value = u64> {
    prop::sample::select(vec![
        0,
        1,
        2,
        3,
        limit / 10,
        limit - 1,
        limit,
        limit + 1,
        u32::MAX as u64,
    ])
}

#[derive(Debug, Clone)]
enum Edit {
    Real(usize, f64),
    Elements(u64),
    Iterations(u64),
}

/// The number of real fields `set_real` knows for `scene`.
fn real_fields(scene: &Scene) -> usize {
    15 + scene.sensors.len() + scene.beam.supports.intermediate.len()
}

/// Set the `k`-th real field (every real of the scene, in a fixed order).
fn set_real(scene: &mut Scene, k: usize, x: f64) -> &'static str {
    let k = k % real_fields(scene);
    let (b, s) = (&mut scene.beam, &mut scene.solver);
    let body = &mut scene.vehicles[0];
    let fixed: [(&'static str, &mut f64); 12] = [
        ("beam.length", &mut b.length),
        ("beam.mass_per_length", &mut b.mass_per_length),
        ("beam.bending_stiffness", &mut b.bending_stiffness),
        ("beam.surface_offset", &mut b.surface_offset),
        ("body.mass", &mut body.mass),
        ("body.initial_position", &mut body.initial_position),
        ("body.initial_speed", &mut body.initial_speed),
        ("body.force_x", &mut body.force_x),
        ("body.force_y", &mut body.force_y),
        ("solver.step", &mut s.step),
        ("solver.velocity_tolerance", &mut s.velocity_tolerance),
        ("solver.gap_tolerance", &mut s.gap_tolerance),
    ];
    if k < fixed.len() {
        let (name, field) = fixed.into_iter().nth(k).unwrap();
        *field = x;
        return name;
    }
    match k - 12 {
        0 => scene.solver.numerical_damping = x,
        1 => scene.solver.end_time = Some(x),
        // a glider has no inertia or radius: setting one is itself an edit
        2 => scene.vehicles[0].inertia = Some(x),
        i if i - 3 < scene.sensors.len() => scene.sensors[i - 3].position = x,
        i => scene.beam.supports.intermediate[i - 3 - scene.sensors.len()] = x,
    }
    "other"
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        8 => (any::<usize>(), magnitude()).prop_map(|(k, x)| Edit::Real(k, x)),
        1 => count(MAX_ELEMENTS as u64).prop_map(Edit::Elements),
        1 => count(MAX_ITERATIONS as u64).prop_map(Edit::Iterations),
    ]
}

fn case() -> impl Strategy<Value = Scene> {
    (
        prop::sample::select(seeds()),
        prop::collection::vec(edit(), 1..4),
    )
        .prop_map(|(mut scene, edits)| {
            for e in edits {
                match e {
                    Edit::Real(k, x) => {
                        set_real(&mut scene, k, x);
                    }
                    Edit::Elements(n) => scene.beam.elements = n as usize,
                    Edit::Iterations(n) => {
                        scene.solver.max_iterations = n.min(u32::MAX as u64) as u32
                    }
                }
            }
            scene
        })
}

/// How the binary ended, with its CPU time and peak memory. The peak is
/// wait4's ru_maxrss, which also counts the test process's memory shared
/// until the child's exec: an upper bound, safe for a budget.
struct Ended {
    code: Option<i32>,
    signal: Option<i32>,
    cpu: Duration,
    max_rss_kb: i64,
    stderr: String,
}

/// Run the binary, killing it after `WALL_LIMIT`; `None` if it had to be
/// killed.
#[allow(clippy::zombie_processes)] // reaped by wait4, which also gives the rusage
fn run_bounded(args: &[&str], stderr_path: &Path) -> Option<Ended> {
    let child = Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(stderr_path).unwrap())
        .spawn()
        .unwrap();
    let pid = child.id() as i32;
    let started = Instant::now();
    let mut status = 0;
    // SAFETY: wait4 and kill on our own child; rusage is plain data.
    let usage = loop {
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        let done = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if done == pid {
            break usage;
        }
        if started.elapsed() > WALL_LIMIT {
            unsafe {
                libc::kill(pid, libc::SIGKILL);
                libc::wait4(pid, &mut status, 0, &mut usage);
            }
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let time = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    Some(Ended {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        signal: libc::WIFSIGNALED(status).then(|| libc::WTERMSIG(status)),
        cpu: time(usage.ru_utime) + time(usage.ru_stime),
        max_rss_kb: usage.ru_maxrss,
        stderr: std::fs::read_to_string(stderr_path).unwrap_or_default(),
    })
}

/// Every field of every data row is a finite number.
fn all_finite(csv: &str) -> Result<(), String> {
    for (i, line) in csv.lines().enumerate().skip(1) {
        for field in line.split(',') {
            match field.parse::<f64>() {
                Ok(x) if x.is_finite() => {}
                _ => return Err(format!("line {}: `{field}` in {line}", i + 1)),
            }
        }
    }
    Ok(())
}

static OUTCOMES: [AtomicUsize; 3] = [
    AtomicUsize::new(0),
    AtomicUsize::new(0),
    AtomicUsize::new(0),
];
static MAX_CPU_MS: AtomicU64 = AtomicU64::new(0);
static MAX_RSS_KB: AtomicU64 = AtomicU64::new(0);

fn check(scene: &Scene, dir: &Path) -> Result<(), String> {
    let file = dir.join("case.toml");
    std::fs::write(&file, scene.to_toml_string()).unwrap();
    let csv = dir.join("case.csv");
    let incomplete = dir.join("case.csv.incomplete");
    let _ = std::fs::remove_file(&csv);
    let _ = std::fs::remove_file(&incomplete);
    let max_steps = (ELEMENT_STEPS / scene.beam.elements.max(1) as u64)
        .max(1)
        .to_string();
    let args = [
        "run",
        file.to_str().unwrap(),
        "--out",
        csv.to_str().unwrap(),
        "--max-steps",
        &max_steps,
        "--quiet",
    ];
    let ended = run_bounded(&args, &dir.join("stderr"))
        .ok_or(format!("killed after {WALL_LIMIT:?}: a hang"))?;
    MAX_CPU_MS.fetch_max(ended.cpu.as_millis() as u64, Relaxed);
    MAX_RSS_KB.fetch_max(ended.max_rss_kb as u64, Relaxed);
    if ended.cpu > CPU_BUDGET {
        return Err(format!(
            "{:?} of CPU time, over the budget of {CPU_BUDGET:?}",
            ended.cpu
        ));
    }
    if ended.max_rss_kb > MEMORY_BUDGET_KB {
        return Err(format!(
            "{} kB of memory, over the budget of {MEMORY_BUDGET_KB} kB",
            ended.max_rss_kb
        ));
    }
    let stderr = &ended.stderr;
    if stderr.contains("panicked") {
        return Err(format!("panicked: {stderr}"));
    }
    match ended.code {
        Some(0) => {
            all_finite(
                &std::fs::read_to_string(&csv)
                    .map_err(|e| format!("exit 0 without the CSV: {e}"))?,
            )?;
        }
        Some(code @ (1 | 2)) => {
            if csv.exists() {
                return Err(format!("exit {code} but the CSV was written: {stderr}"));
            }
            if !stderr.starts_with("error: ") {
                return Err(format!("exit {code} without a diagnostic: {stderr}"));
            }
            if let Ok(rows) = std::fs::read_to_string(&incomplete) {
                all_finite(&rows)?;
            }
        }
        code => {
            return Err(format!(
                "exit {code:?}, signal {:?}: {stderr}",
                ended.signal
            ))
        }
    }
    OUTCOMES[ended.code.unwrap() as usize].fetch_add(1, Relaxed);
    Ok(())
}

fn cases() -> u32 {
    std::env::var("GUIDEWAY_MAGNITUDE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60)
}

#[test]
fn scenes_with_extreme_magnitudes_run_within_budget_or_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let config = Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    };
    let started = Instant::now();
    let result = TestRunner::new(config).run(&case(), |scene| {
        check(&scene, dir.path()).map_err(|e| {
            TestCaseError::fail(format!("{e}\n--- scene:\n{}", scene.to_toml_string()))
        })
    });
    let [done, stopped, refused] = OUTCOMES.each_ref().map(|c| c.load(Relaxed));
    eprintln!(
        "magnitude fuzz: {} runs ({} cases): {done} done, {stopped} stopped by the solver, \
         {refused} refused; largest CPU time {:.2} s, largest peak memory {:.0} MB; 0 over \
         budget, 0 non-finite values written, {:.1} s",
        done + stopped + refused,
        cases(),
        MAX_CPU_MS.load(Relaxed) as f64 / 1e3,
        MAX_RSS_KB.load(Relaxed) as f64 / 1024.0,
        started.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(done > 0 && refused > 0, "done {done}, refused {refused}");
}

#[test]
fn a_case_over_budget_or_writing_a_non_finite_value_is_caught() {
    assert!(all_finite("time,x\n0.0,1.0\n").is_ok());
    assert!(all_finite("time,x\n0.0,NaN\n").is_err());
    assert!(all_finite("time,x\n0.0,inf\n").is_err());
    // a run refused for its length exits 2; with a budget of one step the
    // default scene is refused
    let dir = tempfile::tempdir().unwrap();
    let ended = run_bounded(
        &["run", "--max-steps", "1", "--quiet"],
        &dir.path().join("e"),
    )
    .unwrap();
    assert_eq!(ended.code, Some(2));
    assert!(ended.cpu < CPU_BUDGET && ended.max_rss_kb > 0);
}
