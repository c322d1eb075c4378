//! The contact-force iteration of Lee (1994), section 3.3.
//!
//! Per step: hold a trial contact force p over the step, integrate, measure
//! the velocity error e at the end, correct p ← p − A e with A = C⁻¹ (C the
//! step's 2×2 Delassus operator), until |e| is within tolerance; then the
//! position stage corrects the normal force until the gap error |g| is within
//! its tolerance. A glider (r = 0, J = 0) has no tangential row: its
//! tangential force stays exactly zero.

use nalgebra::{DVector, Matrix2, Matrix4, Vector2, Vector4};

use crate::contact::{foot_point, ContactForce, ContactFrame};
use crate::integrate::{DynamicState, IntegrationError, Integrator, StepStart};
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

/// Displacements and velocities at an element's four DOFs after one step
/// under a unit load held on each of them (column = loaded DOF).
#[derive(Debug, Clone, Copy)]
struct ElementResponse {
    displacement: Matrix4<f64>,
    velocity: Matrix4<f64>,
}

/// The iteration's workspace: integrator scratch and unit-load responses.
pub struct ContactIteration {
    integrator: Integrator,
    load: DVector<f64>,
    response_u: [DVector<f64>; 2],
    response_v: [DVector<f64>; 2],
    /// Per-element responses for steps of the nominal length, filled as the
    /// contact reaches each element: the Delassus operator then costs a few
    /// flops per step instead of two beam integrations. They depend only on
    /// the element and the nominal step, never on the history, so a restored
    /// state continues bit-identically.
    element_responses: Vec<Option<ElementResponse>>,
    nominal_step: f64,
}

impl ContactIteration {
    /// `nominal_step`: the fixed step whose unit-load responses are cached.
    pub fn new(
        integrator: Integrator,
        free_dofs: usize,
        elements: usize,
        nominal_step: f64,
    ) -> ContactIteration {
        let z = || DVector::zeros(free_dofs);
        ContactIteration {
            integrator,
            load: z(),
            response_u: [z(), z()],
            response_v: [z(), z()],
            element_responses: vec![None; elements],
            nominal_step,
        }
    }

    fn element_response(&mut self, system: &System, element: usize) -> ElementResponse {
        if let Some(response) = self.element_responses[element] {
            return response;
        }
        let dt = self.nominal_step;
        let dofs = system.beam.shape(element, system.beam.node_x[element]).dofs;
        let mut response = ElementResponse {
            displacement: Matrix4::zeros(),
            velocity: Matrix4::zeros(),
        };
        for (l, loaded) in dofs.iter().enumerate() {
            let Some(loaded) = *loaded else { continue };
            self.load.fill(0.0);
            self.load[loaded] = 1.0;
            let (u, v) = (&mut self.response_u[0], &mut self.response_v[0]);
            self.integrator.beam_response(system, &self.load, dt, u, v);
            for (k, measured) in dofs.iter().enumerate() {
                if let Some(measured) = *measured {
                    response.displacement[(k, l)] = self.response_u[0][measured];
                    response.velocity[(k, l)] = self.response_v[0][measured];
                }
            }
        }
        self.element_responses[element] = Some(response);
        response
    }

    /// Beam parts of ∂e/∂p and ∂g/∂p_n: the measured rows times the beam's
    /// response to the applied rows.
    fn beam_compliance(
        &mut self,
        system: &System,
        apply: &ContactFrame,
        measure: &ContactFrame,
        dt: f64,
    ) -> (Matrix2<f64>, f64) {
        let beam = &system.beam;
        let (t_row, n_row) = apply.beam_rows(beam.surface_offset);
        let (mt_row, mn_row) = measure.beam_rows(beam.surface_offset);
        let active = if system.body.rolls { 0..2 } else { 1..2 };
        let mut velocity = Matrix2::zeros();
        // Grid steps differ from the nominal step by round-off only.
        let nominal = (dt - self.nominal_step).abs() <= 1e-9 * self.nominal_step;
        if nominal && apply.shape.element == measure.shape.element {
            let r = self.element_response(system, apply.shape.element);
            let rows = [Vector4::from(t_row), Vector4::from(n_row)];
            let measure_rows = [Vector4::from(mt_row), Vector4::from(mn_row)];
            for i in active.clone() {
                for j in active.clone() {
                    velocity[(i, j)] = measure_rows[i].dot(&(r.velocity * rows[j]));
                }
            }
            let gap = measure_rows[1].dot(&(r.displacement * rows[1]));
            return (velocity, gap);
        }
        // The step crosses a node: integrate the responses directly.
        let rows = [t_row, n_row];
        let measure_rows = [mt_row, mn_row];
        for j in active.clone() {
            self.load.fill(0.0);
            apply.shape.scatter(&rows[j], 1.0, &mut self.load);
            let (u, v) = (&mut self.response_u[j], &mut self.response_v[j]);
            self.integrator.beam_response(system, &self.load, dt, u, v);
        }
        for i in active.clone() {
            for j in active.clone() {
                velocity[(i, j)] = measure.shape.dot(&measure_rows[i], &self.response_v[j]);
            }
        }
        let gap = measure.shape.dot(&measure_rows[1], &self.response_u[1]);
        (velocity, gap)
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
        let body = &system.body;
        let (velocity_weight, position_weight) = self.integrator.body_weights(dt);
        let (beam_velocity, beam_gap) = self.beam_compliance(system, apply, measure, dt);
        let (bt, bn) = apply.body_rows(body.radius);
        let body_rows = [bt, bn];
        let (mbt, mbn) = measure.body_rows(body.radius);
        let measure_body_rows = [mbt, mbn];
        let inverse_inertia = body.inverse_inertia();
        let active = if body.rolls { 0..2 } else { 1..2 };
        let mut velocity = beam_velocity;
        for i in active.clone() {
            for j in active.clone() {
                let (a, b) = (&measure_body_rows[i], &body_rows[j]);
                velocity[(i, j)] += velocity_weight
                    * ((a.x * b.x + a.y * b.y) / body.mass + a.z * b.z * inverse_inertia);
            }
        }
        if !body.rolls {
            velocity[(0, 0)] = 1.0;
        }
        let gap = position_weight / body.mass * measure.normal().dot(&apply.normal()) + beam_gap;
        Delassus { velocity, gap }
    }

    fn integrate_and_measure(
        &mut self,
        system: &System,
        from: &StepStart,
        force: ContactForce,
        end: &mut DynamicState,
    ) -> Result<ContactFrame, StepError> {
        self.integrator.step(system, from, force, end)?;
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
        self.integrator.begin_step();
        let from = StepStart {
            state: start,
            frame: &start_frame,
            external,
            dt,
        };
        // Built once per step, on the first correction that needs it.
        let mut delassus: Option<Delassus> = None;

        let mut force = guess;
        if !body.rolls {
            force.tangential = 0.0;
        }
        let mut iterations = 0;
        let mut first_residual = None;
        // Velocity stage (eq. 16).
        let mut frame = loop {
            let frame = self.integrate_and_measure(system, &from, force, end)?;
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
                delassus = Some(self.delassus(system, &start_frame, &frame, dt));
            }
            let d = delassus.as_ref().expect("built above");
            let acceleration_matrix = d
                .velocity
                .try_inverse()
                .ok_or(StepError::NonFinite { stage: "velocity" })?;
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
                delassus = Some(self.delassus(system, &start_frame, &frame, dt));
            }
            let d = delassus.as_ref().expect("built above");
            force.normal -= gap / d.gap;
            frame = self.integrate_and_measure(system, &from, force, end)?;
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
