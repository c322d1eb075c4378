//! A massless follower's contact state: open while its suspension would
//! pull (its force cut to zero, the body in flight), closed while it
//! carries load. The follower has no mass and no rows in the iteration,
//! so its lift-off and its landing are not the closed contacts' events:
//! nothing is solved again and nothing impacts. Its force max(0, law) is
//! continuous in the state, so at a landing it grows from zero again with
//! no impulse and no loss (`energy.impact_loss` is untouched). Each
//! transition is an event at the instant the law crosses zero, linearly
//! interpolated between the ends of the step that saw it.
//!
//! A follower hangs its suspension's height above the track, so where the
//! track kinks (the beam's start sloping down from the approach, the
//! run-off's corner at the beam's end, a piece's start after a rail gap)
//! it turns about the corner, its force's direction sweeping from one
//! surface's normal to the other's, until its attachment is over the
//! surface beyond: h sin φ of travel (1e-5 m, 0.4 µs for a coach's
//! followers entering at 100 km/h). Inside a step that sweep is a jump of
//! the force's direction by the slope φ, which RK4 (its first stage before
//! the jump: weight 1/6) and the trapezoidal rule of HHT-α (1/2) average
//! wrongly: the energy balance gains P φ v Δt / 6 (or / 2) at each such
//! corner, first order in the step. So the step ends where the follower
//! leaves the corner, located like a track event, and each side of it is
//! smooth.

use nalgebra::{DVector, Vector2};

use crate::contact::{foot_point_on, ContactForce, ContactFrame};
use crate::integrate::{follower_gap, DynamicState};
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};
use crate::state::push_event_at;
use crate::state::EventKind;
use crate::system::{System, TrackPart};

impl Step<'_> {
    /// After a step of `dt` was accepted (its start state in `scratch`):
    /// each follower's contact open where its force is zero, with a
    /// lift-off or landing event where that changed.
    pub(crate) fn follower_transitions(&mut self, dt: f64) {
        for c in 0..self.system.contacts.len() {
            let Some(follower) = self.system.contacts[c].follower else {
                continue;
            };
            let slack = self.state.force_history[c][0].normal == 0.0;
            if slack == self.state.contacts[c].open {
                continue;
            }
            self.state.contacts[c].open = slack;
            let law = |d: &DynamicState, step: &Step| -> Option<f64> {
                let frame = step.frame(c, d)?;
                let contact = &step.system.contacts[c];
                let (gap, rate) =
                    follower_gap(step.system, contact, &frame, &d.bodies, &d.beam_velocity);
                Some(follower.law(gap, rate))
            };
            // The fraction of the step at which the law crossed zero.
            let fraction = match (
                law(&self.work.scratch, self),
                law(&self.state.dynamic, self),
            ) {
                (Some(p0), Some(p1)) if p0 != p1 && (p0 - p1).is_finite() => {
                    (p0 / (p0 - p1)).clamp(0.0, 1.0)
                }
                // No frame, or no crossing to interpolate: the step's end.
                _ => 1.0,
            };
            let time = self.state.time - (1.0 - fraction) * dt;
            let kind = if slack {
                EventKind::LiftOff
            } else {
                EventKind::Landing
            };
            push_event_at(self.state, c, kind, time);
        }
    }

    /// The follower that first leaves a corner of the track for the
    /// surface beyond in the step just solved (its end state in
    /// `scratch`), and the fraction of the step at which it does (linear
    /// estimate).
    pub(crate) fn first_corner_departure(&self) -> Option<(f64, usize)> {
        let tolerance = self.corner_tolerance();
        let mut first: Option<(f64, usize)> = None;
        for (c, contact) in self.system.contacts.iter().enumerate() {
            if contact.follower.is_none() {
                continue;
            }
            let part = self.state.parts[c];
            let start = &contact.point(&self.state.dynamic.bodies[contact.body]);
            let end = &contact.point(&self.work.scratch.bodies[contact.body]);
            // Only near a corner, and moving past it: the search for the
            // surface's foot point is not made for every follower at every step.
            let reach = self.state.contacts[c].gap.abs();
            if !near_corner(self.system, part, start.position.x, end.position.x, reach) {
                continue;
            }
            let before = past_corner(
                self.system,
                part,
                &self.state.dynamic.beam_displacement,
                start,
            );
            let after = past_corner(self.system, part, &self.work.scratch.beam_displacement, end);
            let (Some(s0), Some(s1)) = (before, after) else {
                continue;
            };
            // The foot point moves with the attachment: a larger change is
            // a jump (no instant to locate; a step shortened towards it
            // would shrink without end), taken as the step found it.
            let moved = (end.position - start.position).norm();
            if s0 < -tolerance && s1 > tolerance && s1 - s0 <= 2.0 * moved + tolerance {
                let fraction = s0 / (s0 - s1);
                if first.is_none_or(|(f, _)| fraction < f) {
                    first = Some((fraction, c));
                }
            }
        }
        first
    }

    /// Shorten the step so that follower `c` leaves its corner at its end.
    /// Leaves the state at that instant in `scratch`.
    pub(crate) fn locate_corner_departure(
        &mut self,
        c: usize,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64), SolverError> {
        let part = self.state.parts[c];
        let past = |step: &Step, d: &DynamicState| {
            let contact = &step.system.contacts[c];
            let point = contact.point(&d.bodies[contact.body]);
            past_corner(step.system, part, &d.beam_displacement, &point).unwrap_or(f64::NAN)
        };
        let start = past(self, &self.state.dynamic);
        let end = past(self, &self.work.scratch);
        let miss = |step: &Step, _: &StepSolution| past(step, &step.work.scratch);
        let tolerance = self.corner_tolerance();
        self.locate(forces, dt, ((0.0, start), end), tolerance, miss)?
            .ok_or_else(|| SolverError {
                time: self.state.time,
                message: format!(
                    "the instant {} leaves the track's corner could not be located",
                    self.system.contacts[c].name
                ),
            })
    }

    /// Within this distance of the instant it leaves a corner a follower
    /// counts as having left it (m): that of the track events.
    pub(crate) fn corner_tolerance(&self) -> f64 {
        1e-12 * self.system.beam.length
    }

    /// Contact `c`'s frame in state `d` on the part it is on now.
    pub(crate) fn frame(&self, c: usize, d: &DynamicState) -> Option<ContactFrame> {
        self.frames_of(d).ok()?.into_iter().nth(c)
    }
}

