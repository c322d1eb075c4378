//! Error against run time for each integrator, on the paper's cases.
//!
//! For each case a reference solution is established first: RK4 with the
//! quadratic force profile at two fine steps h and h/2, Richardson-
//! extrapolated (fourth order in the step: `solver.force_profile`); the difference of
//! the two fine runs bounds the reference's own error and is reported with
//! it. Every measured run then uses steps 0.01 s / 2^k, so its output times
//! include the common grid on which the midspan deflection is compared.

use crate::report::{run_scene, Run, RunError};
use crate::scene::{builtin, ForceProfile, IntegratorKind, Scene};

/// A scene to measure, with the coarse grid its deflection is compared on.
pub struct Case {
    pub name: &'static str,
    pub scene: Scene,
    /// Reference step h (RK4 runs at h and h/2; halved further if RK4 is
    /// not stable at it).
    pub reference_step: f64,
    /// The swept steps are 0.01 s / 2^k for k = 1 ..= `depth`.
    pub depth: u32,
}

/// An integrator setting whose work-precision curve is drawn.
#[derive(Debug, Clone, Copy)]
pub struct Scheme {
    pub name: &'static str,
    pub integrator: IntegratorKind,
    pub damping: f64,
    pub profile: ForceProfile,
}

pub const SCHEMES: [Scheme; 4] = [
    Scheme {
        name: "rk4",
        integrator: IntegratorKind::Rk4,
        damping: 0.0,
        profile: ForceProfile::Held,
    },
    Scheme {
        name: "rk4-quadratic",
        integrator: IntegratorKind::Rk4,
        damping: 0.0,
        profile: ForceProfile::Quadratic,
    },
    Scheme {
        name: "hht-0",
        integrator: IntegratorKind::Hht,
        damping: 0.0,
        profile: ForceProfile::Held,
    },
    Scheme {
        name: "hht-0.1",
        integrator: IntegratorKind::Hht,
        damping: 0.1,
        profile: ForceProfile::Held,
    },
];

/// The grid all compared runs share (s).
const COARSE_GRID: f64 = 0.01;

/// The three cases of the study.
pub fn cases(quick: bool) -> Vec<Case> {
    let wheel = |name: &str| builtin(name).expect("built-in scene");
    let mut fine = wheel("lee1994-wheel-10");
    fine.beam.elements = 32;
    let reference = |h: f64| if quick { h * 8.0 } else { h };
    let depth = |d: u32| if quick { 4 } else { d };
    vec![
        Case {
            name: "wheel-10 (2 elements)",
            scene: wheel("lee1994-wheel-10"),
            reference_step: reference(COARSE_GRID / 1024.0),
            depth: depth(8),
        },
        Case {
            name: "wheel-100 (2 elements)",
            scene: wheel("lee1994-wheel-100"),
            reference_step: reference(COARSE_GRID / 4096.0),
            depth: depth(8),
        },
        Case {
            name: "wheel-10 (32 elements)",
            scene: fine,
            reference_step: reference(COARSE_GRID / 1024.0),
            // RK4 needs Δt ≤ 35 µs on this mesh: sweep down to 10 µs.
            depth: depth(10),
        },
    ]
}

/// Midspan deflection on the coarse grid, exit speed and energy drift.
struct Sampled {
    deflection: Vec<f64>,
    exit_speed: f64,
    max_energy_drift: f64,
    steps: usize,
    iterations: u64,
}

fn sample(scene: &Scene, run: &Run) -> Result<Sampled, String> {
    let summary = run.summary(scene);
    let exit_speed = summary
        .exit_nominal_speed
        .ok_or("the body did not leave the beam")?;
    let column = run
        .trace
        .names
        .iter()
        .position(|n| n == "sensor.midspan.deflection")
        .ok_or("no midspan sensor")?;
    let per_grid = (COARSE_GRID / scene.solver.step).round() as usize;
    let deflection = run.trace.columns[column]
        .iter()
        .step_by(per_grid.max(1))
        .copied()
        .collect();
    Ok(Sampled {
        deflection,
        exit_speed,
        max_energy_drift: summary.max_energy_drift.unwrap_or(f64::NAN),
        steps: summary.steps,
        iterations: summary.iterations.unwrap_or(0),
    })
}

fn run_with(scene: &Scene) -> Result<Run, String> {
    run_scene(scene, |_| {}).map_err(|e| match e {
        RunError::Setup(m) => m,
        RunError::Solver { error, .. } => error.to_string(),
    })
}

