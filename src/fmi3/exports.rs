//! The FMI 3.0 functions this FMU provides, exported from the cdylib under
//! their standard names (the ones it does not provide are in
//! `unsupported`).
//!
//! Each function is thin: it reads its C arguments (checked by
//! `fmi_common::abi`), runs inside `fmi_common::abi::with_instance` (a panic
//! turns into fmi3Fatal and a logged message, never an unwind across the C
//! boundary; a refusal into fmi3Error and a logged message) and delegates to
//! the shared `Instance`. Each is checked against the standard's typedef at
//! compile time.

use super::instance::{Fmi3, Instance};
use super::logging::Logger;
use crate::fmi_common::abi::{self, categories, slice, slice_mut, string};
use crate::model::{ExportedModel, FmuModel, Value, VarType};
use fmi_sys::fmi3::*;
use std::ffi::c_char;

pub(super) type Inst = Instance<ExportedModel>;

pub(super) const OK: fmi3Status = fmi3Status_fmi3OK;
#[cfg(test)]
pub(super) const ERROR: fmi3Status = fmi3Status_fmi3Error;

/// `abi::with_instance` on an FMI 3.0 instance of the shipped physics.
///
/// # Safety
/// `c` is NULL or a pointer returned by `fmi3InstantiateCoSimulation` and
/// not yet freed.
pub(super) unsafe fn with_instance(
    c: fmi3Instance,
    function: &str,
    f: impl FnOnce(&mut Inst) -> Result<fmi3Status, String>,
) -> fmi3Status {
    unsafe { abi::with_instance(c, function, f) }
}

/// `nValues` must equal `nValueReferences`: every variable here is a scalar.
pub(super) fn check_scalars(nvr: usize, n_values: usize) -> Result<(), String> {
    if n_values != nvr {
        return Err(format!(
            "nValues = {n_values} differs from nValueReferences = {nvr}: every variable of this FMU is a scalar"
        ));
    }
    Ok(())
}

// ---- common functions ------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    fmi3Version.as_ptr() as *const c_char
}
const _: fmi3GetVersionTYPE = Some(fmi3GetVersion);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: fmi3Instance,
    logging_on: fmi3Boolean,
    n_categories: usize,
    list: *const fmi3String,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3SetDebugLogging", |inst| {
            let names = categories(list, n_categories)?;
            inst.logger.configure(logging_on, &names)?;
            Ok(OK)
        })
    }
}
const _: fmi3SetDebugLoggingTYPE = Some(fmi3SetDebugLogging);

