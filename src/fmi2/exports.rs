//! The FMI 2.0 common and co-simulation functions, exported from the cdylib
//! under their standard names.
//!
//! Each function is thin: it checks pointers, reads C arguments, catches
//! panics (a panic turns into fmi2Fatal and a logged message, never an
//! unwind across the C boundary) and delegates to `Instance`. Each is checked
//! against the standard's typedef at compile time.

use super::instance::{Instance, Mode};
use super::logging::Logger;
use super::Physics;
use crate::model::{Value, VarType};
use fmi_sys::fmi2::*;
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

type Inst = Instance<Physics>;

const OK: fmi2Status = fmi2Status_fmi2OK;
const ERROR: fmi2Status = fmi2Status_fmi2Error;
const FATAL: fmi2Status = fmi2Status_fmi2Fatal;

pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Run `f` on the instance behind `c`: NULL gives fmi2Error, `Err` gives
/// fmi2Error with a logged message, a panic gives fmi2Fatal.
///
/// # Safety
/// `c` is NULL or a pointer returned by `fmi2Instantiate` and not yet freed.
unsafe fn with_instance(
    c: fmi2Component,
    function: &str,
    f: impl FnOnce(&mut Inst) -> Result<fmi2Status, String>,
) -> fmi2Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: per the function's contract.
    let inst = unsafe { &mut *(c as *mut Inst) };
    if inst.mode() == Mode::Fatal {
        inst.logger.log(
            ERROR,
            &format!(
                "{function}: the instance had a fatal error; only fmi2FreeInstance is allowed"
            ),
        );
        return ERROR;
    }
    match catch_unwind(AssertUnwindSafe(|| f(&mut *inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            let message = if message.starts_with(function) {
                message
            } else {
                format!("{function}: {message}")
            };
            inst.logger.log(ERROR, &message);
            ERROR
        }
        Err(payload) => {
            inst.set_fatal();
            let message = format!("{function}: internal error: {}", panic_message(&*payload));
            // The logger itself is the importer's; do not let it unwind us.
            let _ = catch_unwind(AssertUnwindSafe(|| inst.logger.log(FATAL, &message)));
            FATAL
        }
    }
}

/// Refuse lengths no array can have (more bytes than `isize::MAX`).
fn check_len<T>(n: usize, what: &str) -> Result<(), String> {
    let max = isize::MAX as usize / std::mem::size_of::<T>().max(1);
    if n > max {
        return Err(format!("the length of {what}, {n}, is impossibly large"));
    }
    Ok(())
}

