//! Impacts at landing: Newton's restitution law at the velocity level.
//!
//! At the instant a contact lands, the velocities jump under impulses P on
//! the rows of the contacts that take part (tangential for wheels, normal
//! for all): Δe = W P with W = Σ r_body M_b⁻¹ r_bodyᵀ + r_beam M⁻¹ r_beamᵀ
//! the impulsive Delassus operator of bodies and beam, the limit of the
//! iteration's operator for a vanishing step. The landing contacts' normal
//! errors become −e times their approach, the closed contacts' stay, each
//! with a compressive normal impulse, or else the contact leaves the track
//! with none: a linear complementarity problem over all of them
//! (`crate::complementarity`). The positions do not move; the kinetic
//! energy the impulses remove is returned as the impact's loss.

use nalgebra::{DMatrix, DVector, Vector2, Vector3};

use crate::complementarity::{self, Row};
use crate::contact::ContactFrame;
use crate::integrate::DynamicState;
use crate::system::System;

/// How a contact takes part in an impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Part {
    /// Open and not landing: no impulse.
    Out,
    /// Landing with Newton's coefficient e: its normal velocity error
    /// becomes −e times its approach with a compressive impulse, or more
    /// with none.
    Landing(f64),
    /// Closed: its normal velocity error kept with a compressive impulse,
    /// or growing (it leaves the track) with none.
    Closed,
    /// Held closed (bilateral): its normal error kept, the impulse of
    /// either sign.
    Held,
}

/// Result of one impact.
#[derive(Debug, Clone, PartialEq)]
pub struct Impact {
    /// Per contact, the impulse on its body in the contact frame (N s):
    /// tangential, normal (zero for contacts that took no part).
    pub impulses: Vec<Vector2<f64>>,
    /// Kinetic energy of bodies and beam the impact removed (J).
    pub loss: f64,
    /// Per contact, the speed (m/s) at which it leaves the track: its
    /// normal velocity beyond what the law asks, with no normal impulse;
    /// zero where it keeps (or took no) part.
    pub separation: Vec<f64>,
}

/// One row's unit impulse: the body's change of (ẋ, ẏ, θ̇) and the beam's
/// change of velocity.
struct Response {
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

/// The impact of the contacts taking part as `parts` says in `state`, whose
/// contact frames are `frames`: every wheel's no-slip row an equality (its
/// tangential error zeroed when landing, kept when closed: a wheel that
/// leaves in the impact leaves rolling, the limit of Coulomb friction as
/// μ → ∞; no sliding friction is modelled), every normal row unilateral
/// but a held one's. Applies the impulses to `state`.
pub fn resolve(
    system: &System,
    frames: &[ContactFrame],
    parts: &[Part],
    state: &mut DynamicState,
) -> Result<Impact, String> {
    let active: Vec<bool> = parts.iter().map(|&p| p != Part::Out).collect();
    let responses = unit_responses(system, frames, &active);
    let w = delassus(system, frames, &responses);
    let (b, rows) = targets(system, frames, parts, state, &responses);
    let solution = complementarity::solve(&w, &b, &rows)?;
    let before = kinetic_energy(system, state);
    apply(system, &responses, &solution.p, state);
    let loss = before - kinetic_energy(system, state);
    let n = system.contacts.len();
    let mut per_contact = vec![Vector2::zeros(); n];
    let mut separation = vec![0.0; n];
    for (i, r) in responses.iter().enumerate() {
        per_contact[r.contact][r.kind] = solution.p[i];
        if r.kind == 1 && !solution.held[i] {
            separation[r.contact] = solution.w[i].max(0.0);
        }
    }
    Ok(Impact {
        impulses: per_contact,
        loss,
        separation,
    })
}

/// The change b each row's velocity error must make (at least, on a
/// unilateral row) and how the row is held.
fn targets(
    system: &System,
    frames: &[ContactFrame],
    parts: &[Part],
    state: &DynamicState,
    responses: &[Response],
) -> (DVector<f64>, Vec<Row>) {
    let mut b = DVector::zeros(responses.len());
    let mut rows = Vec::with_capacity(responses.len());
    for (i, r) in responses.iter().enumerate() {
        let contact = &system.contacts[r.contact];
        let body = &state.bodies[contact.body];
        let error = frames[r.contact].velocity_error(
            &system.beam,
            contact.radius(),
            body,
            &state.beam_velocity,
        );
        let part = parts[r.contact];
        b[i] = match (part, r.kind) {
            (Part::Landing(_), 0) => -error.x,
            (Part::Landing(e), _) => -(1.0 + e) * error.y.min(0.0),
            _ => 0.0,
        };
        rows.push(if r.kind == 0 || part == Part::Held {
            Row::Equality
        } else {
            Row::Unilateral
        });
    }
    (b, rows)
}

/// The response to a unit impulse on each row of each active contact.
fn unit_responses(system: &System, frames: &[ContactFrame], active: &[bool]) -> Vec<Response> {
    let mut responses = Vec::new();
    for (c, contact) in system.contacts.iter().enumerate() {
        if !active[c] {
            continue;
        }
        let frame = &frames[c];
        let body = &system.bodies[contact.body];
        let body_rows = frame.body_rows(contact.radius());
        let beam_rows = frame.beam_rows(system.beam.surface_offset);
        for &kind in kinds(contact.rolls()) {
            let (body_row, beam_row) = if kind == 0 {
                (body_rows.0, beam_rows.0)
            } else {
                (body_rows.1, beam_rows.1)
            };
            // The beam takes the opposite impulse.
            let beam = frame.on_beam.then(|| {
                let mut load = DVector::zeros(system.beam.coordinates());
                system
                    .beam
                    .scatter(&frame.shape, &beam_row, -1.0, &mut load);
                system.beam.solve_mass(&mut load);
                load
            });
            responses.push(Response {
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
        let row = if kind == 0 { &t } else { &n };
        change -= system.beam.dot(&frame.shape, row, beam);
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
