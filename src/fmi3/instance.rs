//! One FMI 3.0 co-simulation instance: the state machine around a `Model`
//! (the same model the FMI 2.0 layer drives), plus the FMU states handed out
//! to the importer.
//!
//! Every operation checks the instance's mode first; a call in the wrong
//! mode is refused (the exports turn the `Err` into fmi3Error and a log line
//! naming the function and the mode) and leaves the instance as it was.
//! The FMU declares `hasEventMode="false"`: after initialization it is in
//! Step Mode, and the end of the structure and the other simulation events
//! are reported in the log (and `<contact>.on_beam`), as in FMI 2.0. Where
//! the importer allows it (`earlyReturnAllowed`), fmi3DoStep returns early
//! at the end of the internal step in which an event happened.

use super::logging::Logger;
use super::model_description::{self, time_value_reference};
use crate::model::{Dynamics, Model, Phase, Snapshot, StepOutcome, Value, VarType};
use crate::scene::Scene;
use fmi_sys::fmi3::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The states of the FMI 3.0 co-simulation state machine without event
/// mode (`stepInProgress` never outlives a call here).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    InitializationMode,
    StepMode,
    Terminated,
    /// An internal fault (a caught panic): only fmi3FreeInstance is useful.
    Fatal,
}

use Mode::*;

/// Modes where variables may be read.
const READABLE: &[Mode] = &[InitializationMode, StepMode, Terminated];
/// Modes where FMU states may be got, set, serialized.
const STATEFUL: &[Mode] = &[Instantiated, InitializationMode, StepMode, Terminated];

/// How a doStep ended, for its output arguments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    pub status: fmi3Status,
    pub terminate: bool,
    pub early_return: bool,
    pub last_successful_time: f64,
}

pub struct Instance<D: Dynamics> {
    pub logger: Logger,
    mode: Mode,
    model: Model<D>,
    token: String,
    /// The value reference of the independent variable `time`.
    time_vr: u32,
    /// FMU states handed out, keyed by the handle the importer holds.
    states: HashMap<usize, Snapshot<D::State>>,
    /// The importer allows fmi3DoStep to return early: it then ends at the
    /// end of the internal step of a simulation event.
    early_return_allowed: bool,
}

/// The next FMU state handle: tokens, never addresses, never reused within
/// the process (a stale or foreign handle is not in an instance's registry
/// and is refused).
static NEXT_STATE_HANDLE: AtomicUsize = AtomicUsize::new(1);

/// A fresh handle: a multiple of 8 above 0x4733_0000_0000 ("G3").
fn new_state_handle() -> usize {
    0x4733_0000_0000 + 8 * NEXT_STATE_HANDLE.fetch_add(1, Ordering::Relaxed)
}

/// The resources directory from FMI 3.0's `resourcePath` (an absolute path
/// with a trailing separator, not a URI).
pub fn read_scene(resource_path: &str) -> Result<Scene, String> {
    if resource_path.is_empty() {
        return Err("resourcePath is empty: the FMU needs its resources/scene.toml".into());
    }
    crate::fmi2::instance::read_scene(std::path::Path::new(resource_path))
}

impl<D: Dynamics> Instance<D> {
    /// An instance of `scene`, whose model description must have the
    /// instantiation token `token`.
    pub fn new(scene: Scene, token: &str, logger: Logger) -> Result<Instance<D>, (Logger, String)> {
        let model = match Model::<D>::new(scene) {
            Ok(m) => m,
            Err(e) => return Err((logger, format!("the FMU's scene is invalid: {e}"))),
        };
        let (_, own_token) = model_description::generate(model.scene(), model.table());
        if own_token != token {
            return Err((
                logger,
                format!("instantiationToken \"{token}\" does not match this FMU's \"{own_token}\""),
            ));
        }
        let time_vr = time_value_reference(model.table());
        Ok(Instance {
            logger,
            mode: Instantiated,
            model,
            token: own_token,
            time_vr,
            states: HashMap::new(),
            early_return_allowed: false,
        })
    }

    /// `earlyReturnAllowed` of fmi3InstantiateCoSimulation.
    pub fn allow_early_return(&mut self, allowed: bool) {
        self.early_return_allowed = allowed;
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn set_fatal(&mut self) {
        self.mode = Fatal;
    }

    /// Refuse `function` unless the instance is in one of `allowed`.
    pub fn require(&self, function: &str, allowed: &[Mode]) -> Result<(), String> {
        if allowed.contains(&self.mode) {
            return Ok(());
        }
        Err(format!(
            "{function} is not allowed in state {:?} (allowed in: {allowed:?})",
            self.mode
        ))
    }

    pub fn enter_initialization_mode(
        &mut self,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), String> {
        self.require("fmi3EnterInitializationMode", &[Instantiated])?;
        self.model.set_experiment(start, stop).map_err(|e| e.0)?;
        self.mode = InitializationMode;
        Ok(())
    }

    pub fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.require("fmi3ExitInitializationMode", &[InitializationMode])?;
        self.model.initialize().map_err(|e| e.0)?;
        self.mode = StepMode;
        self.logger.log(fmi3Status_fmi3OK, "initialized");
        Ok(())
    }

    pub fn terminate(&mut self) -> Result<(), String> {
        self.require("fmi3Terminate", &[StepMode])?;
        self.mode = Terminated;
        Ok(())
    }

    pub fn reset(&mut self) -> Result<(), String> {
        self.require("fmi3Reset", STATEFUL)?;
        self.model.reset();
        self.mode = Instantiated;
        Ok(())
    }

