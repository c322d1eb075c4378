//! The contact-force iteration of Lee (1994), section 3.3.
//!
//! Per step: hold a trial contact force p over the step, integrate, measure
//! the velocity error e at the end, correct p ← p − A e with A = C⁻¹ (C the
//! step's 2×2 Delassus operator), until |e| is within tolerance; then the
//! position stage corrects the normal force until the gap error |g| is within
//! its tolerance. A glider (r = 0, J = 0) has no tangential row: its
//! tangential force stays exactly zero.

use nalgebra::{DVector, Matrix2, Vector2};

use crate::contact::{foot_point, ContactForce, ContactFrame};
use crate::integrate::{DynamicState, IntegrationError, Rk4};
use crate::system::System;

/// Tolerances and caps of the iteration (the paper's: 1e-7 m/s, 1e-5 m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationSettings {
    pub velocity_tolerance: f64,
    pub gap_tolerance: f64,
    pub max_iterations: u32,
}

/// Converged step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSolution {
    pub force: ContactForce,
    /// Integrations performed (velocity and position stages together).
    pub iterations: u32,
    /// |e| at the end of the step (m/s).
    pub velocity_error: f64,
    /// g at the end of the step (m).
    pub gap_error: f64,
}

/// Why a step failed.
#[derive(Debug, Clone, PartialEq)]
pub enum StepError {
    NotConverged {
        stage: &'static str,
        iterations: u32,
        residual: f64,
        tolerance: f64,
    },
    Diverged {
        stage: &'static str,
        iterations: u32,
        first: f64,
        last: f64,
    },
    NonFinite {
        stage: &'static str,
    },
    LostContact {
        x: f64,
    },
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepError::NotConverged {
                stage,
                iterations,
                residual,
                tolerance,
            } => write!(
                f,
                "the {stage} stage of the contact iteration did not converge in {iterations} \
                 iterations (error {residual:.3e}, tolerance {tolerance:.3e}); \
                 raise solver.max_iterations, loosen the tolerance or shorten solver.step"
            ),
            StepError::Diverged {
                stage,
                iterations,
                first,
                last,
            } => write!(
                f,
                "the {stage} stage of the contact iteration diverged (error grew from \
                 {first:.3e} to {last:.3e} in {iterations} iterations); shorten solver.step"
            ),
            StepError::NonFinite { stage } => write!(
                f,
                "a non-finite value appeared in the {stage} stage; the step is beyond the \
                 integrator's stability limit or the scene is degenerate"
            ),
            StepError::LostContact { x } => write!(
                f,
                "no foot point of the body on the beam could be found (last abscissa {x:.6} m)"
            ),
        }
    }
}

impl From<IntegrationError> for StepError {
    fn from(e: IntegrationError) -> StepError {
        match e {
            IntegrationError::LostContact { x } => StepError::LostContact { x },
        }
    }
}

/// Sensitivities of the end-of-step errors to the held force.
struct Delassus {
    /// ∂e/∂p (s/kg): the Delassus operator scaled by the step.
    velocity: Matrix2<f64>,
    /// ∂g/∂p_n (m/N).
    gap: f64,
}

/// The iteration's workspace: integrator scratch and unit-load responses.
pub struct ContactIteration {
    rk4: Rk4,
    load: DVector<f64>,
    response_u: [DVector<f64>; 2],
    response_v: [DVector<f64>; 2],
}

impl ContactIteration {
    pub fn new(free_dofs: usize) -> ContactIteration {
        let z = || DVector::zeros(free_dofs);
        ContactIteration {
            rk4: Rk4::new(free_dofs),
            load: z(),
            response_u: [z(), z()],
            response_v: [z(), z()],
        }
    }

    /// Sensitivities of the errors measured in `measure` (the end-of-step
    /// frame) to a force applied in `apply` (where the step starts).
    fn delassus(
        &mut self,
        system: &System,
        apply: &ContactFrame,
        measure: &ContactFrame,
        dt: f64,
    ) -> Delassus {
        let beam = &system.beam;
        let body = &system.body;
        let (t_row, n_row) = apply.beam_rows(beam.surface_offset);
        let rows = [t_row, n_row];
        let (mt_row, mn_row) = measure.beam_rows(beam.surface_offset);
        let measure_rows = [mt_row, mn_row];
        let active = if body.rolls { 0..2 } else { 1..2 };
        for j in active.clone() {
            self.load.fill(0.0);
            apply.shape.scatter(&rows[j], 1.0, &mut self.load);
            let (u, v) = (&mut self.response_u[j], &mut self.response_v[j]);
            self.rk4.beam_response(system, &self.load, dt, u, v);
        }
        let (bt, bn) = apply.body_rows(body.radius);
        let body_rows = [bt, bn];
        let (mbt, mbn) = measure.body_rows(body.radius);
        let measure_body_rows = [mbt, mbn];
        let inverse_inertia = if body.rolls && body.inertia > 0.0 {
            1.0 / body.inertia
        } else {
            0.0
        };
        let mut velocity = Matrix2::zeros();
        for i in active.clone() {
            for j in active.clone() {
                let (a, b) = (&measure_body_rows[i], &body_rows[j]);
                let body_part =
                    dt * ((a.x * b.x + a.y * b.y) / body.mass + a.z * b.z * inverse_inertia);
                velocity[(i, j)] =
                    body_part + measure.shape.dot(&measure_rows[i], &self.response_v[j]);
            }
        }
        if !body.rolls {
            velocity[(0, 0)] = 1.0;
        }
        let gap = dt * dt / (2.0 * body.mass) * measure.normal().dot(&apply.normal())
            + measure.shape.dot(&mn_row, &self.response_u[1]);
        Delassus { velocity, gap }
    }

