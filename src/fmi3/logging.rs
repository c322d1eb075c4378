//! Messages to the importer's FMI 3.0 `logMessage` callback (not variadic,
//! unlike FMI 2.0's). Warning, Discard, Error and Fatal messages are always
//! passed on; others only when debug logging is on and their category is
//! enabled. The categories are the FMI 2.0 layer's.

use crate::fmi2::model_description::LOG_CATEGORIES;
use fmi_sys::fmi3::*;
use std::ffi::CString;

pub struct Logger {
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
    debug: bool,
    /// Enabled categories, by index into `LOG_CATEGORIES`.
    enabled: Vec<bool>,
}

fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NUL bytes were replaced")
}

impl Logger {
    pub fn new(
        callback: fmi3LogMessageCallback,
        environment: fmi3InstanceEnvironment,
        debug: bool,
    ) -> Logger {
        Logger {
            callback,
            environment,
            debug,
            enabled: vec![true; LOG_CATEGORIES.len()],
        }
    }

    /// fmi3SetDebugLogging: switch debug logging, and with a non-empty list
    /// enable just those categories (an empty list enables all).
    pub fn configure(&mut self, debug: bool, categories: &[String]) -> Result<(), String> {
        let mut enabled = vec![categories.is_empty(); LOG_CATEGORIES.len()];
        for c in categories {
            let Some(i) = LOG_CATEGORIES.iter().position(|(name, _)| name == c) else {
                let known: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.0).collect();
                return Err(format!(
                    "unknown log category \"{c}\" (known: {})",
                    known.join(", ")
                ));
            };
            enabled[i] = true;
        }
        self.debug = debug;
        self.enabled = enabled;
        Ok(())
    }

    #[allow(non_upper_case_globals)]
    pub fn log(&self, status: fmi3Status, message: &str) {
        let category = match status {
            fmi3Status_fmi3Warning => "logStatusWarning",
            fmi3Status_fmi3Discard => "logStatusDiscard",
            fmi3Status_fmi3Error => "logStatusError",
            fmi3Status_fmi3Fatal => "logStatusFatal",
            _ => "logEvents",
        };
        let always = status != fmi3Status_fmi3OK;
        let index = LOG_CATEGORIES.iter().position(|c| c.0 == category);
        let wanted = self.debug && index.is_some_and(|i| self.enabled[i]);
        if !(always || wanted) {
            return;
        }
        let Some(callback) = self.callback else {
            return;
        };
        let (category, message) = (c_string(category), c_string(message));
        // SAFETY: the importer gave us this callback for this purpose; both
        // strings are NUL-terminated and live across the call.
        unsafe {
            callback(
                self.environment,
                status,
                category.as_ptr(),
                message.as_ptr(),
            )
        };
    }
}
