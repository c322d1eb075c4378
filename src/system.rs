//! The assembled mechanical system: the structure (a beam between rigid
//! approach and run-off ground), the rigid bodies, the force elements
//! between them and the contacts of the contact bodies with the track.

use nalgebra::{DVector, Vector2, Vector3};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{foot_point_on, Contact, ContactFrame, FootPointError};
use crate::force_element::ForceElements;
use crate::profile::Profile;

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
    pub force_elements: ForceElements,
    pub contacts: Vec<Contact>,
    /// Acceleration of gravity (m/s², acting in −y).
    pub gravity: f64,
    /// Irregularity r(x) of the running surface, beam and ground alike.
    pub profile: Option<Profile>,
    /// The coupling points: bodies (indices) that take an additional load
    /// from outside (the FMU's coupling ports), in the scene's order.
    pub couplings: Vec<usize>,
}

/// Where along the track a contact point is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TrackPart {
    Approach,
    /// On the beam; with joints, on its first smooth piece.
    Beam,
    RunOff,
    /// Off either end of the track.
    Beyond,
    /// On smooth piece k ≥ 1 of a track with joints (`Beam::segments`).
    Span(usize),
    /// Over joint j (between pieces j and j + 1), touching the end corner
    /// of piece j: from the foot point reaching that end to the centre
    /// passing the middle of the gap.
    JointBefore(usize),
    /// Over joint j, touching the start corner of piece j + 1, until the
    /// centre passes it.
    JointAfter(usize),
}

impl TrackPart {
    /// The part of smooth piece `k` of the structure.
    pub fn piece(k: usize) -> TrackPart {
        if k == 0 {
            TrackPart::Beam
        } else {
            TrackPart::Span(k)
        }
    }

    /// The smooth piece of the structure this part is on, if any.
    pub fn piece_index(self) -> Option<usize> {
        match self {
            TrackPart::Beam => Some(0),
            TrackPart::Span(k) => Some(k),
            _ => None,
        }
    }

    /// On the structure: on a piece of it or over one of its joints.
    pub fn on_structure(self) -> bool {
        matches!(
            self,
            TrackPart::Beam
                | TrackPart::Span(_)
                | TrackPart::JointBefore(_)
                | TrackPart::JointAfter(_)
        )
    }
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

    /// Which part of the track the abscissa `x` lies on (on the piece that
    /// starts at `x` where two meet; in a gap, the piece before it).
    pub fn track_part(&self, x: f64) -> TrackPart {
        let length = self.beam.length;
        if x < -self.track.approach || x > length + self.track.run_off {
            TrackPart::Beyond
        } else if x < 0.0 {
            TrackPart::Approach
        } else if x > length {
            TrackPart::RunOff
        } else {
            let pieces = self.beam.segments();
            let k = pieces.partition_point(|p| p.start <= x).saturating_sub(1);
            TrackPart::piece(k)
        }
    }

    /// Whether `part` exists on this track (a state from outside may name
    /// pieces or joints it does not have).
    pub fn has_part(&self, part: TrackPart) -> bool {
        let pieces = self.beam.segments().len();
        match part {
            TrackPart::Span(k) => k < pieces,
            TrackPart::JointBefore(j) | TrackPart::JointAfter(j) => j + 1 < pieces,
            _ => true,
        }
    }

    /// Joint j's end of piece j, start of piece j + 1 and their middle.
    fn joint(&self, j: usize) -> (f64, f64, f64) {
        let pieces = self.beam.segments();
        let (a, b) = (pieces[j].end, pieces[j + 1].start);
        (a, b, 0.5 * (a + b))
    }

