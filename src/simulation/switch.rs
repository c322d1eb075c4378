//! What follows a contact's switch to another surface of the track: the
//! impact where its velocity jumps (the far corner of a rail gap), and the
//! implicit scheme's restart.
//!
//! HHT-α carries the last step's accelerations and loads into the next
//! step. Where a contact switches surfaces (a beam's end corner at a rail
//! joint, the far corner, the next span, the run-off's corner) its path's
//! curvature jumps and so do the force and the accelerations: a wheel that
//! starts turning about a corner at speed v needs m v²/(r + h) less normal
//! force at once. Carried over, the old acceleration makes the trapezoidal
//! rule overshoot the new one by as much again: the force alternates from
//! step to step about its true value (undamped for α = 0), and turns
//! tensile where the jump exceeds half the load. So at such an event the
//! scheme restarts as it starts at t = 0, from loads and accelerations
//! consistent with one force p; p is the fixed point of "take a step from
//! p, end at p₁": the step's mean acceleration is that of p + w (p₁ − p),
//! w = (1 + α) γ, so that update finds it in two or three steps (one, if
//! the step were linear in p).

use nalgebra::Vector3;

use super::{JointImpact, Simulation, SolverError, MAX_EVENTS};
use crate::contact::ContactForce;
use crate::integrate::{contact_frames, loads, DynamicState, IntegrationError};
use crate::system::{System, TrackPart};

/// Trial steps of a restart at most.
const RESTART_PASSES: usize = 6;
/// A restart is done when no force changes by more than this fraction of
/// the largest.
const RESTART_TOLERANCE: f64 = 1e-9;

impl Simulation {
    /// After the track events of the step just taken (the contacts were on
    /// `before`): the impact of a velocity jump at the located contact,
    /// then, for the implicit scheme, the restart of every body whose
    /// contact switched.
    pub(super) fn after_switch(
        &mut self,
        located: usize,
        before: &[TrackPart],
    ) -> Result<(), SolverError> {
        let now = self.state.parts[located];
        if self.system.velocity_jump(before[located], now) {
            self.joint_impact(located)?;
        }
        if let Some(weight) = self.restart_weight {
            self.restart_switched(before, weight)?;
        }
        Ok(())
    }

    /// The velocity jump of a contact switching from one corner of a rail
    /// gap to the other (or from a joint onto a concave kink): a plastic
    /// impact (Newton's law with e = 0 on the normal row, the no-slip row
    /// brought to zero; the other closed contacts keep their velocity
    /// errors), the positions unchanged. The impulse is recorded
    /// (`joint_impacts`, and the contact's `impact_impulse` outputs); its
    /// loss enters `energy.impact_loss`.
    fn joint_impact(&mut self, contact: usize) -> Result<(), SolverError> {
        use crate::impact::Part;
        let follower = |d: usize| self.system.contacts[d].follower.is_some();
        // A follower has no mass to take an impulse: its law follows the
        // new surface.
        if self.state.contacts[contact].open || follower(contact) {
            return Ok(());
        }
        let frames = self.frames_now()?;
        let grid = self.state.grid_step;
        // The switching contact meets its new corner plastically; the other
        // closed ones keep their velocity errors with a compressive impulse
        // (held bilateral if they opened in this grid step already, as at
        // a landing), or leave the track.
        let parts: Vec<Part> = (self.state.contacts.iter().enumerate())
            .map(|(d, status)| match () {
                _ if d == contact => Part::Landing(0.0),
                _ if status.open || follower(d) => Part::Out,
                _ if status.opened_in == Some(grid) => Part::Held,
                _ => Part::Closed,
            })
            .collect();
        let impact = crate::impact::resolve(&self.system, &frames, &parts, &mut self.state.dynamic)
            .map_err(|message| SolverError {
                time: self.state.time,
                message,
            })?;
        for (d, &part) in parts.iter().enumerate() {
            if part == Part::Closed && d != contact {
                self.leave_at_impact(d, impact.separation[d]);
            }
        }
        self.state.impact_loss += impact.loss;
        let impulse = impact.impulses[contact];
        self.state.contacts[contact].impulse = [impulse.x, impulse.y];
        if self.joint_impacts.len() < MAX_EVENTS {
            self.joint_impacts.push(JointImpact {
                time: self.state.time,
                contact,
                impulse,
            });
        }
        Ok(())
    }

