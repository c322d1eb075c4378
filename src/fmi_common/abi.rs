//! The guards of the C boundary both fronts' exported functions stand on:
//! a call on an instance runs inside `catch_unwind` (a panic becomes a Fatal
//! status, a logged message and an instance that only lets itself be freed,
//! never an unwind into the importer), a refusal becomes an Error status
//! with a logged message naming the function, and every pointer and length
//! from the importer is checked before it is read.
//!
//! The FMU state functions are the same in both standards but for the
//! names and the C types of their arguments, so their bodies are here too.

use super::instance::Instance;
use super::logging::Logger;
use super::{Call, Front, Status};
use crate::model::FmuModel;
use std::ffi::{c_char, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Run `f` on the instance behind `c`: NULL gives Error, `Err` gives Error
/// with a logged message, a panic gives Fatal.
///
/// # Safety
/// `c` is NULL or a pointer returned by the front's instantiation (a boxed
/// `Instance<M, F>`) and not yet freed.
pub unsafe fn with_instance<M: FmuModel, F: Front>(
    c: *mut c_void,
    function: &str,
    f: impl FnOnce(&mut Instance<M, F>) -> Result<F::Status, String>,
) -> F::Status {
    if c.is_null() {
        return F::status(Status::Error);
    }
    // SAFETY: per the function's contract.
    let inst = unsafe { &mut *(c as *mut Instance<M, F>) };
    if inst.mode() == F::FATAL {
        let free = F::name(Call::FreeInstance);
        let message = format!("{function}: the instance had a fatal error; only {free} is allowed");
        inst.logger.log(Status::Error, &message);
        return F::status(Status::Error);
    }
    match catch_unwind(AssertUnwindSafe(|| f(&mut *inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            let message = if message.starts_with(function) {
                message
            } else {
                format!("{function}: {message}")
            };
            inst.logger.log(Status::Error, &message);
            F::status(Status::Error)
        }
        Err(payload) => {
            inst.set_fatal();
            let message = format!("{function}: internal error: {}", panic_message(&*payload));
            // The logger itself is the importer's; do not let it unwind us.
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.logger.log(Status::Fatal, &message)
            }));
            F::status(Status::Fatal)
        }
    }
}

/// A new instance from `make` (run inside `catch_unwind`), boxed for the
/// importer; NULL after a refusal (logged on the logger `make` hands back)
/// or a panic (logged on `fallback`).
pub fn instantiate<M: FmuModel, F: Front>(
    function: &str,
    make: impl FnOnce() -> Result<Instance<M, F>, (Logger<F::Sink>, String)>,
    fallback: impl FnOnce() -> Logger<F::Sink>,
) -> *mut c_void {
    match catch_unwind(AssertUnwindSafe(make)) {
        Ok(Ok(inst)) => Box::into_raw(Box::new(inst)) as *mut c_void,
        Ok(Err((logger, reason))) => {
            logger.log(Status::Error, &format!("{function}: {reason}"));
            std::ptr::null_mut()
        }
        Err(payload) => {
            let message = format!("{function}: internal error: {}", panic_message(&*payload));
            let _ = catch_unwind(AssertUnwindSafe(|| fallback().log(Status::Fatal, &message)));
            std::ptr::null_mut()
        }
    }
}

