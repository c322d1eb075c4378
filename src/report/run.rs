//! Drive a simulation from start to exit, recording every internal step.

use super::stream::{check_run_length, drive_into, StreamError};
use super::summary::RunSummary;
use super::trace::Trace;
use crate::scene::Scene;
use crate::simulation::run_end::{run_end, RunEnd};
use crate::simulation::{Simulation, SolverError};
use std::fmt;
use std::ops::ControlFlow;
use std::time::Duration;

/// When a run without `solver.end_time` gives up waiting for the exit: this
/// many times the rigid-beam travel time of the last vehicle to leave.
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

/// The time at which a run stops if the last contact has not left the
/// beam (`simulation::run_end`, the one rule): `solver.end_time`, or
/// `DEFAULT_END_TIME_FACTOR` × the last exit at the vehicles' initial
/// speeds. Without an end time a vehicle must start moving.
pub fn stop_time(scene: &Scene) -> Result<f64, String> {
    match run_end(scene) {
        RunEnd::EndTime(end) => Ok(end),
        RunEnd::LastExit { distance, speed } => Ok(DEFAULT_END_TIME_FACTOR * distance / speed),
        RunEnd::NoExit => Err(format!(
            "body.initial_speed = {:?} and no vehicle moves: a run without solver.end_time \
             ends when the last contact leaves the beam, so a vehicle must start moving",
            scene.body.initial_speed
        )),
    }
}

pub use crate::simulation::Steppable;

/// Run a valid scene until the body leaves the beam (or the stop time),
/// recording the outputs after every internal step of `solver.step`, and
/// calling `on_step` after each. The whole trace is kept in memory: for
/// runs of bounded length (tests, studies); `guideway run` streams instead
/// (`stream::drive_into`).
pub fn run_scene(scene: &Scene, on_step: impl FnMut(StepProgress)) -> Result<Run, RunError> {
    check_run_length(scene, u64::MAX, "").map_err(RunError::Setup)?;
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
    let mut trace = Trace::for_outputs(simulation.outputs());
    let result = drive_into(scene, simulation, &mut trace, |progress| {
        on_step(progress);
        ControlFlow::Continue(())
    });
    match result {
        Ok(streamed) => Ok(Run {
            trace,
            exit_time: streamed.exit_time,
            solve_time: streamed.solve_time,
            integrator: None,
        }),
        Err(StreamError::Solver { error, .. }) => Err(RunError::Solver {
            error,
            partial: Box::new(Run {
                trace,
                exit_time: None,
                solve_time: Duration::ZERO,
                integrator: None,
            }),
        }),
        // A trace takes every row and `on_step` never stops the run.
        Err(StreamError::Refused(message) | StreamError::Output { message, .. }) => {
            Err(RunError::Setup(message))
        }
        Err(StreamError::Interrupted { time, .. }) => {
            Err(RunError::Setup(format!("interrupted at t = {time} s")))
        }
    }
}
