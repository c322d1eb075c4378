//! The wall-clock deadline of the step running on this thread: set by the
//! FMU's `fmi2DoStep` (`solver.wall_time_budget`) and read inside an
//! internal step (between the beam integrations of the contact iteration),
//! so that one internal step of a huge model cannot run past the budget.
//!
//! Thread-local: each FMU instance steps on its importer's thread, and a
//! command-line run or sweep never sets one. Work whose cost is known from
//! counts before it starts (`foresee`) is refused up front when even a
//! lower bound of its time does not fit before the deadline.

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

thread_local! {
    static DEADLINE: Cell<Option<Instant>> = const { Cell::new(None) };
    /// Why the work was refused up front (`foresee`), until `within` ends.
    static FORESEEN: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Run `work` with `deadline` set on this thread (cleared afterwards, also
/// when `work` panics: the guard's drop clears it).
pub fn within<T>(deadline: Option<Instant>, work: impl FnOnce() -> T) -> T {
    struct Clear(Option<Instant>);
    impl Drop for Clear {
        fn drop(&mut self) {
            DEADLINE.with(|d| d.set(self.0));
            FORESEEN.with(|f| f.replace(None));
        }
    }
    FORESEEN.with(|f| f.replace(None));
    let _restore = Clear(DEADLINE.with(|d| d.replace(deadline)));
    work()
}

/// Whether this thread's deadline has passed (never without one), or work
/// was refused up front by `foresee`.
pub fn passed() -> bool {
    DEADLINE.with(Cell::get).is_some_and(|d| Instant::now() > d)
        || FORESEEN.with(|f| f.borrow().is_some())
}

/// Whether a deadline is set on this thread (what `foresee` needs; the
/// counts it takes are worth computing only then).
pub fn is_set() -> bool {
    DEADLINE.with(Cell::get).is_some()
}

/// Whether work that takes at least `seconds` (a lower bound from counts)
/// cannot end before this thread's deadline. If so it is refused: `why`
/// (what the work is) is kept for `foreseen`, and `passed` holds from now
/// on, so that the work already under way stops as at the deadline.
pub fn foresee(seconds: f64, why: impl FnOnce() -> String) -> bool {
    let Some(deadline) = DEADLINE.with(Cell::get) else {
        return false;
    };
    let needed = Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX);
    let fits = Instant::now()
        .checked_add(needed)
        .is_some_and(|end| end <= deadline);
    if !fits {
        FORESEEN.with(|f| f.replace(Some(why())));
    }
    !fits
}

/// What `foresee` refused inside the current `within`, if anything.
pub fn foreseen() -> Option<String> {
    FORESEEN.with(|f| f.borrow().clone())
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

    #[test]
    fn work_known_to_outlast_the_deadline_is_refused_and_named() {
        assert!(!foresee(1e9, String::new), "no deadline, nothing refused");
        let later = Instant::now() + Duration::from_secs(3600);
        within(Some(later), || {
            assert!(!foresee(1.0, || "an hour is enough".into()));
            assert!(!passed() && foreseen().is_none());
            assert!(foresee(7200.0, || "two hours".into()));
            assert!(passed(), "the refused work stops as at the deadline");
            assert_eq!(foreseen().as_deref(), Some("two hours"));
        });
        assert!(!passed() && foreseen().is_none(), "cleared afterwards");
    }
}
