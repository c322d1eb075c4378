//! One FMU instance: the FMI 2.0 co-simulation state machine around a
//! `Model`, plus the FMU states handed out to the importer.
//!
//! Every operation checks the instance's mode first; a call in the wrong
//! mode is refused (the exports turn the `Err` into fmi2Error and a log line
//! naming the function and the mode) and leaves the instance as it was.

use super::logging::Logger;
use super::model_description;
use crate::model::{Dynamics, Model, Phase, Snapshot, StepOutcome, Value, VarType};
use crate::scene::Scene;
use fmi_sys::fmi2::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The states of the FMI 2.0 co-simulation state machine that a synchronous
/// slave can be in (`stepInProgress` never outlives a call here).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    InitializationMode,
    StepComplete,
    /// Last doStep returned fmi2Discard: the body left the beam
    /// (terminated), or the solver failed: then the state was rolled back to
    /// the start of the step and, beyond the standard's state machine, inputs
    /// may be set and the step retried (e.g. with a smaller size).
    StepFailed,
    Terminated,
    /// An internal fault (a caught panic): only fmi2FreeInstance is useful.
    Fatal,
}

use Mode::*;

/// Modes where variables may be read.
const READABLE: &[Mode] = &[InitializationMode, StepComplete, StepFailed, Terminated];
/// Modes where FMU states may be got, set, serialized.
const STATEFUL: &[Mode] = &[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
];

/// The scene file inside the FMU's resources folder.
pub const SCENE_FILE: &str = "scene.toml";

pub struct Instance<D: Dynamics> {
    pub logger: Logger,
    mode: Mode,
    model: Model<D>,
    guid: String,
    /// FMU states handed out, keyed by the handle the importer holds.
    states: HashMap<usize, Snapshot<D::State>>,
}

/// The next FMU state handle. Handles are tokens, never addresses, and never
/// reused within the process: a stale handle (freed, then the memory reused
/// for another state) or another instance's handle is not in an instance's
/// registry and is refused. The counter is the only thing instances share,
/// and it carries no state of theirs.
static NEXT_STATE_HANDLE: AtomicUsize = AtomicUsize::new(1);

/// A fresh handle: a multiple of 8 above 0x4757_0000_0000 ("GW"), so
/// that it is never NULL and never mistaken for a small integer.
fn new_state_handle() -> usize {
    0x4757_0000_0000 + 8 * NEXT_STATE_HANDLE.fetch_add(1, Ordering::Relaxed)
}

/// Path of a `file:` resource location (`file:///a/b`, `file:/a/b`,
/// percent-encoded).
pub fn resource_path(location: &str) -> Result<PathBuf, String> {
    let url = url::Url::parse(location)
        .map_err(|e| format!("fmuResourceLocation \"{location}\" is not a URI: {e}"))?;
    if url.scheme() != "file" {
        return Err(format!(
            "fmuResourceLocation \"{location}\": only file: URIs are supported"
        ));
    }
    url.to_file_path()
        .map_err(|()| format!("fmuResourceLocation \"{location}\" is not a local file path"))
}

pub fn read_scene(resources: &std::path::Path) -> Result<Scene, String> {
    let path = resources.join(SCENE_FILE);
    let text = crate::input_file::read_text_bounded(&path, crate::scene::MAX_SCENE_BYTES)
        .map_err(|e| format!("the scene: {e}"))?;
    Scene::from_toml_str(&text).map_err(|e| format!("invalid scene {}: {e}", path.display()))
}

impl<D: Dynamics> Instance<D> {
    /// fmi2Instantiate after the C strings have been read.
    pub fn instantiate(
        fmu_type: fmi2Type,
        guid: &str,
        resource_location: &str,
        logger: Logger,
    ) -> Result<Instance<D>, (Logger, String)> {
        if fmu_type != fmi2Type_fmi2CoSimulation {
            return Err((
                logger,
                format!("fmuType = {fmu_type}: this FMU supports co-simulation (fmi2CoSimulation = 1) only"),
            ));
        }
        let scene = match resource_path(resource_location).and_then(|p| read_scene(&p)) {
            Ok(scene) => scene,
            Err(e) => return Err((logger, e)),
        };
        Instance::new(scene, guid, logger)
    }

