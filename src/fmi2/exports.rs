//! The FMI 2.0 common and co-simulation functions, exported from the cdylib
//! under their standard names.
//!
//! Each function is thin: it reads its C arguments (checked by
//! `fmi_common::abi`), runs inside `fmi_common::abi::with_instance` (a panic
//! turns into fmi2Fatal and a logged message, never an unwind across the C
//! boundary; a refusal into fmi2Error and a logged message) and delegates to
//! the shared `Instance`. Each is checked against the standard's typedef at
//! compile time.

use super::instance::{Fmi2, Instance};
use super::logging::Logger;
use crate::fmi_common::abi::{self, categories, no_variables, slice, slice_mut, string};
use crate::model::ExportedModel;
use crate::model::{Value, VarType};
use fmi_sys::fmi2::*;
use std::ffi::c_char;

type Inst = Instance<ExportedModel>;

const OK: fmi2Status = fmi2Status_fmi2OK;
#[cfg(test)]
const ERROR: fmi2Status = fmi2Status_fmi2Error;
#[cfg(test)]
const FATAL: fmi2Status = fmi2Status_fmi2Fatal;

/// `abi::with_instance` on an FMI 2.0 instance of the shipped physics.
///
/// # Safety
/// `c` is NULL or a pointer returned by `fmi2Instantiate` and not yet freed.
unsafe fn with_instance(
    c: fmi2Component,
    function: &str,
    f: impl FnOnce(&mut Inst) -> Result<fmi2Status, String>,
) -> fmi2Status {
    unsafe { abi::with_instance(c, function, f) }
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
    list: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetDebugLogging", |inst| {
            let names = categories(list, n_categories)?;
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
    let logger = |name: &str, debug| {
        Logger::new(
            callbacks.logger,
            callbacks.componentEnvironment,
            name,
            debug,
        )
    };
    let make = || {
        let name = unsafe { string(instance_name, "instanceName") };
        let logger = logger(name.as_deref().unwrap_or_default(), logging_on != 0);
        let args = name.and_then(|_| {
            Ok((unsafe { string(fmu_guid, "fmuGUID") }?, unsafe {
                string(fmu_resource_location, "fmuResourceLocation")
            }?))
        });
        match args {
            Ok((guid, location)) => Inst::instantiate(fmu_type, &guid, &location, logger),
            Err(e) => Err((logger, e)),
        }
    };
    abi::instantiate("fmi2Instantiate", make, || logger("", true))
}
const _: fmi2InstantiateTYPE = Some(fmi2Instantiate);

/// # Safety
/// Standard FMI 2.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    unsafe { abi::free_instance::<ExportedModel, Fmi2>(c) }
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
    (vr, nvr): (*const fmi2ValueReference, usize),
    value: *mut T,
    store: impl Fn(Value) -> T,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let out = slice_mut(value, nvr, "value")?;
            inst.get_into(function, ty, vrs, out, store).map(|()| OK)
        })
    }
}

/// # Safety
/// Standard FMI 2.0 contract for the fmi2Set* functions.
unsafe fn set<T: Copy>(
    c: fmi2Component,
    function: &str,
    (vr, nvr): (*const fmi2ValueReference, usize),
    value: *const T,
    load: impl Fn(T) -> Value,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, |inst| {
            let vrs = slice(vr, nvr, "vr")?;
            let values = slice(value, nvr, "value")?;
            inst.set_from(function, vrs, values, load).map(|()| OK)
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
    let store = |v| match v {
        Value::Integer(n) => n,
        _ => 0,
    };
    unsafe {
        get(
            c,
            "fmi2GetInteger",
            VarType::Integer,
            (vr, nvr),
            value,
            store,
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
    let store = |v| matches!(v, Value::Boolean(true)) as fmi2Boolean;
    unsafe {
        get(
            c,
            "fmi2GetBoolean",
            VarType::Boolean,
            (vr, nvr),
            value,
            store,
        )
    }
}
const _: fmi2GetBooleanTYPE = Some(fmi2GetBoolean);

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
            no_variables(slice(vr, nvr, "vr")?, "String").map(|()| OK)
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
    unsafe { set(c, "fmi2SetReal", (vr, nvr), value, Value::Real) }
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
    unsafe { set(c, "fmi2SetInteger", (vr, nvr), value, Value::Integer) }
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
    let load = |b| Value::Boolean(b != 0);
    unsafe { set(c, "fmi2SetBoolean", (vr, nvr), value, load) }
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
            no_variables(slice(vr, nvr, "vr")?, "String").map(|()| OK)
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
            abi::get_state(inst, state).map(|()| OK)
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
            abi::free_state(inst, state).map(|()| OK)
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
            abi::state_size(inst, state, size).map(|()| OK)
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
            abi::serialize_state(inst, state, serialized as *mut u8, size).map(|()| OK)
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
            abi::deserialize_state(inst, serialized as *const u8, size, state).map(|()| OK)
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
            let function = "fmi2SetRealInputDerivatives";
            inst.set_input_derivatives(function, vrs, orders, values)
                .map(|()| OK)
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
            let report = inst.do_step(current_communication_point, communication_step_size)?;
            Ok(report.status)
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
        let guid = describe::<ExportedModel>(scene.clone()).unwrap().guid;
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
