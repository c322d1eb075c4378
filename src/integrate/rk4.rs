//! The paper's scheme: classical RK4 for beam and bodies together, with the
//! contact forces held over the step.
//!
//! Each force is held in its contact frame; the frames follow the foot
//! points through the RK4 stages, so within a step the equations of motion
//! are smooth and RK4 keeps its order. Force elements are evaluated at every
//! stage. Stable for Δt ≤ 2√2 / ω_max of the beam (and of the suspensions).

use nalgebra::{DVector, Vector3};

use super::{contact_frames, loads, DynamicState, ForceShape, IntegrationError, StepStart};
use crate::body::BodyState;
use crate::contact::{ContactForce, ContactFrame};
use crate::system::System;

const STAGE_TIME: [f64; 3] = [0.5, 0.5, 1.0];
const WEIGHT: [f64; 4] = [1.0, 2.0, 2.0, 1.0];
/// Which of the force shape's stage times (0, ½, 1) each stage is at.
const SHAPE_TIME: [usize; 4] = [0, 1, 1, 2];

/// Scratch of the RK4 step, allocated once per simulation.
pub struct Rk4 {
    stage_u: DVector<f64>,
    stage_v: DVector<f64>,
    sum_u: DVector<f64>,
    sum_v: DVector<f64>,
    load: DVector<f64>,
    accel: DVector<f64>,
    stage_bodies: Vec<BodyState>,
    body_loads: Vec<Vector3<f64>>,
    /// Weighted sums of the bodies' rates (ẋ, ẏ, θ̇) and accelerations.
    sum_rates: Vec<Vector3<f64>>,
    sum_accelerations: Vec<Vector3<f64>>,
    frames: Vec<ContactFrame>,
    /// The contact forces at the current stage's time.
    stage_forces: Vec<ContactForce>,
    /// The beam's energy at the start of the step (the same for every
    /// integration of the step): computed at its first, cleared by
    /// `begin_step`.
    start_energy: Option<f64>,
}

impl Rk4 {
    pub fn new(free_dofs: usize, bodies: usize) -> Rk4 {
        let z = || DVector::zeros(free_dofs);
        Rk4 {
            stage_u: z(),
            stage_v: z(),
            sum_u: z(),
            sum_v: z(),
            load: z(),
            accel: z(),
            stage_bodies: Vec::with_capacity(bodies),
            body_loads: vec![Vector3::zeros(); bodies],
            sum_rates: vec![Vector3::zeros(); bodies],
            sum_accelerations: vec![Vector3::zeros(); bodies],
            frames: Vec::new(),
            stage_forces: Vec::new(),
            start_energy: None,
        }
    }

    /// Called once before the integrations of each step.
    pub fn begin_step(&mut self) {
        self.start_energy = None;
    }

