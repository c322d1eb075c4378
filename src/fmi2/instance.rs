//! FMI 2.0's view of the shared instance (`fmi_common::Instance`): the
//! modes of its co-simulation state machine, which calls each mode allows,
//! the names and status numbers of the standard, and the two things only
//! FMI 2.0 has: the resource location as a `file:` URI with the FMU type,
//! and the status queries.

use super::logging::{Logger, Sink};
use super::model_description;
use crate::fmi_common::{self, Call, Front, Status};
use crate::model::{FmuModel, ModelInfo, VariableTable};
use fmi_sys::fmi2::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// An FMI 2.0 instance.
pub type Instance<M> = fmi_common::Instance<M, Fmi2>;

/// The FMI 2.0 front.
pub struct Fmi2;

/// The states of the FMI 2.0 co-simulation state machine that a synchronous
/// slave can be in (`stepInProgress` never outlives a call here).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    InitializationMode,
    StepComplete,
    /// Last doStep returned fmi2Discard: the run ended (terminated), or
    /// the solver failed: then the state was rolled back to
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
/// Every mode but Fatal: FMU states may be got, set, serialized; reset.
const ALIVE: &[Mode] = &[
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
];
const STATUS_MODES: &[Mode] = &[StepComplete, StepFailed, Terminated];

/// The FMI 2.0 number of a status.
pub fn status(s: Status) -> fmi2Status {
    match s {
        Status::Ok => fmi2Status_fmi2OK,
        Status::Warning => fmi2Status_fmi2Warning,
        Status::Discard => fmi2Status_fmi2Discard,
        Status::Error => fmi2Status_fmi2Error,
        Status::Fatal => fmi2Status_fmi2Fatal,
    }
}

/// The next FMU state handle (the counter is the only thing instances
/// share, and it carries no state of theirs).
static NEXT_STATE_HANDLE: AtomicUsize = AtomicUsize::new(1);

impl Front for Fmi2 {
    type Status = fmi2Status;
    type Mode = Mode;
    type Sink = Sink;

    const INSTANTIATED: Mode = Instantiated;
    const INITIALIZATION_MODE: Mode = InitializationMode;
    const STEPPING: Mode = StepComplete;
    const DISCARDED: Mode = StepFailed;
    const TERMINATED: Mode = Terminated;
    const FATAL: Mode = Fatal;
    const STATE_NOUN: &'static str = "FMUstate";

    fn status(s: Status) -> fmi2Status {
        status(s)
    }

    fn name(call: Call) -> &'static str {
        match call {
            Call::SetupExperiment => "fmi2SetupExperiment",
            Call::EnterInitializationMode => "fmi2EnterInitializationMode",
            Call::ExitInitializationMode => "fmi2ExitInitializationMode",
            Call::Terminate => "fmi2Terminate",
            Call::Reset => "fmi2Reset",
            Call::FreeInstance => "fmi2FreeInstance",
            Call::GetReal | Call::Get => "fmi2GetReal",
            Call::Set => "fmi2SetReal",
            Call::DoStep => "fmi2DoStep",
            Call::GetState => "fmi2GetFMUstate",
            Call::SetState => "fmi2SetFMUstate",
            Call::FreeState => "fmi2FreeFMUstate",
            Call::StateSize => "fmi2SerializedFMUstateSize",
            Call::SerializeState => "fmi2SerializeFMUstate",
            Call::DeserializeState => "fmi2DeSerializeFMUstate",
        }
    }

    fn allowed(call: Call) -> &'static [Mode] {
        match call {
            Call::SetupExperiment | Call::EnterInitializationMode => &[Instantiated],
            Call::ExitInitializationMode => &[InitializationMode],
            Call::Terminate | Call::DoStep => &[StepComplete, StepFailed],
            Call::GetReal | Call::Get => READABLE,
            Call::Set => &[Instantiated, InitializationMode, StepComplete],
            Call::Reset | Call::FreeInstance | Call::GetState | Call::SetState => ALIVE,
            Call::FreeState | Call::StateSize | Call::SerializeState => ALIVE,
            Call::DeserializeState => ALIVE,
        }
    }

    /// A fresh handle: a multiple of 8 above 0x4757_0000_0000 ("GW"), so
    /// that it is never NULL and never mistaken for a small integer.
    fn next_state_handle() -> usize {
        0x4757_0000_0000 + 8 * NEXT_STATE_HANDLE.fetch_add(1, Ordering::Relaxed)
    }

    fn token_mismatch(given: &str, own: &str) -> String {
        format!("fmuGUID \"{given}\" does not match this FMU's GUID \"{own}\"")
    }

    fn independent_variable(_: &VariableTable) -> Option<u32> {
        None
    }

    fn generate(info: &ModelInfo, table: &VariableTable) -> (String, String) {
        model_description::generate(info, table)
    }
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

impl<M: FmuModel> Instance<M> {
    /// fmi2Instantiate after the C strings have been read.
    pub fn instantiate(
        fmu_type: fmi2Type,
        guid: &str,
        resource_location: &str,
        logger: Logger,
    ) -> Result<Instance<M>, (Logger, String)> {
        if fmu_type != fmi2Type_fmi2CoSimulation {
            return Err((
                logger,
                format!("fmuType = {fmu_type}: this FMU supports co-simulation (fmi2CoSimulation = 1) only"),
            ));
        }
        match resource_path(resource_location).and_then(|p| M::read_resources(&p)) {
            Ok(config) => Instance::new(config, guid, logger),
            Err(e) => Err((logger, e)),
        }
    }

    pub fn get_real_status(&self, kind: fmi2StatusKind) -> Result<f64, String> {
        self.require("fmi2GetRealStatus", STATUS_MODES)?;
        if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(format!(
                "fmi2GetRealStatus: status kind {kind} has no Real value (only fmi2LastSuccessfulTime = 2)"
            ));
        }
        Ok(self.model().time())
    }

    pub fn get_boolean_status(&self, kind: fmi2StatusKind) -> Result<bool, String> {
        self.require("fmi2GetBooleanStatus", STATUS_MODES)?;
        if kind != fmi2StatusKind_fmi2Terminated {
            return Err(format!(
                "fmi2GetBooleanStatus: status kind {kind} has no Boolean value (only fmi2Terminated = 3)"
            ));
        }
        Ok(self.terminated())
    }
}