/// The arguments of fmi3InstantiateCoSimulation, read.
///
/// # Safety
/// The strings are NULL or NUL-terminated.
unsafe fn instantiate(
    name: fmi3String,
    token: fmi3String,
    resource_path: fmi3String,
    (event_mode_used, early_return_allowed): (bool, bool),
    logger: Logger,
) -> Result<Inst, (Logger, String)> {
    let args = unsafe {
        string(name, "instanceName").and_then(|_| {
            Ok((
                string(token, "instantiationToken")?,
                string(resource_path, "resourcePath")?,
            ))
        })
    };
    let (token, resources) = match args {
        Ok(a) => a,
        Err(e) => return Err((logger, e)),
    };
    if event_mode_used {
        let seen_in = ExportedModel::EVENT_OUTPUTS;
        let why = format!(
            "eventModeUsed = true: this FMU has no event mode (hasEventMode=\"false\"); \
             its events are logged and seen in {seen_in}"
        );
        return Err((logger, why));
    }
    let mut inst = match super::instance::read_resources::<ExportedModel>(&resources) {
        Ok(config) => Inst::new(config, &token, logger)?,
        Err(e) => return Err((logger, e)),
    };
    inst.allow_early_return(early_return_allowed);
    Ok(inst)
}

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    _visible: fmi3Boolean,
    logging_on: fmi3Boolean,
    event_mode_used: fmi3Boolean,
    early_return_allowed: fmi3Boolean,
    _required_intermediate_variables: *const fmi3ValueReference,
    _n_required_intermediate_variables: usize,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    _intermediate_update: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let make = || {
        let logger = Logger::new(log_message, instance_environment, logging_on);
        unsafe {
            instantiate(
                instance_name,
                instantiation_token,
                resource_path,
                (event_mode_used, early_return_allowed),
                logger,
            )
        }
    };
    let fallback = || Logger::new(log_message, instance_environment, true);
    abi::instantiate("fmi3InstantiateCoSimulation", make, fallback)
}
const _: fmi3InstantiateCoSimulationTYPE = Some(fmi3InstantiateCoSimulation);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
    unsafe { abi::free_instance::<ExportedModel, Fmi3>(c) }
}
const _: fmi3FreeInstanceTYPE = Some(fmi3FreeInstance);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: fmi3Instance,
    _tolerance_defined: fmi3Boolean,
    _tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3EnterInitializationMode", |inst| {
            let stop = stop_time_defined.then_some(stop_time);
            inst.setup_experiment(start_time, stop)?;
            inst.enter_initialization_mode().map(|()| OK)
        })
    }
}
const _: fmi3EnterInitializationModeTYPE = Some(fmi3EnterInitializationMode);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: fmi3Instance) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3ExitInitializationMode", |inst| {
            inst.exit_initialization_mode().map(|()| OK)
        })
    }
}
const _: fmi3ExitInitializationModeTYPE = Some(fmi3ExitInitializationMode);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(c: fmi3Instance) -> fmi3Status {
    unsafe { with_instance(c, "fmi3Terminate", |inst| inst.terminate().map(|()| OK)) }
}
const _: fmi3TerminateTYPE = Some(fmi3Terminate);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(c: fmi3Instance) -> fmi3Status {
    unsafe { with_instance(c, "fmi3Reset", |inst| inst.reset().map(|()| OK)) }
}
const _: fmi3ResetTYPE = Some(fmi3Reset);

// ---- getters and setters ----------------------------------------------------

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3GetFloat64", |inst| {
            check_scalars(nvr, n_values)?;
            let vrs = slice(vr, nvr, "valueReferences")?;
            let out = slice_mut(values, nvr, "values")?;
            inst.get_reals(vrs, out).map(|()| OK)
        })
    }
}
const _: fmi3GetFloat64TYPE = Some(fmi3GetFloat64);

/// Read `nvr` variables of type `ty` and write them through `store`.
///
/// # Safety
/// Standard FMI 3.0 contract for the fmi3Get* functions.
unsafe fn get<T>(
    c: fmi3Instance,
    function: &str,
    ty: VarType,
    (vr, nvr): (*const fmi3ValueReference, usize),
    (values, n_values): (*mut T, usize),
    store: impl Fn(Value) -> T,
) -> fmi3Status {
    unsafe {
        with_instance(c, function, |inst| {
            check_scalars(nvr, n_values)?;
            let vrs = slice(vr, nvr, "valueReferences")?;
            let out = slice_mut(values, nvr, "values")?;
            inst.get_into(function, ty, vrs, out, store).map(|()| OK)
        })
    }
}

