//! The exported model: a scene seen as a table of named, typed variables,
//! with model-agnostic operations (set/get by value reference,
//! initialization, step, save/restore/serialize state).
//!
//! This is the only module that knows both the scene and the variables; the
//! FMI layer above it knows nothing of beams, the physics below it nothing of
//! FMI.

mod advance;
mod dynamics;
#[cfg(any(test, feature = "fake-physics"))]
pub mod fake;
pub mod snapshot;
pub mod variables;

pub use dynamics::Dynamics;
pub use variables::{
    Causality, Role, Setting, Value, VarType, Variability, Variable, VariableTable,
};

use crate::scene::Scene;
use crate::simulation::Advance;
use serde::{Deserialize, Serialize};
use variables::{param_value, set_param, Input};

/// Most internal solver steps one `do_step` may take. fmi2DoStep is
/// synchronous and cannot be cancelled: a communication step of 1e6 s with a
/// body at rest, or any step with a subnormal `solver.step`, would otherwise
/// hold the importer's thread for hours or forever. A million steps take
/// about 1.3 s on the built-in scenes, and allow communication steps of
/// 2500 s at their solver step.
pub const MAX_INTERNAL_STEPS_PER_CALL: f64 = 1e6;

/// Most internal steps a whole run may need (from the start to the stop
/// time, or to the estimated exit at the initial speed): leaving
/// initialization is refused beyond, before anything runs. At the built-in
/// scenes' cost of about 2 µs a step this is a few minutes; on fine meshes,
/// hours.
pub const MAX_RUN_STEPS: f64 = 1e8;

/// Default of `solver.wall_time_budget`: the wall-clock time one fmi2DoStep
/// may take before it is rolled back and discarded.
pub const DEFAULT_WALL_TIME_BUDGET: f64 = 10.0;

/// A refused operation, with a message naming what was wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelError(pub String);

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for ModelError {}

fn err<T>(msg: impl Into<String>) -> Result<T, ModelError> {
    Err(ModelError(msg.into()))
}

/// Before initialization is left, parameters may change; afterwards only
/// inputs may.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    Configuring,
    Running,
}

/// How a communication step ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StepOutcome {
    /// The communication point was reached.
    Completed,
    /// The body left the beam at `time` (communication time); the state is
    /// the exit state.
    Exited { time: f64 },
    /// The step failed; the state was rolled back to the start of the step.
    /// `curable`: a smaller communication step gets further (the message
    /// names one); otherwise every retry of it would fail the same way.
    Failed { message: String, curable: bool },
}

/// A saved state of the model (what `fmi2GetFMUstate` hands out).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Snapshot<S> {
    scene: Scene,
    inputs: [f64; 2],
    start_time: f64,
    phase: Phase,
    sim: Option<S>,
}

pub struct Model<D: Dynamics> {
    table: VariableTable,
    start_scene: Scene,
    scene: Scene,
    inputs: [f64; 2],
    /// Communication time of simulation time 0 (from fmi2SetupExperiment).
    start_time: f64,
    phase: Phase,
    /// Built on demand while configuring (to answer output getters), kept
    /// from initialization on.
    sim: Option<D>,
    /// End of the experiment (fmi2SetupExperiment), if the importer gave one.
    stop_time: Option<f64>,
    /// Wall-clock seconds one `do_step` may take (`solver.wall_time_budget`).
    wall_time_budget: f64,
    /// The last step discarded as curable, and why: retried unchanged it
    /// would fail again, so it is refused instead of run.
    discarded: Option<(DiscardedStep, String)>,
}

/// What a step is determined by, besides the state: its time, size, inputs.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DiscardedStep {
    t: f64,
    h: f64,
    inputs: [f64; 2],
}

/// The FMU variable that a scene field path stands for: `body.mass` is
/// `wheel.mass`, `sensors[0].position` is `sensor.midspan.position`; other
/// paths (`beam.*`, `solver.*`) are the same.
pub fn variable_name(scene: &Scene, path: &str) -> String {
    if let Some(rest) = path.strip_prefix("body.") {
        return format!("{}.{rest}", scene.body.name);
    }
    if let Some(rest) = path.strip_prefix("sensors[") {
        if let Some((index, field)) = rest.split_once("].") {
            if let Some(s) = index
                .parse::<usize>()
                .ok()
                .and_then(|i| scene.sensors.get(i))
            {
                return format!("sensor.{}.{field}", s.name);
            }
        }
    }
    path.to_string()
}

