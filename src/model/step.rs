//! Initialization's run-length check and the communication step: checks
//! before anything runs, the advance under the wall-time budget, roll-back
//! and the classification of failures (see `advance`).

use super::estimate::Estimator;
use super::extrapolate::{InputHistory, Ramp};
use super::{
    advance, apply_inputs, err, DiscardedStep, Dynamics, Model, ModelError, Phase, StepOutcome,
    MAX_INTERNAL_STEPS_PER_CALL, MAX_RUN_STEPS,
};
use crate::outputs::non_finite_output;
use crate::scene::Scene;
use crate::simulation::run_end::{exit_time, run_end, RunEnd};
use crate::simulation::Advance;

impl<D: Dynamics> Model<D> {
    /// Refuse a run that would need more than `MAX_RUN_STEPS` internal steps:
    /// to whichever comes first of the experiment's stop time and the run's
    /// end (`simulation::run_end`, the one rule: the scene's end time, else
    /// the last vehicle's exit at the initial speeds, an estimate: forces
    /// may change the speeds). A run at rest with no stop time is left to
    /// the per-call limits.
    pub(super) fn check_run_length(&self) -> Result<(), ModelError> {
        let (scene, step) = (&self.scene, self.scene.solver.step);
        let run_end = match run_end(scene) {
            RunEnd::EndTime(t) => Some((t, "to solver.end_time")),
            RunEnd::LastExit { distance, speed } => Some((
                exit_time((distance, speed)),
                "to the last vehicle's exit at the initial speeds",
            )),
            RunEnd::NoExit => None,
        };
        let ends = [
            self.stop_time
                .map(|t| (t - self.start_time, "to the stop time")),
            run_end,
        ];
        let Some((horizon, what)) = ends
            .into_iter()
            .flatten()
            .min_by(|a, b| a.0.total_cmp(&b.0))
        else {
            return Ok(());
        };
        let steps = (horizon / step).ceil();
        if steps > MAX_RUN_STEPS {
            return err(format!(
                "the run would need {steps:e} internal steps of solver.step = {step:e} s \
                 ({what}, {horizon:e} s), more than the {MAX_RUN_STEPS:e} allowed; \
                 use a larger solver.step (integrator \"hht\" is stable at any step) \
                 or a shorter run"
            ));
        }
        Ok(())
    }

    /// Refuse a communication step the model cannot take as asked (before
    /// anything runs): bad size, too many internal steps, wrong time, a size
    /// below the resolution of the time.
    fn check_step(&self, t: f64, h: f64) -> Result<(), ModelError> {
        if self.phase != Phase::Running {
            return err("the model is not initialized");
        }
        if !(h.is_finite() && h > 0.0) {
            return err(format!(
                "communicationStepSize = {h}: must be finite and > 0"
            ));
        }
        let internal_steps = (h / self.scene.solver.step).ceil();
        if internal_steps > MAX_INTERNAL_STEPS_PER_CALL {
            return err(format!(
                "communicationStepSize = {h} s needs {internal_steps:e} internal steps of \
                 solver.step = {:e} s, more than the {MAX_INTERNAL_STEPS_PER_CALL:e} one call \
                 may take; use shorter communication steps",
                self.scene.solver.step
            ));
        }
        let now = self.time();
        if !t.is_finite() || (t - now).abs() > 1e-9 * now.abs().max(1.0) {
            return err(format!(
                "currentCommunicationPoint = {t} s does not match the model's time {now} s"
            ));
        }
        // t + h must be a different number, close to the step asked for:
        // otherwise the master's clock and the model's part ways.
        let taken = (t + h) - t;
        if (taken - h).abs() > 1e-6 * h {
            return err(format!(
                "communicationStepSize = {h:e} s is below the resolution of \
                 currentCommunicationPoint = {t:e} s (t + h - t = {taken:e} s); \
                 use larger steps or a start time nearer 0"
            ));
        }
        Ok(())
    }