/// A slice of `n` elements at `p`; NULL is allowed only when `n` is 0.
///
/// # Safety
/// If not NULL, `p` points to `n` valid elements.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    check_len::<T>(n, what)?;
    if n == 0 {
        Ok(&[])
    } else if p.is_null() {
        Err(format!("{what} is NULL but its length is {n}"))
    } else {
        // SAFETY: per the function's contract.
        Ok(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// # Safety
/// If not NULL, `p` points to `n` writable elements.
pub(crate) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
    check_len::<T>(n, what)?;
    if n == 0 {
        Ok(&mut [])
    } else if p.is_null() {
        Err(format!("{what} is NULL but its length is {n}"))
    } else {
        // SAFETY: per the function's contract.
        Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// # Safety
/// `p` is NULL or a NUL-terminated string.
pub(crate) unsafe fn string(p: *const c_char, what: &str) -> Result<String, String> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: per the function's contract.
    Ok(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

// ---- common functions ------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    fmi2TypesPlatform.as_ptr() as *const c_char
}
const _: fmi2GetTypesPlatformTYPE = Some(fmi2GetTypesPlatform);

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    fmi2Version.as_ptr() as *const c_char
}
const _: fmi2GetVersionTYPE = Some(fmi2GetVersion);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n_categories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetDebugLogging", |inst| {
            let list = slice(categories, n_categories, "categories")?;
            let names = list
                .iter()
                .map(|&p| string(p, "a category"))
                .collect::<Result<Vec<_>, _>>()?;
            inst.logger.configure(logging_on != 0, &names)?;
            Ok(OK)
        })
    }
}
const _: fmi2SetDebugLoggingTYPE = Some(fmi2SetDebugLogging);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    if functions.is_null() {
        return std::ptr::null_mut();
    }
    // SAFETY: not NULL; the importer passes a valid callback struct.
    let callbacks = unsafe { *functions };
    let result = catch_unwind(AssertUnwindSafe(|| {
        let name = unsafe { string(instance_name, "instanceName") };
        let name_shown = name.clone().unwrap_or_default();
        let logger = Logger::new(
            callbacks.logger,
            callbacks.componentEnvironment,
            &name_shown,
            logging_on != 0,
        );
        let args = name.and_then(|_| {
            Ok((unsafe { string(fmu_guid, "fmuGUID") }?, unsafe {
                string(fmu_resource_location, "fmuResourceLocation")
            }?))
        });
        let (guid, location) = match args {
            Ok(a) => a,
            Err(e) => return Err((logger, e)),
        };
        Inst::instantiate(fmu_type, &guid, &location, logger)
    }));
    match result {
        Ok(Ok(inst)) => Box::into_raw(Box::new(inst)) as fmi2Component,
        Ok(Err((logger, reason))) => {
            logger.log(ERROR, &format!("fmi2Instantiate: {reason}"));
            std::ptr::null_mut()
        }
        Err(payload) => {
            let logger = Logger::new(callbacks.logger, callbacks.componentEnvironment, "", true);
            let msg = format!(
                "fmi2Instantiate: internal error: {}",
                panic_message(&*payload)
            );
            let _ = catch_unwind(AssertUnwindSafe(|| logger.log(FATAL, &msg)));
            std::ptr::null_mut()
        }
    }
}
const _: fmi2InstantiateTYPE = Some(fmi2Instantiate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if c.is_null() {
        return;
    }
    // SAFETY: `c` came from fmi2Instantiate (Box::into_raw) and is freed once.
    let inst = unsafe { Box::from_raw(c as *mut Inst) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
}
const _: fmi2FreeInstanceTYPE = Some(fmi2FreeInstance);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _tolerance_defined: fmi2Boolean,
    _tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetupExperiment", |inst| {
            let stop = (stop_time_defined != 0).then_some(stop_time);
            inst.setup_experiment(start_time, stop).map(|()| OK)
        })
    }
}
const _: fmi2SetupExperimentTYPE = Some(fmi2SetupExperiment);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2EnterInitializationMode", |inst| {
            inst.enter_initialization_mode().map(|()| OK)
        })
    }
}
const _: fmi2EnterInitializationModeTYPE = Some(fmi2EnterInitializationMode);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2ExitInitializationMode", |inst| {
            inst.exit_initialization_mode().map(|()| OK)
        })
    }
}
const _: fmi2ExitInitializationModeTYPE = Some(fmi2ExitInitializationMode);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    unsafe { with_instance(c, "fmi2Terminate", |inst| inst.terminate().map(|()| OK)) }
}
const _: fmi2TerminateTYPE = Some(fmi2Terminate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    unsafe { with_instance(c, "fmi2Reset", |inst| inst.reset().map(|()| OK)) }
}
const _: fmi2ResetTYPE = Some(fmi2Reset);

// ---- getters and setters ----------------------------------------------------

/// Read `nvr` variables of type `ty` and write them through `store`.
///
/// # Safety
/// Standard FMI 2.0 contract for the fmi2Get* functions.
unsafe fn get<T>(
    c: fmi2Component,
    function: &str,
    ty: VarType,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut T,
    store: impl Fn(Value) -> T,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let out = slice_mut(value, nvr, "value")?;
            let mut out = out.iter_mut();
            inst.get_each(function, ty, vrs, |v| {
                if let Some(o) = out.next() {
                    *o = store(v);
                }
            })?;
            Ok(OK)
        })
    }
}

/// # Safety
/// Standard FMI 2.0 contract for the fmi2Set* functions.
unsafe fn set<T: Copy>(
    c: fmi2Component,
    function: &str,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
    load: impl Fn(T) -> Value,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values: Vec<Value> = slice(value, nvr, "value")?
                .iter()
                .map(|&x| load(x))
                .collect();
            inst.set(function, vrs, &values).map(|()| OK)
        })
    }
}

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetReal", |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let out = slice_mut(value, nvr, "value")?;
            inst.get_reals(vrs, out)?;
            Ok(OK)
        })
    }
}
const _: fmi2GetRealTYPE = Some(fmi2GetReal);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        get(
            c,
            "fmi2GetInteger",
            VarType::Integer,
            vr,
            nvr,
            value,
            |v| match v {
                Value::Integer(n) => n,
                _ => 0,
            },
        )
    }
}
const _: fmi2GetIntegerTYPE = Some(fmi2GetInteger);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        get(c, "fmi2GetBoolean", VarType::Boolean, vr, nvr, value, |v| {
            matches!(v, Value::Boolean(true)) as fmi2Boolean
        })
    }
}
const _: fmi2GetBooleanTYPE = Some(fmi2GetBoolean);

