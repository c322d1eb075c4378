//! The paper's scheme: classical RK4 for beam and bodies together, with the
//! contact forces held over the step.
//!
//! Each force is held in its contact frame; the frames follow the foot
//! points through the RK4 stages, so within a step the equations of motion
//! are smooth and RK4 keeps its order. Force elements are evaluated at every
//! stage. Stable for Δt ≤ 2√2 / ω_max of the beam (and of the suspensions).

use nalgebra::{DVector, Vector3};

use super::{
    contact_frames, loads, rk4_step_limit, DynamicState, ForceProfile, ForceShape,
    IntegrationError, StepStart, TimeIntegrator,
};
use crate::band::DENSE_LIMIT;
use crate::beam::VelocityFreeBand;
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
    bodies: BodyStages,
    frames: Vec<ContactFrame>,
    /// The stages' vectors when two stages are solved together (allocated
    /// at the first such step).
    paired: Option<Box<PairedStages>>,
    /// The beam's energy at the start of the step (the same for every
    /// integration of the step): computed at its first, cleared by
    /// `begin_step`.
    start_energy: Option<f64>,
}

impl TimeIntegrator for Rk4 {
    const NAME: &'static str = "rk4";
    const TITLE: &'static str = "explicit RK4";
    // Each step starts afresh from its start state.
    const CARRIES_STEP_END: bool = false;
    const FITS_FORCE_SHAPE: bool = true;
    // Force elements are evaluated in its stages.
    const LAGS_FORCE_LAWS: bool = false;
    const STEPS_TRACK_ON_DECK: bool = false;
    // Its stages sample the forces along the step (the paper's operator,
    // in the start frames).
    const HOLDS_FORCES_AT_END: bool = false;

    fn build(system: &System, _step: f64, _damping: f64) -> Result<(Rk4, String), String> {
        let rk4 = Rk4::new(system.beam.coordinates(), system.bodies.len());
        Ok((rk4, "rk4 (explicit)".to_string()))
    }

    fn stable_step(system: &System) -> Option<f64> {
        Some(rk4_step_limit(system))
    }

    /// Fourth order with the quadratic force profile; the held and linear
    /// profiles limit it to second (docs/error-estimates.md).
    fn order(profile: ForceProfile) -> f64 {
        if profile == ForceProfile::Quadratic {
            4.0
        } else {
            2.0
        }
    }

    fn begin_step(&mut self, _system: &System, _dt: f64) -> Result<(), IntegrationError> {
        Rk4::begin_step(self);
        Ok(())
    }

    fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        Rk4::step(self, system, from, forces, end)
    }

    /// The held force's weights: (Δt, Δt²/2).
    fn body_weights(&self, dt: f64) -> (f64, f64) {
        (dt, 0.5 * dt * dt)
    }

    fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    ) {
        Rk4::beam_response(self, system, load, dt, displacement, velocity)
    }
}

/// The bodies through the stages: their stage states, the stage's loads
/// (then accelerations) and the weighted sums of their rates.
struct BodyStages {
    stage_bodies: Vec<BodyState>,
    body_loads: Vec<Vector3<f64>>,
    /// Weighted sums of the bodies' rates (ẋ, ẏ, θ̇) and accelerations.
    sum_rates: Vec<Vector3<f64>>,
    sum_accelerations: Vec<Vector3<f64>>,
    /// The contact forces at the current stage's time.
    stage_forces: Vec<ContactForce>,
}

/// RK4's weighted sums of the powers over the stages.
#[derive(Default)]
struct PowerSums {
    dissipation: f64,
    beam_dissipation: f64,
    tractive: f64,
    beam_load: f64,
}

