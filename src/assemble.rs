//! From a scene to the mechanical system and its initial state: the bodies,
//! force elements and contacts, where they start and the contact forces the
//! first step's iteration starts from.

use nalgebra::{Vector2, Vector3};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactForce, ContactKind};
use crate::force_element::{Direction, ForceElement};
use crate::scene::{BodyKind, BodySpec, Scene, SuspensionSpec};
use crate::system::{System, Track};

/// The system a scene asks for, where everything starts, the static
/// contact forces (the first guesses) and the applied force on each body.
pub struct Assembly {
    pub system: System,
    pub bodies: Vec<BodyState>,
    pub forces: Vec<ContactForce>,
    /// The first body of each vehicle and the constant force (fx, fy) on it
    /// (the first is the driven body: the FMU's force inputs act on it).
    pub vehicle_forces: Vec<(usize, [f64; 2])>,
}

/// The first body of each of the `count` vehicles: the body of each
/// vehicle's first contact for wheels and gliders, the sprung body before it
/// for a sprung mass.
fn first_bodies(system: &System, count: usize) -> Vec<usize> {
    let mut firsts = Vec::with_capacity(count);
    let mut next = 0;
    for contact in &system.contacts {
        firsts.push(next);
        next = contact.body + 1;
    }
    firsts
}

/// Height of a sprung mass's centre above its unsprung mass at rest (m):
/// only differences of heights enter the model.
pub const SPRUNG_HEIGHT: f64 = 1.0;

/// Longitudinal stiffness of a sprung mass's guide, per unit of its vertical
/// stiffness: it keeps the unsprung glider under the sprung mass (a glider
/// alone drifts with the horizontal part of its normal force).
pub const GUIDE_STIFFNESS_RATIO: f64 = 100.0;

/// A one-body vehicle: a wheel or a glider with one contact.
fn single_body(spec: &BodySpec, beam: &Beam) -> (RigidBody, Contact, BodyState) {
    let (inertia, kind) = match spec.kind {
        BodyKind::Wheel => (
            spec.inertia.unwrap_or(0.0),
            ContactKind::Wheel {
                radius: spec.radius.unwrap_or(0.0),
            },
        ),
        BodyKind::Glider | BodyKind::SprungMass => (0.0, ContactKind::Glider),
    };
    let body = RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia,
    };
    let contact = Contact {
        name: "contact".into(),
        body: 0,
        kind,
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

/// The moving oscillator: body 0 the sprung mass (J = 0), body 1 the
/// unsprung glider, a vertical spring–damper preloaded with the sprung
/// weight and a stiff longitudinal guide between them.
fn sprung_mass(spec: &BodySpec, beam: &Beam, gravity: f64) -> Vehicle {
    let suspension = spec.suspension.unwrap_or(SuspensionSpec {
        stiffness: 0.0,
        damping: 0.0,
        unsprung_mass: 0.0,
    });
    let (unsprung, mut contact, contact_state) = single_body(spec, beam);
    let unsprung = RigidBody {
        name: format!("{}_unsprung", spec.name),
        mass: suspension.unsprung_mass,
        ..unsprung
    };
    contact.body = 1;
    let sprung = RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia: 0.0,
    };
    let sprung_state = BodyState {
        position: contact_state.position + Vector2::new(0.0, SPRUNG_HEIGHT),
        ..contact_state
    };
    let element = |name: &str, direction, stiffness, damping, preload, rest| ForceElement {
        name: format!("{}.{name}", spec.name),
        body_a: 0,
        point_a: Vector2::zeros(),
        body_b: 1,
        point_b: Vector2::zeros(),
        direction,
        stiffness,
        damping,
        preload,
        rest,
    };
    let force_elements = vec![
        element(
            "suspension",
            Direction::Vertical,
            suspension.stiffness,
            suspension.damping,
            spec.mass * gravity,
            SPRUNG_HEIGHT,
        ),
        element(
            "guide",
            Direction::Longitudinal,
            GUIDE_STIFFNESS_RATIO * suspension.stiffness,
            0.0,
            0.0,
            0.0,
        ),
    ];
    Vehicle {
        bodies: vec![sprung, unsprung],
        contacts: vec![contact],
        force_elements,
        states: vec![sprung_state, contact_state],
    }
}

/// Bodies, contacts and force elements of one vehicle, and where its
/// bodies start; body indices are the vehicle's own.
struct Vehicle {
    bodies: Vec<RigidBody>,
    contacts: Vec<Contact>,
    force_elements: Vec<ForceElement>,
    states: Vec<BodyState>,
}

pub fn assemble(scene: &Scene) -> Result<Assembly, String> {
    let beam = Beam::new(&scene.beam)?;
    let spec = &scene.body;
    let gravity = scene.gravity;
    let (mut forces, mut applied) = (Vec::new(), Vec::new());
    let mut system = System {
        beam,
        track: Track {
            approach: scene.track.approach,
            run_off: scene.track.run_off,
        },
        bodies: Vec::new(),
        force_elements: Vec::new(),
        contacts: Vec::new(),
        gravity,
    };
    let mut bodies = Vec::new();
    for (v, spec) in std::iter::once(spec).chain(&scene.vehicles).enumerate() {
        let mut vehicle = match spec.kind {
            BodyKind::Wheel | BodyKind::Glider => {
                let (body, contact, state) = single_body(spec, &system.beam);
                Vehicle {
                    bodies: vec![body],
                    contacts: vec![contact],
                    force_elements: Vec::new(),
                    states: vec![state],
                }
            }
            BodyKind::SprungMass => sprung_mass(spec, &system.beam, gravity),
        };
        // The first vehicle's contact keeps the name `contact` of the
        // single-body scenes; the others' are named after their vehicle.
        let offset = system.bodies.len();
        for contact in &mut vehicle.contacts {
            contact.body += offset;
            if v > 0 {
                contact.name = format!("{}_contact", spec.name);
            }
        }
        for element in &mut vehicle.force_elements {
            element.body_a += offset;
            element.body_b += offset;
        }
        // The normal force carries the vehicle's weight and balances its
        // applied force.
        let weight: f64 = vehicle.bodies.iter().map(|b| b.mass * gravity).sum();
        forces.push(ContactForce {
            tangential: 0.0,
            normal: weight - spec.force_y,
        });
        applied.push([spec.force_x, spec.force_y]);
        system.bodies.extend(vehicle.bodies);
        system.contacts.extend(vehicle.contacts);
        system.force_elements.extend(vehicle.force_elements);
        bodies.extend(vehicle.states);
    }
    let driven: Vec<usize> = first_bodies(&system, applied.len());
    Ok(Assembly {
        system,
        bodies,
        forces,
        vehicle_forces: driven.into_iter().zip(applied).collect(),
    })
}

/// The constant generalized force on each body: its weight, plus the
/// applied force (fx, fy) on the driven body and the vehicles' constant
/// forces on their first bodies (`forces`: body index, force).
pub fn constant_forces<'a>(
    system: &'a System,
    forces: &'a [(usize, [f64; 2])],
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    system.bodies.iter().enumerate().map(move |(b, body)| {
        let weight = Vector3::new(0.0, -body.mass * system.gravity, 0.0);
        match forces.iter().find(|(first, _)| *first == b) {
            Some((_, f)) => weight + Vector3::new(f[0], f[1], 0.0),
            None => weight,
        }
    })
}
