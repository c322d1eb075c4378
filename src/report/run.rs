//! Drive a simulation from start to exit, recording every internal step.

use super::stream::{check_run_length, drive_into, StepProgress, StreamError};
use super::summary::RunSummary;
use super::trace::Trace;
use crate::scene::Scene;
use crate::simulation::{Simulation, SolverError};
use std::fmt;
use std::ops::ControlFlow;
use std::time::Duration;

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