/// The stages' beam vectors of a step whose stages are solved in pairs:
/// displacements u₁..u₃, velocities v₁..v₃ and loads f₀..f₃.
struct PairedStages {
    u: [DVector<f64>; 3],
    v: [DVector<f64>; 3],
    loads: [DVector<f64>; 4],
    /// The forward sweep of the pair of stages being solved.
    scratch: Vec<[f64; 2]>,
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
            bodies: BodyStages {
                stage_bodies: Vec::with_capacity(bodies),
                body_loads: vec![Vector3::zeros(); bodies],
                sum_rates: vec![Vector3::zeros(); bodies],
                sum_accelerations: vec![Vector3::zeros(); bodies],
                stage_forces: Vec::new(),
            },
            frames: Vec::new(),
            paired: None,
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
        let start = from.state;
        self.bodies.begin(&start.bodies);
        end.contact_x.copy_from_slice(&start.contact_x);
        // Tested once per integration, not at each stage.
        let held = from.shapes.iter().all(ForceShape::is_held);
        let shapes = if held { &[][..] } else { from.shapes };
        let stages = Stages {
            system,
            from,
            forces,
            shapes,
        };
        // A follower's force reads the stage's beam velocity, so its load
        // waits for the previous stage's accelerations. On the smallest
        // meshes the solve is a dense product with no chain to overlap,
        // and the sequential stages are cheaper (2.8 against 3.0 µs a step
        // at 2 elements).
        let followers = system.contacts.iter().any(|c| c.follower.is_some());
        let small = start.beam_displacement.len() <= DENSE_LIMIT;
        let sums = match system.beam.velocity_free_band() {
            Some(band) if !followers && !small => self.paired_stages(&stages, band, end)?,
            _ => self.sequential_stages(&stages, end)?,
        };
        let w = from.dt / 6.0;
        self.bodies.finish(&start.bodies, w, &mut end.bodies);
        end.dissipated = start.dissipated + w * sums.dissipation;
        end.beam_dissipated = start.beam_dissipated + w * sums.beam_dissipation;
        end.tractive_work = start.tractive_work + w * sums.tractive;
        let start_energy = self
            .start_energy
            .get_or_insert_with(|| beam_energy(system, start));
        end.numerical_dissipation = start.numerical_dissipation
            + beam_dissipation(
                system,
                (*start_energy, &*end),
                w * sums.beam_load,
                w * sums.beam_dissipation,
            );
        Ok(())
    }

    /// The four stages one after the other: each stage's accelerations
    /// from its displacements and velocities.
    fn sequential_stages(
        &mut self,
        stages: &Stages,
        end: &mut DynamicState,
    ) -> Result<PowerSums, IntegrationError> {
        let (start, dt) = (stages.from.state, stages.from.dt);
        let beam = &stages.system.beam;
        self.stage_u.copy_from(&start.beam_displacement);
        self.stage_v.copy_from(&start.beam_velocity);
        self.sum_u.fill(0.0);
        self.sum_v.fill(0.0);
        let mut sums = PowerSums::default();
        for stage in 0..4 {
            let frames =
                stages.frames(stage, &self.stage_u, &self.bodies, &mut self.frames, end)?;
            let at = (frames, &self.stage_v);
            stages.loads(stage, at, &mut self.bodies, &mut self.load, &mut sums);
            beam.accelerations((&self.stage_u, &self.stage_v), &self.load, &mut self.accel);
            let weight = WEIGHT[stage];
            sums.beam_dissipation += weight * beam.damping_power(&self.stage_v);
            sums.beam_load += weight * self.load.dot(&self.stage_v);
            add_scaled(&mut self.sum_u, weight, &self.stage_v);
            add_scaled(&mut self.sum_v, weight, &self.accel);
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
                self.bodies.advance(&start.bodies, h);
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
        Ok(sums)
    }

    /// The stages in two pairs, for a beam whose loads and accelerations
    /// before the mass solve do not depend on its velocity: u₁ = u₀ + ½Δt v₀
    /// needs no acceleration, u₂ and u₃ only a₀ and a₁, so stages 0 and 1
    /// are solved together, then 2 and 3 (`BandLdlt::solve_residual_pair`:
    /// a single stage's solve waits on its rows one after the other, two
    /// run side by side). The same operations in the same order per entry
    /// as `sequential_stages` (the same bits).
    fn paired_stages(
        &mut self,
        stages: &Stages,
        band: VelocityFreeBand,
        end: &mut DynamicState,
    ) -> Result<PowerSums, IntegrationError> {
        let n = stages.from.state.beam_displacement.len();
        // Out of `self` while the stages borrow it (and back on failure too).
        let mut paired = (self.paired.take()).unwrap_or_else(|| Box::new(PairedStages::new(n)));
        let mut sums = PowerSums::default();
        let solved = self
            .first_pair(stages, &band, &mut paired, &mut sums, end)
            .and_then(|()| self.second_pair(stages, &band, &mut paired, &mut sums, end));
        let beam = &stages.system.beam;
        let PairedStages { v, loads, .. } = &*paired;
        let v0 = &stages.from.state.beam_velocity;
        let velocities = [v0, &v[0], &v[1], &v[2]];
        if solved.is_ok() {
            for ((weight, v), f) in WEIGHT.iter().zip(velocities).zip(loads) {
                sums.beam_dissipation += weight * beam.damping_power(v);
                sums.beam_load += weight * f.dot(v);
            }
        }
        self.paired = Some(paired);
        solved.map(|()| sums)
    }

    /// Stages 0 and 1 of `paired_stages`: their loads, then one paired
    /// solve for a₀ and a₁, giving v₁, v₂, u₂, u₃ and the sums' first terms.
    #[inline(always)]
    fn first_pair(
        &mut self,
        stages: &Stages,
        band: &VelocityFreeBand,
        paired: &mut PairedStages,
        sums: &mut PowerSums,
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, dt) = (stages.from.state, stages.from.dt);
        let (u0, v0) = (&start.beam_displacement, &start.beam_velocity);
        let PairedStages {
            u: [u1, u2, u3],
            v: [v1, v2, _],
            loads: [f0, f1, _, _],
            scratch,
        } = paired;
        let bodies = &mut self.bodies;
        let (h1, h) = (STAGE_TIME[0] * dt, STAGE_TIME[2] * dt);
        let alpha = band.mass_damping;
        let frames = stages.frames(0, u0, bodies, &mut self.frames, end)?;
        stages.loads(0, (frames, v0), bodies, f0, sums);
        bodies.advance(&start.bodies, h1);
        set_sum(u1, u0, h1, v0);
        let frames = stages.frames(1, u1, bodies, &mut self.frames, end)?;
        stages.loads(1, (frames, v0), bodies, f1, sums);
        bodies.advance(&start.bodies, STAGE_TIME[1] * dt);
        let columns = (
            [u0.as_slice(), u1.as_slice()],
            [f0.as_slice(), f1.as_slice()],
        );
        let start_rows = u0.as_slice().iter().zip(v0.as_slice());
        let stage_u = u2.as_mut_slice().iter_mut().zip(u3.as_mut_slice());
        let stage_v = v1.as_mut_slice().iter_mut().zip(v2.as_mut_slice());
        let sums_uv = (self.sum_u.as_mut_slice().iter_mut()).zip(self.sum_v.as_mut_slice());
        let rows = start_rows.zip(stage_u).zip(stage_v).zip(sums_uv);
        band.mass_factor.solve_residual_pair(
            band.stiffness,
            columns,
            scratch,
            rows,
            |a, ((((&u0, &v0), (u2, u3)), (v1, v2)), (sum_u, sum_v))| {
                let a0 = damped(a[0], alpha, v0);
                *v1 = v0 + h1 * a0;
                let a1 = damped(a[1], alpha, *v1);
                *v2 = v0 + h1 * a1;
                *sum_u = (0.0 + WEIGHT[0] * v0) + WEIGHT[1] * *v1;
                *sum_v = (0.0 + WEIGHT[0] * a0) + WEIGHT[1] * a1;
                *u2 = u0 + h1 * *v1;
                *u3 = u0 + h * *v2;
            },
        );
        Ok(())
    }

    /// Stages 2 and 3 of `paired_stages`: their loads, then one paired
    /// solve for a₂ and a₃, giving v₃ and the end of the step.
    #[inline(always)]
    fn second_pair(
        &mut self,
        stages: &Stages,
        band: &VelocityFreeBand,
        paired: &mut PairedStages,
        sums: &mut PowerSums,
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, dt) = (stages.from.state, stages.from.dt);
        let (u0, v0) = (&start.beam_displacement, &start.beam_velocity);
        let PairedStages {
            u: [_, u2, u3],
            v: [_, v2, v3],
            loads: [_, _, f2, f3],
            scratch,
        } = paired;
        let bodies = &mut self.bodies;
        let (w, h) = (dt / 6.0, STAGE_TIME[2] * dt);
        let alpha = band.mass_damping;
        let frames = stages.frames(2, u2, bodies, &mut self.frames, end)?;
        stages.loads(2, (frames, v0), bodies, f2, sums);
        bodies.advance(&start.bodies, h);
        let frames = stages.frames(3, u3, bodies, &mut self.frames, end)?;
        stages.loads(3, (frames, v0), bodies, f3, sums);
        let columns = (
            [u2.as_slice(), u3.as_slice()],
            [f2.as_slice(), f3.as_slice()],
        );
        let start_rows = u0.as_slice().iter().zip(v0.as_slice());
        let stage_v = v2.as_slice().iter().zip(v3.as_mut_slice());
        let sums_uv = self.sum_u.as_slice().iter().zip(self.sum_v.as_slice());
        let ends = end.beam_displacement.as_mut_slice().iter_mut();
        let ends = ends.zip(end.beam_velocity.as_mut_slice());
        let rows = start_rows.zip(stage_v).zip(sums_uv).zip(ends);
        band.mass_factor.solve_residual_pair(
            band.stiffness,
            columns,
            scratch,
            rows,
            |a, ((((&u0, &v0), (&v2, v3)), (sum_u, sum_v)), (end_u, end_v))| {
                let a2 = damped(a[0], alpha, v2);
                *v3 = v0 + h * a2;
                let a3 = damped(a[1], alpha, *v3);
                let su = (sum_u + WEIGHT[2] * v2) + WEIGHT[3] * *v3;
                let sv = (sum_v + WEIGHT[2] * a2) + WEIGHT[3] * a3;
                *end_u = u0 + w * su;
                *end_v = v0 + w * sv;
            },
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

/// What every stage of one integration shares.
struct Stages<'a> {
    system: &'a System,
    from: &'a StepStart<'a>,
    /// The step's mean forces and, unless every force is held, their shapes.
    forces: &'a [ContactForce],
    shapes: &'a [ForceShape],
}