    /// fmi3GetFloat64: the values of `vrs` (the table's Real variables and
    /// `time`) written into `out`.
    pub fn get_float64(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        self.require("fmi3GetFloat64", READABLE)?;
        let e = |e: crate::model::ModelError| format!("fmi3GetFloat64: {e}");
        if !vrs.contains(&self.time_vr) {
            return self.model.get_reals(vrs, out).map_err(e);
        }
        for (vr, o) in vrs.iter().zip(out.iter_mut()) {
            if *vr == self.time_vr {
                *o = self.model.time();
            } else {
                self.model
                    .get_reals(std::slice::from_ref(vr), std::slice::from_mut(o))
                    .map_err(e)?;
            }
        }
        Ok(())
    }

    /// fmi3GetInt32 and fmi3GetBoolean: each value handed to `put`.
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

    pub fn set(&mut self, function: &str, vrs: &[u32], values: &[Value]) -> Result<(), String> {
        self.require(function, &[Instantiated, InitializationMode, StepMode])?;
        if vrs.contains(&self.time_vr) {
            return Err(format!(
                "{function}: time (value reference {}) is the independent variable and cannot be set",
                self.time_vr
            ));
        }
        self.model
            .set(vrs, values)
            .map_err(|e| format!("{function}: {e}"))
    }

    fn terminated(&self) -> bool {
        self.model.exit_time().is_some()
    }

    /// fmi3DoStep: OK, or Discard with `terminate` at the end of the run or
    /// after a failure a smaller step cures (rolled back to `t`), or `Err`
    /// for a failure no retry of it cures (rolled back).
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<StepReport, String> {
        self.require("fmi3DoStep", &[StepMode])?;
        if self.terminated() {
            return Err(format!(
                "fmi3DoStep: the body left the beam at t = {} s; the simulation cannot go on",
                self.model.time()
            ));
        }
        let outcome = if self.early_return_allowed {
            self.model.do_step_until_event(t, h)
        } else {
            self.model.do_step(t, h)
        }
        .map_err(|e| format!("fmi3DoStep: {e}"))?;
        let early_return = self.model.ended_at_event();
        for event in self.model.take_events() {
            self.logger
                .log(fmi3Status_fmi3OK, &format!("event: {event}"));
        }
        let report = |status, terminate| StepReport {
            status,
            terminate,
            early_return,
            last_successful_time: self.model.time(),
        };
        match outcome {
            StepOutcome::Completed => Ok(report(fmi3Status_fmi3OK, false)),
            StepOutcome::Exited { time } => {
                self.logger.log(
                    fmi3Status_fmi3Discard,
                    &format!("fmi3DoStep: the body reached the end of the beam at t = {time} s; simulation terminated"),
                );
                Ok(report(fmi3Status_fmi3Discard, true))
            }
            StepOutcome::Failed {
                message,
                curable: true,
            } => {
                self.logger
                    .log(fmi3Status_fmi3Discard, &format!("fmi3DoStep: {message}"));
                Ok(report(fmi3Status_fmi3Discard, false))
            }
            StepOutcome::Failed {
                message,
                curable: false,
            } => Err(format!("fmi3DoStep: {message}")),
        }
    }

    // ---- FMU states -------------------------------------------------------

    /// fmi3GetFMUState: a new state, or `existing` (one of ours) overwritten.
    pub fn get_state(&mut self, existing: usize) -> Result<usize, String> {
        self.require("fmi3GetFMUState", STATEFUL)?;
        let snap = self.model.snapshot();
        if existing == 0 {
            return Ok(self.keep(snap));
        }
        let Some(slot) = self.states.get_mut(&existing) else {
            return Err(format!(
                "fmi3GetFMUState: FMUState {existing:#x} was not created by this instance"
            ));
        };
        *slot = snap;
        Ok(existing)
    }

    fn keep(&mut self, snap: Snapshot<D::State>) -> usize {
        let key = new_state_handle();
        self.states.insert(key, snap);
        key
    }

    fn state(&self, function: &str, key: usize) -> Result<&Snapshot<D::State>, String> {
        self.states.get(&key).ok_or_else(|| {
            format!("{function}: FMUState {key:#x} is not a live state of this instance")
        })
    }

    pub fn set_state(&mut self, key: usize) -> Result<(), String> {
        self.require("fmi3SetFMUState", STATEFUL)?;
        let snap = self.state("fmi3SetFMUState", key)?.clone();
        self.model
            .restore(&snap)
            .map_err(|e| format!("fmi3SetFMUState: {e}"))?;
        self.mode = match self.model.phase() {
            Phase::Running => StepMode,
            Phase::Configuring if self.mode == Instantiated => Instantiated,
            Phase::Configuring => InitializationMode,
        };
        self.logger.log(fmi3Status_fmi3OK, "FMU state restored");
        Ok(())
    }

    pub fn free_state(&mut self, key: usize) -> Result<(), String> {
        if key == 0 {
            return Ok(());
        }
        self.states.remove(&key).map(drop).ok_or_else(|| {
            format!("fmi3FreeFMUState: FMUState {key:#x} is not a live state of this instance")
        })
    }

    pub fn serialize_state(&self, key: usize) -> Result<Vec<u8>, String> {
        self.require("fmi3SerializeFMUState", STATEFUL)?;
        let snap = self.state("fmi3SerializeFMUState", key)?;
        Model::<D>::serialize(snap, &self.token).map_err(|e| format!("fmi3SerializeFMUState: {e}"))
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<usize, String> {
        self.require("fmi3DeserializeFMUState", STATEFUL)?;
        let snap = self
            .model
            .deserialize_checked(bytes, &self.token)
            .map_err(|e| format!("fmi3DeserializeFMUState: {e}"))?;
        Ok(self.keep(snap))
    }
}