    /// One communication step from `t` (which must match the model's time up
    /// to accumulated rounding) to `t + h`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        self.step_to(t, h, false)
    }

    /// `do_step`, but ending early at the end of the internal step in which
    /// a simulation event (entry, exit, lift-off, landing, ...) happened:
    /// then `ended_at_event()` and `time()` is below `t + h` (FMI 3.0's early
    /// return). The internal steps are the ones `do_step` takes (it passes
    /// the same grid points).
    pub fn do_step_until_event(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        self.step_to(t, h, true)
    }

    /// Whether the last step ended early at an event
    /// (`do_step_until_event`).
    pub fn ended_at_event(&self) -> bool {
        self.ended_at_event
    }

    fn step_to(&mut self, t: f64, h: f64, until_event: bool) -> Result<StepOutcome, ModelError> {
        self.ended_at_event = false;
        self.check_step(t, h)?;
        if let Some((step, reason)) = &self.discarded {
            if step.t == t && step.h == h && step.inputs == self.inputs {
                return Ok(StepOutcome::Failed {
                    message: format!(
                        "this step (t = {t} s, h = {h} s) was discarded by the previous call and \
                         nothing has changed since, so it would fail the same way ({reason}); \
                         retry with a smaller step or other inputs"
                    ),
                    curable: false,
                });
            }
        }
        // The outputs' storage is reused for the step's outputs. (Not
        // `changing`: the roll-back copy is the step's own business.)
        let spare = self.outputs_now.take().unwrap_or_default();
        let events_before = self.sim.as_ref().map_or(0, |s| s.event_count());
        let to = self.snapped_target(t, h);
        let outcome = self.advance(to, spare, until_event)?;
        self.new_events = match (&outcome, &self.sim) {
            (StepOutcome::Failed { .. }, _) | (_, None) => Vec::new(),
            (_, Some(sim)) if sim.event_count() == events_before => Vec::new(),
            (_, Some(sim)) => sim.events_since(events_before),
        };
        self.discarded = match &outcome {
            StepOutcome::Failed {
                message,
                curable: true,
            } => {
                let inputs = self.inputs.clone();
                Some((DiscardedStep { t, h, inputs }, message.clone()))
            }
            _ => None,
        };
        Ok(outcome)
    }

    /// Where a step from `t` of `h` ends, free of the ulp-level noise of
    /// masters that count time in integers (libcosim passes t[k+1] - t[k],
    /// off by ulps of t): a step within a few ulp of the first step's size
    /// is that size, and a `t` within a few ulp of the model's time is the
    /// model's time.
    fn snapped_target(&mut self, t: f64, h: f64) -> f64 {
        let now = self.time();
        let ulp = f64::EPSILON * (now.abs() + h);
        let nominal = *self.nominal_step.get_or_insert(h);
        let h = if (h - nominal).abs() <= 8.0 * ulp {
            nominal
        } else {
            h
        };
        if (t - now).abs() <= 8.0 * ulp {
            now + h
        } else {
            t + h
        }
    }

    /// Advance the dynamics to communication time `to` within the wall-time
    /// budget; a failure is rolled back and classified. `spare`: storage
    /// for the outputs; `until_event`: stop after the internal step of an
    /// event.
    fn advance(
        &mut self,
        to: f64,
        spare: Vec<f64>,
        until_event: bool,
    ) -> Result<StepOutcome, ModelError> {
        let (now, t0, step) = (self.time(), self.start_time, self.scene.solver.step);
        let budget = self.wall_time_budget;
        let probe = (to - now).min(step) / 1024.0;
        let sim = self.sim.as_mut().expect("running model has a simulation");
        if let Some(time) = sim.exit_time() {
            return Ok(StepOutcome::Exited { time: t0 + time });
        }
        // (refused before anything changes: the step is not run)
        sim.check_target(snap_to_grid(to - t0, step))
            .map_err(|e| ModelError(format!("cannot step to t = {to} s: {e}")))?;
        let start = sim.time();
        let ramp = Ramp::new(
            start,
            now,
            &self.inputs,
            &self.input_derivatives,
            self.input_history.as_ref(),
        );
        if ramp.is_none() && self.loads_ramped {
            // The last step left a ramp's loads: back to the held inputs.
            apply_inputs(sim, &self.inputs, self.scene.vehicles.len());
            self.rollback.invalidate();
        }
        let (saved, next) = self.rollback.start(sim);
        let target = snap_to_grid(to - t0, step);
        let started = std::time::Instant::now();
        let ramp = ramp.as_ref().map(|r| (r, self.scene.vehicles.len()));
        let advanced = advance::advance_within(sim, target, step, budget, (until_event, ramp));
        let ended_at_event = matches!(advanced, Ok((Advance::Reached, true)));
        let span = (start, probe, now);
        let outcome = classify(advanced, (sim, saved), span, (budget, step), (t0, to));
        // (what the main run left of the budget; none left is 0, not the
        // unbounded budget a negative one would read as)
        let left = (budget - started.elapsed().as_secs_f64()).max(0.0);
        let estimator = self.estimator.as_mut();
        let span = (start, step, left, now);
        let outcome = estimated(outcome, estimator, &self.scene, (sim, saved), span);
        let (outcome, outputs) = check_reached(sim, outcome, t0, || rolled_back(now), spare, next);
        let outputs = outputs.map(|values| with_estimates(values, self.estimator.as_ref()));
        self.ended_at_event = ended_at_event && outcome == StepOutcome::Completed;
        if let StepOutcome::Failed { .. } = outcome {
            sim.restore(saved)
                .map_err(|e| ModelError(format!("cannot roll back the failed step: {e}")))?;
            self.rollback.restored();
        } else {
            self.completed(now, ramp.is_some());
        }
        // (Of the table's length: otherwise the getters' own check speaks.)
        let outputs_in_table = self.output_count;
        self.outputs_now = outputs.filter(|v| v.len() == outputs_in_table);
        Ok(outcome)
    }

    /// Keep a completed step (from communication time `now`; `ramped`:
    /// under a ramp of the inputs): its roll-back copy, and the inputs as
    /// the next step's history.
    fn completed(&mut self, now: f64, ramped: bool) {
        self.rollback.completed();
        self.loads_ramped = ramped;
        self.input_history = Some(InputHistory {
            time: now,
            values: self.inputs.clone(),
        });
        self.input_derivatives.clear();
    }
}