/// Check every rule of the scene (`Scene::validate`), reporting each broken
/// one with the FMU variable's name, its value and the rule.
pub fn validate(scene: &Scene) -> Result<(), String> {
    scene.validate().map_err(|e| {
        let problems = e.problems();
        if problems.is_empty() {
            return e.to_string();
        }
        problems
            .into_iter()
            .map(|mut p| {
                p.path = variable_name(scene, &p.path);
                p.to_string()
            })
            .collect::<Vec<_>>()
            .join("; ")
    })
}

/// The first output of `sim` that is not finite, with its value.
fn first_non_finite<D: Dynamics>(sim: &D) -> Option<(String, f64)> {
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    let k = values.iter().position(|x| !x.is_finite())?;
    Some((sim.outputs()[k].name.clone(), values[k]))
}

impl<D: Dynamics> Model<D> {
    /// The model of `scene`, with the scene's values as start values.
    pub fn new(scene: Scene) -> Result<Model<D>, ModelError> {
        validate(&scene).map_err(ModelError)?;
        let sim =
            D::build(&scene).map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
        let table = VariableTable::new(&scene, sim.outputs());
        Ok(Model {
            table,
            start_scene: scene.clone(),
            inputs: [scene.body.force_x, scene.body.force_y],
            scene,
            start_time: 0.0,
            phase: Phase::Configuring,
            sim: Some(sim),
            stop_time: None,
            wall_time_budget: DEFAULT_WALL_TIME_BUDGET,
            discarded: None,
        })
    }

    pub fn table(&self) -> &VariableTable {
        &self.table
    }

    /// The scene with the parameters applied so far.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Back to the start values, before initialization.
    pub fn reset(&mut self) {
        self.scene = self.start_scene.clone();
        self.inputs = [self.scene.body.force_x, self.scene.body.force_y];
        self.start_time = 0.0;
        self.phase = Phase::Configuring;
        self.sim = None;
        self.stop_time = None;
        self.wall_time_budget = DEFAULT_WALL_TIME_BUDGET;
        self.discarded = None;
    }

    /// fmi2SetupExperiment's times: all or nothing. A stop time bounds the
    /// run's length (checked when initialization is left).
    pub fn set_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ModelError> {
        if !start.is_finite() {
            return err(format!("startTime = {start}: must be finite"));
        }
        if let Some(t) = stop {
            if !(t.is_finite() && t >= start) {
                return err(format!(
                    "stopTime = {t}: must be finite and >= startTime = {start}"
                ));
            }
        }
        self.start_time = start;
        self.stop_time = stop;
        Ok(())
    }

    /// Communication time of the current state.
    pub fn time(&self) -> f64 {
        self.start_time + self.sim.as_ref().map_or(0.0, |s| s.time())
    }

    /// Communication time of the exit, once the body has left the beam.
    pub fn exit_time(&self) -> Option<f64> {
        let sim = self.sim.as_ref().filter(|_| self.phase == Phase::Running)?;
        sim.exit_time().map(|t| self.start_time + t)
    }

    fn variable(&self, vr: u32, ty: VarType) -> Result<&Variable, ModelError> {
        let Some(v) = self.table.get(vr) else {
            return err(format!(
                "unknown value reference {vr} (this model has 0..={})",
                self.table.variables().len().saturating_sub(1)
            ));
        };
        if v.ty != ty {
            return err(format!(
                "value reference {vr} ({}) is of type {}, not {}",
                v.name,
                v.ty.as_str(),
                ty.as_str()
            ));
        }
        Ok(v)
    }

    fn ensure_sim(&mut self) -> Result<&mut D, ModelError> {
        if self.sim.is_none() {
            validate(&self.scene).map_err(ModelError)?;
            let mut sim = D::build(&self.scene)
                .map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
            sim.set_body_force(self.inputs[0], self.inputs[1]);
            self.sim = Some(sim);
        }
        Ok(self.sim.as_mut().expect("just built"))
    }

