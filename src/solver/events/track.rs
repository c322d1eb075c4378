//! Track events: a contact crossing a boundary of the track (onto the
//! structure, off it, over a joint, beyond the track), located inside the
//! step, recorded, and the end of the run it may bring.

use crate::contact::ContactForce;
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};
use crate::state::{push_event, EventKind};
use crate::system::TrackPart;

impl Step<'_> {
    /// The contact whose crossing of a track boundary comes first in the
    /// step just solved (into `scratch`): the fraction of the step at which
    /// it does (linear estimate), the contact, the boundary's abscissa and
    /// the part beyond it.
    pub(crate) fn first_event(&self) -> Option<(f64, usize, f64, TrackPart)> {
        let (start, end) = (&self.state.dynamic.contact_x, &self.work.scratch.contact_x);
        let mut first: Option<(f64, usize, f64, TrackPart)> = None;
        for c in 0..start.len() {
            let from = self.state.parts[c];
            let Some(right) = self.system.leaves(from, start[c], end[c]) else {
                continue;
            };
            let (edge, part) = self.system.next_part(from, right);
            // Linear estimate of when in the step the edge is crossed.
            let fraction = ((edge - start[c]) / (end[c] - start[c])).clamp(0.0, 1.0);
            if first.is_none_or(|(f, ..)| fraction < f) {
                first = Some((fraction, c, edge, part));
            }
        }
        first
    }

    /// Shorten the step so that contact `contact` lands on `edge`. Leaves
    /// the state at that instant in `scratch`.
    pub(crate) fn locate_event(
        &mut self,
        contact: usize,
        edge: f64,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64), SolverError> {
        let start = self.state.dynamic.contact_x[contact] - edge;
        let tolerance = 1e-12 * self.system.beam.length;
        let miss = |step: &Step, _: &StepSolution| step.work.scratch.contact_x[contact] - edge;
        let end = self.work.scratch.contact_x[contact] - edge;
        self.locate(forces, dt, ((0.0, start), end), tolerance, miss)?
            .ok_or_else(|| SolverError {
                time: self.state.time,
                message: format!(
                    "the instant {} reaches x = {edge} m could not be located",
                    self.system.contacts[contact].name
                ),
            })
    }

    /// Record the track events of the step just taken, which ends where
    /// contact `located.0` reaches part `located.1` (or at another event),
    /// and end the run if it is over.
    pub(crate) fn record_events(&mut self, located: Option<(usize, TrackPart)>) {
        let s = &mut *self.state;
        // `accept` swapped the step's start state into `scratch`.
        let starts = &self.work.scratch.contact_x;
        for (c, &start) in starts.iter().enumerate() {
            let x = s.dynamic.contact_x[c];
            let from = s.parts[c];
            // The located contact sits on its edge to round-off: take the
            // side it was moving to.
            let to = if let Some((_, part)) = located.filter(|&(l, _)| l == c) {
                part
            } else {
                match self.system.leaves(from, start, x) {
                    Some(right) => self.system.next_part(from, right).1,
                    None => continue,
                }
            };
            let contact = &self.system.contacts[c];
            let centre_x = contact.point(&s.dynamic.bodies[contact.body]).position.x;
            let to = self.system.settle_part(to, centre_x);
            if matches!(to, TrackPart::JointBefore(_) | TrackPart::JointAfter(_)) {
                // Over a joint the contact's abscissa is its centre's.
                s.dynamic.contact_x[c] = centre_x;
            }
            s.parts[c] = to;
            let kind = match (from, to) {
                (_, TrackPart::Beyond) => EventKind::LeftTrack,
                // From piece to joint to piece: still on the structure.
                _ if from.on_structure() && to.on_structure() => continue,
                _ if to.on_structure() => EventKind::Entry,
                _ => EventKind::Exit,
            };
            if from.on_structure() && kind == EventKind::LeftTrack {
                push_event(s, c, EventKind::Exit);
            }
            push_event(s, c, kind);
        }
        let left_track = s.parts.contains(&TrackPart::Beyond);
        let all_left_beam = !s.parts.iter().any(|p| p.on_structure())
            && (0..s.parts.len()).all(|c| {
                s.events
                    .iter()
                    .any(|e| e.contact == c && e.kind == EventKind::Exit)
            });
        let run_over = left_track || (self.setup.stop_at_beam_exit && all_left_beam);
        if run_over && !self.system.track.open_ends {
            s.exit_time = Some(s.time);
        }
    }
}
