//! Drive a simulation from start to exit, recording every internal step.

use super::output_names;
use super::summary::RunSummary;
use super::trace::Trace;
use crate::scene::Scene;
use crate::simulation::{Advance, Simulation, SolverError};
use std::fmt;
use std::time::{Duration, Instant};

/// When a run without `solver.end_time` gives up waiting for the exit: this
/// many times the rigid-beam travel time (L − x0) / V0.
pub const DEFAULT_END_TIME_FACTOR: f64 = 10.0;

/// A finished (or, inside `RunError::Solver`, interrupted) run.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub trace: Trace,
    /// When the contact point reached the end of the beam, if it did.
    pub exit_time: Option<f64>,
    /// Wall-clock time spent inside `Simulation::advance_to`.
    pub solve_time: Duration,
    /// The integrator that ran (`Simulation::integrator_choice`), when known.
    pub integrator: Option<String>,
}

impl Run {
    pub fn summary(&self, scene: &Scene) -> RunSummary {
        let mut summary = RunSummary::from_trace(
            scene,
            &self.trace,
            self.exit_time,
            self.solve_time.as_secs_f64(),
        );
        summary.integrator = self.integrator.clone();
        summary
    }
}

/// Where a run is, reported after each internal step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepProgress {
    pub time: f64,
    /// 0 at the start, 1 at the exit or the end time (an estimate between).
    pub fraction: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub enum RunError {
    /// The model could not be built from the scene.
    Setup(String),
    /// A step failed; `partial` holds the steps before it.
    Solver {
        error: SolverError,
        partial: Box<Run>,
    },
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Setup(message) => write!(f, "cannot build the model: {message}"),
            RunError::Solver { error, .. } => write!(f, "the solver failed {error}"),
        }
    }
}

impl std::error::Error for RunError {}

/// The time at which a run stops if the body has not left the beam:
/// `solver.end_time`, or `DEFAULT_END_TIME_FACTOR` × (L − x0) / V0. Without
/// an end time the body must start moving towards the exit.
pub fn stop_time(scene: &Scene) -> Result<f64, String> {
    if let Some(end) = scene.solver.end_time {
        return Ok(end);
    }
    let speed = scene.body.initial_speed;
    if speed > 0.0 {
        let travel = scene.beam.length - scene.body.initial_position;
        Ok(DEFAULT_END_TIME_FACTOR * travel / speed)
    } else {
        Err(format!(
            "body.initial_speed = {speed:?}: must be > 0 for a run without solver.end_time \
             (the run ends when the body leaves the beam at x = L)"
        ))
    }
}

pub use crate::simulation::Steppable;

/// Run a valid scene until the body leaves the beam (or the stop time),
/// recording the outputs after every internal step of `solver.step`, and
/// calling `on_step` after each.
pub fn run_scene(scene: &Scene, on_step: impl FnMut(StepProgress)) -> Result<Run, RunError> {
    stop_time(scene).map_err(RunError::Setup)?;
    let mut simulation = Simulation::new(scene).map_err(RunError::Setup)?;
    let integrator = Some(simulation.integrator_choice().to_string());
    match drive(scene, &mut simulation, on_step) {
        Ok(run) => Ok(Run { integrator, ..run }),
        Err(RunError::Solver { error, partial }) => Err(RunError::Solver {
            error,
            partial: Box::new(Run {
                integrator,
                ..*partial
            }),
        }),
        Err(other) => Err(other),
    }
}

/// Drive an already built simulation of `scene` as `run_scene` does.
pub fn drive(
    scene: &Scene,
    simulation: &mut impl Steppable,
    mut on_step: impl FnMut(StepProgress),
) -> Result<Run, RunError> {
    let stop = stop_time(scene).map_err(RunError::Setup)?;
    let mut trace = Trace::for_outputs(simulation.outputs());
    let mut values = vec![0.0; trace.names.len()];
    simulation.output_values(&mut values);
    trace.push(simulation.time(), &values);

    let position = output_names::travel_position(&trace.names, &scene.body.name);
    let start_position = scene.body.initial_position;
    let travel = scene.beam.length - start_position;
    let start_time = simulation.time();
    let fraction_done = |time: f64, values: &[f64]| {
        let by_time = (time - start_time) / (stop - start_time);
        let by_position = position.map_or(0.0, |i| (values[i] - start_position) / travel);
        by_time.max(by_position).clamp(0.0, 1.0)
    };

    let mut solve_time = Duration::ZERO;
    let mut exit_time = None;
    let mut step_index: u64 = 0;
    loop {
        step_index += 1;
        // Multiples of the step, so that step times carry no accumulated
        // rounding.
        let target = (start_time + step_index as f64 * scene.solver.step).min(stop);
        let started = Instant::now();
        let advanced = simulation.advance_to(target);
        solve_time += started.elapsed();
        let advance = match advanced {
            Ok(advance) => advance,
            Err(error) => {
                let partial = Box::new(Run {
                    trace,
                    exit_time: None,
                    solve_time,
                    integrator: None,
                });
                return Err(RunError::Solver { error, partial });
            }
        };
        simulation.output_values(&mut values);
        let time = simulation.time();
        trace.push(time, &values);
        on_step(StepProgress {
            time,
            fraction: fraction_done(time, &values),
        });
        match advance {
            Advance::Exited { time } => {
                exit_time = Some(time);
                break;
            }
            Advance::Reached if target >= stop => break,
            Advance::Reached => {}
        }
    }
    Ok(Run {
        trace,
        exit_time,
        solve_time,
        integrator: None,
    })
}
