//! The FMI 3.0 functions this co-simulation FMU does not provide, exported
//! all the same (the standard wants every function of the API in the
//! binary): each refuses with fmi3Error and a log line saying why, as its
//! modelDescription.xml declares. Written by macro: they differ only in
//! their signatures (each checked against the standard's typedef).

use super::exports::{with_instance, OK};
use crate::fmi_common::abi::{self, slice};
use crate::fmi_common::Status;
use fmi_sys::fmi3::*;

/// Functions on an instance that always refuse, with the reason.
macro_rules! not_provided {
    ($($name:ident: $ty:ident ($($arg:ident: $argty:ty),*) => $why:expr;)*) => {$(
        /// # Safety
        /// Standard FMI 3.0 contract for this function.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: fmi3Instance $(, $arg: $argty)*) -> fmi3Status {
            $(let _ = $arg;)*
            unsafe { with_instance(c, stringify!($name), |_| Err($why.to_string())) }
        }
        const _: $ty = Some($name);
    )*};
}

/// Getters and setters of types the model has no variable of: an empty
/// request is fine, any value reference is unknown.
macro_rules! no_variables {
    ($($name:ident: $ty:ident, $what:literal ($($arg:ident: $argty:ty),*);)*) => {$(
        /// # Safety
        /// Standard FMI 3.0 contract for this function.
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            nvr: usize
            $(, $arg: $argty)*
        ) -> fmi3Status {
            $(let _ = $arg;)*
            unsafe {
                with_instance(c, stringify!($name), |_| {
                    abi::no_variables(slice(vr, nvr, "valueReferences")?, $what).map(|()| OK)
                })
            }
        }
        const _: $ty = Some($name);
    )*};
}

const NO_EVENT_MODE: &str = "not provided: this FMU has no event mode (hasEventMode=\"false\")";
const NO_CLOCKS: &str = "not provided: this FMU has no clocks";
const NO_ME: &str = "not provided: this FMU is for co-simulation only";

