//! The exported model: a scene seen as a table of named, typed variables,
//! with model-agnostic operations (set/get by value reference,
//! initialization, step, save/restore/serialize state).
//!
//! This is the only module that knows both the scene and the variables; the
//! FMI layer above it knows nothing of beams, the physics below it nothing of
//! FMI.

mod advance;
mod dynamics;
mod estimate;
pub mod experiment;
mod extrapolate;
#[cfg(any(test, feature = "fake-physics"))]
pub mod fake;
mod fmu_model;
mod forces;
mod physics;
mod restore;
mod rollback;
pub mod snapshot;
mod step;
mod structure;
pub mod variables;

pub use dynamics::Dynamics;
pub use fmu_model::{FmuModel, ModelInfo, SCENE_FILE};
pub use physics::{SceneDynamics, SceneState};
pub use structure::initial_dependencies;
pub use variables::{
    Causality, DisplayUnit, Role, Setting, Value, VarType, Variability, Variable, VariableTable,
};

use crate::outputs::non_finite_output;
use crate::scene::{Scene, MAX_MAGNITUDE};
use serde::{Deserialize, Serialize};
use variables::{param_value, set_param, start_inputs};

/// The physics behind the exported FMUs: the scene's (vehicles or moving
/// forces), or the stand-in of `fake` when built with the `fake-physics`
/// feature (to test the FMI machinery alone).
#[cfg(not(feature = "fake-physics"))]
pub type ExportedDynamics = SceneDynamics;
#[cfg(feature = "fake-physics")]
pub type ExportedDynamics = fake::FakeDynamics;

/// The model the FMI fronts export (`FmuModel`).
pub type ExportedModel = Model<ExportedDynamics>;

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
    inputs: Vec<f64>,
    start_time: f64,
    phase: Phase,
    sim: Option<S>,
    /// The inputs at the start of the last completed step (the line the
    /// next step's inputs are extrapolated along). Absent in states saved
    /// before second-order coupling: the next step then holds its inputs.
    #[serde(default)]
    input_history: Option<extrapolate::InputHistory>,
}

/// What `Model::set` changes, written into the model only once every
/// value has passed.
struct Staged {
    scene: Scene,
    inputs: Vec<f64>,
    budget: f64,
    params_changed: bool,
}

pub struct Model<D: Dynamics> {
    table: VariableTable,
    start_scene: Scene,
    scene: Scene,
    /// Input values, in the order of `Input::index`.
    inputs: Vec<f64>,
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
    /// The simulation events of the last completed step, in words.
    new_events: Vec<String>,
    /// The last step ended early, at an event (`do_step_until_event`).
    ended_at_event: bool,
    /// The outputs of the current state, once computed (by the step's
    /// check or a getter), so that the getters after a step do not compute
    /// them again. Cleared by everything that changes the state, the
    /// inputs or the parameters (`changing`).
    outputs_now: Option<Vec<f64>>,
    /// How many outputs the table has (fixed with the table).
    output_count: usize,
    /// The communication step's roll-back copies, kept between steps (no
    /// allocation per step); out of date once anything changes the state
    /// (`changing`).
    rollback: rollback::RollBack<D::State>,
    /// Per value reference, the index among the outputs of a Real output
    /// (`NOT_A_REAL_OUTPUT` for every other variable): what the Real
    /// getter reads after every step, without the general path.
    real_slots: Vec<u32>,
    /// The value references of the last Real read that asked for Real
    /// outputs only, and their `real_slots`: an importer reads the same
    /// list after every step, which then needs no look-up per variable.
    last_reals: (Vec<u32>, Vec<u32>),
    /// The inputs at the start of the last completed step.
    input_history: Option<extrapolate::InputHistory>,
    /// Input derivatives (first, second) the master set for the next step
    /// (fmi2SetRealInputDerivatives), per input; cleared by each completed
    /// step.
    input_derivatives: Vec<Option<[f64; 2]>>,
    /// The dynamics hold the loads of a ramp, not `inputs`.
    loads_ramped: bool,
    /// The first communication step's size: later steps within a few ulp
    /// of it are taken as it (`snapped_target`).
    nominal_step: Option<f64>,
    /// The running error estimate's companions and values, where the scene
    /// asks for them (`error_estimate`).
    estimator: Option<estimate::Estimator<D>>,
}

/// `real_slots` of a variable that is not a Real output.
const NOT_A_REAL_OUTPUT: u32 = u32::MAX;

