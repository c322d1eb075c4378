//! FMI 3.0's view of the shared instance (`fmi_common::Instance`): the
//! modes of its co-simulation state machine without event mode, which
//! calls each mode allows, the names and status numbers of the standard,
//! its independent variable `time`, and the resource path (a directory,
//! not a URI).
//!
//! The FMU declares `hasEventMode="false"`: after initialization it is in
//! Step Mode, and the end of the run and the model's other events are
//! reported in the log (and in `FmuModel::EVENT_OUTPUTS`), as in FMI 2.0. Where
//! the importer allows it (`earlyReturnAllowed`), fmi3DoStep returns early
//! at the end of the internal step in which an event happened.

use super::logging::Sink;
use super::model_description::{self, time_value_reference};
use crate::fmi_common::{self, Call, Front, Status};
use crate::model::{FmuModel, ModelInfo, VariableTable};
use fmi_sys::fmi3::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// An FMI 3.0 instance.
pub type Instance<M> = fmi_common::Instance<M, Fmi3>;

/// How an FMI 3.0 doStep ended, for its output arguments.
pub type StepReport = fmi_common::StepReport<fmi3Status>;

/// The FMI 3.0 front.
pub struct Fmi3;

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

/// Every mode but Fatal: FMU states may be got, set, serialized; reset.
const ALIVE: &[Mode] = &[Instantiated, InitializationMode, StepMode, Terminated];

/// The FMI 3.0 number of a status.
pub fn status(s: Status) -> fmi3Status {
    match s {
        Status::Ok => fmi3Status_fmi3OK,
        Status::Warning => fmi3Status_fmi3Warning,
        Status::Discard => fmi3Status_fmi3Discard,
        Status::Error => fmi3Status_fmi3Error,
        Status::Fatal => fmi3Status_fmi3Fatal,
    }
}

/// The next FMU state handle of this front.
static NEXT_STATE_HANDLE: AtomicUsize = AtomicUsize::new(1);

impl Front for Fmi3 {
    type Status = fmi3Status;
    type Mode = Mode;
    type Sink = Sink;

    const INSTANTIATED: Mode = Instantiated;
    const INITIALIZATION_MODE: Mode = InitializationMode;
    const STEPPING: Mode = StepMode;
    /// Without event mode the instance stays in Step Mode after a Discard.
    const DISCARDED: Mode = StepMode;
    const TERMINATED: Mode = Terminated;
    const FATAL: Mode = Fatal;
    const STATE_NOUN: &'static str = "FMUState";

    fn status(s: Status) -> fmi3Status {
        status(s)
    }

    fn name(call: Call) -> &'static str {
        match call {
            // FMI 3.0 sets up the experiment on entering initialization.
            Call::SetupExperiment | Call::EnterInitializationMode => "fmi3EnterInitializationMode",
            Call::ExitInitializationMode => "fmi3ExitInitializationMode",
            Call::Terminate => "fmi3Terminate",
            Call::Reset => "fmi3Reset",
            Call::FreeInstance => "fmi3FreeInstance",
            Call::GetReal | Call::Get => "fmi3GetFloat64",
            Call::Set => "fmi3SetFloat64",
            Call::DoStep => "fmi3DoStep",
            Call::GetState => "fmi3GetFMUState",
            Call::SetState => "fmi3SetFMUState",
            Call::FreeState => "fmi3FreeFMUState",
            Call::StateSize => "fmi3SerializedFMUStateSize",
            Call::SerializeState => "fmi3SerializeFMUState",
            Call::DeserializeState => "fmi3DeserializeFMUState",
        }
    }

    fn allowed(call: Call) -> &'static [Mode] {
        match call {
            Call::SetupExperiment | Call::EnterInitializationMode => &[Instantiated],
            Call::ExitInitializationMode => &[InitializationMode],
            Call::Terminate | Call::DoStep => &[StepMode],
            Call::GetReal | Call::Get => &[InitializationMode, StepMode, Terminated],
            Call::Set => &[Instantiated, InitializationMode, StepMode],
            Call::Reset | Call::FreeInstance | Call::GetState | Call::SetState => ALIVE,
            Call::FreeState | Call::StateSize | Call::SerializeState => ALIVE,
            Call::DeserializeState => ALIVE,
        }
    }

    /// A fresh handle: a multiple of 8 above 0x4733_0000_0000 ("G3").
    fn next_state_handle() -> usize {
        0x4733_0000_0000 + 8 * NEXT_STATE_HANDLE.fetch_add(1, Ordering::Relaxed)
    }

    fn token_mismatch(given: &str, own: &str) -> String {
        format!("instantiationToken \"{given}\" does not match this FMU's \"{own}\"")
    }

    fn independent_variable(table: &VariableTable) -> Option<u32> {
        Some(time_value_reference(table))
    }

    fn generate(info: &ModelInfo, table: &VariableTable) -> (String, String) {
        model_description::generate(info, table)
    }
}

/// The model's configuration in the resources directory of FMI 3.0's
/// `resourcePath` (an absolute path with a trailing separator, not a URI).
pub fn read_resources<M: FmuModel>(resource_path: &str) -> Result<M::Config, String> {
    if resource_path.is_empty() {
        let file = M::RESOURCE_FILE;
        return Err(format!(
            "resourcePath is empty: the FMU needs its resources/{file}"
        ));
    }
    M::read_resources(std::path::Path::new(resource_path))
}
