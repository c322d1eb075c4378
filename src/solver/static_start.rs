//! The static start (`solver.start = "static"`): the beam deflected under
//! the vehicles' weight (K u = f), the contact bodies on its deflected
//! surface, and every force element at its preload, so that the vehicles
//! start in equilibrium.
//!
//! The contact forces, the deflection and the contact bodies' heights depend
//! on each other only through the small slope of the beam, so a fixed-point
//! iteration converges to round-off in a few passes. The suspensions keep
//! their preloads: each element's rest separation is reset to the one of the
//! start, which is how far the suspension is compressed at equilibrium.
//! A glider on a sloped surface feels the horizontal part of its normal
//! force; it is carried by preloading the longitudinal elements, in their
//! order (leaves first: wheelset guides, then bogie guides).
//! A massless follower's body is set at its suspension's rest above the
//! deflected surface, where the follower carries its preload, the body's
//! weight; the beam deflects under it like under any contact force.
//! A follower attached off its body's centre (a bogie's axle, a car body's
//! magnet station) does not move its body, which several of them hold:
//! like a force element, its rest becomes its start gap, and its preload
//! is set so that its vertical part is the load it was built to carry.
//! A contact body with mass on a compliant law is set at its law's rest,
//! and the law's preload becomes what the body's equilibrium needs.

use nalgebra::{DVector, Vector3};

use crate::body::BodyState;
use crate::contact::{ContactForce, ContactFrame};
use crate::force_element::Direction;
use crate::integrate::{contact_frames_at_bodies, loads};
use crate::system::System;

/// Passes of the fixed-point iteration; each shrinks the error by about the
/// square of the beam's slope, so a few reach round-off.
const PASSES: usize = 8;

/// Deflect the beam, move the contact bodies onto it and set the contact
/// forces and the elements' rests and longitudinal preloads. Returns u.
pub fn static_start(
    system: &mut System,
    bodies: &mut [BodyState],
    forces: &mut [ContactForce],
    applied: &[Vector3<f64>],
) -> Result<DVector<f64>, String> {
    let n = system.beam.coordinates();
    let mut u = DVector::zeros(n);
    let mut work = Work {
        at_rest: DVector::zeros(n),
        frames: Vec::new(),
        beam_load: DVector::zeros(n),
        body_loads: vec![Vector3::zeros(); bodies.len()],
    };
    let carried: Vec<f64> = system
        .contacts
        .iter()
        .map(|c| c.follower.map_or(0.0, |f| f.preload))
        .collect();
    for _ in 0..PASSES {
        u = one_pass(system, (bodies, forces, applied), &u, &carried, &mut work)?;
    }
    let Work { frames, .. } = &mut work;
    locate(system, &u, bodies, frames)?;
    settle_on_surface(system, bodies, frames);
    follow_surface(system, bodies, frames);
    reset_rests(system, bodies);
    rest_attached_followers(system, bodies, frames, &carried);
    work.loads(system, forces, applied, bodies);
    balance_horizontally(system, &mut work.body_loads);
    Ok(u)
}

/// The static start's vectors, kept from pass to pass.
struct Work {
    /// The beam's velocity (zero: at rest) that a follower's law reads.
    at_rest: DVector<f64>,
    frames: Vec<ContactFrame>,
    beam_load: DVector<f64>,
    body_loads: Vec<Vector3<f64>>,
}

impl Work {
    /// Every load for the contact `forces` at the frames.
    fn loads(
        &mut self,
        system: &System,
        forces: &[ContactForce],
        applied: &[Vector3<f64>],
        bodies: &[BodyState],
    ) {
        let (beam_load, body_loads) = (&mut self.beam_load, &mut self.body_loads);
        let (frames, at_rest) = (&self.frames, &self.at_rest);
        loads(
            system, frames, forces, applied, bodies, at_rest, beam_load, body_loads,
        );
    }
}

/// One pass of the fixed-point iteration from the deflection `u`: the
/// bodies onto the surface, the forces that carry them, and the beam's
/// deflection under those forces (returned).
fn one_pass(
    system: &mut System,
    (bodies, forces, applied): (&mut [BodyState], &mut [ContactForce], &[Vector3<f64>]),
    u: &DVector<f64>,
    carried: &[f64],
    work: &mut Work,
) -> Result<DVector<f64>, String> {
    locate(system, u, bodies, &mut work.frames)?;
    settle_on_surface(system, bodies, &work.frames);
    reset_rests(system, bodies);
    rest_attached_followers(system, bodies, &work.frames, carried);
    let free = vec![ContactForce::default(); forces.len()];
    work.loads(system, &free, applied, bodies);
    preload_compliant_contacts(system, &work.frames, &work.body_loads);
    carry_loads(system, &work.frames, &work.body_loads, forces);
    work.loads(system, forces, applied, bodies);
    system.beam.static_deflection(&work.beam_load)
}