/// Frees an instance; NULL is nothing to free.
///
/// # Safety
/// `c` is NULL or came from `instantiate` (Box::into_raw) and is freed once.
pub unsafe fn free_instance<M: FmuModel, F: Front>(c: *mut c_void) {
    if c.is_null() {
        return;
    }
    // SAFETY: per the function's contract.
    let inst = unsafe { Box::from_raw(c as *mut Instance<M, F>) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
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
pub unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
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
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
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
pub unsafe fn string(p: *const c_char, what: &str) -> Result<String, String> {
    if p.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: per the function's contract.
    Ok(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// The `n` category names of fmiXSetDebugLogging.
///
/// # Safety
/// If not NULL, `list` points to `n` strings, each NULL or NUL-terminated.
pub unsafe fn categories(list: *const *const c_char, n: usize) -> Result<Vec<String>, String> {
    let list = unsafe { slice(list, n, "categories") }?;
    list.iter()
        .map(|&p| unsafe { string(p, "a category") })
        .collect()
}

/// A getter or setter of a type the model has no variable of: an empty
/// request is fine, any value reference is unknown.
pub fn no_variables(vrs: &[u32], what: &str) -> Result<(), String> {
    match vrs.first() {
        None => Ok(()),
        Some(vr) => Err(format!(
            "unknown value reference {vr}: this model has no {what} variables"
        )),
    }
}

// ---- FMU states ---------------------------------------------------------------

/// GetFMUState: a new state into `*state`, or the one there overwritten.
///
/// # Safety
/// `state` is NULL or points to a writable FMU state pointer.
pub unsafe fn get_state<M: FmuModel, F: Front>(
    inst: &mut Instance<M, F>,
    state: *mut *mut c_void,
) -> Result<(), String> {
    if state.is_null() {
        return Err(format!("{} is NULL", F::STATE_NOUN));
    }
    let key = inst.get_state(unsafe { *state } as usize)?;
    unsafe { *state = key as *mut c_void };
    Ok(())
}

/// FreeFMUState: frees `*state` and sets it to NULL; NULL is nothing.
///
/// # Safety
/// `state` is NULL or points to a writable FMU state pointer.
pub unsafe fn free_state<M: FmuModel, F: Front>(
    inst: &mut Instance<M, F>,
    state: *mut *mut c_void,
) -> Result<(), String> {
    if state.is_null() {
        return Ok(());
    }
    inst.free_state(unsafe { *state } as usize)?;
    unsafe { *state = std::ptr::null_mut() };
    Ok(())
}

/// SerializedFMUStateSize into `*size`.
///
/// # Safety
/// `size` is NULL or writable.
pub unsafe fn state_size<M: FmuModel, F: Front>(
    inst: &Instance<M, F>,
    state: *mut c_void,
    size: *mut usize,
) -> Result<(), String> {
    if size.is_null() {
        return Err("size is NULL".into());
    }
    unsafe { *size = inst.serialize_state(state as usize)?.len() };
    Ok(())
}

/// SerializeFMUState into the `size` bytes at `serialized`.
///
/// # Safety
/// If not NULL, `serialized` points to `size` writable bytes.
pub unsafe fn serialize_state<M: FmuModel, F: Front>(
    inst: &Instance<M, F>,
    state: *mut c_void,
    serialized: *mut u8,
    size: usize,
) -> Result<(), String> {
    let bytes = inst.serialize_state(state as usize)?;
    if size < bytes.len() {
        return Err(format!(
            "size = {size} is too small: the state needs {} bytes ({})",
            bytes.len(),
            F::name(Call::StateSize)
        ));
    }
    let out = unsafe { slice_mut(serialized, bytes.len(), "serializedState") }?;
    out.copy_from_slice(&bytes);
    Ok(())
}

/// DeserializeFMUState: a new state from the `size` bytes at `serialized`
/// into `*state`.
///
/// # Safety
/// If not NULL, `serialized` points to `size` bytes and `state` is
/// writable.
pub unsafe fn deserialize_state<M: FmuModel, F: Front>(
    inst: &mut Instance<M, F>,
    serialized: *const u8,
    size: usize,
    state: *mut *mut c_void,
) -> Result<(), String> {
    if state.is_null() {
        return Err(format!("{} is NULL", F::STATE_NOUN));
    }
    let bytes = unsafe { slice(serialized, size, "serializedState") }?;
    let key = inst.deserialize_state(bytes)?;
    unsafe { *state = key as *mut c_void };
    Ok(())
}
