//! Which messages reach the importer's logger: Warning, Discard, Error and
//! Fatal always; others only when debug logging is on and their category
//! is enabled. How a message is handed over (FMI 2.0's variadic callback,
//! FMI 3.0's plain one) is the front's `LogSink`.

use super::description::LOG_CATEGORIES;
use super::Status;
use std::ffi::{CStr, CString};

/// A front's way of calling the importer's logger callback (which may be
/// NULL: then nothing is called).
pub trait LogSink {
    fn emit(&self, status: Status, category: &CStr, message: &CStr);
}

pub struct Logger<S: LogSink> {
    sink: S,
    debug: bool,
    /// Enabled categories, by index into `LOG_CATEGORIES`.
    enabled: Vec<bool>,
}

/// `s` as a C string, a NUL byte written as `\0`.
pub fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NUL bytes were replaced")
}

impl<S: LogSink> Logger<S> {
    /// A logger with every category enabled, debug messages on or off.
    pub fn with_sink(sink: S, debug: bool) -> Logger<S> {
        Logger {
            sink,
            debug,
            enabled: vec![true; LOG_CATEGORIES.len()],
        }
    }

    /// fmiXSetDebugLogging: switch debug logging, and with a non-empty list
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

    pub fn log(&self, status: Status, message: &str) {
        let category = match status {
            Status::Warning => "logStatusWarning",
            Status::Discard => "logStatusDiscard",
            Status::Error => "logStatusError",
            Status::Fatal => "logStatusFatal",
            Status::Ok => "logEvents",
        };
        let always = status != Status::Ok;
        let index = LOG_CATEGORIES.iter().position(|c| c.0 == category);
        let wanted = self.debug && index.is_some_and(|i| self.enabled[i]);
        if always || wanted {
            self.sink
                .emit(status, &c_string(category), &c_string(message));
        }
    }
}