    /// An instance of `scene`, whose model description must have GUID `guid`.
    pub fn new(scene: Scene, guid: &str, logger: Logger) -> Result<Instance<D>, (Logger, String)> {
        let model = match Model::<D>::new(scene) {
            Ok(m) => m,
            Err(e) => return Err((logger, format!("the FMU's scene is invalid: {e}"))),
        };
        let (_, own_guid) = model_description::generate(model.scene(), model.table());
        if own_guid != guid {
            return Err((
                logger,
                format!("fmuGUID \"{guid}\" does not match this FMU's GUID \"{own_guid}\""),
            ));
        }
        Ok(Instance {
            logger,
            mode: Instantiated,
            model,
            guid: own_guid,
            states: HashMap::new(),
        })
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn model(&self) -> &Model<D> {
        &self.model
    }

    pub fn set_fatal(&mut self) {
        self.mode = Fatal;
    }

    /// Refuse `function` unless the instance is in one of `allowed`.
    pub fn require(&self, function: &str, allowed: &[Mode]) -> Result<(), String> {
        if allowed.contains(&self.mode) {
            Ok(())
        } else {
            Err(format!(
                "{function} is not allowed in state {:?} (allowed in: {:?})",
                self.mode, allowed
            ))
        }
    }

    pub fn setup_experiment(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), String> {
        self.require("fmi2SetupExperiment", &[Instantiated])?;
        self.model
            .set_experiment(start_time, stop_time)
            .map_err(|e| e.0)
    }

    pub fn enter_initialization_mode(&mut self) -> Result<(), String> {
        self.require("fmi2EnterInitializationMode", &[Instantiated])?;
        self.mode = InitializationMode;
        Ok(())
    }

    pub fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.require("fmi2ExitInitializationMode", &[InitializationMode])?;
        self.model.initialize().map_err(|e| e.0)?;
        self.mode = StepComplete;
        self.logger.log(fmi2Status_fmi2OK, "initialized");
        Ok(())
    }

    pub fn terminate(&mut self) -> Result<(), String> {
        self.require("fmi2Terminate", &[StepComplete, StepFailed])?;
        self.mode = Terminated;
        Ok(())
    }

