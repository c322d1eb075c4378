//! Landings: the open contact whose gap closes first in a step, the
//! instant it does, and the impact over every contact that takes part.

use crate::contact::ContactForce;
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};
use crate::state::{push_event, EventKind};

impl Step<'_> {
    /// The open contact (open at the step's start) whose gap closes first
    /// in the step just solved, with a linear estimate of the fraction of
    /// the step at which it does: 0 for a contact that starts the step on
    /// the track (it has just bounced) and ends it below.
    pub(crate) fn first_landing(&self) -> Option<(f64, usize)> {
        let end = self.work.iteration.contact_gaps();
        let mut first: Option<(f64, usize)> = None;
        for c in self.landing_candidates() {
            let (g0, g1) = (self.state.contacts[c].gap, end[c]);
            let fraction = if g0 > 0.0 { g0 / (g0 - g1) } else { 0.0 };
            if first.is_none_or(|(f, _)| fraction < f) {
                first = Some((fraction, c));
            }
        }
        first
    }

    /// An open contact that starts the step on or below the track and
    /// approaching it (left there by an event located just before its
    /// landing) lands now.
    pub(crate) fn land_at_start(&mut self) -> Result<(), SolverError> {
        for c in 0..self.state.contacts.len() {
            let status = self.state.contacts[c];
            let follower = self.system.contacts[c].follower.is_some();
            if status.open && !follower && status.gap <= 0.0 && self.normal_velocity_error(c)? < 0.0
            {
                self.land(c, false)?;
            }
        }
        Ok(())
    }

    /// The open contacts whose gap closes in the step just solved: not
    /// opened in it, and not slack followers (a follower's gap is its
    /// suspension's: it lands by its law).
    pub(crate) fn landing_candidates(&self) -> impl Iterator<Item = usize> + '_ {
        let end = self.work.iteration.contact_gaps();
        (self.state.contacts.iter().enumerate())
            .filter(move |&(c, status)| {
                let follower = self.system.contacts[c].follower.is_some();
                status.open && !self.work.opened[c] && !follower && end[c] < 0.0
            })
            .map(|(c, _)| c)
    }

    /// Shorten the step so that open contact `contact`'s gap closes at its
    /// end, or, where another landing contact is then below the track (its
    /// gap crossed zero first, though a straight line through its gaps at
    /// the step's ends put `contact` first: a contact that has just bounced
    /// comes down again late in the step), so that the first of them
    /// closes. Leaves the state at that instant in `scratch`; returns the
    /// contact that lands.
    pub(crate) fn locate_landing(
        &mut self,
        contact: usize,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<Option<(StepSolution, f64, usize)>, SolverError> {
        let candidates: Vec<usize> = self.landing_candidates().collect();
        let end_gaps = self.work.iteration.contact_gaps().to_vec();
        let start = self.state.contacts[contact].gap;
        let gap = |step: &Step, _: &StepSolution| step.work.iteration.contact_gaps()[contact];
        let ends = (start, end_gaps[contact]);
        let Some(bracket) = self.landing_bracket(forces, dt, ends, gap)? else {
            return Ok(None);
        };
        let (low, (high, at_high)) = bracket;
        let located = self.locate(forces, high, (low, at_high), LANDING_GAP, gap)?;
        let below = |step: &Step| {
            let gaps = step.work.iteration.contact_gaps();
            candidates.iter().any(|&d| gaps[d] < -LANDING_GAP)
        };
        if let Some((solution, tau)) = located.filter(|_| !below(self)) {
            return Ok(Some((solution, tau, contact)));
        }
        let lowest = |gaps: &[f64]| {
            (candidates.iter().map(|&d| (gaps[d], d))).fold((f64::INFINITY, contact), |a, b| {
                if b.0 < a.0 {
                    b
                } else {
                    a
                }
            })
        };
        let start = candidates.iter().map(|&d| self.state.contacts[d].gap);
        let ends = (start.fold(f64::INFINITY, f64::min), lowest(&end_gaps).0);
        let miss = |step: &Step, _: &StepSolution| lowest(step.work.iteration.contact_gaps()).0;
        let Some(bracket) = self.landing_bracket(forces, dt, ends, miss)? else {
            return Ok(None);
        };
        let (low, (high, at_high)) = bracket;
        let (solution, tau) = self
            .locate(forces, high, (low, at_high), LANDING_GAP, miss)?
            .ok_or_else(|| SolverError {
                time: self.state.time,
                message: format!(
                    "the instant {} lands could not be located",
                    self.system.contacts[contact].name
                ),
            })?;
        let first = lowest(self.work.iteration.contact_gaps()).1;
        Ok(Some((solution, tau, first)))
    }

    /// The bracket ((lo, gap), (hi, gap)) of the step in which `gap`
    /// closes: the whole step where it starts above `LANDING_GAP`. One that
    /// starts on the track (a contact that has just bounced) first rises:
    /// the locator would take the start itself for the landing and leave a
    /// sliver of a step whose closed contacts' forces explode; its bracket
    /// starts at the largest dt/2^k at which it is above. None where it is
    /// above nowhere down to dt/2^`BOUNCE_HALVINGS`: the bounce is lost in
    /// the step, and the contact lands now.
    pub(crate) fn landing_bracket(
        &mut self,
        forces: &[ContactForce],
        dt: f64,
        (start, end): (f64, f64),
        gap: impl Fn(&Step, &StepSolution) -> f64,
    ) -> Result<Option<Bracket>, SolverError> {
        let mut hi = (dt, end);
        if start > LANDING_GAP {
            return Ok(Some(((0.0, start), hi)));
        }
        for k in 1..=BOUNCE_HALVINGS {
            let tau = dt * 0.5f64.powi(k);
            let solution = self.solve(forces, tau)?;
            let g = gap(self, &solution);
            if g > LANDING_GAP {
                return Ok(Some(((tau, g), hi)));
            }
            if g < 0.0 {
                hi = (tau, g);
            }
        }
        Ok(None)
    }

    /// Open contact `c` lands now, with every other open contact on the
    /// track (gap within `LANDING_GAP`) and approaching it: one impact over
    /// them and all closed contacts (`crate::impact`), Newton's law on each
    /// landing contact with its restitution (plastic below
    /// `RESTING_SPEED`, for a second landing in the same grid step and, for
    /// `c`, if `plastic`), the closed ones kept (held bilateral if they
    /// opened in this grid step already, see `solve_active_set`). A landing
    /// contact closes unless it bounces; one whose impulse would pull
    /// leaves the track instead (a closed one: a lift-off at the impact),
    /// if at `RESTING_SPEED` at least and, for a landing one, at its first
    /// landing in the grid step (else it closes, with no impulse).
    pub(crate) fn land(&mut self, c: usize, plastic: bool) -> Result<(), SolverError> {
        let frames = self.frames_now()?;
        let parts = self.impact_parts(c, plastic, &frames);
        let impact = crate::impact::resolve(self.system, &frames, &parts, &mut self.state.dynamic)
            .map_err(|message| SolverError {
                time: self.state.time,
                message,
            })?;
        let grid = self.state.grid_step;
        self.state.impact_loss += impact.loss;
        let mut relanded = Vec::new();
        for (d, &part) in parts.iter().enumerate() {
            let s = &mut *self.state;
            let status = &mut s.contacts[d];
            if part != crate::impact::Part::Out {
                status.impulse = [impact.impulses[d].x, impact.impulses[d].y];
            }
            let leaves = impact.separation[d] >= self.params.resting_speed;
            match part {
                crate::impact::Part::Landing(e) => {
                    let first = status.landed_in != Some(grid);
                    status.open = e > 0.0 || (leaves && first);
                    status.landed_in = Some(grid);
                    if !first && !status.open {
                        relanded.push(d);
                    }
                    s.force_history[d] = [ContactForce::default(); 3];
                    push_event(s, d, EventKind::Landing);
                }
                crate::impact::Part::Closed => self.leave_at_impact(d, impact.separation[d]),
                _ => {}
            }
        }
        self.restart(&relanded, self.grid_remainder())
    }

    /// A closed contact that an impact sends away from the track at
    /// `separation` (m/s) opens, with a lift-off event, if that is at least
    /// `RESTING_SPEED`; slower, it stays closed.
    pub(crate) fn leave_at_impact(&mut self, d: usize, separation: f64) {
        if separation < self.params.resting_speed {
            return;
        }
        let s = &mut *self.state;
        s.contacts[d].open = true;
        s.contacts[d].opened_in = Some(s.grid_step);
        s.force_history[d] = [ContactForce::default(); 3];
        push_event(s, d, EventKind::LiftOff);
    }

    /// How each contact takes part in the impact of `c`'s landing.
    pub(crate) fn impact_parts(
        &self,
        c: usize,
        plastic: bool,
        frames: &[crate::contact::ContactFrame],
    ) -> Vec<crate::impact::Part> {
        use crate::impact::Part;
        let errors = self.velocity_errors(frames);
        let grid = self.state.grid_step;
        let statuses = self.state.contacts.iter().enumerate();
        statuses
            .map(|(d, status)| {
                let approach = errors[d].y.min(0.0);
                if self.system.contacts[d].follower.is_some() {
                    // A force law with no mass: no impulse passes through it.
                    return Part::Out;
                }
                if !status.open {
                    return if status.opened_in == Some(grid) {
                        Part::Held
                    } else {
                        Part::Closed
                    };
                }
                if d != c && (status.gap > LANDING_GAP || approach == 0.0) {
                    return Part::Out;
                }
                let again = status.landed_in == Some(grid);
                if -approach < self.params.resting_speed || again || (plastic && d == c) {
                    Part::Landing(0.0)
                } else {
                    Part::Landing(self.setup.restitution[d])
                }
            })
            .collect()
    }
}

/// Gaps within which a landing counts as located (m).
const LANDING_GAP: f64 = 1e-12;

/// Two instants of a step with a signed distance at each: (τ, miss).
type Bracket = ((f64, f64), (f64, f64));

/// How far (dt/2^k) the landing locator looks for a just-bounced contact
/// above the track before it counts the bounce as lost in the step.
const BOUNCE_HALVINGS: i32 = 30;
