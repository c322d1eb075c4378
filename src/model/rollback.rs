//! The roll-back copies of a communication step: the state at its start,
//! to go back to if it fails, and the storage the state it reaches is
//! copied into as it is checked (`Dynamics::save_checked_into`). When the
//! step completes the two trade places, so that the next step starts with
//! its roll-back copy already taken: one copy per step, fused with the
//! check, and no state moved (the states are large: their places are
//! swapped by index).

use super::Dynamics;

pub(super) struct RollBack<S> {
    copies: [Option<S>; 2],
    /// Which copy is the start of the step.
    start: usize,
    /// Whether that copy is the current state (nothing changed it since
    /// it was taken).
    current: bool,
}

impl<S> RollBack<S> {
    pub fn new() -> RollBack<S> {
        RollBack {
            copies: [None, None],
            start: 0,
            current: false,
        }
    }

    /// The state has changed (inputs, a restore, a reset): the next step
    /// takes its copy afresh.
    pub fn invalidate(&mut self) {
        self.current = false;
    }

    /// Before a step of `sim`: the copy of its state to roll back to, and
    /// the storage for the state the step reaches. Until `completed` or
    /// `restored` the copies count as out of date.
    pub fn start<D: Dynamics<State = S>>(&mut self, sim: &D) -> (&mut S, &mut S) {
        let current = std::mem::replace(&mut self.current, false);
        let [a, b] = &mut self.copies;
        let (start, next) = if self.start == 0 { (a, b) } else { (b, a) };
        match start {
            Some(_) if current => {}
            Some(saved) => sim.save_into(saved),
            None => *start = Some(sim.state()),
        }
        let start = start.as_mut().expect("just taken");
        let next = next.get_or_insert_with(|| sim.state());
        (start, next)
    }

    /// The step completed and its state was copied (and checked) into the
    /// second storage `start` handed out: that copy is the next step's
    /// start.
    pub fn completed(&mut self) {
        self.start = 1 - self.start;
        self.current = true;
    }

    /// The step failed and the state was put back to the start copy.
    pub fn restored(&mut self) {
        self.current = true;
    }
}