not_provided! {
    fmi3EnterEventMode: fmi3EnterEventModeTYPE () => NO_EVENT_MODE;
    fmi3EnterStepMode: fmi3EnterStepModeTYPE () => NO_EVENT_MODE;
    fmi3EvaluateDiscreteStates: fmi3EvaluateDiscreteStatesTYPE () => NO_EVENT_MODE;
    fmi3UpdateDiscreteStates: fmi3UpdateDiscreteStatesTYPE (
        a: *mut fmi3Boolean, b: *mut fmi3Boolean, d: *mut fmi3Boolean, e: *mut fmi3Boolean,
        f: *mut fmi3Boolean, g: *mut fmi3Float64) => NO_EVENT_MODE;
    fmi3GetNumberOfVariableDependencies: fmi3GetNumberOfVariableDependenciesTYPE (
        vr: fmi3ValueReference, n: *mut usize) =>
        "not provided (providesPerElementDependencies=\"false\"): the dependencies are in modelDescription.xml";
    fmi3GetVariableDependencies: fmi3GetVariableDependenciesTYPE (
        vr: fmi3ValueReference, a: *mut usize, b: *mut fmi3ValueReference, d: *mut usize,
        e: *mut fmi3DependencyKind, n: usize) =>
        "not provided (providesPerElementDependencies=\"false\"): the dependencies are in modelDescription.xml";
    fmi3GetDirectionalDerivative: fmi3GetDirectionalDerivativeTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3ValueReference, e: usize,
        f: *const fmi3Float64, g: usize, h: *mut fmi3Float64, i: usize) =>
        "not provided (providesDirectionalDerivative=\"false\")";
    fmi3GetAdjointDerivative: fmi3GetAdjointDerivativeTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3ValueReference, e: usize,
        f: *const fmi3Float64, g: usize, h: *mut fmi3Float64, i: usize) =>
        "not provided (providesAdjointDerivatives=\"false\")";
    fmi3EnterConfigurationMode: fmi3EnterConfigurationModeTYPE () =>
        "not provided: this FMU has no structural parameters";
    fmi3ExitConfigurationMode: fmi3ExitConfigurationModeTYPE () =>
        "not provided: this FMU has no structural parameters";
    fmi3GetIntervalDecimal: fmi3GetIntervalDecimalTYPE (
        a: *const fmi3ValueReference, b: usize, d: *mut fmi3Float64,
        e: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetIntervalFraction: fmi3GetIntervalFractionTYPE (
        a: *const fmi3ValueReference, b: usize, d: *mut fmi3UInt64, e: *mut fmi3UInt64,
        f: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetShiftDecimal: fmi3GetShiftDecimalTYPE (
        a: *const fmi3ValueReference, b: usize, d: *mut fmi3Float64) => NO_CLOCKS;
    fmi3GetShiftFraction: fmi3GetShiftFractionTYPE (
        a: *const fmi3ValueReference, b: usize, d: *mut fmi3UInt64, e: *mut fmi3UInt64) => NO_CLOCKS;
    fmi3SetIntervalDecimal: fmi3SetIntervalDecimalTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetIntervalFraction: fmi3SetIntervalFractionTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3UInt64,
        e: *const fmi3UInt64) => NO_CLOCKS;
    fmi3SetShiftDecimal: fmi3SetShiftDecimalTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetShiftFraction: fmi3SetShiftFractionTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3UInt64,
        e: *const fmi3UInt64) => NO_CLOCKS;
    fmi3ActivateModelPartition: fmi3ActivateModelPartitionTYPE (
        a: fmi3ValueReference, b: fmi3Float64) => NO_CLOCKS;
    fmi3EnterContinuousTimeMode: fmi3EnterContinuousTimeModeTYPE () => NO_ME;
    fmi3CompletedIntegratorStep: fmi3CompletedIntegratorStepTYPE (
        a: fmi3Boolean, b: *mut fmi3Boolean, d: *mut fmi3Boolean) => NO_ME;
    fmi3SetTime: fmi3SetTimeTYPE (a: fmi3Float64) => NO_ME;
    fmi3SetContinuousStates: fmi3SetContinuousStatesTYPE (
        a: *const fmi3Float64, b: usize) => NO_ME;
    fmi3GetContinuousStateDerivatives: fmi3GetContinuousStateDerivativesTYPE (
        a: *mut fmi3Float64, b: usize) => NO_ME;
    fmi3GetEventIndicators: fmi3GetEventIndicatorsTYPE (a: *mut fmi3Float64, b: usize) => NO_ME;
    fmi3GetContinuousStates: fmi3GetContinuousStatesTYPE (a: *mut fmi3Float64, b: usize) => NO_ME;
    fmi3GetNominalsOfContinuousStates: fmi3GetNominalsOfContinuousStatesTYPE (
        a: *mut fmi3Float64, b: usize) => NO_ME;
    fmi3GetNumberOfEventIndicators: fmi3GetNumberOfEventIndicatorsTYPE (a: *mut usize) => NO_ME;
    fmi3GetNumberOfContinuousStates: fmi3GetNumberOfContinuousStatesTYPE (a: *mut usize) => NO_ME;
    fmi3GetOutputDerivatives: fmi3GetOutputDerivativesTYPE (
        a: *const fmi3ValueReference, b: usize, d: *const fmi3Int32, e: *mut fmi3Float64,
        f: usize) => "not provided (maxOutputDerivativeOrder=\"0\")";
}