/// The corner a contact on `part` may turn about before the surface
/// beyond: the start of a piece of the structure (from the approach, or
/// after a rail gap), or the beam's end for the run-off.
fn corner_of(system: &System, part: TrackPart) -> Option<f64> {
    match part {
        TrackPart::RunOff => Some(system.beam.length),
        TrackPart::Beam if system.track.approach <= 0.0 => None,
        _ => Some(system.beam.segments()[part.piece_index()?].start),
    }
}

/// Whether a follower on `part` whose attachment moved from `start` to
/// `end` along x may have left its corner in between: it ends the step
/// past the corner and started it within `reach` (its height above the
/// track, beyond which it no longer leans on the corner) of it.
fn near_corner(system: &System, part: TrackPart, start: f64, end: f64, reach: f64) -> bool {
    corner_of(system, part).is_some_and(|corner| end >= corner && start <= corner + reach)
}

/// How far past the corner of `part` a follower whose attachment is at
/// `point` is (m): the abscissa of the foot point on the surface beyond,
/// less the corner's. Negative while it turns about the corner; `None`
/// where there is no corner or no foot point.
fn past_corner(
    system: &System,
    part: TrackPart,
    u: &DVector<f64>,
    point: &crate::body::BodyState,
) -> Option<f64> {
    let corner = corner_of(system, part)?;
    let centre: &Vector2<f64> = &point.position;
    let foot = match (part, system.profile.as_ref()) {
        (TrackPart::RunOff, None) => centre.x,
        (TrackPart::RunOff, Some(profile)) => ContactFrame::on_profile(profile, centre).ok()?.x,
        // Searched from just inside the piece, as its frames are.
        _ => {
            let inside = corner + 1e-9 * system.beam.length;
            foot_point_on(&system.beam, system.profile.as_ref(), u, centre, inside)
                .ok()?
                .x
        }
    };
    Some(foot - corner)
}
