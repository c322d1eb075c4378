//! The exported model: a scene seen as a table of named, typed variables,
//! with model-agnostic operations (set/get by value reference,
//! initialization, step, save/restore/serialize state).
//!
//! This is the only module that knows both the scene and the variables; the
//! FMI layer above it knows nothing of beams, the physics below it nothing of
//! FMI.

mod dynamics;
#[cfg(any(test, feature = "fake-physics"))]
pub mod fake;
pub mod snapshot;
mod structure;
pub mod variables;

pub use dynamics::Dynamics;
pub use structure::initial_dependencies;
pub use variables::{
    Causality, DisplayUnit, Role, Value, VarType, Variability, Variable, VariableTable,
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
    /// The solver failed; the state was rolled back to the start of the step.
    Failed { message: String },
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

impl<D: Dynamics> Model<D> {
    /// The model of `scene`, with the scene's values as start values.
    pub fn new(scene: Scene) -> Result<Model<D>, ModelError> {
        validate(&scene).map_err(ModelError)?;
        let sim =
            D::build(&scene).map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
        let mut table = VariableTable::new(&scene, sim.outputs());
        let mut start_values = vec![0.0; sim.outputs().len()];
        sim.output_values(&mut start_values);
        table.set_output_nominals(&start_values);
        Ok(Model {
            table,
            start_scene: scene.clone(),
            inputs: [scene.body.force_x, scene.body.force_y],
            scene,
            start_time: 0.0,
            phase: Phase::Configuring,
            sim: Some(sim),
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
    }

    pub fn set_start_time(&mut self, t: f64) -> Result<(), ModelError> {
        if !t.is_finite() {
            return err(format!("startTime = {t}: must be finite"));
        }
        self.start_time = t;
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
            // Built with the inputs as the scene's forces, so that the
            // state at t = 0 (the contact force) balances them.
            let mut scene = self.scene.clone();
            scene.body.force_x = self.inputs[Input::ForceX as usize];
            scene.body.force_y = self.inputs[Input::ForceY as usize];
            let mut sim =
                D::build(&scene).map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
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
                Role::Parameter(_) if self.phase == Phase::Running => {
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
                Role::Input(i) => match value {
                    Value::Real(x) if x.is_finite() => inputs[i as usize] = x,
                    _ => return refuse("must be finite"),
                },
            }
        }
        let inputs_changed = inputs != self.inputs;
        self.scene = scene;
        self.inputs = inputs;
        // Before initialization is left the state at t = 0 follows the
        // parameters and the inputs: rebuild it on demand.
        if params_changed || (inputs_changed && self.phase == Phase::Configuring) {
            self.sim = None;
        } else if let Some(sim) = self.sim.as_mut() {
            sim.set_body_force(inputs[0], inputs[1]);
        }
        Ok(())
    }

    /// Leave initialization: check the whole scene and build the simulation.
    pub fn initialize(&mut self) -> Result<(), ModelError> {
        validate(&self.scene).map_err(|e| ModelError(format!("invalid parameters: {e}")))?;
        self.output_values()?;
        self.phase = Phase::Running;
        Ok(())
    }

    /// One communication step from `t` (which must match the model's time up
    /// to accumulated rounding) to `t + h`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
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
        let t0 = self.start_time;
        let target = t + h - t0;
        let sim = self.sim.as_mut().expect("running model has a simulation");
        if let Some(time) = sim.exit_time() {
            return Ok(StepOutcome::Exited { time: t0 + time });
        }
        let saved = sim.state();
        let outcome = match sim.advance_to(target) {
            Ok(Advance::Reached) => StepOutcome::Completed,
            Ok(Advance::Exited { time }) => StepOutcome::Exited { time: t0 + time },
            Err(e) => StepOutcome::Failed {
                message: format!("solver failed {e}; step rolled back to t = {now} s"),
            },
        };
        let mut values = vec![0.0; sim.outputs().len()];
        sim.output_values(&mut values);
        let outcome = match values.iter().position(|x| !x.is_finite()) {
            Some(k) if !matches!(outcome, StepOutcome::Failed { .. }) => StepOutcome::Failed {
                message: format!(
                    "output {} became {} at t = {} s; step rolled back to t = {now} s",
                    sim.outputs()[k].name,
                    values[k],
                    t0 + sim.time()
                ),
            },
            _ => outcome,
        };
        if let StepOutcome::Failed { .. } = outcome {
            sim.restore(&saved)
                .map_err(|e| ModelError(format!("cannot roll back the failed step: {e}")))?;
        }
        Ok(outcome)
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

    pub fn restore(&mut self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        if snap.scene.body.name != self.start_scene.body.name
            || snap.scene.sensors.len() != self.start_scene.sensors.len()
        {
            return err("the state belongs to another model");
        }
        let sim = match &snap.sim {
            Some(state) => {
                let mut sim = match self.sim.take() {
                    Some(sim) if self.scene == snap.scene => sim,
                    _ => D::build(&snap.scene)
                        .map_err(|e| ModelError(format!("cannot rebuild the model: {e}")))?,
                };
                sim.restore(state)
                    .map_err(|e| ModelError(format!("cannot restore the state: {e}")))?;
                sim.set_body_force(snap.inputs[0], snap.inputs[1]);
                Some(sim)
            }
            None => None,
        };
        self.scene = snap.scene.clone();
        self.inputs = snap.inputs;
        self.start_time = snap.start_time;
        self.phase = snap.phase;
        self.sim = sim;
        Ok(())
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