/// The converged solution of a case.
pub struct Reference {
    pub exit_speed: f64,
    pub deflection: Vec<f64>,
    /// |V(h) − V(h/2)|: how far the fine runs themselves still differ.
    pub exit_speed_spread: f64,
    /// RMS of the two fine runs' deflection difference / static deflection.
    pub deflection_spread: f64,
}

/// P L³ / (48 EI) under the first vehicle's load: the study runs the
/// paper's one-body scenes.
fn static_deflection(scene: &Scene) -> f64 {
    let l = scene.beam.length;
    scene.vehicles[0].force_y.abs() * l * l * l / (48.0 * scene.beam.bending_stiffness)
}

fn rms_difference(a: &[f64], b: &[f64], scale: f64) -> f64 {
    let n = a.len().min(b.len());
    let sum: f64 = a[..n]
        .iter()
        .zip(&b[..n])
        .map(|(x, y)| (x - y).powi(2))
        .sum();
    (sum / n as f64).sqrt() / scale
}

pub fn reference(case: &Case) -> Result<Reference, String> {
    let mut scene = case.scene.clone();
    scene.solver.integrator = IntegratorKind::Rk4;
    scene.solver.force_profile = ForceProfile::Quadratic;
    scene.solver.velocity_tolerance = 1e-11;
    scene.solver.gap_tolerance = 1e-9;
    scene.solver.step = case.reference_step;
    while crate::Simulation::new(&scene).is_err() && scene.solver.step > 1e-9 {
        scene.solver.step /= 2.0;
    }
    let coarse = sample(&scene, &run_with(&scene)?)?;
    scene.solver.step /= 2.0;
    let fine = sample(&scene, &run_with(&scene)?)?;
    // Richardson extrapolation for a fourth-order scheme.
    let extrapolate = |c: f64, f: f64| f + (f - c) / 15.0;
    let n = coarse.deflection.len().min(fine.deflection.len());
    Ok(Reference {
        exit_speed: extrapolate(coarse.exit_speed, fine.exit_speed),
        deflection: (0..n)
            .map(|i| extrapolate(coarse.deflection[i], fine.deflection[i]))
            .collect(),
        exit_speed_spread: (coarse.exit_speed - fine.exit_speed).abs(),
        deflection_spread: rms_difference(
            &coarse.deflection,
            &fine.deflection,
            static_deflection(&case.scene),
        ),
    })
}

/// One measured point of a curve.
#[derive(Debug, Clone)]
pub struct Point {
    pub case: &'static str,
    pub scheme: &'static str,
    pub step: f64,
    pub velocity_tolerance: f64,
    /// The paper's own setting (RK4, the built-in step and tolerances).
    pub paper_setting: bool,
    pub exit_speed_error: f64,
    pub rms_deflection_error: f64,
    pub max_energy_drift: f64,
    /// Median wall time of the repeats (s).
    pub wall_time_s: f64,
    pub steps: usize,
    pub iterations: u64,
    /// Why the run did not complete, if it did not.
    pub failure: Option<String>,
}

/// The settings swept: steps 0.01 s / 2^k, and tolerances at the paper's
/// step.
fn settings(case: &Case) -> Vec<(f64, f64)> {
    let paper = (case.scene.solver.step, case.scene.solver.velocity_tolerance);
    let mut settings: Vec<(f64, f64)> = (1..=case.depth)
        .map(|k| (COARSE_GRID / f64::from(1u32 << k), paper.1))
        .collect();
    for tolerance in [1e-4, 1e-5, 1e-9] {
        settings.push((paper.0, tolerance));
    }
    settings
}

/// Measure every scheme on `case` against `reference`, repeating each run
/// `repeats` times for the median wall time; `progress` is told each point.
pub fn measure(
    case: &Case,
    reference: &Reference,
    repeats: usize,
    mut progress: impl FnMut(&Point),
) -> Vec<Point> {
    let mut points = Vec::new();
    let scale = static_deflection(&case.scene);
    for scheme in &SCHEMES {
        for (step, tolerance) in settings(case) {
            let mut scene = case.scene.clone();
            scene.solver.integrator = scheme.integrator;
            scene.solver.numerical_damping = scheme.damping;
            scene.solver.force_profile = scheme.profile;
            scene.solver.step = step;
            scene.solver.velocity_tolerance = tolerance;
            let paper_setting = scheme.name == "rk4"
                && step == case.scene.solver.step
                && tolerance == case.scene.solver.velocity_tolerance;
            let point = measure_point(
                (case.name, scheme.name),
                &scene,
                paper_setting,
                (reference, scale),
                repeats,
            );
            progress(&point);
            points.push(point);
        }
    }
    points
}

