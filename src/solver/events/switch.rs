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
//! the step were linear in p). The same restart follows a lift-off
//! located inside a step (`lift_off.rs`), and a switch onto a surface the
//! contact approaches (a concave kink) is a plastic impact under HHT-α.
//! Each trial step hands its end on to the next as its first prediction,
//! and the last one its end and forces to the rest of the grid step that
//! follows (`seeds_trials`): the same steps from almost the same start.

use nalgebra::Vector3;

use crate::contact::ContactForce;
use crate::integrate::{contact_frames, loads, DynamicState, IntegrationError};
use crate::solver::stepper::{JointImpact, SolverError, Step};
use crate::system::{System, TrackPart};

impl Step<'_> {
    /// After the track events of the step just taken (the contacts were on
    /// `before`): the impact of a velocity jump at the located contact,
    /// then, for the implicit scheme, the restart of every body whose
    /// contact switched.
    pub(crate) fn after_switch(
        &mut self,
        located: usize,
        before: &[TrackPart],
    ) -> Result<(), SolverError> {
        let now = self.state.parts[located];
        let was_open: Vec<bool> = self.state.contacts.iter().map(|s| s.open).collect();
        if self.system.velocity_jump(before[located], now) || self.kink_impact(located)? {
            self.joint_impact(located)?;
        }
        // The contacts that switched, and those the impact sent away.
        let changed: Vec<usize> = (0..before.len())
            .filter(|&c| {
                before[c] != self.state.parts[c] || was_open[c] != self.state.contacts[c].open
            })
            .collect();
        self.restart(&changed, self.grid_remainder())
    }

    /// Whether the implicit scheme meets the contact's switch as an impact:
    /// the contact is closed and approaches its new surface, as over a
    /// concave kink (a beam's end sloping down into its support, onto
    /// level ground). RK4 takes the jump into the step's force; HHT-α,
    /// which carries that force into the next step, would make it
    /// alternate (and pull, for α = 0) ever after.
    pub(crate) fn kink_impact(&self, c: usize) -> Result<bool, SolverError> {
        let carries = self.work.iteration.integrator().carries_step_end();
        if !carries || self.state.contacts[c].open {
            return Ok(false);
        }
        let approach = -self.normal_velocity_error(c)?;
        Ok(approach > self.params.iteration.velocity_tolerance)
    }

    /// The velocity jump of a contact switching from one corner of a rail
    /// gap to the other (or from a joint onto a concave kink): a plastic
    /// impact (Newton's law with e = 0 on the normal row, the no-slip row
    /// brought to zero; the other closed contacts keep their velocity
    /// errors), the positions unchanged. The impulse is recorded
    /// (`joint_impacts`, and the contact's `impact_impulse` outputs); its
    /// loss enters `energy.impact_loss`.
    pub(crate) fn joint_impact(&mut self, contact: usize) -> Result<(), SolverError> {
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
        let impact = crate::impact::resolve(self.system, &frames, &parts, &mut self.state.dynamic)
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
        if self.work.joint_impacts.len() < self.params.max_events {
            self.work.joint_impacts.push(JointImpact {
                time: self.state.time,
                contact,
                impulse,
            });
        }
        Ok(())
    }

    /// The step's active set from the contacts' statuses (after an event
    /// or an impact changed them).
    pub(crate) fn sync_open(&mut self) {
        for (open, status) in self.work.open.iter_mut().zip(&self.state.contacts) {
            *open = status.open;
        }
    }

    /// HHT-α's restart where the contacts in `changed` changed state (a
    /// surface switch, an impact at it, a lift-off inside a step): loads and
    /// accelerations of the current state made those of one force per
    /// contact, zero for the open ones (by their statuses), the fixed point of
    /// the module's comment for the closed ones on the changed contacts'
    /// bodies, the others held. A no-op under RK4, which carries nothing.
    ///
    /// Any p ≥ 0 gives a consistent start; the fixed point only picks the
    /// p whose step ends at p (no alternation). So the search is bounded
    /// (`RESTART_PASSES` trial steps) and cannot make things worse: it
    /// stops at a trial step that fails or moves p more than the pass
    /// before (diverging), and then restarts from the p of the pass that
    /// moved least (at worst the held forces, which the step would have
    /// carried anyway, with the open contacts' zeroed).
    pub(crate) fn restart(&mut self, changed: &[usize], dt: f64) -> Result<(), SolverError> {
        let Some(weight) = self.work.restart_weight else {
            return Ok(());
        };
        self.sync_open();
        if changed.is_empty() || self.state.exit_time.is_some() {
            return Ok(());
        }
        let bodies: Vec<usize> = changed
            .iter()
            .map(|&c| self.system.contacts[c].body)
            .collect();
        let restarted: Vec<bool> = (self.system.contacts.iter().zip(&self.work.open))
            .map(|(c, &open)| !open && bodies.contains(&c.body))
            .collect();
        let mut forces: Vec<ContactForce> = (self.state.force_history.iter().zip(&self.work.open))
            .map(|(h, &open)| if open { ContactForce::default() } else { h[0] })
            .collect();
        if restarted.contains(&true) {
            forces = self.restart_fixed_point(forces, &restarted, weight, dt)?;
        }
        if dt < self.params.step * (1.0 - 1e-9) {
            for &c in changed {
                if !self.state.pending_restart.contains(&c) {
                    self.state.pending_restart.push(c);
                }
            }
        }
        self.restart_from(&forces, &restarted)
    }

    /// The restarts left pending by events inside the grid step just
    /// ended, now for full steps.
    pub(crate) fn restart_pending(&mut self) -> Result<(), SolverError> {
        let pending = std::mem::take(&mut self.state.pending_restart);
        if pending.is_empty() {
            return Ok(());
        }
        self.restart(&pending, self.params.step)
    }

    /// The time from now to the next grid point: the length of the step
    /// that follows an event (the grid step, from a grid point).
    pub(crate) fn grid_remainder(&self) -> f64 {
        let next = (self.state.grid_step + 1) as f64 * self.params.step;
        let remainder = next - self.state.time;
        if remainder > self.params.same_instant() {
            remainder.min(self.params.step)
        } else {
            self.params.step
        }
    }

    /// The fixed point p of "a step from p ends at p₁" for the `restarted`
    /// contacts (see `restart`): the converged p; else the update of the
    /// pass that moved p least; at a trial step that fails, the p of the
    /// last one solved (at first, the held forces). Every trial step starts
    /// from the same state with the same step length, so they share one
    /// velocity operator (built by the first that corrects).
    pub(crate) fn restart_fixed_point(
        &mut self,
        forces: Vec<ContactForce>,
        restarted: &[bool],
        weight: f64,
        dt: f64,
    ) -> Result<Vec<ContactForce>, SolverError> {
        self.work.iteration.set_open(&self.work.open);
        self.work.iteration.share_operator(true);
        let found = self.restart_passes(forces, restarted, weight, dt);
        self.work.iteration.share_operator(false);
        // The step after a restart on the grid step is a step as any
        // other (two integrations with or without its trials' end) and
        // may begin in the next call.
        if found.is_err() || self.params.is_nominal_step(dt) {
            self.work.forget_restart();
        }
        found
    }

    /// Whether the restart's trial steps of `dt` hand their ends and forces
    /// on (`Stepper::restart_guess`, `TimeIntegrator::seed_prediction`):
    /// each trial after the first starts from the state of the one before
    /// it with p moved a little, and so does the rest step after them
    /// (the rest of a grid step after an event inside it). Not on steps
    /// below half the grid step: the force such a step resolves to the
    /// velocity tolerance grows as 1/Δt (m · 1e-7 m/s / 2.5e-8 s = 5.7 kN
    /// on a 1.4 t wheelset), and taking its trial's end moved a located
    /// rest step's normal forces by 2 % within that band (measured on
    /// the rigid 8-coach bench, 2026-11-29).
    fn seeds_trials(&self, dt: f64) -> bool {
        self.work.seeds_restarts && dt >= 0.5 * self.params.step
    }

    /// The force change the contact iteration resolves on the `restarted`
    /// contacts' bodies: the one that changes the lightest one's velocity
    /// over a step of `dt` by the velocity tolerance (the beam's compliance
    /// only makes it smaller). A trial step's p₁ is no better than that.
    pub(crate) fn resolved_force(&self, restarted: &[bool], dt: f64) -> f64 {
        let lightest = (self.system.contacts.iter().zip(restarted))
            .filter(|(_, &r)| r)
            .map(|(c, _)| self.system.bodies[c.body].mass)
            .fold(f64::INFINITY, f64::min);
        self.params.iteration.velocity_tolerance * lightest / dt
    }

    /// The passes of `restart_fixed_point`. The update converges linearly
    /// (each pass moves p by a ratio ρ of the pass before, about 1e-3 on
    /// the 8-coach train), so after a pass that moved p by δ the update
    /// is within ρ δ / (1 − ρ) of the fixed point: the passes stop once
    /// that is below what a trial step resolves (`resolved_force`), which
    /// saves the last one or two of four or five passes.
    pub(crate) fn restart_passes(
        &mut self,
        mut forces: Vec<ContactForce>,
        restarted: &[bool],
        weight: f64,
        dt: f64,
    ) -> Result<Vec<ContactForce>, SolverError> {
        let resolved = self.resolved_force(restarted, dt);
        let mut solved_from = forces.clone();
        let mut least = f64::INFINITY;
        let mut guess = forces.clone();
        for _ in 0..self.params.restart_passes {
            self.restart_from(&forces, restarted)?;
            let trial = self.solve(&guess, dt);
            let Ok(trial) = trial else {
                self.work.forget_restart();
                return Ok(solved_from);
            };
            let seeds = self.seeds_trials(dt);
            if seeds {
                let end = (&self.work.scratch, dt);
                self.work
                    .iteration
                    .integrator_mut()
                    .seed_prediction(Some(end));
            }
            let scale = (forces.iter().chain(&trial.forces))
                .map(|f| f.as_vector().norm())
                .fold(0.0, f64::max);
            let mut change = 0.0f64;
            let mut next = forces.clone();
            for c in (0..forces.len()).filter(|&c| restarted[c]) {
                let (p, p1) = (forces[c].as_vector(), trial.forces[c].as_vector());
                let mut mean = ContactForce::from_vector(p + weight * (p1 - p));
                // A pulling mean: the contact lifts off in the next step.
                mean.normal = mean.normal.max(0.0);
                change = change.max((mean.as_vector() - p).norm());
                next[c] = mean;
            }
            if change >= least {
                // Diverging: the last update moved p least.
                self.work.forget_restart();
                return Ok(forces);
            }
            // The first pass has no ratio to go by.
            let ratio = change / least;
            let left = if least.is_finite() {
                ratio / (1.0 - ratio) * change
            } else {
                f64::INFINITY
            };
            least = change;
            // The next trial step starts from this one's forces (the same
            // state, p moved a little): one or two integrations, not five.
            guess.clone_from(&trial.forces);
            for c in (0..forces.len()).filter(|&c| restarted[c]) {
                guess[c] = next[c];
            }
            if seeds {
                self.work.restart_guess = Some((dt, guess.clone()));
            }
            solved_from = std::mem::replace(&mut forces, next);
            if change <= self.params.restart_tolerance * scale || left <= resolved {
                break;
            }
        }
        Ok(forces)
    }

    /// The constant forces on the bodies in the last step.
    pub(crate) fn applied_now(&self) -> Vec<nalgebra::Vector3<f64>> {
        match self.state.last_applied.len() {
            0 => self.constant_forces(),
            _ => self.state.last_applied.clone(),
        }
    }

    /// Loads and accelerations of `forces` into the state, and a constant
    /// force history of the `restarted` contacts (the next step's guess).
    pub(crate) fn restart_from(
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