impl<'a> Stages<'a> {
    /// The contact frames of stage `stage`: the step's own at stage 0,
    /// else found at displacement `u` and the bodies' stage states from
    /// the foot points in `end.contact_x`; each foot point into
    /// `end.contact_x`.
    #[inline(always)]
    fn frames<'f>(
        &self,
        stage: usize,
        u: &DVector<f64>,
        bodies: &BodyStages,
        found: &'f mut Vec<ContactFrame>,
        end: &mut DynamicState,
    ) -> Result<&'f [ContactFrame], IntegrationError>
    where
        'a: 'f,
    {
        let frames = if stage == 0 {
            self.from.frames
        } else {
            let located = (end.contact_x.as_slice(), self.from.parts);
            contact_frames(self.system, u, &bodies.stage_bodies, located, found)?;
            &found[..]
        };
        for (x, frame) in end.contact_x.iter_mut().zip(frames) {
            *x = frame.x;
        }
        Ok(frames)
    }

    /// The loads of stage `stage` at `frames`, the beam's into `load`; the
    /// bodies' accelerations, and the stage's weighted powers into `sums`.
    /// `beam_velocity` is the stage's (a follower's gap rate reads it).
    #[inline(always)]
    fn loads(
        &self,
        stage: usize,
        (frames, beam_velocity): (&[ContactFrame], &DVector<f64>),
        bodies: &mut BodyStages,
        load: &mut DVector<f64>,
        sums: &mut PowerSums,
    ) {
        let system = self.system;
        let forces = stage_forces(
            self.forces,
            self.shapes,
            SHAPE_TIME[stage],
            &mut bodies.stage_forces,
        );
        let weight = WEIGHT[stage];
        sums.dissipation += weight
            * loads(
                system,
                frames,
                forces,
                self.from.applied,
                &bodies.stage_bodies,
                beam_velocity,
                load,
                &mut bodies.body_loads,
            );
        for (b, body) in system.bodies.iter().enumerate() {
            let stage_body = &bodies.stage_bodies[b];
            // RK4's own quadrature of the tractive power F_x ẋ.
            sums.tractive +=
                weight * body.tractive_force(&bodies.body_loads[b]) * stage_body.velocity.x;
            let acceleration = body.acceleration(&bodies.body_loads[b]);
            // Kept as the stage's acceleration for `advance`.
            bodies.body_loads[b] = acceleration;
            bodies.sum_rates[b] += weight * stage_body.generalized_velocity();
            bodies.sum_accelerations[b] += weight * acceleration;
        }
    }
}