/// What the step's advance came to: completed, exited, or failed (a solver
/// failure asks `curable` whether a shorter step gets further, probing from
/// `start` by `probe`; an overrun of the budget says what to change; `now`:
/// the communication time the step began at).
fn classify<D: Dynamics>(
    advanced: Result<(Advance, bool), advance::Stop>,
    (sim, saved): (&mut D, &D::State),
    (start, probe, now): (f64, f64, f64),
    (budget, step): (f64, f64),
    (t0, to): (f64, f64),
) -> StepOutcome {
    match advanced {
        Ok((Advance::Reached, _)) => StepOutcome::Completed,
        Ok((Advance::Exited { time }, _)) => StepOutcome::Exited { time: t0 + time },
        Err(advance::Stop::Solver(e)) => {
            let (curable, cure) = match advance::curable(sim, start, saved, probe) {
                Ok(m) => (true, m),
                Err(m) => (false, m),
            };
            StepOutcome::Failed {
                message: format!("solver failed {e}; {}; {cure}", rolled_back(now)),
                curable,
            }
        }
        Err(advance::Stop::OverBudget { reached, foreseen }) => {
            let budget = (budget, step);
            over_budget(
                budget,
                (start, reached, foreseen),
                (t0, to),
                &rolled_back(now),
            )
        }
    }
}

/// A completed step with its error estimated, when the scene asks for an
/// estimate: failed (curable) where no companion could run it. `span`: the
/// step's start (dynamics time), the internal step, the wall time left and
/// the communication time the step began at.
fn estimated<D: Dynamics>(
    outcome: StepOutcome,
    estimator: Option<&mut Estimator<D>>,
    scene: &Scene,
    (sim, saved): (&D, &D::State),
    (start, step, left, now): (f64, f64, f64, f64),
) -> StepOutcome {
    let (StepOutcome::Completed, Some(estimator)) = (&outcome, estimator) else {
        return outcome;
    };
    let span = (sim.time(), step, left);
    match estimator.estimate(scene, sim, saved, span, start) {
        Ok(()) => StepOutcome::Completed,
        Err(problem) => StepOutcome::Failed {
            message: format!("{problem}; {}", rolled_back(now)),
            curable: true,
        },
    }
}

