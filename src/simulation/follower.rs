//! A massless follower's contact state: open while its suspension would
//! pull (its force cut to zero, the body in flight), closed while it
//! carries load. The follower has no mass and no rows in the iteration,
//! so its lift-off and its landing are not the closed contacts' events:
//! nothing is solved again and nothing impacts. Its force max(0, law) is
//! continuous in the state, so at a landing it grows from zero again with
//! no impulse and no loss (`energy.impact_loss` is untouched). Each
//! transition is an event at the instant the law crosses zero, linearly
//! interpolated between the ends of the step that saw it.

use super::{ContactEvent, EventKind, SimState, Simulation, MAX_EVENTS};
use crate::contact::ContactFrame;
use crate::integrate::{follower_gap, DynamicState};

impl Simulation {
    /// After a step of `dt` was accepted (its start state in `scratch`):
    /// each follower's contact open where its force is zero, with a
    /// lift-off or landing event where that changed.
    pub(super) fn follower_transitions(&mut self, dt: f64) {
        for c in 0..self.system.contacts.len() {
            let Some(follower) = self.system.contacts[c].follower else {
                continue;
            };
            let slack = self.state.force_history[c][0].normal == 0.0;
            if slack == self.state.contacts[c].open {
                continue;
            }
            self.state.contacts[c].open = slack;
            let law = |d: &DynamicState, sim: &Simulation| -> Option<f64> {
                let frame = sim.frame(c, d)?;
                let contact = &sim.system.contacts[c];
                let (gap, rate) =
                    follower_gap(&sim.system, contact, &frame, &d.bodies, &d.beam_velocity);
                Some(follower.law(gap, rate))
            };
            // The fraction of the step at which the law crossed zero.
            let fraction = match (law(&self.scratch, self), law(&self.state.dynamic, self)) {
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
            push_event_at(&mut self.state, c, kind, time);
        }
    }

    /// Contact `c`'s frame in state `d` on the part it is on now.
    fn frame(&self, c: usize, d: &DynamicState) -> Option<ContactFrame> {
        self.frames_of(d).ok()?.into_iter().nth(c)
    }
}

/// Record an event of contact `c` at `time` (counted, not kept, beyond
/// `MAX_EVENTS`).
fn push_event_at(s: &mut SimState, c: usize, kind: EventKind, time: f64) {
    if s.events.len() < MAX_EVENTS {
        s.events.push(ContactEvent {
            contact: c,
            time,
            kind,
        });
    } else {
        s.events_dropped += 1;
    }
}
