//! Drive a simulation from start to exit, handing every row of outputs to a
//! sink as it is computed (a CSV file, a trace in memory, a summary), so
//! that memory does not grow with the length of the run.

use super::output_names;
use super::trace::Trace;
use crate::outputs::non_finite_output;
use crate::scene::Scene;
use crate::simulation::run_end::{last_to_leave, run_end, RunEnd};
use crate::simulation::{Advance, SolverError, Steppable};
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// Steps a run may take unless told otherwise (`guideway run --max-steps`):
/// a few seconds on the paper's two-element beam, about a minute on 128
/// elements (the cost of a step grows linearly with the elements).
pub const DEFAULT_MAX_STEPS: u64 = 1_000_000;

/// When a run without `solver.end_time` gives up waiting for the exit: this
/// many times the rigid-beam travel time of the last vehicle to leave.
pub const DEFAULT_END_TIME_FACTOR: f64 = 10.0;

/// Where a run is, reported after each internal step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepProgress {
    pub time: f64,
    /// 0 at the start, 1 at the exit or the end time (an estimate between).
    pub fraction: f64,
}

/// The time at which a run stops if the last contact has not left the
/// beam (`simulation::run_end`, the one rule): `solver.end_time`, or
/// `DEFAULT_END_TIME_FACTOR` × the last exit at the vehicles' initial
/// speeds. Without an end time a vehicle must start moving.
pub fn stop_time(scene: &Scene) -> Result<f64, String> {
    match run_end(scene) {
        RunEnd::EndTime(end) => Ok(end),
        RunEnd::LastExit { distance, speed } => Ok(DEFAULT_END_TIME_FACTOR * distance / speed),
        // Every vehicle is at rest: the first one's speed names the field.
        RunEnd::NoExit => Err(format!(
            "body.initial_speed = {:?} and no vehicle moves: a run without solver.end_time \
             ends when the last contact leaves the beam, so a vehicle must start moving",
            scene.vehicles[0].initial_speed
        )),
    }
}

/// Where the rows of a run go.
pub trait RowSink {
    /// One row: the time and every output, in the simulation's order. An
    /// error stops the run.
    fn row(&mut self, time: f64, values: &[f64]) -> Result<(), String>;
}

impl RowSink for Trace {
    fn row(&mut self, time: f64, values: &[f64]) -> Result<(), String> {
        self.push(time, values);
        Ok(())
    }
}

/// How a streamed run ended well.
#[derive(Debug, Clone, PartialEq)]
pub struct Streamed {
    /// When the contact point reached the end of the beam, if it did.
    pub exit_time: Option<f64>,
    /// Wall-clock time spent inside `advance_to`.
    pub solve_time: Duration,
    /// Rows after the initial one.
    pub steps: u64,
}

/// How a streamed run ended badly. `steps` counts the rows written after
/// the initial one.
#[derive(Debug, Clone, PartialEq)]
pub enum StreamError {
    /// Refused before the first step: nothing was simulated.
    Refused(String),
    /// A step failed, or gave a non-finite output (not written).
    Solver { error: SolverError, steps: u64 },
    /// `on_step` asked to stop (Ctrl-C).
    Interrupted { time: f64, steps: u64 },
    /// The sink failed.
    Output { message: String, steps: u64 },
}

/// The number of steps a run of `scene` takes at most, refused when it
/// exceeds `max_steps` (the message then ends with `how_to_raise`) or when
/// the stop time is below the time resolution of the simulation (1e-9 of a
/// step: no step would be taken).
pub fn check_run_length(scene: &Scene, max_steps: u64, how_to_raise: &str) -> Result<u64, String> {
    let stop = stop_time(scene)?;
    let step = scene.solver.step;
    let why_stop = match scene.solver.end_time {
        Some(_) => "solver.end_time".to_string(),
        None => format!(
            "{} × the last vehicle's exit at its initial_speed",
            super::DEFAULT_END_TIME_FACTOR
        ),
    };
    if stop.is_nan() || stop <= 1e-9 * step {
        return Err(format!(
            "the run would stop at t = {stop:e} s ({why_stop}), below the time resolution of \
             1e-9 × solver.step = {:e} s: no step would be taken",
            1e-9 * step
        ));
    }
    let steps = (stop / step).ceil();
    if steps.is_nan() || steps > max_steps as f64 {
        return Err(format!(
            "the run needs up to {steps:e} steps of solver.step = {step:e} s to reach t = \
             {stop:e} s ({why_stop}), more than the limit of {max_steps} steps{how_to_raise}"
        ));
    }
    Ok(steps as u64)
}

