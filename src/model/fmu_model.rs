//! The seam between the FMI fronts and the model they export: `FmuModel`,
//! everything `fmi_common`, `fmi2` and `fmi3` may ask of a model (its
//! variable table, what its modelDescription.xml says about it, how it is
//! read from the FMU's resources folder, its life cycle and its states),
//! and guideway's answer for a scene (`Model<D>`).
//!
//! The fronts see the model's configuration (here a scene) as an opaque
//! `FmuModel::Config` and its words as the strings this trait hands out,
//! so that no FMI file names the scene format or the physics.

use super::experiment::{default_stop_time, variable_communication_steps};
use super::{
    initial_dependencies, Dynamics, Model, ModelError, Phase, Snapshot, StepOutcome, Value,
    VarType, VariableTable,
};
use crate::scene::{Scene, MAX_SCENE_BYTES};
use std::path::Path;

/// The file in an FMU's resources folder that holds its scene.
pub const SCENE_FILE: &str = "scene.toml";

/// What a model description says of the model besides its variables.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelInfo {
    /// `modelName`; the model identifier is derived from it.
    pub name: String,
    /// `description` (left out where empty).
    pub description: String,
    /// Communication steps of any size
    /// (`canHandleVariableCommunicationStepSize`).
    pub variable_communication_steps: bool,
    /// The default experiment's stop time and step (s).
    pub stop_time: f64,
    pub step_size: f64,
    /// What the model logs as events (the `logEvents` category).
    pub events: &'static str,
}

/// The events a scene's model logs.
const SCENE_EVENTS: &str = "every simulation event (a contact's entry onto and exit from the \
                            structure, leaving the track, ...) with its time";

/// A model an FMI front can export: built from its configuration, read
/// from the FMU's resources folder, described, stepped, saved and
/// restored. Every refusal is a `ModelError` naming the bad value.
pub trait FmuModel: Sized {
    /// What the model is built from (its file in the resources folder).
    type Config;
    /// A saved state (what GetFMUState hands out).
    type Snapshot: Clone;

    /// The file in the resources folder that holds the configuration.
    const RESOURCE_FILE: &'static str;
    /// What the configuration is called in messages.
    const CONFIG_NOUN: &'static str;
    /// The outputs in which the model's events show (for an importer that
    /// asks for an event mode the FMU does not have).
    const EVENT_OUTPUTS: &'static str;

    /// The configuration in the resources folder `dir`, read within its
    /// size bound.
    fn read_resources(dir: &Path) -> Result<Self::Config, String>;
    /// The model of `config`, with its values as start values.
    fn new(config: Self::Config) -> Result<Self, ModelError>;
    fn info(&self) -> ModelInfo;
    fn table(&self) -> &VariableTable;
    /// Per output, the value references its initial value depends on
    /// (measured, for the description's InitialUnknowns).
    fn initial_dependencies(&self) -> Result<Vec<Vec<u32>>, String>;
    /// Why a step after the end of the run (at communication time `time`)
    /// is refused.
    fn after_end(time: f64) -> String;
    /// What the log says of a step that reached the end of the run.
    fn end_reached(time: f64) -> String;

    fn phase(&self) -> Phase;
    /// Communication time of the current state.
    fn time(&self) -> f64;
    /// Communication time of the end of the run, once it has ended.
    fn exit_time(&self) -> Option<f64>;
    fn reset(&mut self);
    fn set_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ModelError>;
    fn initialize(&mut self) -> Result<(), ModelError>;
    fn get_each(
        &mut self,
        ty: VarType,
        vrs: &[u32],
        put: impl FnMut(Value),
    ) -> Result<(), ModelError>;
    fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), ModelError>;
    fn set(&mut self, vrs: &[u32], values: &[Value]) -> Result<(), ModelError>;
    fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), ModelError>;
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError>;
    fn do_step_until_event(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError>;
    fn ended_at_event(&self) -> bool;
    fn take_events(&mut self) -> Vec<String>;
    fn snapshot(&self) -> Self::Snapshot;
    fn restore(&mut self, snap: &Self::Snapshot) -> Result<(), ModelError>;
    /// The versioned bytes of `snap`, tied to the model description's `token`.
    fn serialize(snap: &Self::Snapshot, token: &str) -> Result<Vec<u8>, ModelError>;
    /// The snapshot in `bytes`, refused unless it is a whole state of this
    /// model with `token`.
    fn deserialize_checked(&self, bytes: &[u8], token: &str) -> Result<Self::Snapshot, ModelError>;
}

