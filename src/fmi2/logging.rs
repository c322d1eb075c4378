//! FMI 2.0's logger callback. It is variadic (printf-like): it is always
//! called with the format `"%s"` and the message as its argument, so a `%`
//! in a message is never read as a format. Which messages are passed on is
//! `fmi_common::logging`'s rule.

use super::instance::status;
use crate::fmi_common::logging::c_string;
use crate::fmi_common::{LogSink, Status};
use fmi_sys::fmi2::*;
use std::ffi::{CStr, CString};

pub type Logger = crate::fmi_common::Logger<Sink>;

/// The importer's callback, its environment and the instance's name.
pub struct Sink {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
}

impl Logger {
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        debug: bool,
    ) -> Logger {
        let instance_name = c_string(instance_name);
        let sink = Sink {
            callback,
            environment,
            instance_name,
        };
        Logger::with_sink(sink, debug)
    }
}

impl LogSink for Sink {
    fn emit(&self, s: Status, category: &CStr, message: &CStr) {
        let Some(callback) = self.callback else {
            return;
        };
        // SAFETY: the importer gave us this callback for this purpose; every
        // pointer passed is a valid NUL-terminated string living across the
        // call, and the format "%s" consumes exactly the one argument.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status(s),
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}
