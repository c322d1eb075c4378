//! The companion runs of an error estimate: a scene refined in time (step
//! halved or doubled) or in space (elements doubled or halved), run in
//! parallel and summarised without keeping their rows, then handed to the
//! estimator (`convergence`) with the base run.

use super::convergence::{estimate, figures, Estimate, Level};
use crate::report::exits::{self, ExitWatch};
use crate::report::{
    check_run_length, drive_into, RowSink, RunSummary, SummaryBuilder, SummaryEvent, Trace,
};
use crate::scene::{IntegratorKind, Scene};
use crate::simulation::Simulation;
use std::ops::ControlFlow;
use std::str::FromStr;
use std::time::Instant;

/// What is refined: the time step or the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refinement {
    Time,
    Mesh,
}

impl FromStr for Refinement {
    type Err = String;
    fn from_str(s: &str) -> Result<Refinement, String> {
        match s {
            "time" => Ok(Refinement::Time),
            "mesh" => Ok(Refinement::Mesh),
            _ => Err(format!("`{s}`: the error is estimated in `time` or `mesh`")),
        }
    }
}

/// `scene` refined `halvings` times (negative: coarsened): the step divided
/// by 2^halvings, or the elements multiplied by it.
pub fn refined(scene: &Scene, refinement: Refinement, halvings: i32) -> Result<Scene, String> {
    let mut refined = scene.clone();
    match refinement {
        Refinement::Time => refined.solver.step = scene.solver.step / 2f64.powi(halvings),
        Refinement::Mesh => {
            let n = scene.beam.elements as f64 * 2f64.powi(halvings);
            if n.fract() != 0.0 || n < 1.0 {
                return Err(format!(
                    "beam.elements = {} cannot be halved",
                    scene.beam.elements
                ));
            }
            if n > crate::scene::MAX_ELEMENTS as f64 {
                return Err(format!(
                    "{n} elements exceed the limit of {}",
                    crate::scene::MAX_ELEMENTS
                ));
            }
            refined.beam.elements = n as usize;
        }
    }
    Ok(refined)
}

/// The companions run the base run's integrator: `auto` could otherwise
/// switch scheme between the steps and mix two schemes' errors.
pub fn pin_integrator(scene: &mut Scene, integrator_choice: &str) {
    if scene.solver.integrator != IntegratorKind::Auto {
        return;
    }
    let damping = scene.solver.numerical_damping;
    (scene.solver.integrator, scene.solver.numerical_damping) =
        crate::integrate::auto_pick(integrator_choice, damping);
}

/// The summary rows of a run feed, nothing else.
struct SummaryOnly(SummaryBuilder);

impl RowSink for SummaryOnly {
    fn row(&mut self, time: f64, values: &[f64]) -> Result<(), String> {
        self.0.push(time, values);
        Ok(())
    }
}

/// Run `scene` to its end, keeping only its summary (with events and
/// integrator), refused beyond `max_steps` steps.
pub fn summarise(scene: &Scene, max_steps: u64) -> Result<RunSummary, String> {
    check_run_length(scene, max_steps, " (--max-steps N raises it)")?;
    let mut simulation = Simulation::new(scene)?;
    let trace = Trace::for_outputs(simulation.outputs());
    let mut sink = SummaryOnly(SummaryBuilder::new(scene, &trace.names));
    let mut read = vec![false; trace.names.len()];
    // Each vehicle's exits, as `guideway run` records them, so that the
    // companions' summaries hold the same figures as the base run's.
    let vehicles = exits::vehicle_names(scene);
    let exit_columns = exits::exit_columns(&simulation, &vehicles);
    for k in sink.0.columns().into_iter().chain(exit_columns) {
        read[k] = true;
    }
    simulation.read_only(Some(&read));
    let mut watch = ExitWatch::new(&mut simulation, &vehicles);
    let streamed = drive_into(scene, &mut watch, &mut sink, |_| ControlFlow::Continue(()))
        .map_err(stream_error_message)?;
    let vehicle_exits = watch.finish();
    let envelope = |s: &Scene| crate::design::envelope_of_run(&simulation, s).ok();
    let mut summary = sink.0.finish_with(
        streamed.exit_time,
        streamed.solve_time.as_secs_f64(),
        envelope,
    );
    summary.integrator = Some(simulation.integrator_choice().to_string());
    summary.events = SummaryEvent::list(&simulation);
    summary.set_vehicles(vehicle_exits);
    Ok(summary)
}

