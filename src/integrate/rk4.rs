//! The paper's scheme: classical RK4 for beam and body together, with the
//! contact force held over the step.
//!
//! The force is held in the contact frame; the frame itself follows the
//! foot point through the RK4 stages, so within a step the equations of
//! motion are smooth and RK4 keeps its order. Stable for
//! Δt ≤ 2√2 / ω_max of the beam.

use nalgebra::{DVector, Vector2};

use super::{contact_loads, DynamicState, IntegrationError, StepStart};
use crate::contact::{foot_point, ContactForce};
use crate::system::System;

/// Scratch vectors of the RK4 step, allocated once per simulation.
pub struct Rk4 {
    stage_u: DVector<f64>,
    stage_v: DVector<f64>,
    sum_u: DVector<f64>,
    sum_v: DVector<f64>,
    load: DVector<f64>,
    accel: DVector<f64>,
}

impl Rk4 {
    pub fn new(free_dofs: usize) -> Rk4 {
        let z = || DVector::zeros(free_dofs);
        Rk4 {
            stage_u: z(),
            stage_v: z(),
            sum_u: z(),
            sum_v: z(),
            load: z(),
            accel: z(),
        }
    }

    /// Advance from `from` over its step with `force` held, into `end`.
    pub fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        force: ContactForce,
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, external, dt) = (from.state, from.external, from.dt);
        const STAGE_TIME: [f64; 3] = [0.5, 0.5, 1.0];
        const WEIGHT: [f64; 4] = [1.0, 2.0, 2.0, 1.0];
        let beam = &system.beam;
        let body = &system.body;
        self.stage_u.copy_from(&start.beam_displacement);
        self.stage_v.copy_from(&start.beam_velocity);
        self.sum_u.fill(0.0);
        self.sum_v.fill(0.0);
        let mut stage_body = start.body;
        let mut contact_x = start.contact_x;
        let (mut sum_pos, mut sum_vel) = (Vector2::zeros(), Vector2::zeros());
        let (mut sum_angle, mut sum_rate) = (0.0, 0.0);

        for stage in 0..4 {
            let frame = if stage == 0 {
                *from.frame
            } else {
                foot_point(beam, &self.stage_u, &stage_body.position, contact_x)
                    .map_err(|e| IntegrationError::LostContact { x: e.last_x })?
            };
            contact_x = frame.x;
            let generalized = contact_loads(system, &frame, force, external, &mut self.load);
            beam.accelerations(&self.stage_u, &self.load, &mut self.accel);
            let acceleration = body.acceleration(&generalized);
            let (body_accel, angular_accel) = (acceleration.xy(), acceleration.z);

            let weight = WEIGHT[stage];
            self.sum_u.axpy(weight, &self.stage_v, 1.0);
            self.sum_v.axpy(weight, &self.accel, 1.0);
            sum_pos += weight * stage_body.velocity;
            sum_vel += weight * body_accel;
            sum_angle += weight * stage_body.angular_velocity;
            sum_rate += weight * angular_accel;

            if stage < 3 {
                let h = STAGE_TIME[stage] * dt;
                // stage_u ← u0 + h v_stage, then stage_v ← v0 + h a_stage.
                self.stage_u.copy_from(&start.beam_displacement);
                self.stage_u.axpy(h, &self.stage_v, 1.0);
                self.stage_v.copy_from(&start.beam_velocity);
                self.stage_v.axpy(h, &self.accel, 1.0);
                let next = crate::body::BodyState {
                    position: start.body.position + h * stage_body.velocity,
                    velocity: start.body.velocity + h * body_accel,
                    angle: start.body.angle + h * stage_body.angular_velocity,
                    angular_velocity: start.body.angular_velocity + h * angular_accel,
                };
                stage_body = next;
            }
        }
        let w = dt / 6.0;
        end.beam_displacement.copy_from(&start.beam_displacement);
        end.beam_displacement.axpy(w, &self.sum_u, 1.0);
        end.beam_velocity.copy_from(&start.beam_velocity);
        end.beam_velocity.axpy(w, &self.sum_v, 1.0);
        end.body = crate::body::BodyState {
            position: start.body.position + w * sum_pos,
            velocity: start.body.velocity + w * sum_vel,
            angle: start.body.angle + w * sum_angle,
            angular_velocity: start.body.angular_velocity + w * sum_rate,
        };
        end.contact_x = contact_x;
        Ok(())
    }

    /// Displacement and velocity of the beam alone after `dt` under a constant
    /// `load`, from rest at zero displacement: the step's response to a unit
    /// contact load, from which the iteration builds its Delassus operator.
    pub fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    ) {
        const STAGE_TIME: [f64; 3] = [0.5, 0.5, 1.0];
        const WEIGHT: [f64; 4] = [1.0, 2.0, 2.0, 1.0];
        let beam = &system.beam;
        self.stage_u.fill(0.0);
        self.stage_v.fill(0.0);
        self.sum_u.fill(0.0);
        self.sum_v.fill(0.0);
        for stage in 0..4 {
            beam.accelerations(&self.stage_u, load, &mut self.accel);
            let weight = WEIGHT[stage];
            self.sum_u.axpy(weight, &self.stage_v, 1.0);
            self.sum_v.axpy(weight, &self.accel, 1.0);
            if stage < 3 {
                let h = STAGE_TIME[stage] * dt;
                self.stage_u.copy_from(&self.stage_v);
                self.stage_u.scale_mut(h);
                self.stage_v.copy_from(&self.accel);
                self.stage_v.scale_mut(h);
            }
        }
        displacement.copy_from(&self.sum_u);
        displacement.scale_mut(dt / 6.0);
        velocity.copy_from(&self.sum_v);
        velocity.scale_mut(dt / 6.0);
    }
}