    /// The implicit scheme restarts every closed contact on the bodies
    /// whose contacts switched surfaces (the other contacts' forces held):
    /// see the module's comment.
    fn restart_switched(&mut self, before: &[TrackPart], weight: f64) -> Result<(), SolverError> {
        let switched_bodies: Vec<usize> = (0..before.len())
            .filter(|&c| before[c] != self.state.parts[c] && !self.state.contacts[c].open)
            .map(|c| self.system.contacts[c].body)
            .collect();
        if switched_bodies.is_empty() || self.state.exit_time.is_some() {
            return Ok(());
        }
        let restarted: Vec<bool> = self
            .system
            .contacts
            .iter()
            .zip(&self.state.contacts)
            .map(|(c, s)| !s.open && switched_bodies.contains(&c.body))
            .collect();
        let mut forces: Vec<_> = self.state.force_history.iter().map(|h| h[0]).collect();
        for _ in 0..RESTART_PASSES {
            self.restart_from(&forces, &restarted)?;
            let trial = self.solve(&forces, self.step)?;
            let scale = forces
                .iter()
                .map(|f| f.as_vector().norm())
                .fold(0.0, f64::max);
            let mut change = 0.0f64;
            for c in (0..forces.len()).filter(|&c| restarted[c]) {
                let (p, p1) = (forces[c].as_vector(), trial.forces[c].as_vector());
                let mut mean = ContactForce::from_vector(p + weight * (p1 - p));
                // A pulling mean: the contact lifts off in the next step.
                mean.normal = mean.normal.max(0.0);
                change = change.max((mean.as_vector() - p).norm());
                forces[c] = mean;
            }
            if change <= RESTART_TOLERANCE * scale {
                break;
            }
        }
        self.restart_from(&forces, &restarted)
    }

    /// The constant forces on the bodies in the last step.
    fn applied_now(&self) -> Vec<nalgebra::Vector3<f64>> {
        match self.state.last_applied.len() {
            0 => self.constant_forces(),
            _ => self.state.last_applied.clone(),
        }
    }

    /// Loads and accelerations of `forces` into the state, and a constant
    /// force history of the `restarted` contacts (the next step's guess).
    fn restart_from(
        &mut self,
        forces: &[ContactForce],
        restarted: &[bool],
    ) -> Result<(), SolverError> {
        let applied = self.applied_now();
        let (system, parts) = (&self.system, &self.state.parts);
        consistent_start(system, parts, &applied, forces, &mut self.state.dynamic).map_err(
            |e| SolverError {
                time: self.state.time,
                message: crate::iteration::StepError::from(e).to_string(),
            },
        )?;
        for (c, force) in forces.iter().enumerate() {
            if restarted[c] {
                self.state.force_history[c] = [*force; 3];
            }
        }
        Ok(())
    }
}

/// The loads of `forces` (with the constant `applied` forces and the force
/// elements) and the accelerations they give, into `state`: what the
/// implicit scheme starts a step from.
fn consistent_start(
    system: &System,
    parts: &[TrackPart],
    applied: &[Vector3<f64>],
    forces: &[ContactForce],
    state: &mut DynamicState,
) -> Result<(), IntegrationError> {
    let mut frames = Vec::new();
    let (u, v) = (&state.beam_displacement, &state.beam_velocity);
    let located = (state.contact_x.as_slice(), parts);
    contact_frames(system, u, &state.bodies, located, &mut frames)?;
    loads(
        system,
        &frames,
        forces,
        applied,
        &state.bodies,
        &state.beam_velocity,
        &mut state.beam_load,
        &mut state.body_loads,
    );
    system
        .beam
        .accelerations((u, v), &state.beam_load, &mut state.beam_acceleration);
    for ((a, body), load) in state
        .body_accelerations
        .iter_mut()
        .zip(&system.bodies)
        .zip(&state.body_loads)
    {
        *a = body.acceleration(load);
    }
    Ok(())
}