impl BodyStages {
    /// Stage 0 at `start`, the sums cleared.
    #[inline(always)]
    fn begin(&mut self, start: &[BodyState]) {
        self.stage_bodies.clear();
        self.stage_bodies.extend_from_slice(start);
        self.sum_rates.fill(Vector3::zeros());
        self.sum_accelerations.fill(Vector3::zeros());
    }

    /// The next stage's states: `h` after `start` at the last stage's rates.
    #[inline(always)]
    fn advance(&mut self, start: &[BodyState], h: f64) {
        for (b, stage_body) in self.stage_bodies.iter_mut().enumerate() {
            *stage_body = start[b].advanced(h, stage_body, &self.body_loads[b]);
        }
    }

    /// The end of the step: `start` plus `w` times the weighted sums.
    #[inline(always)]
    fn finish(&self, start: &[BodyState], w: f64, end: &mut [BodyState]) {
        for (b, body) in end.iter_mut().enumerate() {
            let (b0, rates, accelerations) =
                (&start[b], &self.sum_rates[b], &self.sum_accelerations[b]);
            *body = BodyState {
                position: b0.position + w * rates.xy(),
                velocity: b0.velocity + w * accelerations.xy(),
                angle: b0.angle + w * rates.z,
                angular_velocity: b0.angular_velocity + w * accelerations.z,
            };
        }
    }
}

impl PairedStages {
    fn new(n: usize) -> PairedStages {
        let z = || DVector::zeros(n);
        PairedStages {
            u: [z(), z(), z()],
            v: [z(), z(), z()],
            loads: [z(), z(), z(), z()],
            scratch: Vec::with_capacity(n),
        }
    }
}

/// `a − α v` as `accelerations` forms it (nothing when α = 0).
#[inline(always)]
fn damped(a: f64, alpha: f64, v: f64) -> f64 {
    if alpha == 0.0 {
        a
    } else {
        -alpha * v + a
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
