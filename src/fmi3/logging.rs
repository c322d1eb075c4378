//! FMI 3.0's `logMessage` callback (not variadic, unlike FMI 2.0's). Which
//! messages are passed on is `fmi_common::logging`'s rule, with the same
//! categories as FMI 2.0.

use super::instance::status;
use crate::fmi_common::{LogSink, Status};
use fmi_sys::fmi3::*;
use std::ffi::CStr;

pub type Logger = crate::fmi_common::Logger<Sink>;

/// The importer's callback and its environment.
pub struct Sink {
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
}

impl Logger {
    pub fn new(
        callback: fmi3LogMessageCallback,
        environment: fmi3InstanceEnvironment,
        debug: bool,
    ) -> Logger {
        Logger::with_sink(
            Sink {
                callback,
                environment,
            },
            debug,
        )
    }
}

impl LogSink for Sink {
    fn emit(&self, s: Status, category: &CStr, message: &CStr) {
        let Some(callback) = self.callback else {
            return;
        };
        // SAFETY: the importer gave us this callback for this purpose; both
        // strings are NUL-terminated and live across the call.
        unsafe {
            callback(
                self.environment,
                status(s),
                category.as_ptr(),
                message.as_ptr(),
            )
        };
    }
}