    pub fn reset(&mut self) -> Result<(), String> {
        self.require(
            "fmi2Reset",
            &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                Terminated,
            ],
        )?;
        self.model.reset();
        self.mode = Instantiated;
        Ok(())
    }

    pub fn get(&mut self, function: &str, ty: VarType, vrs: &[u32]) -> Result<Vec<Value>, String> {
        let mut values = Vec::with_capacity(vrs.len());
        self.get_each(function, ty, vrs, |v| values.push(v))?;
        Ok(values)
    }

    /// `get`, each value handed to `put` in the order of `vrs`.
    pub fn get_each(
        &mut self,
        function: &str,
        ty: VarType,
        vrs: &[u32],
        put: impl FnMut(Value),
    ) -> Result<(), String> {
        self.require(function, READABLE)?;
        self.model
            .get_each(ty, vrs, put)
            .map_err(|e| format!("{function}: {e}"))
    }

    /// fmi2GetReal: the values of `vrs` written into `out`.
    pub fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        self.require("fmi2GetReal", READABLE)?;
        self.model
            .get_reals(vrs, out)
            .map_err(|e| format!("fmi2GetReal: {e}"))
    }

    pub fn set(&mut self, function: &str, vrs: &[u32], values: &[Value]) -> Result<(), String> {
        // After a rolled-back solver failure (StepFailed, not terminated) the
        // master may change inputs and retry the step.
        if self.mode != StepFailed || self.terminated() {
            self.require(function, &[Instantiated, InitializationMode, StepComplete])?;
        }
        self.model
            .set(vrs, values)
            .map_err(|e| format!("{function}: {e}"))
    }

    /// fmi2SetRealInputDerivatives: derivatives of inputs for the next
    /// step (allowed where inputs may be set).
    pub fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), String> {
        let function = "fmi2SetRealInputDerivatives";
        if self.mode != StepFailed || self.terminated() {
            self.require(function, &[Instantiated, InitializationMode, StepComplete])?;
        }
        self.model
            .set_input_derivatives(vrs, orders, values)
            .map_err(|e| format!("{function}: {e}"))
    }

    fn terminated(&self) -> bool {
        self.model.exit_time().is_some()
    }

    /// fmi2DoStep: `Ok(fmi2OK)`, or `Ok(fmi2Discard)` with a logged reason
    /// (exit: terminated; a failure a smaller step cures: rolled back, retry
    /// possible), or `Err` for a failure no retry of it cures (rolled back).
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<fmi2Status, String> {
        self.require("fmi2DoStep", &[StepComplete, StepFailed])?;
        if self.terminated() {
            return Err(format!(
                "fmi2DoStep: the body left the beam at t = {} s; the simulation cannot go on",
                self.model.time()
            ));
        }
        let outcome = self
            .model
            .do_step(t, h)
            .map_err(|e| format!("fmi2DoStep: {e}"))?;
        for event in self.model.take_events() {
            self.logger
                .log(fmi2Status_fmi2OK, &format!("event: {event}"));
        }
        match outcome {
            StepOutcome::Completed => {
                self.mode = StepComplete;
                Ok(fmi2Status_fmi2OK)
            }
            StepOutcome::Exited { time } => {
                self.mode = StepFailed;
                self.logger.log(
                    fmi2Status_fmi2Discard,
                    &format!("fmi2DoStep: the body reached the end of the beam at t = {time} s; simulation terminated"),
                );
                Ok(fmi2Status_fmi2Discard)
            }
            StepOutcome::Failed {
                message,
                curable: true,
            } => {
                self.mode = StepFailed;
                self.logger
                    .log(fmi2Status_fmi2Discard, &format!("fmi2DoStep: {message}"));
                Ok(fmi2Status_fmi2Discard)
            }
            // A master retrying this would loop forever: an error, not a
            // Discard. The state is rolled back; other inputs may cure it.
            StepOutcome::Failed {
                message,
                curable: false,
            } => Err(format!("fmi2DoStep: {message}")),
        }
    }

    const STATUS_MODES: &'static [Mode] = &[StepComplete, StepFailed, Terminated];

    pub fn get_real_status(&self, kind: fmi2StatusKind) -> Result<f64, String> {
        self.require("fmi2GetRealStatus", Self::STATUS_MODES)?;
        if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(format!(
                "fmi2GetRealStatus: status kind {kind} has no Real value (only fmi2LastSuccessfulTime = 2)"
            ));
        }
        Ok(self.model.time())
    }

    pub fn get_boolean_status(&self, kind: fmi2StatusKind) -> Result<bool, String> {
        self.require("fmi2GetBooleanStatus", Self::STATUS_MODES)?;
        if kind != fmi2StatusKind_fmi2Terminated {
            return Err(format!(
                "fmi2GetBooleanStatus: status kind {kind} has no Boolean value (only fmi2Terminated = 3)"
            ));
        }
        Ok(self.terminated())
    }

    // ---- FMU states -------------------------------------------------------

    /// fmi2GetFMUstate: a new state, or `existing` (one of ours) overwritten.
    pub fn get_state(&mut self, existing: usize) -> Result<usize, String> {
        self.require("fmi2GetFMUstate", STATEFUL)?;
        let snap = self.model.snapshot();
        if existing != 0 {
            let Some(slot) = self.states.get_mut(&existing) else {
                return Err(format!(
                    "fmi2GetFMUstate: FMUstate {existing:#x} was not created by this instance"
                ));
            };
            *slot = snap;
            return Ok(existing);
        }
        Ok(self.keep(snap))
    }

    fn keep(&mut self, snap: Snapshot<D::State>) -> usize {
        let key = new_state_handle();
        self.states.insert(key, snap);
        key
    }

    fn state(&self, function: &str, key: usize) -> Result<&Snapshot<D::State>, String> {
        self.states.get(&key).ok_or_else(|| {
            format!("{function}: FMUstate {key:#x} is not a live state of this instance")
        })
    }

    pub fn set_state(&mut self, key: usize) -> Result<(), String> {
        self.require("fmi2SetFMUstate", STATEFUL)?;
        let snap = self.state("fmi2SetFMUstate", key)?.clone();
        self.model
            .restore(&snap)
            .map_err(|e| format!("fmi2SetFMUstate: {e}"))?;
        self.mode = match self.model.phase() {
            Phase::Running if self.terminated() => StepFailed,
            Phase::Running => StepComplete,
            Phase::Configuring if self.mode == Instantiated => Instantiated,
            Phase::Configuring => InitializationMode,
        };
        self.logger.log(fmi2Status_fmi2OK, "FMU state restored");
        Ok(())
    }

    pub fn free_state(&mut self, key: usize) -> Result<(), String> {
        if key == 0 {
            return Ok(());
        }
        self.states.remove(&key).map(drop).ok_or_else(|| {
            format!("fmi2FreeFMUstate: FMUstate {key:#x} is not a live state of this instance")
        })
    }

    pub fn serialize_state(&self, key: usize) -> Result<Vec<u8>, String> {
        self.require("fmi2SerializeFMUstate", STATEFUL)?;
        let snap = self.state("fmi2SerializeFMUstate", key)?;
        Model::<D>::serialize(snap, &self.guid).map_err(|e| format!("fmi2SerializeFMUstate: {e}"))
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<usize, String> {
        self.require("fmi2DeSerializeFMUstate", STATEFUL)?;
        let snap = self
            .model
            .deserialize_checked(bytes, &self.guid)
            .map_err(|e| format!("fmi2DeSerializeFMUstate: {e}"))?;
        Ok(self.keep(snap))
    }
}