no_variables! {
    fmi3GetFloat32: fmi3GetFloat32TYPE, "Float32" (v: *mut fmi3Float32, n: usize);
    fmi3GetInt8: fmi3GetInt8TYPE, "Int8" (v: *mut fmi3Int8, n: usize);
    fmi3GetUInt8: fmi3GetUInt8TYPE, "UInt8" (v: *mut fmi3UInt8, n: usize);
    fmi3GetInt16: fmi3GetInt16TYPE, "Int16" (v: *mut fmi3Int16, n: usize);
    fmi3GetUInt16: fmi3GetUInt16TYPE, "UInt16" (v: *mut fmi3UInt16, n: usize);
    fmi3GetUInt32: fmi3GetUInt32TYPE, "UInt32" (v: *mut fmi3UInt32, n: usize);
    fmi3GetInt64: fmi3GetInt64TYPE, "Int64" (v: *mut fmi3Int64, n: usize);
    fmi3GetUInt64: fmi3GetUInt64TYPE, "UInt64" (v: *mut fmi3UInt64, n: usize);
    fmi3GetString: fmi3GetStringTYPE, "String" (v: *mut fmi3String, n: usize);
    fmi3GetBinary: fmi3GetBinaryTYPE, "Binary" (s: *mut usize, v: *mut fmi3Binary, n: usize);
    fmi3GetClock: fmi3GetClockTYPE, "Clock" (v: *mut fmi3Clock);
    fmi3SetFloat32: fmi3SetFloat32TYPE, "Float32" (v: *const fmi3Float32, n: usize);
    fmi3SetInt8: fmi3SetInt8TYPE, "Int8" (v: *const fmi3Int8, n: usize);
    fmi3SetUInt8: fmi3SetUInt8TYPE, "UInt8" (v: *const fmi3UInt8, n: usize);
    fmi3SetInt16: fmi3SetInt16TYPE, "Int16" (v: *const fmi3Int16, n: usize);
    fmi3SetUInt16: fmi3SetUInt16TYPE, "UInt16" (v: *const fmi3UInt16, n: usize);
    fmi3SetUInt32: fmi3SetUInt32TYPE, "UInt32" (v: *const fmi3UInt32, n: usize);
    fmi3SetInt64: fmi3SetInt64TYPE, "Int64" (v: *const fmi3Int64, n: usize);
    fmi3SetUInt64: fmi3SetUInt64TYPE, "UInt64" (v: *const fmi3UInt64, n: usize);
    fmi3SetString: fmi3SetStringTYPE, "String" (v: *const fmi3String, n: usize);
    fmi3SetBinary: fmi3SetBinaryTYPE, "Binary" (s: *const usize, v: *const fmi3Binary, n: usize);
    fmi3SetClock: fmi3SetClockTYPE, "Clock" (v: *const fmi3Clock);
}

/// Model exchange and scheduled execution are not provided: no instance.
///
/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instance_name: fmi3String,
    _instantiation_token: fmi3String,
    _resource_path: fmi3String,
    _visible: fmi3Boolean,
    _logging_on: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    refuse_instance(
        instance_environment,
        log_message,
        "fmi3InstantiateModelExchange",
    )
}
const _: fmi3InstantiateModelExchangeTYPE = Some(fmi3InstantiateModelExchange);

/// # Safety
/// Standard FMI 3.0 contract for this function.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instance_name: fmi3String,
    _instantiation_token: fmi3String,
    _resource_path: fmi3String,
    _visible: fmi3Boolean,
    _logging_on: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    _clock_update: fmi3ClockUpdateCallback,
    _lock_preemption: fmi3LockPreemptionCallback,
    _unlock_preemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    refuse_instance(
        instance_environment,
        log_message,
        "fmi3InstantiateScheduledExecution",
    )
}
const _: fmi3InstantiateScheduledExecutionTYPE = Some(fmi3InstantiateScheduledExecution);

fn refuse_instance(
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    function: &str,
) -> fmi3Instance {
    let logger = super::logging::Logger::new(log_message, environment, true);
    let message = format!("{function}: this FMU supports co-simulation only");
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        logger.log(Status::Error, &message)
    }));
    std::ptr::null_mut()
}
