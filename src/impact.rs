//! Impacts at landing: Newton's restitution law at the velocity level.
//!
//! At the instant a contact lands, the velocities jump under impulses P on
//! the rows of the contacts that take part (tangential for wheels, normal
//! for all): Δe = W P with W = Σ r_body M_b⁻¹ r_bodyᵀ + r_beam M⁻¹ r_beamᵀ
//! the impulsive Delassus operator of bodies and beam, the limit of the
//! iteration's operator for a vanishing step. The positions do not move;
//! the kinetic energy the impulses remove is returned as the impact's loss.

use nalgebra::{DMatrix, DVector, Vector2, Vector3};

use crate::contact::ContactFrame;
use crate::integrate::DynamicState;
use crate::system::System;

/// Result of one impact.
#[derive(Debug, Clone, PartialEq)]
pub struct Impact {
    /// Per contact, the impulse on its body in the contact frame (N s):
    /// tangential, normal (zero for contacts that took no part).
    pub impulses: Vec<Vector2<f64>>,
    /// Kinetic energy of bodies and beam the impact removed (J).
    pub loss: f64,
}

/// One row's unit impulse: the body's change of (ẋ, ẏ, θ̇) and the beam's
/// change of velocity.
struct Response {
    /// The row in the stacked rows of `System::row_offsets`.
    row: usize,
    contact: usize,
    kind: usize,
    body: Vector3<f64>,
    beam: Option<DVector<f64>>,
}

/// The kinds of a contact's rows: 0 tangential, 1 normal.
fn kinds(rolls: bool) -> &'static [usize] {
    if rolls {
        &[0, 1]
    } else {
        &[1]
    }
}

/// Apply the impulses that change the velocity errors of the `active`
/// contacts' rows by `change` (stacked as `System::row_offsets`; other rows
/// keep their errors) to `state`, whose contact frames are `frames`.
pub fn resolve(
    system: &System,
    frames: &[ContactFrame],
    active: &[bool],
    change: &DVector<f64>,
    state: &mut DynamicState,
) -> Result<Impact, String> {
    let responses = unit_responses(system, frames, active);
    let w = delassus(system, frames, &responses);
    let rhs = DVector::from_iterator(responses.len(), responses.iter().map(|r| change[r.row]));
    let impulses = w
        .lu()
        .solve(&rhs)
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .ok_or("the impact's Delassus operator is singular")?;
    let before = kinetic_energy(system, state);
    apply(system, &responses, &impulses, state);
    let loss = before - kinetic_energy(system, state);
    let mut per_contact = vec![Vector2::zeros(); system.contacts.len()];
    for (r, p) in responses.iter().zip(impulses.iter()) {
        per_contact[r.contact][r.kind] = *p;
    }
    Ok(Impact {
        impulses: per_contact,
        loss,
    })
}

/// The response to a unit impulse on each row of each active contact.
fn unit_responses(system: &System, frames: &[ContactFrame], active: &[bool]) -> Vec<Response> {
    let mut responses = Vec::new();
    let (offsets, _) = system.row_offsets();
    for (c, contact) in system.contacts.iter().enumerate() {
        if !active[c] {
            continue;
        }
        let frame = &frames[c];
        let body = &system.bodies[contact.body];
        let body_rows = frame.body_rows(contact.radius());
        let beam_rows = frame.beam_rows(system.beam.surface_offset);
        for (k, &kind) in kinds(contact.rolls()).iter().enumerate() {
            let (body_row, beam_row) = if kind == 0 {
                (body_rows.0, beam_rows.0)
            } else {
                (body_rows.1, beam_rows.1)
            };
            // The beam takes the opposite impulse.
            let beam = frame.on_beam.then(|| {
                let mut load = DVector::zeros(system.beam.free_dofs());
                frame.shape.scatter(&beam_row, -1.0, &mut load);
                system.beam.solve_mass(&mut load);
                load
            });
            responses.push(Response {
                row: offsets[c] + k,
                contact: c,
                kind,
                body: body.acceleration(&body_row),
                beam,
            });
        }
    }
    responses
}

/// The row's velocity error e = rim velocity − surface velocity changed by
/// a response.
fn error_change(
    system: &System,
    frames: &[ContactFrame],
    row: (usize, usize),
    r: &Response,
) -> f64 {
    let (c, kind) = row;
    let contact = &system.contacts[c];
    let frame = &frames[c];
    let body_rows = frame.body_rows(contact.radius());
    let body_row = if kind == 0 { body_rows.0 } else { body_rows.1 };
    let mut change = 0.0;
    if system.contacts[r.contact].body == contact.body {
        change += body_row.dot(&r.body);
    }
    if let (true, Some(beam)) = (frame.on_beam, &r.beam) {
        let (t, n) = frame.beam_rows(system.beam.surface_offset);
        change -= frame.shape.dot(if kind == 0 { &t } else { &n }, beam);
    }
    change
}

/// W over the active rows: column j is the change of every row's error
/// under row j's unit impulse.
fn delassus(system: &System, frames: &[ContactFrame], responses: &[Response]) -> DMatrix<f64> {
    let n = responses.len();
    DMatrix::from_fn(n, n, |i, j| {
        let row = (responses[i].contact, responses[i].kind);
        error_change(system, frames, row, &responses[j])
    })
}

fn apply(
    system: &System,
    responses: &[Response],
    impulses: &DVector<f64>,
    state: &mut DynamicState,
) {
    for (r, &p) in responses.iter().zip(impulses.iter()) {
        let b = system.contacts[r.contact].body;
        let body = &mut state.bodies[b];
        body.velocity += p * r.body.xy();
        body.angular_velocity += p * r.body.z;
        if let Some(beam) = &r.beam {
            state.beam_velocity.axpy(p, beam, 1.0);
        }
    }
}

/// Kinetic energy of the bodies and the beam (J).
pub fn kinetic_energy(system: &System, state: &DynamicState) -> f64 {
    let bodies: f64 = system
        .bodies
        .iter()
        .zip(&state.bodies)
        .map(|(body, s)| body.kinetic_energy(s))
        .sum();
    bodies + system.beam.kinetic_energy(&state.beam_velocity)
}
