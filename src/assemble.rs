//! From a scene to the mechanical system and its initial state: the bodies,
//! force elements and contacts, where they start and the contact forces the
//! first step's iteration starts from.

use nalgebra::{Vector2, Vector3};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactForce, ContactKind};
use crate::scene::{BodyKind, BodySpec, Scene};
use crate::system::{System, Track};

/// The system a scene asks for, where everything starts, the static
/// contact forces (the first guesses) and the applied force on each body.
pub struct Assembly {
    pub system: System,
    pub bodies: Vec<BodyState>,
    pub forces: Vec<ContactForce>,
    /// Index of the body that receives the scene's applied force (the FMU's
    /// force inputs).
    pub driven_body: usize,
}

/// A single `[body]`: a one-body vehicle with one contact.
fn single_body(spec: &BodySpec, beam: &Beam) -> (RigidBody, Contact, BodyState) {
    let (inertia, kind) = match spec.kind {
        BodyKind::Wheel => (
            spec.inertia.unwrap_or(0.0),
            ContactKind::Wheel {
                radius: spec.radius.unwrap_or(0.0),
            },
        ),
        BodyKind::Glider => (0.0, ContactKind::Glider),
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

pub fn assemble(scene: &Scene) -> Result<Assembly, String> {
    let beam = Beam::new(&scene.beam)?;
    let (body, contact, state) = single_body(&scene.body, &beam);
    // The normal force balances the applied force.
    let forces = vec![ContactForce {
        tangential: 0.0,
        normal: -scene.body.force_y,
    }];
    let system = System {
        beam,
        track: Track::default(),
        bodies: vec![body],
        force_elements: Vec::new(),
        contacts: vec![contact],
        gravity: 0.0,
    };
    Ok(Assembly {
        system,
        bodies: vec![state],
        forces,
        driven_body: 0,
    })
}

/// The constant generalized force on each body: its weight, plus the
/// applied force (fx, fy) on the driven body.
pub fn constant_forces(system: &System, driven: usize, applied: [f64; 2]) -> Vec<Vector3<f64>> {
    system
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let weight = Vector3::new(0.0, -body.mass * system.gravity, 0.0);
            if b == driven {
                weight + Vector3::new(applied[0], applied[1], 0.0)
            } else {
                weight
            }
        })
        .collect()
}
