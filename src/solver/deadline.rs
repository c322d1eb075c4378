//! The wall-clock deadline of the step running on this thread: set by the
//! FMU's `fmi2DoStep` (`solver.wall_time_budget`) and read inside an
//! internal step (between the beam integrations of the contact iteration),
//! so that one internal step of a huge model cannot run past the budget.
//!
//! Thread-local: each FMU instance steps on its importer's thread, and a
//! command-line run or sweep never sets one.

use std::cell::Cell;
use std::time::Instant;

thread_local! {
    static DEADLINE: Cell<Option<Instant>> = const { Cell::new(None) };
}

/// Run `work` with `deadline` set on this thread (cleared afterwards, also
/// when `work` panics: the guard's drop clears it).
pub fn within<T>(deadline: Option<Instant>, work: impl FnOnce() -> T) -> T {
    struct Clear(Option<Instant>);
    impl Drop for Clear {
        fn drop(&mut self) {
            DEADLINE.with(|d| d.set(self.0));
        }
    }
    let _restore = Clear(DEADLINE.with(|d| d.replace(deadline)));
    work()
}

/// Whether this thread's deadline has passed (never without one).
pub fn passed() -> bool {
    DEADLINE.with(Cell::get).is_some_and(|d| Instant::now() > d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_deadline_holds_only_inside_its_work() {
        assert!(!passed());
        let past = Instant::now() - Duration::from_millis(1);
        assert!(within(Some(past), passed));
        assert!(!passed(), "cleared after the work");
        let later = Instant::now() + Duration::from_secs(3600);
        assert!(!within(Some(later), passed));
    }
}