    /// Advance from `from` over its step with `forces` held, into `end`.
    pub fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, dt) = (from.state, from.dt);
        let beam = &system.beam;
        self.stage_u.copy_from(&start.beam_displacement);
        self.stage_v.copy_from(&start.beam_velocity);
        self.sum_u.fill(0.0);
        self.sum_v.fill(0.0);
        self.stage_bodies.clear();
        self.stage_bodies.extend_from_slice(&start.bodies);
        self.sum_rates.fill(Vector3::zeros());
        self.sum_accelerations.fill(Vector3::zeros());
        end.contact_x.copy_from_slice(&start.contact_x);
        let mut dissipation_sum = 0.0;
        let mut beam_dissipation_sum = 0.0;
        let mut tractive_power_sum = 0.0;
        let mut beam_load_power_sum = 0.0;
        // Tested once per integration, not at each stage.
        let held = from.shapes.iter().all(ForceShape::is_held);
        let shapes = if held { &[][..] } else { from.shapes };

        for stage in 0..4 {
            if stage > 0 {
                let (u, bodies) = (&self.stage_u, &self.stage_bodies);
                let located = (end.contact_x.as_slice(), from.parts);
                contact_frames(system, u, bodies, located, &mut self.frames)?;
            }
            let frames = if stage == 0 {
                from.frames
            } else {
                &self.frames
            };
            for (x, frame) in end.contact_x.iter_mut().zip(frames) {
                *x = frame.x;
            }
            let forces = stage_forces(forces, shapes, SHAPE_TIME[stage], &mut self.stage_forces);
            dissipation_sum += WEIGHT[stage]
                * loads(
                    system,
                    frames,
                    forces,
                    from.applied,
                    &self.stage_bodies,
                    &self.stage_v,
                    &mut self.load,
                    &mut self.body_loads,
                );
            beam.accelerations((&self.stage_u, &self.stage_v), &self.load, &mut self.accel);
            beam_dissipation_sum += WEIGHT[stage] * beam.damping_power(&self.stage_v);
            beam_load_power_sum += WEIGHT[stage] * self.load.dot(&self.stage_v);

            let weight = WEIGHT[stage];
            add_scaled(&mut self.sum_u, weight, &self.stage_v);
            add_scaled(&mut self.sum_v, weight, &self.accel);
            for (b, body) in system.bodies.iter().enumerate() {
                // RK4's own quadrature of the tractive power F_x ẋ.
                tractive_power_sum += weight
                    * body.tractive_force(&self.body_loads[b])
                    * self.stage_bodies[b].velocity.x;
                let acceleration = body.acceleration(&self.body_loads[b]);
                // Kept as the stage's acceleration for the update below.
                self.body_loads[b] = acceleration;
                self.sum_rates[b] += weight * self.stage_bodies[b].generalized_velocity();
                self.sum_accelerations[b] += weight * acceleration;
            }

            if stage < 3 {
                let h = STAGE_TIME[stage] * dt;
                // stage_u ← u0 + h v_stage, then stage_v ← v0 + h a_stage.
                set_sum(
                    &mut self.stage_u,
                    &start.beam_displacement,
                    h,
                    &self.stage_v,
                );
                set_sum(&mut self.stage_v, &start.beam_velocity, h, &self.accel);
                for (b, stage_body) in self.stage_bodies.iter_mut().enumerate() {
                    *stage_body = start.bodies[b].advanced(h, stage_body, &self.body_loads[b]);
                }
            }
        }
        let w = dt / 6.0;
        set_sum(
            &mut end.beam_displacement,
            &start.beam_displacement,
            w,
            &self.sum_u,
        );
        set_sum(&mut end.beam_velocity, &start.beam_velocity, w, &self.sum_v);
        for (b, body) in end.bodies.iter_mut().enumerate() {
            let (b0, rates, accelerations) = (
                &start.bodies[b],
                &self.sum_rates[b],
                &self.sum_accelerations[b],
            );
            *body = BodyState {
                position: b0.position + w * rates.xy(),
                velocity: b0.velocity + w * accelerations.xy(),
                angle: b0.angle + w * rates.z,
                angular_velocity: b0.angular_velocity + w * accelerations.z,
            };
        }
        end.dissipated = start.dissipated + w * dissipation_sum;
        end.beam_dissipated = start.beam_dissipated + w * beam_dissipation_sum;
        end.tractive_work = start.tractive_work + w * tractive_power_sum;
        let start_energy = self
            .start_energy
            .get_or_insert_with(|| beam_energy(system, start));
        end.numerical_dissipation = start.numerical_dissipation
            + beam_dissipation(
                system,
                (*start_energy, &*end),
                w * beam_load_power_sum,
                w * beam_dissipation_sum,
            );
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
        let beam = &system.beam;
        self.stage_u.fill(0.0);
        self.stage_v.fill(0.0);
        self.sum_u.fill(0.0);
        self.sum_v.fill(0.0);
        for stage in 0..4 {
            beam.accelerations((&self.stage_u, &self.stage_v), load, &mut self.accel);
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

/// The beam energy RK4 removed in a step from `start` to `end`: the work
/// of the loads on the beam and of its structural damping, by RK4's own
/// quadrature of their power at the stages, less the change of its
/// kinetic and strain energy. Zero to the method's order where the step
/// resolves the motion; for a mode at ω Δt near the limit 2√2 (which an
/// impulse on the consistent mass excites) RK4's amplification
/// |R(iωΔt)|² = 1 − (ωΔt)⁶/72 + (ωΔt)⁸/576 < 1 removes up to three
/// quarters of the mode's energy per step: that is what this books.
fn beam_dissipation(
    system: &System,
    (start_energy, end): (f64, &DynamicState),
    load_work: f64,
    damping_work: f64,
) -> f64 {
    load_work - damping_work - (beam_energy(system, end) - start_energy)
}

/// The beam's kinetic and strain energy in state `s`.
fn beam_energy(system: &System, s: &DynamicState) -> f64 {
    let beam = &system.beam;
    beam.kinetic_energy(&s.beam_velocity) + beam.strain_energy(&s.beam_displacement)
}

/// `y ← y + a x`. By hand: nalgebra's `axpy` on a dynamic vector of a
/// few entries (the small meshes) costs several times its flops; the
/// same operations in the same order (same bits).
fn add_scaled(y: &mut DVector<f64>, a: f64, x: &DVector<f64>) {
    for (y, x) in y.as_mut_slice().iter_mut().zip(x.as_slice()) {
        *y += a * x;
    }
}

/// `y ← b + a x` (see `add_scaled`).
fn set_sum(y: &mut DVector<f64>, b: &DVector<f64>, a: f64, x: &DVector<f64>) {
    let terms = b.as_slice().iter().zip(x.as_slice());
    for (y, (b, x)) in y.as_mut_slice().iter_mut().zip(terms) {
        *y = b + a * x;
    }
}

/// The contact forces at stage time `k` of the shapes, for the step's mean
/// `forces` (the means themselves where every force is held).
fn stage_forces<'a>(
    forces: &'a [ContactForce],
    shapes: &[ForceShape],
    k: usize,
    out: &'a mut Vec<ContactForce>,
) -> &'a [ContactForce] {
    if shapes.len() != forces.len() || shapes.iter().all(ForceShape::is_held) {
        return forces;
    }
    out.clear();
    out.extend(forces.iter().zip(shapes).map(|(f, shape)| shape.at(k, f)));
    out
}