/// A summarised run as a level of a study; its cost the solve time.
pub fn level_of(scene: &Scene, summary: &RunSummary) -> Level {
    Level {
        step: scene.solver.step,
        elements: scene.beam.elements,
        figures: figures(summary),
        cost_s: summary.wall_time_s,
    }
}

/// The base run and its companions, coarse to fine, with the estimates.
#[derive(Debug, Clone)]
pub struct Study {
    pub refinement: Refinement,
    pub levels: Vec<Level>,
    /// Which level is the base run.
    pub base: usize,
    pub estimates: Vec<Estimate>,
    /// Why the companions are not the coarser and finer runs, if not.
    pub note: Option<String>,
    /// Wall time of the companion runs (s), run in parallel.
    pub companions_wall_s: f64,
}

/// Companion runs (each with its halvings), why they are not the coarser
/// and finer ones if not, and their wall time (s).
pub type CompanionRuns = (Vec<(Level, i32)>, Option<String>, f64);

/// The companion runs of `scene` (whose base run chose `integrator_choice`):
/// once coarser and once finer, in parallel on `threads` threads; if the
/// coarser run fails (beyond RK4's stability limit, say), twice finer.
pub fn companions(
    scene: &Scene,
    refinement: Refinement,
    integrator_choice: &str,
    max_steps: u64,
    threads: usize,
) -> Result<CompanionRuns, String> {
    let started = Instant::now();
    let mut pinned = scene.clone();
    if refinement == Refinement::Time {
        pin_integrator(&mut pinned, integrator_choice);
    }
    let run = |halvings: i32| -> Result<(Level, i32), String> {
        let scene = refined(&pinned, refinement, halvings)?;
        let summary = summarise(&scene, max_steps)?;
        Ok((level_of(&scene, &summary), halvings))
    };
    let results = in_parallel(&[-1, 1], threads, |h| Ok(run(h)))?;
    let mut results = results.into_iter();
    let (coarser, finer) = (results.next().expect("two"), results.next().expect("two"));
    let finer = finer.map_err(|e| format!("the refined companion run failed: {e}"))?;
    match coarser {
        Ok(coarser) => Ok((vec![coarser, finer], None, started.elapsed().as_secs_f64())),
        Err(why) => {
            let finest =
                run(2).map_err(|e| format!("the twice refined companion run failed: {e}"))?;
            let note = format!(
                "the coarser companion run failed ({why}); a twice refined run took its place"
            );
            Ok((
                vec![finer, finest],
                Some(note),
                started.elapsed().as_secs_f64(),
            ))
        }
    }
}

/// The study of a base run and its companions (as `companions` gave them).
pub fn study(
    refinement: Refinement,
    base: Level,
    companions: Vec<(Level, i32)>,
    note: Option<String>,
    companions_wall_s: f64,
) -> Study {
    let mut levels: Vec<(Level, i32)> = companions;
    levels.push((base, 0));
    levels.sort_by_key(|(_, h)| *h);
    let base = levels
        .iter()
        .position(|(_, h)| *h == 0)
        .expect("the base is in");
    let levels: Vec<Level> = levels.into_iter().map(|(l, _)| l).collect();
    let estimates = estimate(&levels, base);
    Study {
        refinement,
        levels,
        base,
        estimates,
        note,
        companions_wall_s,
    }
}

/// Every estimate of a scene's summary figures, base run included (the
/// library entry point; the CLI runs the base itself, streaming its rows).
pub fn error_study(
    scene: &Scene,
    refinement: Refinement,
    max_steps: u64,
    threads: usize,
) -> Result<Study, String> {
    let base_summary = summarise(scene, max_steps)?;
    let base = level_of(scene, &base_summary);
    let choice = base_summary.integrator.clone().unwrap_or_default();
    let (runs, note, wall) = companions(scene, refinement, &choice, max_steps, threads)?;
    Ok(study(refinement, base, runs, note, wall))
}