/// # Safety
/// Standard FMI 3.0 contract for the fmi3Set* functions.
unsafe fn set<T: Copy>(
    c: fmi3Instance,
    function: &str,
    (vr, nvr): (*const fmi3ValueReference, usize),
    (values, n_values): (*const T, usize),
    load: impl Fn(T) -> Value,
) -> fmi3Status {
    unsafe {
        with_instance(c, function, |inst| {
            check_scalars(nvr, n_values)?;
            let vrs = slice(vr, nvr, "valueReferences")?;
            let values = slice(values, nvr, "values")?;
            inst.set_from(function, vrs, values, load).map(|()| OK)
        })
    }
}

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetInt32(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    let store = |v| match v {
        Value::Integer(n) => n,
        _ => 0,
    };
    let (vrs, out) = ((vr, nvr), (values, n_values));
    unsafe { get(c, "fmi3GetInt32", VarType::Integer, vrs, out, store) }
}
const _: fmi3GetInt32TYPE = Some(fmi3GetInt32);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    let store = |v| matches!(v, Value::Boolean(true));
    let (vrs, out) = ((vr, nvr), (values, n_values));
    unsafe { get(c, "fmi3GetBoolean", VarType::Boolean, vrs, out, store) }
}
const _: fmi3GetBooleanTYPE = Some(fmi3GetBoolean);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    unsafe {
        set(
            c,
            "fmi3SetFloat64",
            (vr, nvr),
            (values, n_values),
            Value::Real,
        )
    }
}
const _: fmi3SetFloat64TYPE = Some(fmi3SetFloat64);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetInt32(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    unsafe {
        set(
            c,
            "fmi3SetInt32",
            (vr, nvr),
            (values, n_values),
            Value::Integer,
        )
    }
}
const _: fmi3SetInt32TYPE = Some(fmi3SetInt32);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    unsafe {
        set(
            c,
            "fmi3SetBoolean",
            (vr, nvr),
            (values, n_values),
            Value::Boolean,
        )
    }
}
const _: fmi3SetBooleanTYPE = Some(fmi3SetBoolean);

// ---- FMU state --------------------------------------------------------------

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3GetFMUState", |inst| {
            abi::get_state(inst, state).map(|()| OK)
        })
    }
}
const _: fmi3GetFMUStateTYPE = Some(fmi3GetFMUState);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(c: fmi3Instance, state: fmi3FMUState) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3SetFMUState", |inst| {
            inst.set_state(state as usize).map(|()| OK)
        })
    }
}
const _: fmi3SetFMUStateTYPE = Some(fmi3SetFMUState);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3FreeFMUState", |inst| {
            abi::free_state(inst, state).map(|()| OK)
        })
    }
}
const _: fmi3FreeFMUStateTYPE = Some(fmi3FreeFMUState);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: fmi3Instance,
    state: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3SerializedFMUStateSize", |inst| {
            abi::state_size(inst, state, size).map(|()| OK)
        })
    }
}
const _: fmi3SerializedFMUStateSizeTYPE = Some(fmi3SerializedFMUStateSize);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: fmi3Instance,
    state: fmi3FMUState,
    serialized: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3SerializeFMUState", |inst| {
            abi::serialize_state(inst, state, serialized, size).map(|()| OK)
        })
    }
}
const _: fmi3SerializeFMUStateTYPE = Some(fmi3SerializeFMUState);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: fmi3Instance,
    serialized: *const fmi3Byte,
    size: usize,
    state: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3DeserializeFMUState", |inst| {
            abi::deserialize_state(inst, serialized, size, state).map(|()| OK)
        })
    }
}
const _: fmi3DeserializeFMUStateTYPE = Some(fmi3DeserializeFMUState);

// ---- co-simulation ----------------------------------------------------------

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    c: fmi3Instance,
    current_communication_point: fmi3Float64,
    communication_step_size: fmi3Float64,
    _no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status {
    unsafe {
        with_instance(c, "fmi3DoStep", |inst| {
            let outs = [event_handling_needed, terminate_simulation, early_return];
            if outs.iter().any(|p| p.is_null()) || last_successful_time.is_null() {
                return Err(
                    "an output argument (eventHandlingNeeded, terminateSimulation, \
                            earlyReturn, lastSuccessfulTime) is NULL"
                        .into(),
                );
            }
            let report = inst.do_step(current_communication_point, communication_step_size)?;
            *event_handling_needed = false;
            *terminate_simulation = report.terminate;
            *early_return = report.early_return;
            *last_successful_time = report.last_successful_time;
            Ok(report.status)
        })
    }
}
const _: fmi3DoStepTYPE = Some(fmi3DoStep);