/// Drive `simulation` of `scene` until the body leaves the beam or the stop
/// time, writing the initial state and every internal step to `sink` and
/// calling `on_step` after each step; `ControlFlow::Break` stops the run.
/// The caller checks the run's length first (`check_run_length`).
pub fn drive_into(
    scene: &Scene,
    simulation: &mut impl Steppable,
    sink: &mut impl RowSink,
    mut on_step: impl FnMut(StepProgress) -> ControlFlow<()>,
) -> Result<Streamed, StreamError> {
    let stop = stop_time(scene).map_err(StreamError::Refused)?;
    let mut values = vec![0.0; simulation.outputs().len()];
    write_first_row(simulation, sink, &mut values)?;
    let names: Vec<String> = simulation
        .outputs()
        .iter()
        .map(|o| o.name.clone())
        .collect();
    let fraction = progress_fraction(scene, &names, simulation.time(), stop);
    let start_time = simulation.time();
    let mut streamed = Streamed {
        exit_time: None,
        solve_time: Duration::ZERO,
        steps: 0,
    };
    loop {
        // Multiples of the step, so that step times carry no accumulated
        // rounding.
        let target = (start_time + (streamed.steps + 1) as f64 * scene.solver.step).min(stop);
        let advance = write_step(simulation, sink, &mut values, target, &mut streamed)?;
        let time = simulation.time();
        let progress = StepProgress {
            time,
            fraction: fraction(time, &values),
        };
        if on_step(progress).is_break() {
            let steps = streamed.steps;
            return Err(StreamError::Interrupted { time, steps });
        }
        match advance {
            Advance::Exited { time } => {
                streamed.exit_time = Some(time);
                return Ok(streamed);
            }
            Advance::Reached if target >= stop => return Ok(streamed),
            Advance::Reached => {}
        }
    }
}

/// The row at the start, refused if an output is not finite.
fn write_first_row(
    simulation: &impl Steppable,
    sink: &mut impl RowSink,
    values: &mut [f64],
) -> Result<(), StreamError> {
    simulation.output_values(values);
    if let Some(bad) = non_finite_output(simulation.outputs(), values) {
        return Err(StreamError::Refused(format!(
            "{bad} at the start with these values; choose smaller ones"
        )));
    }
    sink.row(simulation.time(), values)
        .map_err(|message| StreamError::Output { message, steps: 0 })
}

/// One step to `target` and its row; the step's solve time and count
/// are added to `streamed`. A row with an output that is not finite is
/// not written: the step fails.
fn write_step(
    simulation: &mut impl Steppable,
    sink: &mut impl RowSink,
    values: &mut [f64],
    target: f64,
    streamed: &mut Streamed,
) -> Result<Advance, StreamError> {
    let steps = streamed.steps;
    let started = Instant::now();
    let advanced = simulation.advance_to(target);
    streamed.solve_time += started.elapsed();
    let advance = advanced.map_err(|error| StreamError::Solver { error, steps })?;
    simulation.output_values(values);
    let time = simulation.time();
    if let Some(bad) = non_finite_output(simulation.outputs(), values) {
        let message = format!("{bad} after the step to t = {time} s; nothing of it written");
        return Err(StreamError::Solver {
            error: SolverError { time, message },
            steps,
        });
    }
    sink.row(time, values)
        .map_err(|message| StreamError::Output { message, steps })?;
    streamed.steps += 1;
    Ok(advance)
}

/// The output the progress follows (`progress_fraction`): the travel
/// position of the vehicle that leaves last (`run_end::last_to_leave`),
/// whose exit ends a run without an end time; none if no vehicle moves.
pub fn progress_column(scene: &Scene, names: &[String]) -> Option<usize> {
    let (last, _) = last_to_leave(scene)?;
    output_names::travel_position(names, &scene.vehicles[last].name)
}

/// 0 at the start, 1 at the exit or the stop time: the larger of the
/// fractions of time and of the last vehicle's travel to its exit done.
pub(super) fn progress_fraction(
    scene: &Scene,
    names: &[String],
    start_time: f64,
    stop: f64,
) -> impl Fn(f64, &[f64]) -> f64 {
    let position = progress_column(scene, names);
    let travel = last_to_leave(scene).map(|(v, (distance, _))| {
        let start_position = scene.vehicles[v].initial_position;
        (start_position, distance)
    });
    move |time: f64, values: &[f64]| {
        let by_time = (time - start_time) / (stop - start_time);
        let by_position = match (position, travel) {
            (Some(i), Some((start, distance))) => (values[i] - start).abs() / distance,
            _ => 0.0,
        };
        by_time.max(by_position).clamp(0.0, 1.0)
    }
}
