//! The FMU states an instance has handed out, keyed by the handle the
//! importer holds.
//!
//! Handles are tokens, never addresses, and never reused within the process
//! (each front counts its own): a stale handle (freed, then the memory
//! reused for another state) or another instance's handle is not in an
//! instance's registry and is refused.

use std::collections::HashMap;

pub struct States<S> {
    live: HashMap<usize, S>,
    /// What the standard calls an FMU state, for messages.
    noun: &'static str,
}

impl<S> States<S> {
    pub fn new(noun: &'static str) -> States<S> {
        States {
            live: HashMap::new(),
            noun,
        }
    }

    /// Keeps `state` under `handle` (fresh from the front's counter).
    pub fn keep(&mut self, handle: usize, state: S) -> usize {
        self.live.insert(handle, state);
        handle
    }

    /// Overwrites the live state `handle` with `state` (fmiXGetFMUState on
    /// an existing state).
    pub fn overwrite(&mut self, function: &str, handle: usize, state: S) -> Result<(), String> {
        let Some(slot) = self.live.get_mut(&handle) else {
            return Err(format!(
                "{function}: {} {handle:#x} was not created by this instance",
                self.noun
            ));
        };
        *slot = state;
        Ok(())
    }

    pub fn get(&self, function: &str, handle: usize) -> Result<&S, String> {
        self.live
            .get(&handle)
            .ok_or_else(|| self.not_live(function, handle))
    }

    /// Frees `handle`; the NULL handle is nothing to free.
    pub fn free(&mut self, function: &str, handle: usize) -> Result<(), String> {
        if handle == 0 {
            return Ok(());
        }
        match self.live.remove(&handle) {
            Some(_) => Ok(()),
            None => Err(self.not_live(function, handle)),
        }
    }

    fn not_live(&self, function: &str, handle: usize) -> String {
        format!(
            "{function}: {} {handle:#x} is not a live state of this instance",
            self.noun
        )
    }
}