/// A start at rest on a track with irregularities: each contact body moved
/// vertically onto the profile at its abscissa and moving along it (a jump
/// across it would need an impulse), the force elements at their preloads.
pub fn place_on_profile(
    system: &mut System,
    bodies: &mut [BodyState],
    u: &DVector<f64>,
) -> Result<(), String> {
    let mut frames = Vec::new();
    // The foot point moves with the body's height by the profile's slope:
    // a second pass settles that.
    for _ in 0..2 {
        contact_frames_at_bodies(system, u, bodies, &mut frames)
            .map_err(|_| "a contact point lies off the track at the start".to_string())?;
        settle_on_surface(system, bodies, &frames);
    }
    follow_surface(system, bodies, &frames);
    reset_rests(system, bodies);
    Ok(())
}

fn locate(
    system: &System,
    u: &DVector<f64>,
    bodies: &[BodyState],
    frames: &mut Vec<ContactFrame>,
) -> Result<(), String> {
    contact_frames_at_bodies(system, u, bodies, frames)
        .map_err(|_| "solver.start = \"static\": a contact point lies off the track".to_string())
}

/// Move each contact body vertically so that its gap is zero (a
/// follower's body: so that its suspension is at rest).
fn settle_on_surface(system: &System, bodies: &mut [BodyState], frames: &[ContactFrame]) {
    for (contact, frame) in system.contacts.iter().zip(frames) {
        if contact.is_attached() {
            continue;
        }
        let body = &mut bodies[contact.body];
        let rest = contact.follower.map_or(0.0, |f| f.rest);
        let gap = frame.gap(&system.beam, contact.radius(), &body.position) - rest;
        body.position.y -= gap / frame.normal().y;
    }
}

/// A moving contact body starts along the deflected surface (its normal
/// velocity error zero), not across it: a jump would need an impulse.
fn follow_surface(system: &System, bodies: &mut [BodyState], frames: &[ContactFrame]) {
    for (contact, frame) in system.contacts.iter().zip(frames) {
        if contact.is_attached() {
            continue;
        }
        let body = &mut bodies[contact.body];
        body.velocity.y = body.velocity.x * frame.sin / frame.cos;
    }
}

/// Each attached follower at its preload where it stands: its rest the
/// gap there, its preload the vertical load `carried` (its preload as
/// built) over the normal's vertical part, so that the body's vertical
/// forces and torques balance exactly as over wheelsets with mass.
fn rest_attached_followers(
    system: &mut System,
    bodies: &[BodyState],
    frames: &[ContactFrame],
    carried: &[f64],
) {
    let beam = &system.beam;
    for ((contact, frame), &load) in system.contacts.iter_mut().zip(frames).zip(carried) {
        if !contact.is_attached() {
            continue;
        }
        let point = contact.point(&bodies[contact.body]);
        let gap = frame.gap(beam, 0.0, &point.position);
        if let Some(follower) = contact.follower.as_mut() {
            follower.rest = gap;
            follower.preload = load / frame.normal().y;
        }
    }
}

/// A contact body with mass on a compliant law (`contact_law`) carries
/// what its body needs: its preload (the force at its rest gap, where
/// `settle_on_surface` put it) corrected by the vertical load left on the
/// body, over the normal's vertical part.
fn preload_compliant_contacts(
    system: &mut System,
    frames: &[ContactFrame],
    body_loads: &[Vector3<f64>],
) {
    for (contact, frame) in system.contacts.iter_mut().zip(frames) {
        let body = contact.body;
        let attached = contact.is_attached();
        let Some(follower) = contact.follower.as_mut() else {
            continue;
        };
        if attached || follower.kind == crate::contact_law::LawKind::Suspension {
            continue;
        }
        follower.preload -= body_loads[body].y / frame.normal().y;
        follower.kind = follower.kind.at_preload(follower.preload);
    }
}

/// Every element at its preload in the current configuration.
fn reset_rests(system: &mut System, bodies: &[BodyState]) {
    system.force_elements.update(|elements| {
        for element in elements {
            element.rest = element.separation(&bodies[element.body_a], &bodies[element.body_b]);
        }
    });
}

/// The normal forces that carry each contact body's vertical load
/// `body_loads` (computed without contact forces); the horizontal rest is
/// left to `balance_horizontally` (a wheel gets no tangential force, which
/// would turn it).
fn carry_loads(
    system: &System,
    frames: &[ContactFrame],
    body_loads: &[Vector3<f64>],
    forces: &mut [ContactForce],
) {
    for ((contact, frame), force) in system.contacts.iter().zip(frames).zip(forces) {
        // A follower's force is its suspension's, already in `body_loads`:
        // settled at its rest, the preload.
        let normal = match contact.follower {
            Some(follower) => follower.preload,
            None => -body_loads[contact.body].y / frame.normal().y,
        };
        *force = ContactForce {
            tangential: 0.0,
            normal,
        };
    }
}

/// Preload the longitudinal elements, in order, so that the horizontal
/// force left on each element's body b passes on to its body a.
fn balance_horizontally(system: &mut System, body_loads: &mut [Vector3<f64>]) {
    system.force_elements.update(|elements| {
        for element in elements {
            if element.direction != Direction::Longitudinal {
                continue;
            }
            let residual = body_loads[element.body_b].x;
            element.preload += residual;
            body_loads[element.body_a].x += residual;
            body_loads[element.body_b].x = 0.0;
        }
    });
}
