//! The step's active set: which contacts are open in it. A closed contact
//! that pulls opens, a contact opened in the step that sinks closes again,
//! until the step is complementary; a set that does not settle is settled
//! on a shorter step; a contact reopening without end in a grid step, or a
//! set that settles on no step, stops the run, saying so.

use crate::contact::ContactForce;
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};
use crate::state::{push_event, EventKind};

impl Step<'_> {
    /// Solve the step with the contacts open at its start open, then make
    /// its active set complementary: open every closed contact whose normal
    /// force came out tensile and solve it again; where none pulls, close
    /// again the first contact opened in this step whose gap ends below the
    /// track (it would have pushed: opening it was another contact's doing),
    /// and solve again. The step ends with every closed contact's force
    /// ≥ 0 and every contact it opened off the track (the complementarity
    /// problem of the step's contacts, solved by the switches of
    /// `linalg::complementarity` on the whole step). A closed contact is
    /// not kept closed under tension where it opened and landed in this
    /// grid step already, under RK4 (bounded by `count_reopening`); under
    /// HHT-α it still is (see `open_the_pulling`). At most
    /// `active_set_passes` solves (`settle_active_set`).
    ///
    /// Under HHT-α a contact that carries a compressive force into the step
    /// does not open at its start (which would drop that force's share of
    /// the step's impulse): the step is shortened to the instant its end
    /// force reaches zero (`locate_lift_off`), and the contact opens there.
    /// Where it pulls from the start, it lifts off there with HHT-α's
    /// restart where the step then leaves it off the track
    /// (`lift_off_at_start`), else it opens at the start in the step's set.
    /// Returns the solution, the step's length and that contact.
    ///
    /// A set that does not settle in those solves is settled again on half
    /// the step, and so on down to 2^−`SETTLE_HALVINGS` of it: the step is
    /// then taken that far only (the step's length returned is shorter
    /// than `dt`, with no contact lifting off at its end). Only a step
    /// that would otherwise stop the run takes this way: every step whose
    /// set settles keeps its bits. Where none settles, the run stops with
    /// an error saying so. Why: a set is held over the whole step, and a
    /// contact open over part of it only has none. At 1.524 s of eight
    /// coaches on rigid wheelsets (`tests/vehicles/no_tension.rs`, 40
    /// elements, 1 ms, as run before 2eabf61; docs/robustness.md) contact
    /// 19 starts the step closed 3 µm below the track with a separating
    /// velocity of 2.9 mm/s (a bounce dropped):
    /// held closed over a sliver τ it pulls about m v / τ (−1.1e7 N at
    /// 5.7e-7 s), over the whole step it pushes 1.7e5 N. Contact 21's
    /// lift-off is located in the first 6 µs, where 19 pulls; opened at the
    /// start, 19 ends the whole step 11 µm below the track and closes
    /// again; and so on. On half the step the set settles with 19 and 21
    /// open at its start (19 ends it 5 µm below the track, within the gap
    /// tolerance), and open contact 17 lands 1.3e-4 s into it, which ends
    /// the step; 19 and 21 land with it.
    pub(crate) fn solve_active_set(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64, Option<usize>), SolverError> {
        let mut tau = dt;
        for _ in 0..=SETTLE_HALVINGS {
            let settled = self.settle_active_set(guess, tau)?;
            if let Some(settled) = settled.filter(|_| !unsettled_for_a_test()) {
                return Ok(settled);
            }
            tau *= 0.5;
        }
        Err(SolverError {
            time: self.state.time,
            message: format!(
                "the contacts' active set of a step of {dt:e} s did not settle in {} solves, \
                 nor on steps down to 2^-{SETTLE_HALVINGS} of it \
                 (a contact opened pulls, closed sinks below the track): the rigid contact \
                 chatters here; a compliant contact law is well posed (docs/contact-laws.md)",
                active_set_passes(self.work.open.len())
            ),
        })
    }

    /// The passes of `solve_active_set` on a step of `dt` from the
    /// contacts open now: the settled step, or `None` where
    /// `active_set_passes` solves do not settle it.
    fn settle_active_set(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
    ) -> Result<Option<(StepSolution, f64, Option<usize>)>, SolverError> {
        for (open, status) in self.work.open.iter_mut().zip(&self.state.contacts) {
            *open = status.open;
        }
        self.work.opened.fill(false);
        let mut tried = vec![false; self.work.open.len()];
        for _ in 0..active_set_passes(self.work.open.len()) {
            self.work.iteration.set_open(&self.work.open);
            let solution = self.solve(guess, dt)?;
            if let Some(c) = self.lift_off_inside(&solution.forces) {
                if let Some((solution, tau)) = self.locate_lift_off(c, &solution.forces, dt) {
                    // Another closed contact that pulls at the located
                    // instant opens at the step's start and the step is
                    // solved again: taken as it is, a contact holding a
                    // separating velocity jump over a sliver of a step
                    // pulled 1e11 N, carried into the next step.
                    if self.open_the_pulling_but(&solution.forces, Some(c))? {
                        continue;
                    }
                    if self.state.contacts[c].opened_in == Some(self.state.grid_step) {
                        self.count_reopening()?;
                    }
                    return Ok(Some((solution, tau, Some(c))));
                }
                let first_try = !std::mem::replace(&mut tried[c], true);
                if first_try && self.lift_off_at_start(c, guess, dt)? {
                    continue;
                }
                // Else it opens at the step's start (below).
            }
            if !self.open_the_pulling(&solution.forces)? && !self.close_a_penetrating() {
                return Ok(Some((solution, dt, None)));
            }
        }
        Ok(None)
    }

    /// Open every closed contact whose normal force in `forces` pulls;
    /// whether one did.
    pub(crate) fn open_the_pulling(
        &mut self,
        forces: &[ContactForce],
    ) -> Result<bool, SolverError> {
        self.open_the_pulling_but(forces, None)
    }

    /// `open_the_pulling`, leaving `kept` (a lift-off located at the
    /// step's end, whose force is zero to its tolerance) as it is.
    pub(crate) fn open_the_pulling_but(
        &mut self,
        forces: &[ContactForce],
        kept: Option<usize>,
    ) -> Result<bool, SolverError> {
        let mut opened_any = false;
        let grid = self.state.grid_step;
        for (c, force) in forces.iter().enumerate() {
            if self.work.open[c] || force.normal >= 0.0 || kept == Some(c) {
                continue;
            }
            if self.state.contacts[c].opened_in == Some(grid) {
                self.count_reopening()?;
            }
            self.work.open[c] = true;
            self.work.opened[c] = true;
            opened_any = true;
        }
        Ok(opened_any)
    }

    /// Count a contact's reopening in the grid step it opened in already:
    /// at most `max_reopenings` in a grid step, past which the contacts
    /// chatter without end and the run stops, saying so.
    pub(crate) fn count_reopening(&mut self) -> Result<(), SolverError> {
        let grid = self.state.grid_step;
        if self.work.reopenings.0 != grid {
            self.work.reopenings = (grid, 0);
        }
        self.work.reopenings.1 += 1;
        let bound = max_reopenings(self.work.open.len());
        if self.work.reopenings.1 <= bound {
            return Ok(());
        }
        Err(SolverError {
            time: self.state.time,
            message: format!(
                "the contacts reopened more than {bound} times in one grid step of {} s: \
                 the rigid contact chatters without end here; a compliant contact law is \
                 well posed (docs/contact-laws.md)",
                self.params.step
            ),
        })
    }

    /// Close again the first contact opened in this step whose gap ends
    /// below the track by more than the iteration's gap tolerance (the
    /// band a closed contact's gap is held in: a contact closed at a gap
    /// of −1e-7 m that opens and rises still ends below zero); whether one
    /// was.
    pub(crate) fn close_a_penetrating(&mut self) -> bool {
        let gaps = self.work.iteration.contact_gaps();
        let tolerance = self.params.iteration.gap_tolerance;
        let sinking =
            (0..self.work.opened.len()).find(|&c| self.work.opened[c] && gaps[c] < -tolerance);
        if let Some(c) = sinking {
            self.work.open[c] = false;
            self.work.opened[c] = false;
        }
        sinking.is_some()
    }

    /// The contacts opened in the step just solved lift off at its start.
    pub(crate) fn record_lift_offs(&mut self) {
        let grid = self.state.grid_step;
        for c in 0..self.work.opened.len() {
            if self.work.opened[c] {
                self.state.contacts[c].opened_in = Some(grid);
                push_event(self.state, c, EventKind::LiftOff);
            }
        }
    }
}