/// The scene in the resources folder `dir`, read within the scene size
/// bound.
fn read_scene(dir: &Path) -> Result<Scene, String> {
    let path = dir.join(SCENE_FILE);
    let text = crate::input_file::read_text_bounded(&path, MAX_SCENE_BYTES)
        .map_err(|e| format!("the scene: {e}"))?;
    Scene::from_toml_str(&text).map_err(|e| format!("invalid scene {}: {e}", path.display()))
}

/// A scene's model: the forwards below are `Model`'s own methods.
impl<D: Dynamics> FmuModel for Model<D> {
    type Config = Scene;
    type Snapshot = Snapshot<D::State>;

    const RESOURCE_FILE: &'static str = SCENE_FILE;
    const CONFIG_NOUN: &'static str = "scene";
    const EVENT_OUTPUTS: &'static str = "<contact>.on_beam";

    fn read_resources(dir: &Path) -> Result<Scene, String> {
        read_scene(dir)
    }
    fn new(scene: Scene) -> Result<Self, ModelError> {
        Model::new(scene)
    }
    fn info(&self) -> ModelInfo {
        let scene = self.scene();
        ModelInfo {
            name: scene.name.clone(),
            description: scene.description.clone(),
            variable_communication_steps: variable_communication_steps(scene),
            stop_time: default_stop_time(scene),
            step_size: scene.solver.step,
            events: SCENE_EVENTS,
        }
    }
    fn table(&self) -> &VariableTable {
        Model::table(self)
    }
    fn initial_dependencies(&self) -> Result<Vec<Vec<u32>>, String> {
        initial_dependencies::<D>(self.scene())
    }
    fn after_end(time: f64) -> String {
        format!("the body left the beam at t = {time} s; the simulation cannot go on")
    }
    fn end_reached(time: f64) -> String {
        format!("the body reached the end of the beam at t = {time} s; simulation terminated")
    }

    fn phase(&self) -> Phase {
        Model::phase(self)
    }
    fn time(&self) -> f64 {
        Model::time(self)
    }
    fn exit_time(&self) -> Option<f64> {
        Model::exit_time(self)
    }
    fn reset(&mut self) {
        Model::reset(self)
    }
    fn set_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ModelError> {
        Model::set_experiment(self, start, stop)
    }
    fn initialize(&mut self) -> Result<(), ModelError> {
        Model::initialize(self)
    }
    fn get_each(
        &mut self,
        ty: VarType,
        vrs: &[u32],
        put: impl FnMut(Value),
    ) -> Result<(), ModelError> {
        Model::get_each(self, ty, vrs, put)
    }
    fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), ModelError> {
        Model::get_reals(self, vrs, out)
    }
    fn set(&mut self, vrs: &[u32], values: &[Value]) -> Result<(), ModelError> {
        Model::set(self, vrs, values)
    }
    fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), ModelError> {
        Model::set_input_derivatives(self, vrs, orders, values)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        Model::do_step(self, t, h)
    }
    fn do_step_until_event(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        Model::do_step_until_event(self, t, h)
    }
    fn ended_at_event(&self) -> bool {
        Model::ended_at_event(self)
    }
    fn take_events(&mut self) -> Vec<String> {
        Model::take_events(self)
    }
    fn snapshot(&self) -> Self::Snapshot {
        Model::snapshot(self)
    }
    fn restore(&mut self, snap: &Self::Snapshot) -> Result<(), ModelError> {
        Model::restore(self, snap)
    }
    fn serialize(snap: &Self::Snapshot, token: &str) -> Result<Vec<u8>, ModelError> {
        Model::<D>::serialize(snap, token)
    }
    fn deserialize_checked(&self, bytes: &[u8], token: &str) -> Result<Self::Snapshot, ModelError> {
        Model::deserialize_checked(self, bytes, token)
    }
}
