//! The assembled mechanical system: the structure (a beam between rigid
//! approach and run-off ground), the rigid bodies, the force elements
//! between them and the contacts of the contact bodies with the track.

use nalgebra::{DVector, Vector2};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{foot_point, Contact, ContactFrame, FootPointError};
use crate::force_element::ForceElement;

/// The track: rigid ground of length `approach` before the beam (x < 0) and
/// `run_off` after it (x > L), level with the beam's supports.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Track {
    pub approach: f64,
    pub run_off: f64,
    /// Beyond either end of the track the ground goes on (level with the
    /// supports): a body that leaves the track leaves the structure's
    /// model but keeps a defined motion, so a co-simulation can run on to
    /// its stop time (the FMU). Otherwise leaving the track ends the run.
    pub open_ends: bool,
}

pub struct System {
    pub beam: Beam,
    pub track: Track,
    pub bodies: Vec<RigidBody>,
    pub force_elements: Vec<ForceElement>,
    pub contacts: Vec<Contact>,
    /// Acceleration of gravity (m/s², acting in −y).
    pub gravity: f64,
    /// The coupling points: bodies (indices) that take an additional load
    /// from outside (the FMU's coupling ports), in the scene's order.
    pub couplings: Vec<usize>,
}

/// Where along the track a contact point is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TrackPart {
    Approach,
    Beam,
    RunOff,
    /// Off either end of the track.
    Beyond,
}

impl System {
    /// First row of each contact in the stacked rows, and the total.
    pub fn row_offsets(&self) -> (Vec<usize>, usize) {
        let mut offsets = Vec::with_capacity(self.contacts.len());
        let mut total = 0;
        for contact in &self.contacts {
            offsets.push(total);
            total += contact.rows();
        }
        (offsets, total)
    }

    /// Which part of the track the abscissa `x` lies on.
    pub fn track_part(&self, x: f64) -> TrackPart {
        let length = self.beam.length;
        if x < -self.track.approach || x > length + self.track.run_off {
            TrackPart::Beyond
        } else if x < 0.0 {
            TrackPart::Approach
        } else if x > length {
            TrackPart::RunOff
        } else {
            TrackPart::Beam
        }
    }

    /// The first boundary a contact on `from` crosses moving right (or
    /// left), and the part beyond it.
    pub fn next_part(&self, from: TrackPart, moving_right: bool) -> (f64, TrackPart) {
        let (length, track) = (self.beam.length, &self.track);
        let or_beyond = |exists: bool, part| if exists { part } else { TrackPart::Beyond };
        match (from, moving_right) {
            (TrackPart::Approach, true) => (0.0, TrackPart::Beam),
            (TrackPart::Beam, true) => (length, or_beyond(track.run_off > 0.0, TrackPart::RunOff)),
            (TrackPart::RunOff, true) => (length + track.run_off, TrackPart::Beyond),
            (TrackPart::RunOff, false) => (length, TrackPart::Beam),
            (TrackPart::Beam, false) => (0.0, or_beyond(track.approach > 0.0, TrackPart::Approach)),
            (TrackPart::Approach, false) => (-track.approach, TrackPart::Beyond),
            (TrackPart::Beyond, _) => (f64::NAN, TrackPart::Beyond),
        }
    }

    /// Whether there is rigid ground beyond the beam's end on the side of `x`.
    fn ground_at(&self, x: f64) -> bool {
        (x < 0.0 && self.track.approach > 0.0) || (x > self.beam.length && self.track.run_off > 0.0)
    }

    /// The contact frame of a contact on `part` of the track with its body
    /// centred at `centre`. On the beam: the foot point on the deformed
    /// neutral axis (beyond the ends the end elements' cubics are extended,
    /// so that the instant a contact leaves the beam can be located). On
    /// rigid ground: the ground below the centre, or, on the run-off, the
    /// beam's end (a corner, held in place by its support) while the centre
    /// has not yet passed it, so that the force turns continuously from the
    /// beam's normal to the vertical; likewise at the beam's start when a
    /// contact comes from the approach onto a beam that slopes down.
    #[inline]
    pub fn contact_frame(
        &self,
        u: &DVector<f64>,
        centre: &Vector2<f64>,
        guess: f64,
        part: TrackPart,
    ) -> Result<ContactFrame, FootPointError> {
        let length = self.beam.length;
        Ok(match part {
            TrackPart::Beam => {
                let frame = foot_point(&self.beam, u, centre, guess)?;
                // Onto a beam that slopes down from its start the wheel
                // turns about the start (a corner) until its centre is over
                // the beam's normal there.
                if frame.x < 0.0 && self.track.approach > 0.0 {
                    ContactFrame::at_corner(0.0, centre)
                } else {
                    frame
                }
            }
            TrackPart::RunOff if centre.x < length => ContactFrame::at_corner(length, centre),
            // Contacts enter from the approach at centre.x = 0 (the event):
            // a left-moving exit onto the approach is taken on flat ground.
            TrackPart::Approach | TrackPart::RunOff => ContactFrame::on_ground(centre),
            TrackPart::Beyond if self.track.open_ends || self.ground_at(centre.x) => {
                ContactFrame::on_ground(centre)
            }
            TrackPart::Beyond => foot_point(&self.beam, u, centre, guess)?,
        })
    }

    /// Whether a contact on `part` that moved from `start` to `end` (foot
    /// abscissae) has left it, and if so whether to the right.
    pub fn leaves(&self, part: TrackPart, start: f64, end: f64) -> Option<bool> {
        let (length, track) = (self.beam.length, &self.track);
        let right = end > start;
        let (low, high) = match part {
            TrackPart::Approach => (-track.approach, 0.0),
            TrackPart::Beam => (0.0, length),
            TrackPart::RunOff => (length, length + track.run_off),
            TrackPart::Beyond => return None,
        };
        if right && end >= high {
            Some(true)
        } else if !right && end < low {
            Some(false)
        } else {
            None
        }
    }

    /// Potential energy of gravity, Σ m g y (J).
    pub fn gravity_potential(&self, bodies: &[BodyState]) -> f64 {
        self.bodies
            .iter()
            .zip(bodies)
            .map(|(body, state)| body.mass * self.gravity * state.position.y)
            .sum()
    }

    /// Potential energy of the force elements (J).
    pub fn spring_energy(&self, bodies: &[BodyState]) -> f64 {
        self.force_elements
            .iter()
            .map(|e| e.potential_energy(bodies))
            .sum()
    }
}
