//! HHT-α (Hilber-Hughes-Taylor) for the beam: implicit, unconditionally
//! stable, second order, with numerical damping of the high modes set by
//! `damping` = −α ∈ [0, 1/3] (0: Newmark's average acceleration, no damping).
//!
//! The unknown contact force acts at the end of the step, at the contact
//! frame of the end configuration (predicted from the previous iterate), on
//! beam and body alike; both are integrated with the same Newmark weights,
//! so the forces they receive are equal and opposite over every step and,
//! for α = 0, the contact does no work beyond that of the velocity error.

use crate::band::BandLdlt;
use nalgebra::{DVector, Vector2, Vector3};

use super::{contact_loads, DynamicState, IntegrationError, StepStart};
use crate::contact::{foot_point, ContactForce};
use crate::system::System;

pub struct Hht {
    alpha: f64,
    beta: f64,
    gamma: f64,
    /// Factor of M + (1 + α) β Δt² K for the nominal step, and for the last
    /// other step length met (the shortened last step before an exit or a
    /// communication point).
    nominal: (f64, BandLdlt),
    other: Option<(f64, BandLdlt)>,
    /// The previous iterate's end configuration, within the current step.
    predicted_u: DVector<f64>,
    predicted_centre: Vector2<f64>,
    has_prediction: bool,
    load: DVector<f64>,
    rhs: DVector<f64>,
    work: DVector<f64>,
}

impl Hht {
    pub fn new(system: &System, damping: f64, nominal_step: f64) -> Result<Hht, String> {
        let alpha = -damping;
        let beta = 0.25 * (1.0 - alpha) * (1.0 - alpha);
        let gamma = 0.5 - alpha;
        let weight = (1.0 + alpha) * beta * nominal_step * nominal_step;
        let factor = system.beam.factor_mass_plus_stiffness(weight)?;
        let z = || DVector::zeros(system.beam.free_dofs());
        Ok(Hht {
            alpha,
            beta,
            gamma,
            nominal: (nominal_step, factor),
            other: None,
            predicted_u: z(),
            predicted_centre: Vector2::zeros(),
            has_prediction: false,
            load: z(),
            rhs: z(),
            work: z(),
        })
    }

    pub fn begin_step(&mut self) {
        self.has_prediction = false;
    }

    /// `rhs ← S⁻¹ rhs` for steps of `dt`.
    fn solve_effective(&mut self, system: &System, dt: f64, rhs: &mut DVector<f64>) {
        if (dt - self.nominal.0).abs() <= 1e-9 * self.nominal.0 {
            self.nominal.1.solve_mut(rhs);
            return;
        }
        if self.other.as_ref().map(|(step, _)| *step) != Some(dt) {
            let weight = (1.0 + self.alpha) * self.beta * dt * dt;
            // The nominal factorisation succeeded, so M + c K is SPD for every
            // c >= 0 and this one does too.
            let factor = system
                .beam
                .factor_mass_plus_stiffness(weight)
                .expect("M + c K is positive definite");
            self.other = Some((dt, factor));
        }
        if let Some((_, factor)) = &self.other {
            factor.solve_mut(rhs);
        }
    }

    pub fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        force: ContactForce,
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, dt) = (from.state, from.dt);
        let beam = &system.beam;
        let body = &system.body;
        let (u0, v0, a0) = (
            &start.beam_displacement,
            &start.beam_velocity,
            &start.beam_acceleration,
        );
        if !self.has_prediction {
            self.predicted_u.copy_from(u0);
            self.predicted_u.axpy(dt, v0, 1.0);
            self.predicted_centre = start.body.position + dt * start.body.velocity;
        }
        // Load frame: the predicted end configuration.
        let frame = foot_point(
            beam,
            &self.predicted_u,
            &self.predicted_centre,
            from.frame.x,
        )
        .map_err(|e| IntegrationError::LostContact { x: e.last_x })?;
        let generalized = contact_loads(system, &frame, force, from.external, &mut self.load);
        // Beam: predictors, then M a1 + (1 + α) K u1 − α K u0 = (1 + α) f1 − α f0.
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        let u1 = &mut end.beam_displacement;
        u1.copy_from(u0);
        u1.axpy(dt, v0, 1.0);
        u1.axpy(dt * dt * (0.5 - beta), a0, 1.0);
        let v1 = &mut end.beam_velocity;
        v1.copy_from(v0);
        v1.axpy(dt * (1.0 - gamma), a0, 1.0);
        beam.stiffness_times(u1, &mut self.work);
        self.rhs.copy_from(&self.load);
        self.rhs.scale_mut(1.0 + alpha);
        self.rhs.axpy(-(1.0 + alpha), &self.work, 1.0);
        if alpha != 0.0 {
            beam.stiffness_times(u0, &mut self.work);
            self.rhs.axpy(alpha, &self.work, 1.0);
            self.rhs.axpy(-alpha, &start.beam_load, 1.0);
        }
        let mut a1 = std::mem::replace(&mut self.rhs, DVector::zeros(0));
        self.solve_effective(system, dt, &mut a1);
        end.beam_displacement.axpy(beta * dt * dt, &a1, 1.0);
        end.beam_velocity.axpy(gamma * dt, &a1, 1.0);
        end.beam_acceleration.copy_from(&a1);
        self.rhs = a1;

        // Body: the same forcing and Newmark weights as the beam.
        let a1 = body.acceleration(&((1.0 + alpha) * generalized - alpha * start.body_load));
        let a0 = start.body_acceleration;
        let b = &start.body;
        let position_increment = dt * Vector3::new(b.velocity.x, b.velocity.y, b.angular_velocity)
            + dt * dt * ((0.5 - beta) * a0 + beta * a1);
        let velocity_increment = dt * ((1.0 - gamma) * a0 + gamma * a1);
        end.body = crate::body::BodyState {
            position: b.position + position_increment.xy(),
            velocity: b.velocity + velocity_increment.xy(),
            angle: b.angle + position_increment.z,
            angular_velocity: b.angular_velocity + velocity_increment.z,
        };
        end.body_acceleration = a1;
        end.beam_load.copy_from(&self.load);
        end.body_load = generalized;
        end.contact_x = frame.x;
        self.predicted_u.copy_from(&end.beam_displacement);
        self.predicted_centre = end.body.position;
        self.has_prediction = true;
        Ok(())
    }

    /// The end-of-step force enters with weight 1 + α (at t_{n+1+α}).
    pub fn body_weights(&self, dt: f64) -> (f64, f64) {
        let forcing = 1.0 + self.alpha;
        (forcing * self.gamma * dt, forcing * self.beta * dt * dt)
    }

    pub fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    ) {
        let mut a1 = std::mem::replace(&mut self.work, DVector::zeros(0));
        a1.copy_from(load);
        a1.scale_mut(1.0 + self.alpha);
        self.solve_effective(system, dt, &mut a1);
        displacement.copy_from(&a1);
        displacement.scale_mut(self.beta * dt * dt);
        velocity.copy_from(&a1);
        velocity.scale_mut(self.gamma * dt);
        self.work = a1;
    }
}