/// The outputs followed by the error estimates, if any.
fn with_estimates<D: Dynamics>(mut values: Vec<f64>, estimator: Option<&Estimator<D>>) -> Vec<f64> {
    if let Some(estimator) = estimator {
        values.extend_from_slice(estimator.values());
    }
    values
}

/// The words of a roll-back to communication time `now`.
fn rolled_back(now: f64) -> String {
    format!("step rolled back to t = {now} s")
}

/// A step stopped by `solver.wall_time_budget` (`budget`: the budget and
/// the internal step). Not one internal step done (`reached` ≤ `start`):
/// a shorter communication step cannot help, only a larger budget or a
/// smaller model; otherwise shorter communication steps can.
fn over_budget(
    (budget, step): (f64, f64),
    (start, reached, foreseen): (f64, f64, Option<String>),
    (t0, to): (f64, f64),
    rolled_back: &str,
) -> StepOutcome {
    let budget = crate::numbers::fmt_number(budget);
    if reached <= start {
        let why = match foreseen {
            Some(why) => format!(" (refused up front: {why})"),
            None => String::new(),
        };
        return StepOutcome::Failed {
            message: format!(
                "one internal step (solver.step = {step:e} s) takes longer than \
                 solver.wall_time_budget = {budget} s{why}; {rolled_back}; raise the budget, \
                 or make the model smaller (beam.elements, contacts)"
            ),
            curable: false,
        };
    }
    StepOutcome::Failed {
        message: format!(
            "the step took longer than solver.wall_time_budget = {budget} s (it had reached \
             t = {:e} s of {to:e} s); {rolled_back}; use shorter communication steps or \
             a larger budget",
            t0 + reached,
        ),
        curable: true,
    }
}

/// A target within a few ulp of a grid point of the internal steps is that
/// grid point: masters that count time in integers (libcosim: nanoseconds)
/// pass communication points off by an ulp, and the inputs' ramp over the
/// last internal step must not depend on it.
fn snap_to_grid(target: f64, step: f64) -> f64 {
    // (the grid point as the dynamics compute theirs: a count times the step)
    let grid = (target / step).round() * step;
    if (target - grid).abs() <= 4.0 * f64::EPSILON * grid.abs().max(step) {
        grid
    } else {
        target
    }
}

/// A step that ended with a non-finite output, or in a state that
/// could not be restored, failed (no step size cures an overflow); one
/// that did not hands back the outputs it checked, for the getters, and
/// its state is copied into `next` (the next step's roll-back copy).
fn check_reached<D: Dynamics>(
    sim: &D,
    outcome: StepOutcome,
    t0: f64,
    rolled_back: impl Fn() -> String,
    mut values: Vec<f64>,
    next: &mut D::State,
) -> (StepOutcome, Option<Vec<f64>>) {
    if let StepOutcome::Failed { .. } = outcome {
        return (outcome, None);
    }
    let at = t0 + sim.time();
    // (`output_values` writes every value: no need to clear them first.)
    values.resize(sim.outputs().len(), 0.0);
    sim.output_values(&mut values);
    let problem = match non_finite_output(sim.outputs(), &values) {
        Some(bad) => Some(format!("{bad} at t = {at} s")),
        None => sim
            .save_checked_into(next)
            .err()
            .map(|e| format!("the state at t = {at} s is unusable: {e}")),
    };
    match problem {
        Some(p) => {
            let message = format!("{p}; {}", rolled_back());
            let failed = StepOutcome::Failed {
                message,
                curable: false,
            };
            (failed, None)
        }
        None => (outcome, Some(values)),
    }
}
