//! Ctrl-C: the first one asks the run to stop after the current step (what
//! was written is kept, marked incomplete); a second one ends the process
//! at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Exit code of a run stopped by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// A flag set by Ctrl-C. Without a handler (it could not be installed) the
/// default applies: Ctrl-C ends the process, leaving the final paths as
/// they were.
pub(super) fn install() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let seen = flag.clone();
    let _ = ctrlc::set_handler(move || {
        if seen.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_INTERRUPTED.into());
        }
    });
    flag
}
