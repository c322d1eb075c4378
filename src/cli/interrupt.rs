//! Ctrl-C: the first one asks the run to stop after the current step (what
//! was written is kept, marked incomplete); a second one ends the process
//! at once.
//!
//! The handler only sets a flag (signal-hook), so no thread is started for
//! it: a run at the paper's setting lasts a few milliseconds, and a thread
//! (its stack, its malloc arena) is a measurable part of that.

use signal_hook::consts::SIGINT;
use signal_hook::flag;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Exit code of a run stopped by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// A flag set by Ctrl-C. Without a handler (it could not be installed) the
/// default applies: Ctrl-C ends the process, leaving the final paths as
/// they were.
pub(super) fn install() -> Arc<AtomicBool> {
    let interrupted = Arc::new(AtomicBool::new(false));
    // The exit is registered first: it runs only when the flag was already
    // set, i.e. on the second Ctrl-C.
    let exit_on_second =
        flag::register_conditional_shutdown(SIGINT, EXIT_INTERRUPTED.into(), interrupted.clone());
    if let Ok(exit_on_second) = exit_on_second {
        // Without the flag's action Ctrl-C would do nothing at all: then
        // back to the default.
        if flag::register(SIGINT, interrupted.clone()).is_err() {
            signal_hook::low_level::unregister(exit_on_second);
        }
    }
    interrupted
}
