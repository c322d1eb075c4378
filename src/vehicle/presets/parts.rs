//! The parts the presets build vehicles from: one contact body on the
//! track, a suspension with its guide, and the `Vehicle` they make.

use nalgebra::Vector2;

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactKind};
use crate::force_element::{Direction, ForceElement};
use crate::scene::BodySpec;

/// Bodies, contacts and force elements of one vehicle, and where its
/// bodies start; body indices are the vehicle's own.
pub struct Vehicle {
    pub bodies: Vec<RigidBody>,
    pub contacts: Vec<Contact>,
    pub force_elements: Vec<ForceElement>,
    pub states: Vec<BodyState>,
}

impl Vehicle {
    /// A one-body vehicle with one contact.
    pub(super) fn single((body, contact, state): (RigidBody, Contact, BodyState)) -> Vehicle {
        Vehicle {
            bodies: vec![body],
            contacts: vec![contact],
            force_elements: Vec::new(),
            states: vec![state],
        }
    }
}

/// Longitudinal stiffness of a suspension's guide, per unit of its vertical
/// stiffness: it keeps the unsprung glider under the sprung mass (a glider
/// alone drifts with the horizontal part of its normal force).
pub const GUIDE_STIFFNESS_RATIO: f64 = 100.0;

/// A contact body of `spec`'s mass at its `initial_position` on the track:
/// a wheel (`ContactKind::Wheel`, rolling at the travel speed) or a glider,
/// with one contact named `contact`.
pub(super) fn contact_body(
    spec: &BodySpec,
    beam: &Beam,
    inertia: f64,
    kind: ContactKind,
) -> (RigidBody, Contact, BodyState) {
    let body = RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia,
        drive: None,
    };
    let contact = Contact {
        name: "contact".into(),
        body: 0,
        kind,
        follower: None,
    };
    let radius = contact.radius();
    let rolls = contact.rolls();
    let state = BodyState {
        position: Vector2::new(spec.initial_position, radius + beam.surface_offset),
        velocity: Vector2::new(spec.initial_speed, 0.0),
        angle: 0.0,
        angular_velocity: if rolls && radius > 0.0 {
            -spec.initial_speed / radius
        } else {
            0.0
        },
    };
    (body, contact, state)
}

/// A glider of `spec` moved `dx` along the track.
pub(super) fn glider_at(spec: &BodySpec, beam: &Beam, dx: f64) -> (RigidBody, Contact, BodyState) {
    let mut s = spec.clone();
    s.initial_position += dx;
    contact_body(&s, beam, 0.0, ContactKind::Glider)
}

/// A vertical spring–damper and a stiff longitudinal guide between point
/// `point_a` of body a (above) and the centre of body b, preloaded with
/// `load`; the rest separations are those of the initial states.
#[allow(clippy::too_many_arguments)]
pub(super) fn suspension(
    name: &str,
    (a, point_a): (usize, f64),
    b: usize,
    stiffness: f64,
    damping: f64,
    load: f64,
    states: &[BodyState],
    out: &mut Vec<ForceElement>,
) {
    for (suffix, direction, k, c, preload) in [
        ("", Direction::Vertical, stiffness, damping, load),
        (
            "_guide",
            Direction::Longitudinal,
            GUIDE_STIFFNESS_RATIO * stiffness,
            0.0,
            0.0,
        ),
    ] {
        let mut element = ForceElement {
            name: format!("{name}{suffix}"),
            body_a: a,
            point_a: Vector2::new(point_a, 0.0),
            body_b: b,
            point_b: Vector2::zeros(),
            direction,
            stiffness: k,
            damping: c,
            preload,
            rest: 0.0,
        };
        element.rest = element.separation(&states[a], &states[b]);
        out.push(element);
    }
}