fn no_strings(vrs: &[fmi2ValueReference]) -> Result<fmi2Status, String> {
    match vrs.first() {
        None => Ok(OK),
        Some(vr) => Err(format!(
            "unknown value reference {vr}: this model has no String variables"
        )),
    }
}

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetString", |inst| {
            inst.get("fmi2GetString", VarType::Real, &[])?;
            no_strings(slice(vr, nvr, "vr")?)
        })
    }
}
const _: fmi2GetStringTYPE = Some(fmi2GetString);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe { set(c, "fmi2SetReal", vr, nvr, value, Value::Real) }
}
const _: fmi2SetRealTYPE = Some(fmi2SetReal);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    unsafe { set(c, "fmi2SetInteger", vr, nvr, value, Value::Integer) }
}
const _: fmi2SetIntegerTYPE = Some(fmi2SetInteger);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    unsafe {
        set(c, "fmi2SetBoolean", vr, nvr, value, |b| {
            Value::Boolean(b != 0)
        })
    }
}
const _: fmi2SetBooleanTYPE = Some(fmi2SetBoolean);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetString", |inst| {
            inst.set("fmi2SetString", &[], &[])?;
            no_strings(slice(vr, nvr, "vr")?)
        })
    }
}
const _: fmi2SetStringTYPE = Some(fmi2SetString);

// ---- FMU state --------------------------------------------------------------

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetFMUstate", |inst| {
            if state.is_null() {
                return Err("FMUstate is NULL".into());
            }
            let key = inst.get_state(*state as usize)?;
            *state = key as fmi2FMUstate;
            Ok(OK)
        })
    }
}
const _: fmi2GetFMUstateTYPE = Some(fmi2GetFMUstate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetFMUstate", |inst| {
            inst.set_state(state as usize).map(|()| OK)
        })
    }
}
const _: fmi2SetFMUstateTYPE = Some(fmi2SetFMUstate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2FreeFMUstate", |inst| {
            if state.is_null() {
                return Ok(OK);
            }
            inst.free_state(*state as usize)?;
            *state = std::ptr::null_mut();
            Ok(OK)
        })
    }
}
const _: fmi2FreeFMUstateTYPE = Some(fmi2FreeFMUstate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SerializedFMUstateSize", |inst| {
            if size.is_null() {
                return Err("size is NULL".into());
            }
            *size = inst.serialize_state(state as usize)?.len();
            Ok(OK)
        })
    }
}
const _: fmi2SerializedFMUstateSizeTYPE = Some(fmi2SerializedFMUstateSize);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    state: fmi2FMUstate,
    serialized: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SerializeFMUstate", |inst| {
            let bytes = inst.serialize_state(state as usize)?;
            if size < bytes.len() {
                return Err(format!(
                    "size = {size} is too small: the state needs {} bytes (fmi2SerializedFMUstateSize)",
                    bytes.len()
                ));
            }
            let out = slice_mut(serialized as *mut u8, bytes.len(), "serializedState")?;
            out.copy_from_slice(&bytes);
            Ok(OK)
        })
    }
}
const _: fmi2SerializeFMUstateTYPE = Some(fmi2SerializeFMUstate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serialized: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2DeSerializeFMUstate", |inst| {
            if state.is_null() {
                return Err("FMUstate is NULL".into());
            }
            let bytes = slice(serialized as *const u8, size, "serializedState")?;
            let key = inst.deserialize_state(bytes)?;
            *state = key as fmi2FMUstate;
            Ok(OK)
        })
    }
}
const _: fmi2DeSerializeFMUstateTYPE = Some(fmi2DeSerializeFMUstate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetRealInputDerivatives", |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let orders = slice(order, nvr, "order")?;
            let values = slice(value, nvr, "value")?;
            inst.set_input_derivatives(vrs, orders, values).map(|()| OK)
        })
    }
}
const _: fmi2SetRealInputDerivativesTYPE = Some(fmi2SetRealInputDerivatives);

// ---- not provided (declared so in modelDescription.xml) ---------------------

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _unknown: *const fmi2ValueReference,
    _n_unknown: usize,
    _known: *const fmi2ValueReference,
    _n_known: usize,
    _dv_known: *const fmi2Real,
    _dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetDirectionalDerivative", |_| {
            Err("not provided (providesDirectionalDerivative=\"false\")".into())
        })
    }
}
const _: fmi2GetDirectionalDerivativeTYPE = Some(fmi2GetDirectionalDerivative);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetRealOutputDerivatives", |_| {
            Err("not provided (maxOutputDerivativeOrder=\"0\")".into())
        })
    }
}
const _: fmi2GetRealOutputDerivativesTYPE = Some(fmi2GetRealOutputDerivatives);