    /// The first boundary a contact on `from` crosses moving right (or
    /// left), and the part beyond it.
    pub fn next_part(&self, from: TrackPart, moving_right: bool) -> (f64, TrackPart) {
        let (length, track) = (self.beam.length, &self.track);
        let or_beyond = |exists: bool, part| if exists { part } else { TrackPart::Beyond };
        let pieces = self.beam.segments();
        let last = pieces.len() - 1;
        match (from, moving_right) {
            (TrackPart::Beam, true) if last > 0 => {
                return (pieces[0].end, TrackPart::JointBefore(0))
            }
            (TrackPart::Span(k), true) if k < last => {
                return (pieces[k].end, TrackPart::JointBefore(k))
            }
            (TrackPart::Span(_), true) => {
                return (length, or_beyond(track.run_off > 0.0, TrackPart::RunOff))
            }
            // Joints are crossed moving right: a contact moving left onto
            // one leaves the track (the run ends with that event).
            (TrackPart::Span(k), false) => return (pieces[k].start, TrackPart::Beyond),
            (TrackPart::JointBefore(j), _) => return (self.joint(j).2, TrackPart::JointAfter(j)),
            (TrackPart::JointAfter(j), _) => return (self.joint(j).1, TrackPart::piece(j + 1)),
            (TrackPart::RunOff, false) => return (length, TrackPart::piece(last)),
            _ => {}
        }
        match (from, moving_right) {
            (TrackPart::Approach, true) => (0.0, TrackPart::Beam),
            (TrackPart::Beam, true) => (length, or_beyond(track.run_off > 0.0, TrackPart::RunOff)),
            (TrackPart::RunOff, true) => (length + track.run_off, TrackPart::Beyond),
            (TrackPart::RunOff, false) => (length, TrackPart::Beam),
            (TrackPart::Beam, false) => (0.0, or_beyond(track.approach > 0.0, TrackPart::Approach)),
            (TrackPart::Approach, false) => (-track.approach, TrackPart::Beyond),
            (TrackPart::Beyond, _) => (f64::NAN, TrackPart::Beyond),
            _ => unreachable!("pieces and joints are handled above"),
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
        let (length, profile) = (self.beam.length, self.profile.as_ref());
        let several = self.beam.segments().len() > 1;
        // With an irregularity profile each case runs on the surface
        // raised by r(x) (a joint's corners too); without one, exactly as
        // before it existed.
        let ground = |centre: &Vector2<f64>| match profile {
            None => Ok(ContactFrame::on_ground(centre)),
            Some(profile) => ContactFrame::on_profile(profile, centre),
        };
        match part {
            TrackPart::Beam if !several => self.first_piece_frame(u, centre, guess),
            TrackPart::Beam | TrackPart::Span(_) => {
                let k = part.piece_index().unwrap_or(0);
                self.piece_frame(k, u, centre, guess)
            }
            TrackPart::JointBefore(j) => {
                let piece = &self.beam.segments()[j];
                let element = piece.elements.end - 1;
                match self.corner(u, (element, piece.end), centre) {
                    Some(frame) => Ok(self.toward_far_corner(j, frame, centre)),
                    None => foot_point_on(&self.beam, profile, u, centre, piece.end),
                }
            }
            TrackPart::JointAfter(j) => {
                let piece = &self.beam.segments()[j + 1];
                let element = piece.elements.start;
                match self.corner(u, (element, piece.start), centre) {
                    Some(frame) => Ok(self.along_next_piece(j, u, frame, centre)),
                    None => foot_point_on(&self.beam, profile, u, centre, piece.start),
                }
            }
            // The corner while the ground's foot point is before the beam's
            // end: on flat ground while the centre is, on a profile where
            // the foot leans off the centre (else a body above the kink
            // would hop between beam and run-off in ever shorter steps).
            TrackPart::RunOff => ground(centre).and_then(|frame| {
                if frame.x < length {
                    self.end_corner(length, centre)
                } else {
                    Ok(frame)
                }
            }),
            // Contacts enter from the approach at centre.x = 0 (the event):
            // a left-moving exit onto the approach is taken on flat ground.
            TrackPart::Approach => ground(centre),
            TrackPart::Beyond if self.track.open_ends || self.ground_at(centre.x) => ground(centre),
            TrackPart::Beyond => foot_point_on(&self.beam, profile, u, centre, guess),
        }
    }

    /// Whether `contact_frame` of a contact on `part` centred at `centre`
    /// is `ContactFrame::on_ground(centre)` (flat ground, no profile): the
    /// frame a caller may build in place (most of a train's contacts are
    /// on the approach or the run-off). The same cases as `contact_frame`.
    #[inline]
    pub fn on_flat_ground(&self, centre: &Vector2<f64>, part: TrackPart) -> bool {
        self.profile.is_none()
            && match part {
                TrackPart::Approach => true,
                TrackPart::RunOff => centre.x >= self.beam.length || centre.x.is_nan(),
                TrackPart::Beyond => self.track.open_ends || self.ground_at(centre.x),
                _ => false,
            }
    }

    /// The corner at the beam's end `x`, on the profile where there is one.
    fn end_corner(&self, x: f64, centre: &Vector2<f64>) -> Result<ContactFrame, FootPointError> {
        match self.profile.as_ref() {
            None => Ok(ContactFrame::at_corner(x, centre)),
            Some(profile) => ContactFrame::at_profile_corner(profile, x, centre),
        }
    }

    /// The frame on the first piece: the foot point, or the beam's start
    /// (a corner) while the beam slopes down from it below the centre.
    #[inline]
    fn first_piece_frame(
        &self,
        u: &DVector<f64>,
        centre: &Vector2<f64>,
        guess: f64,
    ) -> Result<ContactFrame, FootPointError> {
        let found = foot_point_on(&self.beam, self.profile.as_ref(), u, centre, guess);
        // Onto a beam that slopes down from its start the wheel
        // turns about the start (a corner) until its centre is over
        // the beam's normal there. (The search's result is passed on
        // whole: unpacked and packed again it was copied twice.)
        match &found {
            Ok(frame) if frame.x < 0.0 && self.track.approach > 0.0 => self.end_corner(0.0, centre),
            _ => found,
        }
    }

    /// The frame on smooth piece `k` of a track with joints: the foot point
    /// on that piece (its end elements continued past its ends), searched
    /// from inside it; where the foot point falls before the start of a
    /// piece after a joint, the corner there (as at the beam's start).
    fn piece_frame(
        &self,
        k: usize,
        u: &DVector<f64>,
        centre: &Vector2<f64>,
        guess: f64,
    ) -> Result<ContactFrame, FootPointError> {
        let piece = &self.beam.segments()[k];
        if k == 0 {
            let inside = piece.start.max(guess.min(piece.end - self.inset(piece)));
            return self.first_piece_frame(u, centre, inside);
        }
        let margin = self.inset(piece);
        let inside = (piece.start + margin).max(guess.min(piece.end - margin));
        let frame = foot_point_on(&self.beam, self.profile.as_ref(), u, centre, inside)?;
        if frame.x < piece.start {
            let element = piece.elements.start;
            if let Some(corner) = self.corner(u, (element, piece.start), centre) {
                return Ok(corner);
            }
        }
        Ok(frame)
    }

    /// `corner_frame` at the end of a piece, raised by the profile there:
    /// the corner is the beam end's plus r at its abscissa.
    fn corner(
        &self,
        u: &DVector<f64>,
        (element, x): (usize, f64),
        centre: &Vector2<f64>,
    ) -> Option<ContactFrame> {
        let raise = self.profile.as_ref().map_or(0.0, |p| p.at(x)[0]);
        corner_frame(&self.beam, u, (element, x, raise), centre)
    }

    /// A frame on joint j's near corner, its abscissa moved along the
    /// corner's tangent (the gap unchanged) to where the centre is along
    /// the line from the near corner to the far one: the switch to the far
    /// corner, where the rim touches both, is then where that abscissa
    /// passes the middle of the gap. Without a profile the corners are
    /// level and that is the centre's abscissa itself (the frame is kept
    /// as it is); with one they differ by r(b) − r(a), and the switch moves
    /// by about (r + h)(r(b) − r(a))/w. (The ends at a gap are held.)
    fn toward_far_corner(
        &self,
        j: usize,
        frame: ContactFrame,
        centre: &Vector2<f64>,
    ) -> ContactFrame {
        let Some(profile) = self.profile.as_ref() else {
            return frame;
        };
        let (a, b, middle) = self.joint(j);
        if b <= a {
            return frame;
        }
        let (near, far) = (profile.at(a)[0], profile.at(b)[0]);
        let along = Vector2::new(b - a, far - near).normalize();
        let from_middle = centre - Vector2::new(middle, 0.5 * (near + far));
        let x = middle + from_middle.dot(&along);
        ContactFrame {
            deflection: frame.deflection + frame.slope * (x - frame.x),
            x,
            ..frame
        }
    }

    /// A frame on joint j's far corner, its abscissa moved along the
    /// corner's tangent to where the centre is along the next piece's
    /// surface at its start: the switch onto the piece, where the centre
    /// crosses that surface's normal through the corner and the velocity
    /// turns continuously, is then where the abscissa passes the corner.
    /// Without a profile the frame is kept as it is (the switch where the
    /// centre's abscissa passes the corner, as before profiles existed).
    fn along_next_piece(
        &self,
        j: usize,
        u: &DVector<f64>,
        frame: ContactFrame,
        centre: &Vector2<f64>,
    ) -> ContactFrame {
        let Some(profile) = self.profile.as_ref() else {
            return frame;
        };
        let piece = &self.beam.segments()[j + 1];
        let b = piece.start;
        let (axis, r) = (self.beam.axis(piece.elements.start, b, u), profile.at(b));
        let corner = Vector2::new(b, axis[0] + r[0]);
        let tangent = Vector2::new(1.0, axis[1] + r[1]).normalize();
        let x = b + (centre - corner).dot(&tangent);
        ContactFrame {
            deflection: frame.deflection + frame.slope * (x - frame.x),
            x,
            ..frame
        }
    }

    /// How far inside a piece its foot-point search starts at the least:
    /// clear of the neighbouring piece's elements where two meet.
    fn inset(&self, piece: &crate::mesh::Segment) -> f64 {
        1e-9 * (piece.end - piece.start)
    }

    /// Whether a contact switching from `from` to `to` may jump in
    /// velocity: onto the far corner of a joint, or from a joint onto the
    /// next piece (a concave kink: the piece before sloping down into the
    /// joint). Where the normal turns continuously the jump is zero.
    pub fn velocity_jump(&self, from: TrackPart, to: TrackPart) -> bool {
        let joint =
            |p: TrackPart| matches!(p, TrackPart::JointBefore(_) | TrackPart::JointAfter(_));
        from != to
            && (joint(from)
                || joint(to) && !from.on_structure()
                || from.piece_index().is_some() && to.piece_index().is_some())
    }

    /// The part a contact that just reached `part` is on, its centre at
    /// `centre_x`: over a joint, the contact passes at once the edges its
    /// centre has already passed (at a joint without gap, or where the
    /// piece before slopes down into the joint, the centre is past the
    /// corner when the foot point reaches it).
    pub fn settle_part(&self, part: TrackPart, centre_x: f64) -> TrackPart {
        let mut part = part;
        for _ in 0..2 {
            part = match part {
                TrackPart::JointBefore(j) if centre_x >= self.joint(j).2 => {
                    TrackPart::JointAfter(j)
                }
                TrackPart::JointAfter(j) if centre_x >= self.joint(j).1 => TrackPart::piece(j + 1),
                _ => return part,
            };
        }
        part
    }

    /// Whether a contact on `part` that moved from `start` to `end` (foot
    /// abscissae) has left it, and if so whether to the right.
    pub fn leaves(&self, part: TrackPart, start: f64, end: f64) -> Option<bool> {
        let (length, track) = (self.beam.length, &self.track);
        let right = end > start;
        let (low, high) = match part {
            TrackPart::Approach => (-track.approach, 0.0),
            TrackPart::Beam if self.beam.segments().len() == 1 => (0.0, length),
            TrackPart::Beam | TrackPart::Span(_) => {
                let k = part.piece_index().unwrap_or(0);
                let piece = &self.beam.segments()[k];
                (piece.start, piece.end)
            }
            TrackPart::RunOff => (length, length + track.run_off),
            TrackPart::Beyond => return None,
            // Over a joint only the forward crossing is an event (the
            // abscissa is the centre's, which jumps back from the foot
            // point's when the contact reaches the corner).
            TrackPart::JointBefore(j) | TrackPart::JointAfter(j) => {
                let (_, b, middle) = self.joint(j);
                let edge = if matches!(part, TrackPart::JointBefore(_)) {
                    middle
                } else {
                    b
                };
                return (start < edge && end >= edge).then_some(true);
            }
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
        crate::force_element::spring_energy(&self.force_elements, bodies)
    }
}

/// The frame of a contact turning about a corner of the structure: the
/// end (`element`'s end at abscissa `x`) of a piece where a joint is,
/// moving with the beam (held where its support holds it). The normal runs
/// from the corner point on the neutral axis to the centre, so the gap is
/// the distance minus r + h (the top edge is rounded with radius h). The
/// frame's abscissa is the centre's, on the tangent through the corner:
/// the gap is the same, and the abscissa moves with the body so that the
/// middle of a gap and the next piece's start can be located as events.
/// The corner is raised by `raise` (the irregularity there, fixed to the
/// beam's end: it moves with the end). `None` when the centre is not above
/// the corner (no corner to turn about).
fn corner_frame(
    beam: &Beam,
    u: &DVector<f64>,
    (element, x, raise): (usize, f64, f64),
    centre: &Vector2<f64>,
) -> Option<ContactFrame> {
    let shape = beam.shape(element, x);
    let w = beam.dot(&shape, &shape.n, u) + raise;
    let offset = centre - Vector2::new(x, w);
    let distance = offset.norm();
    if !(distance > 1e-9 * x.abs().max(1.0) && offset.y > 0.0) {
        return None;
    }
    let n = offset / distance;
    let slope = -n.x / n.y;
    Some(ContactFrame {
        x: centre.x,
        shape,
        deflection: w + slope * (centre.x - x),
        slope,
        curvature: 0.0,
        cos: n.y,
        sin: -n.x,
        on_beam: true,
    })
}

/// The constant generalized force on each body: its weight, plus each
/// vehicle's applied force (fx, fy; `forces`) on its first body
/// (`first_bodies`, in the same order).
pub fn constant_forces<'a>(
    system: &'a System,
    first_bodies: &'a [usize],
    forces: &'a [[f64; 2]],
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    system.bodies.iter().enumerate().map(move |(b, body)| {
        let weight = Vector3::new(0.0, -body.mass * system.gravity, 0.0);
        match first_bodies.iter().position(|&first| first == b) {
            Some(v) => weight + Vector3::new(forces[v][0], forces[v][1], 0.0),
            None => weight,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BodyKind, Scene};
    use crate::structure::beam::{JointKind, JointSpec};

    /// Two 24 m spans with a rail gap of `gap` after x = 24, and a hinge at 36.
    fn track(gap: f64) -> System {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 1e-3);
        scene.beam.length = 48.0 + gap;
        scene.beam.elements = 8;
        scene.beam.supports.intermediate = vec![30.0 + gap];
        scene.beam.joints = vec![
            JointSpec {
                at: 24.0,
                kind: JointKind::Separate,
                gap,
            },
            JointSpec {
                at: 36.0 + gap,
                kind: JointKind::Hinge,
                gap: 0.0,
            },
        ];
        crate::assemble::assemble(&scene).expect("assembles").system
    }

    #[test]
    fn a_contact_crosses_joints_piece_by_piece() {
        let system = track(0.05);
        assert_eq!(system.beam.segments().len(), 3);
        assert_eq!(system.track_part(10.0), TrackPart::Beam);
        assert_eq!(system.track_part(24.05), TrackPart::Span(1));
        assert_eq!(system.track_part(40.0), TrackPart::Span(2));
        // Moving right: piece, its end corner, the far corner, the next piece.
        assert_eq!(
            system.next_part(TrackPart::Beam, true),
            (24.0, TrackPart::JointBefore(0))
        );
        let (middle, after) = system.next_part(TrackPart::JointBefore(0), true);
        assert_eq!(after, TrackPart::JointAfter(0));
        assert!((middle - 24.025).abs() < 1e-12);
        assert_eq!(
            system.next_part(TrackPart::JointAfter(0), true),
            (24.05, TrackPart::Span(1))
        );
        assert_eq!(
            system.next_part(TrackPart::Span(1), true).1,
            TrackPart::JointBefore(1)
        );
        // Moving left onto a joint leaves the track.
        assert_eq!(
            system.next_part(TrackPart::Span(1), false),
            (24.05, TrackPart::Beyond)
        );
        // Only the forward crossing of a corner's edge is an event.
        assert_eq!(
            system.leaves(TrackPart::JointBefore(0), 24.0, 24.03),
            Some(true)
        );
        assert_eq!(system.leaves(TrackPart::JointBefore(0), 24.03, 24.04), None);
        assert_eq!(system.leaves(TrackPart::JointBefore(0), 24.01, 23.99), None);
        // The far corner's switch is an impact; a continuous turn is not.
        assert!(system.velocity_jump(TrackPart::JointBefore(0), TrackPart::JointAfter(0)));
        assert!(!system.velocity_jump(TrackPart::Approach, TrackPart::Beam));
        assert!(system.has_part(TrackPart::JointAfter(1)));
        assert!(!system.has_part(TrackPart::JointAfter(2)));
        assert!(!system.has_part(TrackPart::Span(3)));
    }

    #[test]
    fn a_centre_already_past_the_corner_passes_the_joint_at_once() {
        let system = track(0.0);
        // Without a gap the middle is the corner itself.
        assert_eq!(
            system.settle_part(TrackPart::JointBefore(0), 23.999),
            TrackPart::JointBefore(0)
        );
        assert_eq!(
            system.settle_part(TrackPart::JointBefore(0), 24.001),
            TrackPart::Span(1)
        );
        let gapped = track(0.05);
        assert_eq!(
            gapped.settle_part(TrackPart::JointBefore(0), 24.03),
            TrackPart::JointAfter(0)
        );
    }

    #[test]
    fn the_corner_frame_measures_the_distance_to_the_corner() {
        let system = track(0.05);
        let u = DVector::zeros(system.beam.free_dofs());
        let centre = Vector2::new(24.01, 0.85);
        let frame = system
            .contact_frame(&u, &centre, 24.0, TrackPart::JointBefore(0))
            .expect("frame");
        let distance = (centre - Vector2::new(24.0, 0.0)).norm();
        let gap = frame.gap(&system.beam, 0.3, &centre);
        assert!((gap - (distance - 0.9)).abs() < 1e-12, "{gap}");
        assert_eq!(frame.x, centre.x);
        // The normal points from the corner to the centre.
        let n = frame.normal();
        assert!((n.x - 0.01 / distance).abs() < 1e-12);
        let after = system
            .contact_frame(&u, &centre, 24.0, TrackPart::JointAfter(0))
            .expect("frame");
        let to_far = (centre - Vector2::new(24.05, 0.0)).norm();
        assert!((after.gap(&system.beam, 0.3, &centre) - (to_far - 0.9)).abs() < 1e-12);
    }
}