    fn integrate_and_measure(
        &mut self,
        system: &System,
        start: &DynamicState,
        force: ContactForce,
        external: Vector2<f64>,
        dt: f64,
        end: &mut DynamicState,
    ) -> Result<ContactFrame, StepError> {
        self.rk4.step(system, start, force, external, dt, end)?;
        let frame = foot_point(
            &system.beam,
            &end.beam_displacement,
            &end.body.position,
            end.contact_x,
        )
        .map_err(|e| StepError::LostContact { x: e.last_x })?;
        end.contact_x = frame.x;
        Ok(frame)
    }

    /// Advance `start` by `dt` into `end`, finding the contact force.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        system: &System,
        start: &DynamicState,
        guess: ContactForce,
        external: Vector2<f64>,
        dt: f64,
        settings: &IterationSettings,
        end: &mut DynamicState,
    ) -> Result<StepSolution, StepError> {
        let body = &system.body;
        let beam = &system.beam;
        let start_frame = foot_point(
            beam,
            &start.beam_displacement,
            &start.body.position,
            start.contact_x,
        )
        .map_err(|e| StepError::LostContact { x: e.last_x })?;
        let mut delassus: Option<(Delassus, Matrix2<f64>)> = None;

        let mut force = guess;
        if !body.rolls {
            force.tangential = 0.0;
        }
        let mut iterations = 0;
        let mut first_residual = None;
        // Velocity stage (eq. 16).
        let mut frame = loop {
            let frame = self.integrate_and_measure(system, start, force, external, dt, end)?;
            iterations += 1;
            let mut e = frame.velocity_error(beam, body, &end.body, &end.beam_velocity);
            if !body.rolls {
                e.x = 0.0;
            }
            let residual = e.norm();
            if !residual.is_finite() {
                return Err(StepError::NonFinite { stage: "velocity" });
            }
            if residual <= settings.velocity_tolerance {
                break frame;
            }
            let first = *first_residual.get_or_insert(residual);
            if iterations >= 3 && residual > 10.0 * first {
                return Err(StepError::Diverged {
                    stage: "velocity",
                    iterations,
                    first,
                    last: residual,
                });
            }
            if iterations >= settings.max_iterations {
                return Err(StepError::NotConverged {
                    stage: "velocity",
                    iterations,
                    residual,
                    tolerance: settings.velocity_tolerance,
                });
            }
            if delassus.is_none() {
                let d = self.delassus(system, &start_frame, &frame, dt);
                let a = d
                    .velocity
                    .try_inverse()
                    .ok_or(StepError::NonFinite { stage: "velocity" })?;
                delassus = Some((d, a));
            }
            let (_, acceleration_matrix) = delassus.as_ref().expect("built above");
            force = ContactForce::from_vector(force.as_vector() - acceleration_matrix * e);
        };
        // Position stage (eq. 17).
        let mut gap = frame.gap(beam, body, &end.body.position);
        let mut position_iterations = 0;
        while gap.abs() > settings.gap_tolerance {
            if !gap.is_finite() {
                return Err(StepError::NonFinite { stage: "position" });
            }
            if position_iterations >= settings.max_iterations {
                return Err(StepError::NotConverged {
                    stage: "position",
                    iterations: position_iterations,
                    residual: gap.abs(),
                    tolerance: settings.gap_tolerance,
                });
            }
            if delassus.is_none() {
                let d = self.delassus(system, &start_frame, &frame, dt);
                delassus = Some((d, Matrix2::identity()));
            }
            let (d, _) = delassus.as_ref().expect("built above");
            force.normal -= gap / d.gap;
            frame = self.integrate_and_measure(system, start, force, external, dt, end)?;
            gap = frame.gap(beam, body, &end.body.position);
            iterations += 1;
            position_iterations += 1;
        }
        let mut e = frame.velocity_error(beam, body, &end.body, &end.beam_velocity);
        if !body.rolls {
            e.x = 0.0;
        }
        Ok(StepSolution {
            force,
            iterations,
            velocity_error: e.norm(),
            gap_error: gap,
        })
    }
}