// ---- co-simulation ----------------------------------------------------------

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    _no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2DoStep", |inst| {
            inst.do_step(current_communication_point, communication_step_size)
        })
    }
}
const _: fmi2DoStepTYPE = Some(fmi2DoStep);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2CancelStep", |_| {
            Err("fmi2DoStep is synchronous: there is no step in progress to cancel".into())
        })
    }
}
const _: fmi2CancelStepTYPE = Some(fmi2CancelStep);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2Status,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetStatus", |_| {
            Err(format!(
                "status kind {kind}: fmi2DoStep never returns fmi2Pending, there is no asynchronous status"
            ))
        })
    }
}
const _: fmi2GetStatusTYPE = Some(fmi2GetStatus);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetRealStatus", |inst| {
            if value.is_null() {
                return Err("value is NULL".into());
            }
            *value = inst.get_real_status(kind)?;
            Ok(OK)
        })
    }
}
const _: fmi2GetRealStatusTYPE = Some(fmi2GetRealStatus);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetIntegerStatus", |_| {
            Err(format!("status kind {kind} has no Integer value"))
        })
    }
}
const _: fmi2GetIntegerStatusTYPE = Some(fmi2GetIntegerStatus);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetBooleanStatus", |inst| {
            if value.is_null() {
                return Err("value is NULL".into());
            }
            *value = inst.get_boolean_status(kind)? as fmi2Boolean;
            Ok(OK)
        })
    }
}
const _: fmi2GetBooleanStatusTYPE = Some(fmi2GetBooleanStatus);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetStringStatus", |_| {
            Err(format!("status kind {kind} has no String value"))
        })
    }
}
const _: fmi2GetStringStatusTYPE = Some(fmi2GetStringStatus);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::describe;
    use crate::scene::{BodyKind, Scene};

    fn component() -> fmi2Component {
        let scene = Scene::lee1994(BodyKind::Glider, 10.0, 0.0025);
        let guid = describe::<Physics>(&scene).unwrap().guid;
        let logger = Logger::new(None, std::ptr::null_mut(), "t", false);
        let inst = Inst::new(scene, &guid, logger).unwrap_or_else(|(_, e)| panic!("{e}"));
        Box::into_raw(Box::new(inst)) as fmi2Component
    }

    #[test]
    fn a_panic_becomes_fatal_and_only_free_is_left() {
        let c = component();
        let status = unsafe { with_instance(c, "fmi2Test", |_| panic!("boom")) };
        assert_eq!(status, FATAL);
        assert_eq!(unsafe { fmi2EnterInitializationMode(c) }, ERROR);
        unsafe { fmi2FreeInstance(c) };
    }

    #[test]
    fn null_component_gives_error_and_free_of_null_does_nothing() {
        unsafe {
            assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 0.1, 1), ERROR);
            assert_eq!(fmi2Reset(std::ptr::null_mut()), ERROR);
            fmi2FreeInstance(std::ptr::null_mut());
        }
    }

    #[test]
    fn null_arrays_are_refused_unless_empty() {
        let c = component();
        unsafe {
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(
                fmi2GetReal(c, std::ptr::null(), 0, std::ptr::null_mut()),
                OK
            );
            assert_eq!(
                fmi2GetReal(c, std::ptr::null(), 2, std::ptr::null_mut()),
                ERROR
            );
            let vr = [0u32];
            assert_eq!(fmi2GetReal(c, vr.as_ptr(), 1, std::ptr::null_mut()), ERROR);
            let mut x = [0.0];
            assert_eq!(fmi2GetReal(c, vr.as_ptr(), 1, x.as_mut_ptr()), OK);
            assert_eq!(x[0], 24.0);
            let mut state: fmi2FMUstate = std::ptr::null_mut();
            assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
            assert!(!state.is_null());
            assert_eq!(fmi2FreeFMUstate(c, &mut state), OK);
            assert!(state.is_null());
            assert_eq!(fmi2FreeFMUstate(c, &mut state), OK, "freeing NULL is fine");
            let vr = [0u32];
            assert_eq!(
                fmi2GetReal(c, vr.as_ptr(), usize::MAX, x.as_mut_ptr()),
                ERROR
            );
            let mut foreign = 8usize as fmi2FMUstate;
            assert_eq!(fmi2FreeFMUstate(c, &mut foreign), ERROR);
            fmi2FreeInstance(c);
        }
    }
}
