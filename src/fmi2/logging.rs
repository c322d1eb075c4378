//! Messages to the importer's logger callback.
//!
//! The callback is variadic (printf-like): it is always called with the
//! format `"%s"` and the message as its argument, so a `%` in a message is
//! never read as a format. The callback may be NULL. Messages with status
//! Warning, Discard, Error or Fatal are always passed on; others only when
//! debug logging is on and their category is enabled.

use super::model_description::LOG_CATEGORIES;
use fmi_sys::fmi2::*;
use std::ffi::CString;

pub struct Logger {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    debug: bool,
    /// Enabled categories, by index into `LOG_CATEGORIES`.
    enabled: Vec<bool>,
}

fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NUL bytes were replaced")
}

impl Logger {
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        debug: bool,
    ) -> Logger {
        Logger {
            callback,
            environment,
            instance_name: c_string(instance_name),
            debug,
            enabled: vec![true; LOG_CATEGORIES.len()],
        }
    }

    /// fmi2SetDebugLogging: switch debug logging, and with a non-empty list
    /// enable just those categories (an empty list enables all).
    pub fn configure(&mut self, debug: bool, categories: &[String]) -> Result<(), String> {
        let mut enabled = vec![categories.is_empty(); LOG_CATEGORIES.len()];
        for c in categories {
            match LOG_CATEGORIES.iter().position(|(name, _)| name == c) {
                Some(i) => enabled[i] = true,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.0).collect();
                    return Err(format!(
                        "unknown log category \"{c}\" (known: {})",
                        known.join(", ")
                    ));
                }
            }
        }
        self.debug = debug;
        self.enabled = enabled;
        Ok(())
    }

    #[allow(non_upper_case_globals)]
    pub fn log(&self, status: fmi2Status, message: &str) {
        let category = match status {
            fmi2Status_fmi2Warning => "logStatusWarning",
            fmi2Status_fmi2Discard => "logStatusDiscard",
            fmi2Status_fmi2Error => "logStatusError",
            fmi2Status_fmi2Fatal => "logStatusFatal",
            _ => "logEvents",
        };
        let always = status != fmi2Status_fmi2OK;
        let index = LOG_CATEGORIES.iter().position(|c| c.0 == category);
        let wanted = self.debug && index.is_some_and(|i| self.enabled[i]);
        if always || wanted {
            self.emit(status, category, message);
        }
    }

    fn emit(&self, status: fmi2Status, category: &str, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let category = c_string(category);
        let message = c_string(message);
        // SAFETY: the importer gave us this callback for this purpose; every
        // pointer passed is a valid NUL-terminated string living across the
        // call, and the format "%s" consumes exactly the one argument.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}