    fn output_values(&mut self) -> Result<Vec<f64>, ModelError> {
        let n = self.table.outputs().count();
        let sim = self.ensure_sim()?;
        let mut values = vec![0.0; sim.outputs().len()];
        sim.output_values(&mut values);
        if values.len() != n {
            return err(format!(
                "the model has {} outputs, its variable table {n}",
                values.len()
            ));
        }
        // Parameters can be finite and valid one by one and still overflow
        // an output (a huge speed squared): refuse rather than hand out inf.
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return err(format!(
                "output {} is {} with these parameters; choose smaller values",
                sim.outputs()[k].name,
                values[k]
            ));
        }
        Ok(values)
    }

    /// Values of the variables `vrs`, all of type `ty`.
    pub fn get(&mut self, ty: VarType, vrs: &[u32]) -> Result<Vec<Value>, ModelError> {
        let mut outputs: Option<Vec<f64>> = None;
        let mut values = Vec::with_capacity(vrs.len());
        for &vr in vrs {
            let role = self.variable(vr, ty)?.role;
            let value = match role {
                Role::Parameter(p) => param_value(&self.scene, p),
                Role::Setting(Setting::WallTimeBudget) => Value::Real(self.wall_time_budget),
                Role::Input(i) => Value::Real(self.inputs[i as usize]),
                Role::Output(k) => {
                    if outputs.is_none() {
                        outputs = Some(self.output_values()?);
                    }
                    let x = outputs.as_ref().expect("just computed")[k];
                    match ty {
                        VarType::Integer => Value::Integer(x as i32),
                        VarType::Boolean => Value::Boolean(x != 0.0),
                        VarType::Real => Value::Real(x),
                    }
                }
            };
            values.push(value);
        }
        Ok(values)
    }

    /// Set the variables `vrs`: all or nothing. Parameters only before
    /// initialization is left, inputs at any time, outputs never.
    pub fn set(&mut self, vrs: &[u32], values: &[Value]) -> Result<(), ModelError> {
        let mut scene = self.scene.clone();
        let mut inputs = self.inputs;
        let mut budget = self.wall_time_budget;
        let mut params_changed = false;
        for (&vr, &value) in vrs.iter().zip(values) {
            let ty = match value {
                Value::Real(_) => VarType::Real,
                Value::Integer(_) => VarType::Integer,
                Value::Boolean(_) => VarType::Boolean,
            };
            let v = self.variable(vr, ty)?;
            let shown = match value {
                Value::Real(x) => format!("{x}"),
                Value::Integer(n) => format!("{n}"),
                Value::Boolean(b) => format!("{b}"),
            };
            let refuse = |rule: &str| err(format!("cannot set {} = {shown}: {rule}", v.name));
            match v.role {
                Role::Output(_) => return refuse("it is an output"),
                Role::Parameter(_) | Role::Setting(_) if self.phase == Phase::Running => {
                    return refuse(
                        "it is a fixed parameter, settable only before initialization mode is left",
                    )
                }
                Role::Parameter(p) => {
                    if let Err(rule) = set_param(&mut scene, p, value) {
                        return refuse(&rule);
                    }
                    params_changed = true;
                }
                Role::Setting(Setting::WallTimeBudget) => match value {
                    Value::Real(x) if x.is_finite() && x > 0.0 => budget = x,
                    _ => return refuse("must be a finite number of seconds > 0"),
                },
                Role::Input(i) => match value {
                    Value::Real(x) if x.is_finite() => inputs[i as usize] = x,
                    _ => return refuse("must be finite"),
                },
            }
        }
        self.scene = scene;
        self.inputs = inputs;
        self.wall_time_budget = budget;
        if params_changed {
            self.sim = None;
        } else if let Some(sim) = self.sim.as_mut() {
            sim.set_body_force(inputs[0], inputs[1]);
        }
        Ok(())
    }

    /// Leave initialization: check the whole scene and build the simulation.
    pub fn initialize(&mut self) -> Result<(), ModelError> {
        validate(&self.scene).map_err(|e| ModelError(format!("invalid parameters: {e}")))?;
        self.check_run_length()?;
        self.output_values()?;
        self.phase = Phase::Running;
        Ok(())
    }

    /// Refuse a run that would need more than `MAX_RUN_STEPS` internal steps:
    /// to the stop time (the experiment's, else the scene's), else to the
    /// exit at the initial speed. A body at rest with no stop time is left
    /// to the per-call limits.
    fn check_run_length(&self) -> Result<(), ModelError> {
        let (scene, step) = (&self.scene, self.scene.solver.step);
        let v0 = scene.body.initial_speed;
        let to_exit = if v0 > 0.0 {
            (scene.beam.length - scene.body.initial_position) / v0
        } else {
            scene.body.initial_position / -v0
        };
        let (horizon, what) = match (self.stop_time, scene.solver.end_time) {
            (Some(stop), _) => (stop - self.start_time, "to the stop time"),
            (None, Some(end)) => (end, "to solver.end_time"),
            (None, None) if v0 != 0.0 => (to_exit, "to the exit at the initial speed"),
            (None, None) => return Ok(()),
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
        self.check_step(t, h)?;
        let now = self.time();
        let t0 = self.start_time;
        let this = DiscardedStep {
            t,
            h,
            inputs: self.inputs,
        };
        if let Some((step, reason)) = &self.discarded {
            if *step == this {
                return Ok(StepOutcome::Failed {
                    message: format!(
                        "this step (t = {t} s, h = {h} s) was discarded by the previous call and \
                         nothing has changed since, so it would fail again ({reason}); \
                         retry with a smaller step or other inputs"
                    ),
                    curable: false,
                });
            }
        }
        let budget = std::time::Duration::try_from_secs_f64(self.wall_time_budget)
            .unwrap_or(std::time::Duration::MAX);
        let (step, probe) = (
            self.scene.solver.step,
            h.min(self.scene.solver.step) / 1024.0,
        );
        let sim = self.sim.as_mut().expect("running model has a simulation");
        if let Some(time) = sim.exit_time() {
            return Ok(StepOutcome::Exited { time: t0 + time });
        }
        let saved = sim.state();
        let start = sim.time();
        let rolled_back = format!("step rolled back to t = {now} s");
        let outcome = match advance::advance_within(sim, t + h - t0, step, budget) {
            Ok(Advance::Reached) => StepOutcome::Completed,
            Ok(Advance::Exited { time }) => StepOutcome::Exited { time: t0 + time },
            Err(advance::Stop::Solver(e)) => {
                let (curable, cure) = match advance::curable(sim, start, &saved, probe) {
                    Ok(m) => (true, m),
                    Err(m) => (false, m),
                };
                StepOutcome::Failed {
                    message: format!("solver failed {e}; {rolled_back}; {cure}"),
                    curable,
                }
            }
            Err(advance::Stop::OverBudget { reached }) => StepOutcome::Failed {
                message: format!(
                    "the step took longer than solver.wall_time_budget = {} s (it had reached \
                     t = {} s of {} s); {rolled_back}; use shorter communication steps or a \
                     larger budget",
                    self.wall_time_budget,
                    t0 + reached,
                    t + h
                ),
                curable: true,
            },
        };
        let outcome = Self::check_outputs(sim, outcome, t0, &rolled_back);
        if let StepOutcome::Failed { .. } = outcome {
            sim.restore(&saved)
                .map_err(|e| ModelError(format!("cannot roll back the failed step: {e}")))?;
        }
        self.discarded = match &outcome {
            StepOutcome::Failed {
                message,
                curable: true,
            } => Some((this, message.clone())),
            _ => None,
        };
        Ok(outcome)
    }

    /// A step that ended with a non-finite output, or in a state that
    /// could not be restored, failed (no step size cures an overflow).
    fn check_outputs(sim: &D, outcome: StepOutcome, t0: f64, rolled_back: &str) -> StepOutcome {
        if let StepOutcome::Failed { .. } = outcome {
            return outcome;
        }
        let at = t0 + sim.time();
        let problem = match first_non_finite(sim) {
            Some((name, x)) => Some(format!("output {name} became {x} at t = {at} s")),
            None => sim
                .check_state(&sim.state())
                .err()
                .map(|e| format!("the state at t = {at} s is unusable: {e}")),
        };
        match problem {
            Some(p) => StepOutcome::Failed {
                message: format!("{p}; {rolled_back}"),
                curable: false,
            },
            None => outcome,
        }
    }

    pub fn snapshot(&self) -> Snapshot<D::State> {
        Snapshot {
            scene: self.scene.clone(),
            inputs: self.inputs,
            start_time: self.start_time,
            phase: self.phase,
            sim: match self.phase {
                Phase::Running => self.sim.as_ref().map(|s| s.state()),
                Phase::Configuring => None,
            },
        }
    }

    /// Check a snapshot before anything of it is used: it may come from a
    /// forged serialized state. It must be a state of this model: its scene
    /// this model's with at most the parameters changed, each within its
    /// rule (checked before any vector is sized by them), the whole scene
    /// valid once running; finite inputs and times.
    pub fn check_snapshot(&self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        let theirs = &snap.scene;
        let refuse = |why: String| err(format!("the state does not fit this model: {why}"));
        if theirs.sensors.len() != self.start_scene.sensors.len() {
            return refuse(format!(
                "it has {} sensors, this model {}",
                theirs.sensors.len(),
                self.start_scene.sensors.len()
            ));
        }
        let mut mine = self.start_scene.clone();
        for v in self.table.variables() {
            if let Role::Parameter(p) = v.role {
                let value = param_value(theirs, p);
                if let Err(rule) = set_param(&mut mine, p, value) {
                    return refuse(format!("{} = {value:?}: {rule}", v.name));
                }
            }
        }
        if mine != *theirs {
            return refuse("its scene differs from this model's in more than parameters".into());
        }
        if snap.phase == Phase::Running {
            validate(theirs)
                .map_err(|e| ModelError(format!("the state's scene is invalid: {e}")))?;
        }
        if !(snap.inputs.iter().all(|x| x.is_finite()) && snap.start_time.is_finite()) {
            return refuse("an input or the start time is not finite".into());
        }
        if (snap.phase == Phase::Running) != snap.sim.is_some() {
            return refuse(format!(
                "phase {:?} with the dynamics' state {}",
                snap.phase,
                if snap.sim.is_some() {
                    "present"
                } else {
                    "missing"
                }
            ));
        }
        Ok(())
    }

    /// Restore `snap` (checked first); on any refusal the model is unchanged.
    pub fn restore(&mut self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        self.check_snapshot(snap)?;
        let sim = match &snap.sim {
            Some(state) => Some(self.restored_sim(snap, state)?),
            None => None,
        };
        self.scene = snap.scene.clone();
        self.inputs = snap.inputs;
        self.start_time = snap.start_time;
        self.phase = snap.phase;
        self.sim = sim;
        self.discarded = None;
        Ok(())
    }

    /// The dynamics at `state`: this model's own (when the scene is the
    /// same) or new ones built for the state's (valid) scene. The state must
    /// fit them and give finite outputs; if not, this model's own dynamics
    /// are put back as they were.
    fn restored_sim(
        &mut self,
        snap: &Snapshot<D::State>,
        state: &D::State,
    ) -> Result<D, ModelError> {
        let own = match self.sim.take() {
            Some(sim) if self.scene == snap.scene => Some(sim),
            other => {
                self.sim = other;
                None
            }
        };
        let old = own.as_ref().map(|s| s.state());
        let mut sim = match own {
            Some(sim) => sim,
            None => D::build(&snap.scene)
                .map_err(|e| ModelError(format!("cannot rebuild the model: {e}")))?,
        };
        let fitted = sim.restore(state).and_then(|()| {
            sim.set_body_force(snap.inputs[0], snap.inputs[1]);
            match first_non_finite(&sim) {
                Some((name, x)) => Err(format!("output {name} would be {x}")),
                None if !sim.time().is_finite() => Err(format!("its time is {}", sim.time())),
                None => Ok(()),
            }
        });
        match (fitted, old) {
            (Ok(()), _) => Ok(sim),
            (Err(e), old) => {
                if let Some(old) = old {
                    sim.restore(&old)
                        .map_err(|e| ModelError(format!("cannot put the model back: {e}")))?;
                    sim.set_body_force(self.inputs[0], self.inputs[1]);
                    self.sim = Some(sim);
                }
                err(format!("cannot restore the state: {e}"))
            }
        }
    }

    /// The versioned byte form of a snapshot, tied to the model `guid`.
    pub fn serialize(snap: &Snapshot<D::State>, guid: &str) -> Result<Vec<u8>, ModelError> {
        snapshot::encode(guid, snap).map_err(ModelError)
    }

    pub fn deserialize(bytes: &[u8], guid: &str) -> Result<Snapshot<D::State>, ModelError> {
        snapshot::decode(guid, bytes).map_err(ModelError)
    }

    /// Input values as they are now: (force_x, force_y).
    pub fn input_values(&self) -> (f64, f64) {
        (
            self.inputs[Input::ForceX as usize],
            self.inputs[Input::ForceY as usize],
        )
    }
}

#[cfg(test)]
mod tests;