/// `run` over every job on `threads` threads (`sweep::in_parallel`).
fn in_parallel<R: Send>(
    jobs: &[i32],
    threads: usize,
    run: impl Fn(i32) -> Result<R, String> + Sync,
) -> Result<Vec<R>, String> {
    super::sweep::in_parallel(jobs, threads, run)
}

/// The machine's cores (1 if unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// Rounds of the tolerance loop at most: each refines by the halvings the
/// observed orders ask for, so more rounds mean the orders are not holding.
pub const MAX_TOLERANCE_ROUNDS: usize = 5;

/// The step (or mesh) chosen for a relative tolerance, and what could not
/// meet it.
#[derive(Debug, Clone)]
pub struct StepChoice {
    pub rtol: f64,
    /// What the loop refined: the step, or the elements.
    pub refinement: Refinement,
    /// The chosen step (s): the base of `study`.
    pub step: f64,
    /// The chosen number of elements: the base of `study`.
    pub elements: usize,
    pub study: Study,
    /// Figures above the tolerance at the chosen step, with why.
    pub unmet: Vec<(String, String)>,
    /// Why the loop stopped before every figure met the tolerance.
    pub stopped: Option<String>,
    /// Solve time of every run the loop made (s).
    pub cost_s: f64,
    /// Runs the loop made.
    pub runs: usize,
}

/// Halve the step of `scene` until the estimated error of every summary
/// figure is within `rtol` (relative; absolute for error measures), each
/// round by as many halvings as the figures' observed orders ask for,
/// within `max_steps` per run.
pub fn choose_step(
    scene: &Scene,
    rtol: f64,
    max_steps: u64,
    threads: usize,
) -> Result<StepChoice, String> {
    choose(scene, Refinement::Time, rtol, max_steps, threads)
}

/// Refine `scene` in time (halving the step) or in space (doubling the
/// elements) until the estimated error of every summary figure is within
/// `rtol`, as `choose_step` describes, within `max_steps` per run and the
/// elements' limit.
pub fn choose(
    scene: &Scene,
    refinement: Refinement,
    rtol: f64,
    max_steps: u64,
    threads: usize,
) -> Result<StepChoice, String> {
    let base_summary = summarise(scene, max_steps)?;
    let choice = base_summary.integrator.clone().unwrap_or_default();
    let mut pinned = scene.clone();
    // A finer mesh may need the other scheme (RK4's stability limit): only
    // the time refinement keeps the base run's.
    if refinement == Refinement::Time {
        pin_integrator(&mut pinned, &choice);
    }
    let mut runs: Vec<(i32, Result<Level, String>)> = vec![(0, Ok(level_of(scene, &base_summary)))];
    let mut halvings = 0;
    let at = (refinement, max_steps, threads);
    for _ in 0..MAX_TOLERANCE_ROUNDS {
        let study = study_at(&pinned, halvings, &mut runs, at)?;
        let (needed, unmet) = needed_halvings(&study, rtol);
        let next = halvings + needed as i32;
        let stopped = if needed == 0 {
            None
        } else {
            out_of_bounds(&pinned, refinement, next, max_steps)
        };
        if needed == 0 || stopped.is_some() {
            return Ok(step_choice(rtol, study, unmet, stopped, &runs));
        }
        halvings = next;
    }
    let study = study_at(&pinned, halvings, &mut runs, at)?;
    let (_, unmet) = needed_halvings(&study, rtol);
    // The last round's refinement may have been enough.
    let stopped = (!unmet.is_empty()).then(|| {
        format!("{MAX_TOLERANCE_ROUNDS} rounds of refinement did not bring every figure within it")
    });
    Ok(step_choice(rtol, study, unmet, stopped, &runs))
}

/// Why the run `next` halvings refined (and its finer companion) cannot be
/// made within the bounds, if it cannot.
fn out_of_bounds(
    scene: &Scene,
    refinement: Refinement,
    next: i32,
    max_steps: u64,
) -> Option<String> {
    let why = refined(scene, refinement, next + 1)
        .and_then(|s| check_run_length(&s, max_steps, " (--max-steps N raises it)").map(|_| ()))
        .err()?;
    Some(match refinement {
        Refinement::Time => format!(
            "the next step, {:e} s, is out of bounds: {why}",
            scene.solver.step / 2f64.powi(next)
        ),
        Refinement::Mesh => format!(
            "the next mesh, {} elements, is out of bounds: {why}",
            scene.beam.elements as f64 * 2f64.powi(next)
        ),
    })
}