/// One run setting of a case, repeated `repeats` times for the median
/// solve time, its errors against `reference` (deflections over `scale`).
fn measure_point(
    (case, scheme): (&'static str, &'static str),
    scene: &Scene,
    paper_setting: bool,
    (reference, scale): (&Reference, f64),
    repeats: usize,
) -> Point {
    let mut point = Point {
        case,
        scheme,
        step: scene.solver.step,
        velocity_tolerance: scene.solver.velocity_tolerance,
        paper_setting,
        exit_speed_error: f64::NAN,
        rms_deflection_error: f64::NAN,
        max_energy_drift: f64::NAN,
        wall_time_s: f64::NAN,
        steps: 0,
        iterations: 0,
        failure: None,
    };
    let mut times = Vec::new();
    let mut outcome = Err(String::new());
    for _ in 0..repeats.max(1) {
        outcome = run_with(scene).and_then(|run| {
            times.push(run.solve_time.as_secs_f64());
            sample(scene, &run)
        });
        if outcome.is_err() {
            break;
        }
    }
    match outcome {
        Ok(sampled) => {
            times.sort_by(f64::total_cmp);
            point.wall_time_s = times[times.len() / 2];
            point.exit_speed_error = (sampled.exit_speed - reference.exit_speed).abs();
            point.rms_deflection_error =
                rms_difference(&sampled.deflection, &reference.deflection, scale);
            point.max_energy_drift = sampled.max_energy_drift;
            point.steps = sampled.steps;
            point.iterations = sampled.iterations;
        }
        Err(message) => point.failure = Some(message),
    }
    point
}

/// The modal structures measured (`solver.structure = "modal"`): k modes
/// and the curve's name, each where the beam has more than k free DOFs.
pub const MODAL_MODES: [(usize, &str); 4] = [
    (2, "modal-2"),
    (4, "modal-4"),
    (8, "modal-8"),
    (16, "modal-16"),
];

/// The modal structures of `MODAL_MODES` on `case` over its step sweep,
/// under `auto` (RK4 up to the kept modes' stability limit, HHT-α beyond),
/// against the full model's reference: the error levels off at the
/// truncation error of the k modes.
pub fn measure_modal(
    case: &Case,
    reference: &Reference,
    repeats: usize,
    mut progress: impl FnMut(&Point),
) -> Vec<Point> {
    let mut points = Vec::new();
    let scale = static_deflection(&case.scene);
    let free_dofs = crate::beam::Beam::new(&case.scene.beam).map_or(0, |b| b.free_dofs());
    for (modes, name) in MODAL_MODES.into_iter().filter(|(k, _)| *k < free_dofs) {
        for step in (1..=case.depth).map(|k| COARSE_GRID / f64::from(1u32 << k)) {
            let mut scene = case.scene.clone();
            scene.solver.structure = crate::scene::StructureKind::Modal;
            scene.solver.modes = Some(modes);
            scene.solver.integrator = IntegratorKind::Auto;
            scene.solver.step = step;
            let point = measure_point(
                (case.name, name),
                &scene,
                false,
                (reference, scale),
                repeats,
            );
            progress(&point);
            points.push(point);
        }
    }
    points
}

/// CSV of the points (header first).
pub fn to_csv(points: &[Point]) -> String {
    let mut out = String::from(
        "case,scheme,step,velocity_tolerance,paper_setting,exit_speed_error,\
         rms_deflection_error,max_energy_drift,wall_time_s,steps,iterations,failure\n",
    );
    for p in points {
        out.push_str(&format!(
            "{},{},{:?},{:?},{},{:?},{:?},{:?},{:?},{},{},{}\n",
            p.case,
            p.scheme,
            p.step,
            p.velocity_tolerance,
            p.paper_setting,
            p.exit_speed_error,
            p.rms_deflection_error,
            p.max_energy_drift,
            p.wall_time_s,
            p.steps,
            p.iterations,
            p.failure.as_deref().unwrap_or("").replace(',', ";"),
        ));
    }
    out
}
