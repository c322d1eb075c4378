//! A lift-off under HHT-α, located inside the step.
//!
//! HHT-α carries each step's end force into the next step, whose impulse
//! is Δt (f₀ + f₁)/2. Opening a contact at the start of the step in which
//! its force turns tensile (as RK4, which holds the force over a step, can)
//! would drop f₀'s share: at the paper's step on a 16-element beam, where
//! f₀ is several MN, that is a wrong velocity of metres per second. So the
//! step is shortened to the instant τ its (bilateral) end force reaches
//! zero, and the contact opens there: the force falls from f₀ to zero over
//! [0, τ] and the carried state is that of a zero force.

use crate::contact::ContactForce;
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};
use crate::state::{push_event, EventKind};

impl Step<'_> {
    /// Under HHT-α, the closed contact that starts the step compressed and
    /// whose end force in `forces` pulls, with the earliest linear estimate
    /// of the zero crossing; `None` under RK4 or when there is none.
    pub(crate) fn lift_off_inside(&self, forces: &[ContactForce]) -> Option<usize> {
        self.work.restart_weight?;
        let mut first: Option<(f64, usize)> = None;
        for (c, force) in forces.iter().enumerate() {
            let start = self.state.force_history[c][0].normal;
            if self.work.open[c] || force.normal >= 0.0 || start <= 0.0 {
                continue;
            }
            let fraction = start / (start - force.normal);
            if first.is_none_or(|(f, _)| fraction < f) {
                first = Some((fraction, c));
            }
        }
        first.map(|(_, c)| c)
    }

    /// Shorten the step from its solution `forces` (over `dt`) to the
    /// instant contact `c`'s end force reaches zero, leaving that step in
    /// `scratch`. `None` where the force already pulls at the shortest step
    /// tried (`LIFT_OFF_EARLIEST` of it: opening at the start drops at most
    /// that share of the step's impulse) or the steps fail: the contact
    /// then opens at the step's start.
    pub(crate) fn locate_lift_off(
        &mut self,
        c: usize,
        forces: &[ContactForce],
        dt: f64,
    ) -> Option<(StepSolution, f64)> {
        let tolerance = self.params.lift_off_tolerance * self.state.force_history[c][0].normal;
        let earliest = self.params.lift_off_earliest * dt;
        let early = self.solve(forces, earliest).ok()?.forces[c].normal;
        if early < 0.0 {
            return None;
        }
        let end_force = |_: &Step, solution: &StepSolution| solution.forces[c].normal;
        let bracket = ((earliest, early), forces[c].normal);
        self.locate(forces, dt, bracket, tolerance, end_force)
            .ok()
            .flatten()
    }

    /// Closed contact `c`, which carries a compressive force into the step
    /// but pulls from its start (`locate_lift_off` found no zero crossing),
    /// lifts off now with HHT-α's restart, where the step of `dt` from the
    /// restarted start (the step's `guess`) then leaves it off the track;
    /// whether it did. Opened in the step's active set instead, its body
    /// flies on the start's accelerations, which hold its force: the
    /// contact pushes the body and the track apart as they separate, an
    /// energy gain (up to 0.32 MJ in a grid step of the coaches of
    /// `tests/vehicles/no_tension.rs`). Where the restarted step ends with the contact
    /// below the track, the force the start carried was the one that
    /// lifted it: the state is put back and the contact opens in the
    /// step's active set, as before (without that way back, the paper's
    /// wheel at 250 m/s landed at once and its next step diverged). The
    /// contacts that set opened stay open either way.
    pub(crate) fn lift_off_at_start(
        &mut self,
        c: usize,
        guess: &[ContactForce],
        dt: f64,
    ) -> Result<bool, SolverError> {
        let before = self.state.clone();
        self.lift_off_now(c)?;
        self.open_the_opened();
        self.work.iteration.set_open(&self.work.open);
        let solved = self.solve(guess, dt).is_ok();
        if solved && self.work.iteration.contact_gaps()[c] >= 0.0 {
            if before.contacts[c].opened_in == Some(before.grid_step) {
                self.count_reopening()?;
            }
            return Ok(true);
        }
        *self.state = before;
        self.sync_open();
        self.open_the_opened();
        Ok(false)
    }

    /// The contacts the step's active set opened are open.
    pub(crate) fn open_the_opened(&mut self) {
        for (open, &opened) in self.work.open.iter_mut().zip(&self.work.opened) {
            *open |= opened;
        }
    }

    /// Contact `c`, its force zero at the end of the step just taken,
    /// opens now; HHT-α restarts its body.
    pub(crate) fn lift_off_now(&mut self, c: usize) -> Result<(), SolverError> {
        let s = &mut *self.state;
        s.contacts[c].open = true;
        s.contacts[c].opened_in = Some(s.grid_step);
        s.force_history[c] = [ContactForce::default(); 3];
        push_event(s, c, EventKind::LiftOff);
        self.restart(&[c], self.grid_remainder())
    }
}