/// What a step is determined by, besides the state: its time, size, inputs.
#[derive(Debug, Clone, PartialEq)]
struct DiscardedStep {
    t: f64,
    h: f64,
    inputs: Vec<f64>,
}

/// The FMU variable that a scene field path stands for: `body.mass` is
/// `wheel.mass`, `sensors[0].position` is `sensor.midspan.position`; other
/// paths (`beam.*`, `solver.*`) are the same.
pub fn variable_name(scene: &Scene, path: &str) -> String {
    if let Some(rest) = path.strip_prefix("body.") {
        return format!("{}.{rest}", scene.vehicles[0].name);
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

#[cfg(test)]
thread_local! {
    /// Start states built on this thread (`ensure_sim`): the export's
    /// dependency analysis is tested to build none per coupling input.
    pub(crate) static BUILDS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Hand the input values (`Input::index` order) to the dynamics: the
/// applied force on each of the scene's `vehicles`, then the coupling
/// ports' loads.
fn apply_inputs<D: Dynamics>(sim: &mut D, inputs: &[f64], vehicles: usize) {
    let (forces, loads) = inputs.split_at((2 * vehicles).min(inputs.len()));
    for (vehicle, force) in forces.chunks_exact(2).enumerate() {
        sim.set_vehicle_force(vehicle, [force[0], force[1]]);
    }
    sim.set_coupling_loads(&coupling_loads(loads));
}

/// The coupling ports' loads: the inputs after the vehicles' forces.
fn coupling_loads(loads: &[f64]) -> Vec<[f64; 3]> {
    loads.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// An output's value `x` as a variable of type `ty`.
fn output_value(x: f64, ty: VarType) -> Value {
    match ty {
        VarType::Integer => Value::Integer(x as i32),
        VarType::Boolean => Value::Boolean(x != 0.0),
        VarType::Real => Value::Real(x),
    }
}

/// The first output of `sim` that is not finite, named with its value.
fn first_non_finite<D: Dynamics>(sim: &D) -> Option<String> {
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    non_finite_output(sim.outputs(), &values)
}

impl<D: Dynamics> Model<D> {
    /// The model of `scene`, with the scene's values as start values.
    pub fn new(scene: Scene) -> Result<Model<D>, ModelError> {
        validate(&scene).map_err(ModelError)?;
        let sim =
            D::build(&scene).map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
        let mut outputs = sim.outputs().to_vec();
        let estimator = scene.error_estimate.then(|| {
            let (estimator, errors) = estimate::Estimator::new(&outputs);
            outputs.extend(errors);
            estimator
        });
        let mut table = VariableTable::new(&scene, &outputs);
        let mut start_values = vec![0.0; outputs.len()];
        sim.output_values(&mut start_values[..sim.outputs().len()]);
        table.set_output_nominals(&start_values);
        let output_count = table.outputs().count();
        let real_slots = table
            .variables()
            .iter()
            .map(|v| match v.role {
                Role::Output(k) if v.ty == VarType::Real => {
                    u32::try_from(k).unwrap_or(NOT_A_REAL_OUTPUT)
                }
                _ => NOT_A_REAL_OUTPUT,
            })
            .collect();
        Ok(Model {
            table,
            start_scene: scene.clone(),
            inputs: start_inputs(&scene),
            scene,
            start_time: 0.0,
            phase: Phase::Configuring,
            sim: Some(sim),
            stop_time: None,
            wall_time_budget: DEFAULT_WALL_TIME_BUDGET,
            discarded: None,
            new_events: Vec::new(),
            ended_at_event: false,
            outputs_now: None,
            output_count,
            rollback: rollback::RollBack::new(),
            real_slots,
            last_reals: (Vec::new(), Vec::new()),
            input_history: None,
            input_derivatives: Vec::new(),
            loads_ramped: false,
            nominal_step: None,
            estimator,
        })
    }

    /// Called first by everything that may change the state, the inputs or
    /// the parameters: the outputs kept for the getters are out of date.
    fn changing(&mut self) {
        self.outputs_now = None;
        self.rollback.invalidate();
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
        self.changing();
        self.scene = self.start_scene.clone();
        self.inputs = start_inputs(&self.scene);
        self.start_time = 0.0;
        self.phase = Phase::Configuring;
        self.sim = None;
        self.stop_time = None;
        self.wall_time_budget = DEFAULT_WALL_TIME_BUDGET;
        self.discarded = None;
        self.input_history = None;
        self.input_derivatives.clear();
        self.nominal_step = None;
        if let Some(e) = &mut self.estimator {
            e.clear();
        }
    }

    /// fmi2SetupExperiment's times: all or nothing. A stop time bounds the
    /// run's length (checked when initialization is left).
    pub fn set_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ModelError> {
        self.changing();
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
            #[cfg(test)]
            BUILDS.with(|b| b.set(b.get() + 1));
            validate(&self.scene).map_err(ModelError)?;
            // Built with the inputs as the scene's forces, so that the
            // state at t = 0 (the contact force) balances them.
            let mut scene = self.scene.clone();
            for (vehicle, force) in scene.vehicles.iter_mut().zip(self.inputs.chunks_exact(2)) {
                (vehicle.force_x, vehicle.force_y) = (force[0], force[1]);
            }
            let mut sim =
                D::build(&scene).map_err(|e| ModelError(format!("cannot build the model: {e}")))?;
            apply_inputs(&mut sim, &self.inputs, scene.vehicles.len());
            self.sim = Some(sim);
        }
        Ok(self.sim.as_mut().expect("just built"))
    }

    fn output_values(&mut self) -> Result<Vec<f64>, ModelError> {
        let n = self.output_count;
        let sim = self.ensure_sim()?;
        let mut values = vec![0.0; sim.outputs().len()];
        sim.output_values(&mut values);
        // Parameters can be finite and valid one by one and still overflow
        // an output (a huge speed squared): refuse rather than hand out inf.
        if let Some(bad) = non_finite_output(sim.outputs(), &values) {
            return err(format!(
                "{bad} with these parameters; choose smaller values"
            ));
        }
        if let Some(e) = &self.estimator {
            values.extend_from_slice(e.values());
        }
        if values.len() != n {
            return err(format!(
                "the model has {} outputs, its variable table {n}",
                values.len()
            ));
        }
        Ok(values)
    }

    /// `output_values`, computed once per state.
    fn current_outputs(&mut self) -> Result<&[f64], ModelError> {
        if self.outputs_now.is_none() {
            self.outputs_now = Some(self.output_values()?);
        }
        Ok(self.outputs_now.as_deref().expect("just computed"))
    }

    /// Values of the variables `vrs`, all of type `ty`.
    pub fn get(&mut self, ty: VarType, vrs: &[u32]) -> Result<Vec<Value>, ModelError> {
        let mut values = Vec::with_capacity(vrs.len());
        self.get_each(ty, vrs, |value| values.push(value))?;
        Ok(values)
    }

    /// `get`, each value handed to `put` in the order of `vrs` (the FMI
    /// getters write them straight into the importer's array). On an error
    /// some values may have been handed out already.
    pub fn get_each(
        &mut self,
        ty: VarType,
        vrs: &[u32],
        mut put: impl FnMut(Value),
    ) -> Result<(), ModelError> {
        for (i, &vr) in vrs.iter().enumerate() {
            let role = self.variable(vr, ty)?.role;
            if let Role::Output(_) = role {
                // Computed once here; the rest is read without `&mut self`.
                self.current_outputs()?;
                let outputs = self.outputs_now.as_deref().expect("just computed");
                return self.get_with_outputs(ty, &vrs[i..], outputs, put);
            }
            put(self.value_of(role, ty, &[]));
        }
        Ok(())
    }

    /// `get_each` once the outputs are known.
    fn get_with_outputs(
        &self,
        ty: VarType,
        vrs: &[u32],
        outputs: &[f64],
        mut put: impl FnMut(Value),
    ) -> Result<(), ModelError> {
        for &vr in vrs {
            // An output of the type asked for (what an importer reads after
            // every step) without the general path's checks and copies.
            let output = self.table.get(vr).and_then(|v| match v.role {
                Role::Output(k) if v.ty == ty => Some(k),
                _ => None,
            });
            let value = match output {
                Some(k) => output_value(outputs[k], ty),
                None => {
                    let role = self.variable(vr, ty)?.role;
                    self.value_of(role, ty, outputs)
                }
            };
            put(value);
        }
        Ok(())
    }

    /// `get` of Real variables into `out` (as long as `vrs`). The outputs,
    /// which an importer reads after every step, are read through
    /// `real_slots`. On an error some values may have been written already.
    pub fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), ModelError> {
        if out.len() != vrs.len() {
            return err(format!(
                "{} value references but room for {} values",
                vrs.len(),
                out.len()
            ));
        }
        if !vrs.is_empty() && vrs == self.last_reals.0 {
            self.current_outputs()?;
            let outputs = self.outputs_now.as_deref().expect("just computed");
            for (o, &k) in out.iter_mut().zip(&self.last_reals.1) {
                *o = outputs[k as usize];
            }
            return Ok(());
        }
        for (i, &vr) in vrs.iter().enumerate() {
            if self.real_slot(vr) != NOT_A_REAL_OUTPUT {
                // Computed once here; the rest is read without `&mut self`.
                self.current_outputs()?;
                let outputs = self.outputs_now.as_deref().expect("just computed");
                self.reals_with_outputs(&vrs[i..], outputs, &mut out[i..])?;
                if i == 0 {
                    self.remember_reals(vrs);
                }
                return Ok(());
            }
            out[i] = self.real_value(vr, &[])?;
        }
        Ok(())
    }

    /// Keep `vrs` in `last_reals` if they are all Real outputs.
    fn remember_reals(&mut self, vrs: &[u32]) {
        let (last, slots) = &mut self.last_reals;
        last.clear();
        slots.clear();
        for &vr in vrs {
            let k = self.real_slots.get(vr as usize).copied();
            match k.filter(|&k| k != NOT_A_REAL_OUTPUT) {
                Some(k) => slots.push(k),
                None => return slots.clear(),
            }
        }
        last.extend_from_slice(vrs);
    }

    fn real_slot(&self, vr: u32) -> u32 {
        self.real_slots
            .get(vr as usize)
            .copied()
            .unwrap_or(NOT_A_REAL_OUTPUT)
    }

    /// `get_reals` once the outputs are known.
    fn reals_with_outputs(
        &self,
        vrs: &[u32],
        outputs: &[f64],
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        for (&vr, o) in vrs.iter().zip(out) {
            *o = match outputs.get(self.real_slot(vr) as usize) {
                Some(&x) => x,
                None => self.real_value(vr, outputs)?,
            };
        }
        Ok(())
    }

    /// The value of Real variable `vr` by the general path.
    fn real_value(&self, vr: u32, outputs: &[f64]) -> Result<f64, ModelError> {
        let role = self.variable(vr, VarType::Real)?.role;
        Ok(match self.value_of(role, VarType::Real, outputs) {
            Value::Real(x) => x,
            _ => f64::NAN,
        })
    }

    /// The value of a variable of type `ty` and role `role`; `outputs`:
    /// the current outputs (read only for an output).
    fn value_of(&self, role: Role, ty: VarType, outputs: &[f64]) -> Value {
        match role {
            Role::Parameter(p) => param_value(&self.scene, p),
            Role::Setting(Setting::WallTimeBudget) => Value::Real(self.wall_time_budget),
            Role::Input(i) => Value::Real(self.inputs[i.index(self.scene.vehicles.len())]),
            Role::Output(k) => output_value(outputs[k], ty),
        }
    }

    /// Set the variables `vrs`: all or nothing. Parameters only before
    /// initialization is left, inputs at any time, outputs never.
    pub fn set(&mut self, vrs: &[u32], values: &[Value]) -> Result<(), ModelError> {
        self.changing();
        let mut staged = Staged {
            scene: self.scene.clone(),
            inputs: self.inputs.clone(),
            budget: self.wall_time_budget,
            params_changed: false,
        };
        for (&vr, &value) in vrs.iter().zip(values) {
            self.stage(vr, value, &mut staged)?;
        }
        // Only the vehicles' forces (the first inputs) go into the build of
        // the state at t = 0 (`ensure_sim`); coupling loads are applied to
        // it (its contacts carrying them: `Simulation::set_coupling_loads`).
        let forces = 2 * self.scene.vehicles.len();
        let build_inputs_changed = staged.inputs[..forces] != self.inputs[..forces];
        self.scene = staged.scene;
        self.inputs = staged.inputs;
        self.wall_time_budget = staged.budget;
        // Before initialization is left the state at t = 0 follows the
        // parameters and the body forces: rebuild it on demand.
        if staged.params_changed || (build_inputs_changed && self.phase == Phase::Configuring) {
            self.sim = None;
        } else if let Some(sim) = self.sim.as_mut() {
            apply_inputs(sim, &self.inputs, self.scene.vehicles.len());
            self.loads_ramped = false;
        }
        Ok(())
    }

    /// Check `value` for variable `vr` and write it into `staged`, or
    /// refuse naming the variable, the value and the rule.
    fn stage(&self, vr: u32, value: Value, staged: &mut Staged) -> Result<(), ModelError> {
        let ty = match value {
            Value::Real(_) => VarType::Real,
            Value::Integer(_) => VarType::Integer,
            Value::Boolean(_) => VarType::Boolean,
        };
        let v = self.variable(vr, ty)?;
        let shown = match value {
            Value::Real(x) => format!("{x:?}"),
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
                if let Err(rule) = set_param(&mut staged.scene, p, value) {
                    return refuse(&rule);
                }
                staged.params_changed = true;
            }
            Role::Setting(Setting::WallTimeBudget) => match value {
                Value::Real(x) if x.is_finite() && x > 0.0 => staged.budget = x,
                _ => return refuse("must be a finite number of seconds > 0"),
            },
            // The scene's rule for the same forces (body.force_x/_y).
            Role::Input(i) => match value {
                Value::Real(x) if x.abs() <= MAX_MAGNITUDE => {
                    staged.inputs[i.index(staged.scene.vehicles.len())] = x
                }
                _ => {
                    return refuse(&format!(
                        "must be finite and within ±{MAX_MAGNITUDE:e} (the magnitude limit)"
                    ))
                }
            },
        }
        Ok(())
    }

    /// Set the `orders[k]`-th time derivative of input `vrs[k]` for the
    /// next communication step (fmi2SetRealInputDerivatives): all or
    /// nothing. Orders 1 and 2 are used; a step without them extrapolates
    /// the inputs from their last two communication points.
    pub fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), ModelError> {
        self.changing();
        let mut given = self.input_derivatives.clone();
        given.resize(self.inputs.len(), None);
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = self.variable(vr, VarType::Real)?;
            let refuse = |rule: &str| {
                err(format!(
                    "cannot set derivative {order} of {} = {value:?}: {rule}",
                    v.name
                ))
            };
            let Role::Input(i) = v.role else {
                return refuse("it is not an input");
            };
            if !(order == 1 || order == 2) {
                return refuse("the order must be 1 or 2");
            }
            if !(value.is_finite() && value.abs() <= MAX_MAGNITUDE) {
                return refuse(&format!("must be finite and within ±{MAX_MAGNITUDE:e}"));
            }
            let d = given[i.index(self.scene.vehicles.len())].get_or_insert([0.0, 0.0]);
            d[(order - 1) as usize] = value;
        }
        self.input_derivatives = given;
        Ok(())
    }

    /// Leave initialization: check the whole scene and build the simulation.
    pub fn initialize(&mut self) -> Result<(), ModelError> {
        self.changing();
        validate(&self.scene).map_err(|e| ModelError(format!("invalid parameters: {e}")))?;
        self.check_run_length()?;
        self.output_values()?;
        self.phase = Phase::Running;
        Ok(())
    }

    pub fn snapshot(&self) -> Snapshot<D::State> {
        Snapshot {
            scene: self.scene.clone(),
            inputs: self.inputs.clone(),
            start_time: self.start_time,
            phase: self.phase,
            sim: match self.phase {
                Phase::Running => self.sim.as_ref().map(|s| s.state()),
                Phase::Configuring => None,
            },
            input_history: self.input_history.clone(),
        }
    }

    /// The versioned byte form of a snapshot, tied to the model `guid`.
    pub fn serialize(snap: &Snapshot<D::State>, guid: &str) -> Result<Vec<u8>, ModelError> {
        snapshot::encode(guid, snap).map_err(ModelError)
    }

    pub fn deserialize(bytes: &[u8], guid: &str) -> Result<Snapshot<D::State>, ModelError> {
        snapshot::decode(guid, bytes)
            .map_err(|said| ModelError(D::explain_undecodable(guid, bytes).unwrap_or(said)))
    }

    /// The snapshot in `bytes`, refused unless it is a whole state of this
    /// model (`check_whole`): what every FMI front end's deserialize calls,
    /// so that none can take a forged state the setter would refuse.
    pub fn deserialize_checked(
        &self,
        bytes: &[u8],
        guid: &str,
    ) -> Result<Snapshot<D::State>, ModelError> {
        let snap = Self::deserialize(bytes, guid)?;
        self.check_whole(&snap)?;
        Ok(snap)
    }

    /// The simulation events (entries onto and exits from the structure,
    /// ...) of the last step, in words; each is handed out once.
    pub fn take_events(&mut self) -> Vec<String> {
        std::mem::take(&mut self.new_events)
    }
}

#[cfg(test)]
mod tests;