/// The choice at `study`'s base, with the cost of every run made.
fn step_choice(
    rtol: f64,
    study: Study,
    unmet: Vec<(String, String)>,
    stopped: Option<String>,
    runs: &[(i32, Result<Level, String>)],
) -> StepChoice {
    let made = runs.iter().filter_map(|(_, r)| r.as_ref().ok());
    StepChoice {
        rtol,
        refinement: study.refinement,
        step: study.levels[study.base].step,
        elements: study.levels[study.base].elements,
        study,
        unmet,
        stopped,
        cost_s: made.map(|l| l.cost_s).sum(),
        runs: runs.len(),
    }
}

/// The halvings the figures of `study` need at their observed orders, and
/// the figures that cannot tell (not converged) or fail the tolerance.
fn needed_halvings(study: &Study, rtol: f64) -> (u32, Vec<(String, String)>) {
    let mut needed = 0;
    let mut unmet = Vec::new();
    for estimate in &study.estimates {
        if let Err(why) = super::convergence::check_tolerance(estimate, rtol) {
            unmet.push((estimate.name.clone(), why));
        }
        if let Some(h) = super::convergence::halvings_needed(estimate, rtol) {
            needed = needed.max(h);
        }
    }
    (needed, unmet)
}

/// How the tolerance loop's runs are made: what is refined, the steps'
/// bound per run, the threads.
type RunsAt = (Refinement, u64, usize);

/// The study of the run `halvings` times refined, reusing the runs made
/// (`runs`, by halvings) and making the missing ones in parallel.
fn study_at(
    scene: &Scene,
    halvings: i32,
    runs: &mut Vec<(i32, Result<Level, String>)>,
    at: RunsAt,
) -> Result<Study, String> {
    make_runs(scene, &[halvings - 1, halvings, halvings + 1], runs, at)?;
    let base = run_of(runs, halvings)
        .map_err(|e| format!("the run at {halvings} halvings failed: {e}"))?;
    let finer =
        run_of(runs, halvings + 1).map_err(|e| format!("the refined companion run failed: {e}"))?;
    let (companions, note) = match run_of(runs, halvings - 1) {
        Ok(coarser) => (vec![(coarser, -1), (finer, 1)], None),
        Err(why) => {
            make_runs(scene, &[halvings + 2], runs, at)?;
            let finest = run_of(runs, halvings + 2)
                .map_err(|e| format!("the twice refined companion run failed: {e}"))?;
            let note = format!(
                "the coarser companion run failed ({why}); a twice refined run took its place"
            );
            (vec![(finer, 1), (finest, 2)], Some(note))
        }
    };
    Ok(study(at.0, base, companions, note, 0.0))
}

/// The runs of `wanted` (halvings) not yet in `runs`, made in parallel.
fn make_runs(
    scene: &Scene,
    wanted: &[i32],
    runs: &mut Vec<(i32, Result<Level, String>)>,
    (refinement, max_steps, threads): RunsAt,
) -> Result<(), String> {
    let missing: Vec<i32> = wanted
        .iter()
        .copied()
        .filter(|h| runs.iter().all(|(k, _)| k != h))
        .collect();
    let made = in_parallel(&missing, threads, |h| {
        let scene = refined(scene, refinement, h);
        Ok(scene.and_then(|s| Ok(level_of(&s, &summarise(&s, max_steps)?))))
    })?;
    runs.extend(missing.into_iter().zip(made));
    Ok(())
}

/// The run made at `halvings` (made before by `make_runs`).
fn run_of(runs: &[(i32, Result<Level, String>)], halvings: i32) -> Result<Level, String> {
    let made = runs.iter().find(|(k, _)| *k == halvings);
    made.map(|(_, r)| r.clone()).expect("made before")
}

/// A streamed run's failure in words.
fn stream_error_message(error: crate::report::StreamError) -> String {
    use crate::report::StreamError;
    match error {
        StreamError::Refused(m) | StreamError::Output { message: m, .. } => m,
        StreamError::Solver { error, .. } => format!("the solver failed {error}"),
        StreamError::Interrupted { time, .. } => format!("interrupted at t = {time} s"),
    }
}