/// Reopenings of contacts that opened in the grid step already that one
/// grid step may hold (`Step::count_reopening`): four per contact,
/// and four.
fn max_reopenings(contacts: usize) -> usize {
    4 * contacts + 4
}

/// Solves a step's active set may take (`solve_active_set`): every
/// contact opened once and closed again once, lifted off at the step's
/// start once (under HHT-α), and the first solve.
pub(crate) fn active_set_passes(contacts: usize) -> usize {
    3 * contacts + 2
}

/// How many times `Step::solve_active_set` halves a step whose active set
/// does not settle before it stops the run.
const SETTLE_HALVINGS: usize = 10;

/// Whether the settle just made counts as unsettled: never, but where a
/// test asked for it (`tests::UNSETTLED`), so that the step's shortening
/// can be tested on a run whose sets all settle.
#[cfg(not(test))]
#[inline(always)]
fn unsettled_for_a_test() -> bool {
    false
}

#[cfg(test)]
fn unsettled_for_a_test() -> bool {
    tests::UNSETTLED.with(|left| {
        let n = left.get();
        left.set(n.saturating_sub(1));
        n > 0
    })
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use crate::integrate::IntegratorKind;
    use crate::scene::builtin;
    use crate::Simulation;

    thread_local! {
        /// How many of the next settles count as unsettled.
        pub(super) static UNSETTLED: Cell<usize> = const { Cell::new(0) };
    }

    /// The paper's wheel at 10 m/s up to `to`, by its grid points, with
    /// the settles of the step from `forced_at` counted unsettled
    /// `unsettled` times (that step then taken on 2^−unsettled of itself).
    fn wheel_run(kind: IntegratorKind, forced_at: f64, unsettled: usize, to: f64) -> Simulation {
        let mut scene = builtin("lee1994-wheel-10").expect("built in");
        scene.solver.integrator = kind;
        let h = scene.solver.step;
        let mut sim = Simulation::new(&scene).expect("builds");
        let (forced, end) = ((forced_at / h).round() as u64, (to / h).round() as u64);
        for k in 1..=end {
            if k == forced + 1 {
                UNSETTLED.with(|left| left.set(unsettled));
            }
            sim.advance_to(k as f64 * h).expect("no solver error");
            assert_eq!(UNSETTLED.with(Cell::get), 0, "every forced settle used");
        }
        sim
    }

    /// A step whose active set settles only on a part of it is taken that
    /// far, and the run goes on from there to the grid point it was
    /// asked for (`step_to`'s `dt < full` with no event): one more step,
    /// on the same grid, the same time, and the state of the run that
    /// took the whole step, to the integrators' own difference between
    /// one step and its parts (measured 1.1e-7 m and 2.5e-6 of the peak
    /// deflection at most). Returned as reached instead, the step would
    /// leave 2^−k of it unintegrated: the wheel 25 mm behind at 10 m/s
    /// (k = 1), and no step more.
    #[test]
    fn a_step_settled_on_part_of_it_is_taken_that_far_and_the_run_goes_on() {
        for kind in [IntegratorKind::Rk4, IntegratorKind::Hht] {
            for unsettled in [1, 3] {
                let whole = wheel_run(kind, 1.2, 0, 1.3).state();
                let parts = wheel_run(kind, 1.2, unsettled, 1.3).state();
                let label = format!("{kind:?}, {unsettled} unsettled");
                assert_eq!(parts.time, whole.time, "{label}");
                assert_eq!(parts.grid_step, whole.grid_step, "{label}");
                // The shortened step, then the rest of its grid step.
                assert_eq!(parts.steps, whole.steps + 1, "{label}");
                let (a, b) = (&parts.dynamic.bodies[0], &whole.dynamic.bodies[0]);
                let moved = (a.position - b.position).norm();
                assert!(moved < 1e-6, "{label}: {moved:e} m apart");
                let deflection =
                    &parts.dynamic.beam_displacement - &whole.dynamic.beam_displacement;
                let scale = whole.dynamic.beam_displacement.amax();
                assert!(deflection.amax() < 1e-4 * scale, "{label}");
            }
        }
    }
}
