//! HHT-α (Hilber-Hughes-Taylor) for the beam: implicit, unconditionally
//! stable, second order, with numerical damping of the high modes set by
//! `damping` = −α ∈ [0, 1/3] (0: Newmark's average acceleration, no damping).
//!
//! The unknown contact force acts at the end of the step, at the contact
//! frame of the end configuration (predicted from the previous iterate), on
//! beam and body alike; both are integrated with the same Newmark weights,
//! so the forces they receive are equal and opposite over every step and,
//! for α = 0, the contact does no work beyond that of the velocity error.
//! Force elements and massless followers are evaluated at the same
//! predicted end configuration (a follower's gap rate at the predicted
//! beam velocity too), which the iteration refines with every integration
//! of the step until the end state is a fixed point: they act at the end
//! of the step like every other load, as the scheme needs.

use crate::beam::{EffectiveFactor, InverseWithinBand, Shape};
use nalgebra::{DVector, Matrix4, Vector2, Vector3, Vector4};

use super::hht_energy::{step_dissipation, StepEnds, Weights};
use super::step_end::EndForces;
use super::{
    add_loads_but_laws, contact_frames, follower_dissipation, DynamicState, HeldFollowers,
    IntegrationError, LoadFootprint, StepStart,
};
use crate::body::BodyState;
use crate::contact::{ContactForce, ContactFrame};
use crate::force_element::{add_element_forces, dissipation_power};
use crate::system::System;

/// The beam's end state of a step's first integration and the load it
/// had: the step is linear in the load, so a later integration adds
/// S⁻¹ (1 + α) Δf to it.
#[derive(Debug, Clone)]
struct Base {
    known: bool,
    dt: f64,
    load: DVector<f64>,
    displacement: DVector<f64>,
    velocity: DVector<f64>,
    acceleration: DVector<f64>,
}

/// A step's end handed over as the next step's first prediction
/// (`Hht::seed_prediction`).
#[derive(Debug, Clone)]
struct Seed {
    dt: f64,
    displacement: DVector<f64>,
    velocity: DVector<f64>,
    bodies: Vec<BodyState>,
}

pub struct Hht {
    alpha: f64,
    beta: f64,
    gamma: f64,
    /// Factor of M + (1 + α) β Δt² K for the nominal step, and for the last
    /// other step length met (the shortened last step before an exit or a
    /// communication point).
    nominal: (f64, EffectiveFactor),
    /// The nominal factor's inverse within its band, swept at the first
    /// `point_compliance` (None inside: the factor has none).
    nominal_inverse: Option<Option<InverseWithinBand>>,
    /// Per element, S⁻¹ on its four DOFs from `nominal_inverse`, read at
    /// the first contact on it (`point_compliance`).
    element_inverse: Vec<Option<Matrix4<f64>>>,
    other: Option<(f64, EffectiveFactor)>,
    /// The first integration's predicted end configuration (the beam's
    /// part read only until `has_prediction`).
    predicted_u: DVector<f64>,
    predicted_v: DVector<f64>,
    predicted_bodies: Vec<BodyState>,
    /// The address of the last integration's end displacement: with
    /// `has_prediction`, the beam's prediction is that end, still in the
    /// `end` the next integration is given (a step's integrations share
    /// one end, written only by `beam_step`), read there, not copied (two
    /// vectors an integration on a rail of 922 rows).
    end_address: usize,
    /// The force elements' generalized force on each body in the last
    /// integration (at the prediction it was given).
    law_loads: Vec<Vector3<f64>>,
    has_prediction: bool,
    /// What the iteration handed over for the current prediction
    /// (`know_prediction`), as the dampers' power there: its frames are in
    /// `frames`, its force elements' loads in `law_loads`.
    known_laws: Option<f64>,
    /// With `known_laws`: each follower's gap and rate at the prediction.
    known_gaps: Vec<(f64, f64)>,
    /// Whether the first prediction takes the start's accelerations
    /// (`predict_from`).
    pub(super) predicts_accelerations: bool,
    /// The end handed over for the next step (`seed_prediction`), and the
    /// one `begin_step` took for the step it begins (a step as long),
    /// kept to the step's end (`seeded_bodies`).
    seed: Option<Seed>,
    seeded: Option<Seed>,
    frames: Vec<ContactFrame>,
    guesses: Vec<f64>,
    load: DVector<f64>,
    /// Its entries the last integration's loads were added to.
    load_footprint: LoadFootprint,
    rhs: DVector<f64>,
    work: DVector<f64>,
    scratch: DVector<f64>,
    /// Each body's tractive force at the end of the step (zero if free).
    tractive: Vec<f64>,
    /// The products at the last steps' ends: the books' terms, HHT-α's
    /// next C v₀ + K u₀ and the output rows' internal forces.
    ends: StepEnds,
    /// Terms of the step's start, the same for every integration of the
    /// step: computed at its first (`start_known`), not at every iterate.
    start_known: bool,
    start_internal: DVector<f64>,
    start_dissipation: f64,
    /// C v* + K u* at the step's predictors u*, v* (which depend on the
    /// start and the step length `predictor_dt` alone): the same for every
    /// full integration of the step.
    predictor_dt: Option<f64>,
    predictor_u: DVector<f64>,
    predictor_v: DVector<f64>,
    predictor_internal: DVector<f64>,
    /// The band solve's forward sweep (`BandLdlt::solve_rows`).
    sweep: Vec<f64>,
    /// The step's first integration, which later ones correct by the
    /// response to their change of load (`beam_step`).
    base: Base,
    /// The dampers' power at the last integration's end configuration.
    end_dissipation: f64,
    /// Whether the energy the step removes (dampers, structural and
    /// numerical damping) is booked: off when no sink reads it.
    books: bool,
    /// Per contact: a follower whose force the iteration gives
    /// (`hold_followers`), and every follower's force in the last
    /// integration.
    held_followers: Vec<bool>,
    followers_used: Vec<ContactForce>,
}

/// One full integration by the band factor's fused solve
/// (`BandLdlt::solve_rows`): the right-hand side
/// (1 + α)(f − (C v* + K u*)) + α (C v0 + K u0) − α f0 made row by row in
/// its forward sweep from
/// `terms` = [f, C v* + K u*, C v0 + K u0, f0], and u = u* + β Δt² a,
/// v = v* + γ Δt a from `stars` = [u*, v*] in its backward sweep: the bits
/// of `Hht::full_beam_step_by_vectors`' vector operations, in one pass.
fn fused_band_step(
    factor: &crate::band::BandLdlt,
    ((alpha, beta, gamma), dt): ((f64, f64, f64), f64),
    (terms, [u_star, v_star]): ([&[f64]; 4], [&[f64]; 2]),
    sweep: &mut Vec<f64>,
    end: &mut DynamicState,
) {
    let [load, internal, start_internal, start_load] = terms;
    let terms = (load.iter().zip(internal)).zip(start_internal.iter().zip(start_load));
    let rhs = terms.map(|((load, internal), (start_internal, start_load))| {
        let mut r = load * (1.0 + alpha);
        r += -(1.0 + alpha) * internal;
        if alpha != 0.0 {
            r += alpha * start_internal;
            r += -alpha * start_load;
        }
        r
    });
    let (u_weight, v_weight) = (beta * dt * dt, gamma * dt);
    let ends = (end.beam_displacement.as_mut_slice().iter_mut())
        .zip(end.beam_velocity.as_mut_slice().iter_mut())
        .zip(end.beam_acceleration.as_mut_slice().iter_mut());
    let rows = ends.zip(u_star.iter().zip(v_star));
    factor.solve_rows(sweep, rhs, rows, |a, (((u, v), acc), (u_star, v_star))| {
        *u = u_weight * a + u_star;
        *v = v_weight * a + v_star;
        *acc = a;
    });
}

/// `to ← from` by slice copies in blocks (`linalg::bits::copy_in_blocks`;
/// nalgebra's `copy_from` goes entry by entry: a fifth of an
/// integration's own work on a long viaduct).
#[inline]
fn copy(to: &mut DVector<f64>, from: &DVector<f64>) {
    crate::linalg::bits::copy_in_blocks(to.as_mut_slice(), from.as_slice());
}

/// Factor of the effective matrix M + (1 + α)(γ Δt C + β Δt² K) for steps of `dt`.
fn effective_factor(
    system: &System,
    (alpha, beta, gamma): (f64, f64, f64),
    dt: f64,
) -> Result<EffectiveFactor, String> {
    let forcing = 1.0 + alpha;
    system
        .beam
        .effective_factor(forcing * gamma * dt, forcing * beta * dt * dt)
}

impl Hht {
    pub fn new(system: &System, damping: f64, nominal_step: f64) -> Result<Hht, String> {
        let alpha = -damping;
        let beta = 0.25 * (1.0 - alpha) * (1.0 - alpha);
        let gamma = 0.5 - alpha;
        let factor = effective_factor(system, (alpha, beta, gamma), nominal_step)?;
        let z = || DVector::zeros(system.beam.coordinates());
        Ok(Hht {
            alpha,
            beta,
            gamma,
            nominal: (nominal_step, factor),
            nominal_inverse: None,
            element_inverse: Vec::new(),
            other: None,
            predicted_u: z(),
            predicted_v: z(),
            predicted_bodies: Vec::new(),
            end_address: 0,
            law_loads: vec![Vector3::zeros(); system.bodies.len()],
            has_prediction: false,
            known_laws: None,
            known_gaps: Vec::new(),
            predicts_accelerations: false,
            seed: None,
            seeded: None,
            frames: Vec::new(),
            guesses: Vec::new(),
            load: z(),
            load_footprint: LoadFootprint::default(),
            rhs: z(),
            work: z(),
            scratch: z(),
            tractive: vec![0.0; system.bodies.len()],
            ends: StepEnds::default(),
            start_known: false,
            start_internal: z(),
            start_dissipation: 0.0,
            predictor_dt: None,
            predictor_u: z(),
            predictor_v: z(),
            predictor_internal: z(),
            sweep: Vec::new(),
            end_dissipation: 0.0,
            books: true,
            held_followers: vec![false; system.contacts.len()],
            followers_used: vec![ContactForce::default(); system.contacts.len()],
            base: Base {
                known: false,
                dt: 0.0,
                load: z(),
                displacement: z(),
                velocity: z(),
                acceleration: z(),
            },
        })
    }

    /// Reset the step's caches and factor the effective matrix for `dt`
    /// if it is not the nominal step's.
    pub fn begin_step(&mut self, system: &System, dt: f64) -> Result<(), IntegrationError> {
        self.has_prediction = false;
        self.seeded = self.seed.take().filter(|seed| seed.dt == dt);
        self.known_laws = None;
        self.start_known = false;
        self.predictor_dt = None;
        self.base.known = false;
        self.prepare_factor(system, dt)
    }

    fn is_nominal(&self, dt: f64) -> bool {
        crate::solver::parameters::is_nominal_step(dt, self.nominal.0)
    }

    /// The factor of the effective matrix for a step of `dt`, kept until
    /// another step length is asked for. M + c C + d K is positive definite
    /// for every c, d >= 0, but on a very fine mesh (100,000 elements) the
    /// band LDLᵀ of a shortened step's matrix can meet a non-positive pivot
    /// by rounding: that is a failed step, not a panic.
    fn prepare_factor(&mut self, system: &System, dt: f64) -> Result<(), IntegrationError> {
        if self.is_nominal(dt) || self.other.as_ref().map(|(step, _)| *step) == Some(dt) {
            return Ok(());
        }
        self.other = None;
        let factor = effective_factor(system, (self.alpha, self.beta, self.gamma), dt)
            .map_err(|reason| IntegrationError::Factorization { step: dt, reason })?;
        self.other = Some((dt, factor));
        Ok(())
    }

    /// `rhs ← S⁻¹ rhs` for steps of `dt`.
    fn solve_effective(&mut self, system: &System, dt: f64, rhs: &mut DVector<f64>) {
        if self.is_nominal(dt) {
            self.nominal.1.solve_recalling(rhs);
            return;
        }
        // A step not prepared by `begin_step` (a restart's trial step)
        // factors here; without a factor its result is NaN, which the
        // iteration reports as a non-finite step.
        if self.prepare_factor(system, dt).is_err() {
            rhs.fill(f64::NAN);
            return;
        }
        if let Some((_, factor)) = &mut self.other {
            factor.solve_recalling(rhs);
        }
    }

    /// One integration of the step `from` with the contacts' `forces`,
    /// written into `end`: the loads at the predicted end, the beam's solve
    /// and the bodies' update.
    pub fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let (start, dt) = (from.state, from.dt);
        if !self.has_prediction {
            self.predict_from(start, dt);
        }
        self.loads_at_prediction(system, from, forces, end)?;
        if !self.start_known {
            self.know_start(system, from);
        }
        self.beam_step(system, start, dt, end);
        self.bodies_step(system, start, dt, end);
        copy(&mut end.beam_load, &self.load);
        for (x, frame) in end.contact_x.iter_mut().zip(&self.frames) {
            *x = frame.x;
        }
        self.keep_prediction(end);
        Ok(())
    }

    /// The step's loads on the beam (`load`) and the bodies
    /// (`end.body_loads`) at the predicted end configuration: its contact
    /// frames and force elements, found by the iteration at the last
    /// integration's end (`know_prediction`) or here.
    #[inline]
    fn loads_at_prediction(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        let known_laws = self.known_laws.take();
        let (predicted_u, predicted_v) = match self.has_prediction {
            true => {
                let address = end.beam_displacement.as_ptr() as usize;
                assert_eq!(address, self.end_address, "a step's integrations share one end");
                (&end.beam_displacement, &end.beam_velocity)
            }
            false => (&self.predicted_u, &self.predicted_v),
        };
        if known_laws.is_none() {
            self.guesses.clear();
            self.guesses.extend(from.frames.iter().map(|f| f.x));
            contact_frames(
                system,
                predicted_u,
                &self.predicted_bodies,
                (&self.guesses, from.parts),
                &mut self.frames,
            )?;
        }
        // The force elements' loads apart: the contact iteration reads them
        // (`ContactIteration::anticipate_laws`).
        let at = (self.predicted_bodies.as_slice(), predicted_v);
        let followers = HeldFollowers {
            held: &self.held_followers,
            used: &mut self.followers_used,
            gaps: match known_laws {
                Some(_) => self.known_gaps.as_slice(),
                None => &[],
            },
        };
        self.load_footprint.clear(&mut self.load);
        let contacts = add_loads_but_laws(
            system,
            &self.frames,
            (forces, followers),
            from.applied,
            at,
            (&mut self.load, &mut end.body_loads),
        );
        self.load_footprint.note(system, &self.frames);
        let laws = match known_laws {
            Some(power) => power,
            None => {
                self.law_loads.fill(Vector3::zeros());
                add_element_forces(&system.force_elements, at.0, &mut self.law_loads)
            }
        };
        for (load, law) in end.body_loads.iter_mut().zip(&self.law_loads) {
            *load += law;
        }
        self.end_dissipation = contacts + laws;
        Ok(())
    }

    /// The first integration's predicted end: the start moved on at its
    /// velocities, or (`predicts_accelerations`) at its accelerations.
    #[inline]
    fn predict_from(&mut self, start: &DynamicState, dt: f64) {
        self.known_laws = None;
        if let Some(seed) = &self.seeded {
            if seed.displacement.len() == start.beam_displacement.len()
                && seed.bodies.len() == start.bodies.len()
            {
                copy(&mut self.predicted_u, &seed.displacement);
                copy(&mut self.predicted_v, &seed.velocity);
                self.predicted_bodies.clear();
                self.predicted_bodies.extend_from_slice(&seed.bodies);
                return;
            }
        }
        copy(&mut self.predicted_u, &start.beam_displacement);
        self.predicted_u.axpy(dt, &start.beam_velocity, 1.0);
        copy(&mut self.predicted_v, &start.beam_velocity);
        self.predicted_bodies.clear();
        if self.predicts_accelerations {
            return self.predict_accelerated(start, dt);
        }
        self.predicted_bodies
            .extend(start.bodies.iter().map(|b| BodyState {
                position: b.position + dt * b.velocity,
                angle: b.angle + dt * b.angular_velocity,
                ..*b
            }));
    }

    /// `predict_from`'s second half with the start's accelerations: the
    /// compliant laws and force elements are then taken where the step
    /// ends to O(Δt³), not O(Δt²), and the step's first residual is
    /// smaller (`iteration::followers`).
    fn predict_accelerated(&mut self, start: &DynamicState, dt: f64) {
        let half = 0.5 * dt * dt;
        self.predicted_u.axpy(half, &start.beam_acceleration, 1.0);
        self.predicted_v.axpy(dt, &start.beam_acceleration, 1.0);
        let accelerated = start.bodies.iter().zip(&start.body_accelerations);
        self.predicted_bodies
            .extend(accelerated.map(|(b, a)| BodyState {
                position: b.position + dt * b.velocity + half * a.xy(),
                angle: b.angle + dt * b.angular_velocity + half * a.z,
                velocity: b.velocity + dt * a.xy(),
                angular_velocity: b.angular_velocity + dt * a.z,
            }));
    }

    /// The next integration's predicted end: this one's (the beam's left
    /// in `end`, `end_address`).
    #[inline]
    fn keep_prediction(&mut self, end: &DynamicState) {
        self.end_address = end.beam_displacement.as_ptr() as usize;
        self.predicted_bodies.clear();
        self.predicted_bodies.extend_from_slice(&end.bodies);
        self.has_prediction = true;
    }

    /// The start's terms of every integration of the step: C v0 + K u0
    /// and the dampers' power.
    fn know_start(&mut self, system: &System, from: &StepStart) {
        let start = from.state;
        if self.alpha != 0.0 {
            let (u0, v0) = (&start.beam_displacement, &start.beam_velocity);
            match self.ends.end_forces().recall((u0, v0)) {
                Some(kept) => copy(&mut self.start_internal, kept),
                None => {
                    let beam = &system.beam;
                    beam.internal_forces(u0, v0, &mut self.scratch, &mut self.start_internal);
                }
            }
        }
        if self.books {
            // The last step's end kept it where this is that end.
            let kept = self.ends.end_forces().element_sums_at(system, &start.bodies);
            let elements = kept.map_or_else(
                || dissipation_power(&system.force_elements, &start.bodies),
                |(power, _)| power,
            );
            self.start_dissipation = elements
                + follower_dissipation(system, from.frames, &start.bodies, &start.beam_velocity);
        }
        self.start_known = true;
    }

    /// Book the energy each step removes (`finish_step`), or not: a run
    /// that reads no energy output carries the start's totals unchanged.
    pub fn keep_energy_books(&mut self, on: bool) {
        self.books = on;
    }

    pub fn keeps_energy_books(&self) -> bool {
        self.books
    }

    /// The energy bookkeeping of the step from `from` that ended in `end`
    /// (its last integration): once per step, after the iteration has
    /// converged, instead of at every iterate.
    pub fn finish_step(&mut self, system: &System, from: &StepStart, end: &mut DynamicState) {
        let (start, dt) = (from.state, from.dt);
        if !self.books {
            // The next step's start needs K u + C v of this end where α ≠ 0.
            let keep = self.alpha != 0.0;
            (self.ends).keep_end_forces(system, end, keep, &mut self.scratch);
            end.beam_dissipated = start.beam_dissipated;
            end.dissipated = start.dissipated;
            end.numerical_dissipation = start.numerical_dissipation;
            return;
        }
        // Trapezoidal rule for the dampers' dissipation over the step.
        end.dissipated =
            start.dissipated + 0.5 * dt * (self.start_dissipation + self.end_dissipation);
        let weights = Weights {
            beta: self.beta,
            gamma: self.gamma,
        };
        // Structural damping: the power at the mean velocity, which for the
        // trapezoidal scheme (α = 0) is exactly the energy the step removes.
        let (structural, numerical) = step_dissipation(
            system,
            weights,
            (dt, &self.tractive),
            (start, end),
            (&mut self.ends, &mut self.scratch),
        );
        end.beam_dissipated = start.beam_dissipated + structural;
        end.numerical_dissipation = start.numerical_dissipation + numerical;
        // The next step's start power and this state's output row read them.
        self.ends.keep_element_sums(system, &end.bodies);
    }

    /// Beam: predictors, then
    /// M a1 + (1 + α) (C v1 + K u1) − α (C v0 + K u0) = (1 + α) f1 − α f0.
    /// Where the solve has the coarse-mesh correction, that is done at the
    /// step's first integration only; the others take its end state plus
    /// the response to their change of load, which is what the iteration's
    /// Delassus operator assumes. Solving the whole right-hand side again
    /// let its rounding, of the order of ε K u (at 65,536 elements 1e21 N
    /// on the start's acceleration spike under a wheel set down at rest),
    /// reach the contact through the correction as a different force at
    /// every iterate, and the iteration stalled. Elsewhere every
    /// integration solves the whole step: with the plain band factor the
    /// same scheme made a bouncing coach (`tests/physics/hht_events.rs`) gain
    /// 12 kJ of 2.2e8 J, not explained (so did the step's free motion plus
    /// the response to the whole load, 0.4 MJ).
    fn beam_step(
        &mut self,
        system: &System,
        start: &DynamicState,
        dt: f64,
        end: &mut DynamicState,
    ) {
        if !self.nominal.1.is_two_level() {
            return self.full_beam_step(system, start, dt, end);
        }
        if !self.base.known || self.base.dt != dt {
            self.full_beam_step(system, start, dt, end);
            let base = &mut self.base;
            copy(&mut base.load, &self.load);
            copy(&mut base.displacement, &end.beam_displacement);
            copy(&mut base.velocity, &end.beam_velocity);
            copy(&mut base.acceleration, &end.beam_acceleration);
            (base.known, base.dt) = (true, dt);
            return;
        }
        let (beta, gamma) = (self.beta, self.gamma);
        let mut change = std::mem::replace(&mut self.rhs, DVector::zeros(0));
        copy(&mut change, &self.load);
        change.axpy(-1.0, &self.base.load, 1.0);
        change.scale_mut(1.0 + self.alpha);
        self.solve_effective(system, dt, &mut change);
        copy(&mut end.beam_displacement, &self.base.displacement);
        end.beam_displacement.axpy(beta * dt * dt, &change, 1.0);
        copy(&mut end.beam_velocity, &self.base.velocity);
        end.beam_velocity.axpy(gamma * dt, &change, 1.0);
        copy(&mut end.beam_acceleration, &self.base.acceleration);
        end.beam_acceleration += &change;
        self.rhs = change;
    }

    fn full_beam_step(
        &mut self,
        system: &System,
        start: &DynamicState,
        dt: f64,
        end: &mut DynamicState,
    ) {
        if self.predictor_dt != Some(dt) {
            self.predict(system, start, dt);
        }
        let nominal = self.is_nominal(dt);
        if !nominal && self.prepare_factor(system, dt).is_err() {
            // Without a factor the step's result is NaN, which the
            // iteration reports as a non-finite step.
            for x in [
                &mut end.beam_displacement,
                &mut end.beam_velocity,
                &mut end.beam_acceleration,
            ] {
                x.fill(f64::NAN);
            }
            return;
        }
        let factor = match (nominal, &self.other) {
            (false, Some((_, factor))) => factor,
            _ => &self.nominal.1,
        };
        let EffectiveFactor::Band(factor) = factor else {
            return self.full_beam_step_by_vectors(system, start, dt, end);
        };
        let weights = ((self.alpha, self.beta, self.gamma), dt);
        let (load, internal) = (self.load.as_slice(), self.predictor_internal.as_slice());
        let start_terms = (self.start_internal.as_slice(), start.beam_load.as_slice());
        let terms = [load, internal, start_terms.0, start_terms.1];
        let stars = [self.predictor_u.as_slice(), self.predictor_v.as_slice()];
        fused_band_step(factor, weights, (terms, stars), &mut self.sweep, end);
    }

    /// The step's predictors u* = u0 + Δt v0 + Δt² (½ − β) a0 and
    /// v* = v0 + Δt (1 − γ) a0, and C v* + K u*: the same for every full
    /// integration of the step.
    fn predict(&mut self, system: &System, start: &DynamicState, dt: f64) {
        let (u0, v0, a0) = (
            &start.beam_displacement,
            &start.beam_velocity,
            &start.beam_acceleration,
        );
        let (beta, gamma) = (self.beta, self.gamma);
        let u1 = &mut self.predictor_u;
        copy(u1, u0);
        u1.axpy(dt, v0, 1.0);
        u1.axpy(dt * dt * (0.5 - beta), a0, 1.0);
        let v1 = &mut self.predictor_v;
        copy(v1, v0);
        v1.axpy(dt * (1.0 - gamma), a0, 1.0);
        let internal = &mut self.predictor_internal;
        system
            .beam
            .internal_forces(u1, v1, &mut self.scratch, internal);
        self.predictor_dt = Some(dt);
    }

    /// `full_beam_step` where the solve is not the plain band factor's
    /// (modal, two-level and wide-band solves), by whole-vector operations.
    fn full_beam_step_by_vectors(
        &mut self,
        system: &System,
        start: &DynamicState,
        dt: f64,
        end: &mut DynamicState,
    ) {
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        let n = self.load.len();
        // One pass each side of the solve, each entry's operations those
        // of the whole-vector passes they replace, in their order (scale,
        // then a x + y per axpy): the same bits, a tenth of the passes.
        fn of(x: &DVector<f64>, n: usize) -> &[f64] {
            &x.as_slice()[..n]
        }
        let (load, internal) = (of(&self.load, n), of(&self.predictor_internal, n));
        let (start_internal, start_load) = (of(&self.start_internal, n), of(&start.beam_load, n));
        let forcing = 1.0 + alpha;
        for (i, r) in self.rhs.as_mut_slice()[..n].iter_mut().enumerate() {
            let mut sum = load[i] * forcing;
            sum += -forcing * internal[i];
            if alpha != 0.0 {
                sum += alpha * start_internal[i];
                sum += -alpha * start_load[i];
            }
            *r = sum;
        }
        let mut a1 = std::mem::replace(&mut self.rhs, DVector::zeros(0));
        self.solve_effective(system, dt, &mut a1);
        let (to_u, to_v) = (beta * dt * dt, gamma * dt);
        let (u_star, v_star) = (of(&self.predictor_u, n), of(&self.predictor_v, n));
        let (u1, v1) = (&mut end.beam_displacement, &mut end.beam_velocity);
        let (u1, v1) = (&mut u1.as_mut_slice()[..n], &mut v1.as_mut_slice()[..n]);
        for (i, &a) in a1.as_slice()[..n].iter().enumerate() {
            u1[i] = to_u * a + u_star[i];
            v1[i] = to_v * a + v_star[i];
        }
        // The solved vector is the end's acceleration: handed over, not
        // copied (the end's old buffer, of the same length, becomes the
        // next right-hand side, whose rows are all written before read).
        let length = end.beam_acceleration.len();
        assert_eq!(length, a1.len(), "the end's acceleration's length");
        self.rhs = std::mem::replace(&mut end.beam_acceleration, a1);
    }

    /// Every body: the same forcing and Newmark weights as the beam. Its
    /// end-of-step load is already in `end.body_loads`; each body's
    /// tractive force at the step's end (zero if free) into `tractive`.
    /// Component by component, in the order of the vector expressions
    /// (f = (1 + α) g − α g₀, Δq = Δt q̇₀ + Δt² ((½ − β) a₀ + β a₁),
    /// Δq̇ = Δt ((1 − γ) a₀ + γ a₁)): the same bits, with every slice cut
    /// to one length so the loop has no index checks (nalgebra's small
    /// vectors and the checks were two thirds of the loop).
    fn bodies_step(&mut self, system: &System, start: &DynamicState, dt: f64, end: &mut DynamicState) {
        let (alpha, beta, gamma) = (self.alpha, self.beta, self.gamma);
        let n = system.bodies.len();
        let (bodies, tractive) = (&system.bodies[..n], &mut self.tractive[..n]);
        let (starts, start_loads) = (&start.bodies[..n], &start.body_loads[..n]);
        let start_accelerations = &start.body_accelerations[..n];
        let (ends, loads) = (&mut end.bodies[..n], &end.body_loads[..n]);
        let end_accelerations = &mut end.body_accelerations[..n];
        let (dt2, forcing) = (dt * dt, 1.0 + alpha);
        let (a0_u, a0_v) = (0.5 - beta, 1.0 - gamma);
        end.tractive_work = start.tractive_work;
        for b in 0..n {
            let (g, g0, a0, s) = (&loads[b], &start_loads[b], &start_accelerations[b], &starts[b]);
            let f = Vector3::from_fn(|i, _| forcing * g[i] - alpha * g0[i]);
            let a1 = bodies[b].acceleration(&f);
            let rates = [s.velocity.x, s.velocity.y, s.angular_velocity];
            let du: [f64; 3] =
                std::array::from_fn(|i| dt * rates[i] + dt2 * (a0_u * a0[i] + beta * a1[i]));
            let dv: [f64; 3] = std::array::from_fn(|i| dt * (a0_v * a0[i] + gamma * a1[i]));
            ends[b] = BodyState {
                position: Vector2::new(s.position.x + du[0], s.position.y + du[1]),
                velocity: Vector2::new(s.velocity.x + dv[0], s.velocity.y + dv[1]),
                angle: s.angle + du[2],
                angular_velocity: s.angular_velocity + dv[2],
            };
            end_accelerations[b] = a1;
            tractive[b] = match bodies[b].drive {
                None => 0.0,
                // Trapezoidal, as the scheme moves the body: exact in the
                // balance for α = 0 (the start's force is the last step's).
                Some(_) => {
                    let start_force = bodies[b].mass * a0.x - g0.x;
                    let end_force = bodies[b].tractive_force(&f);
                    end.tractive_work += 0.5 * (start_force + end_force) * du[0];
                    end_force
                }
            };
        }
    }

    /// See `TimeIntegrator::seed_prediction`.
    pub fn seed_prediction(&mut self, end: Option<(&DynamicState, f64)>) {
        self.seed = end.map(|(end, dt)| Seed {
            dt,
            displacement: end.beam_displacement.clone(),
            velocity: end.beam_velocity.clone(),
            bodies: end.bodies.clone(),
        });
    }

    /// See `TimeIntegrator::seeded_bodies`.
    pub fn seeded_bodies(&self) -> Option<&[BodyState]> {
        self.seeded.as_ref().map(|seed| seed.bodies.as_slice())
    }

    /// K u + C v at the last accepted step's end, kept (see `EndForces`).
    pub fn end_forces(&self) -> &EndForces {
        self.ends.end_forces()
    }

    /// See `Integrator::hold_followers`.
    pub fn hold_followers(&mut self, held: &[bool]) {
        self.held_followers.clear();
        self.held_followers.extend_from_slice(held);
    }

    /// What the iteration measured at the last integration's end, which
    /// is the next one's prediction (`TimeIntegrator::know_prediction`):
    /// taken only while there is such a prediction and the frames are one
    /// per contact.
    pub fn know_prediction(&mut self, known: super::KnownAtPrediction) {
        if !self.has_prediction || known.frames.len() != self.frames.len() {
            return;
        }
        let (laws, frames) = (known.laws, known.frames);
        let gaps = laws.follower_gaps;
        if laws.element_loads.len() == self.law_loads.len() && gaps.len() == self.frames.len() {
            self.frames.copy_from_slice(frames);
            self.law_loads.copy_from_slice(laws.element_loads);
            self.known_gaps.clear();
            self.known_gaps.extend_from_slice(gaps);
            self.known_laws = Some(laws.element_power);
        }
    }

    /// Every follower's force in the last integration.
    pub fn follower_forces_used(&self) -> &[ContactForce] {
        &self.followers_used
    }

    /// The force elements' loads on each body in the last integration, and
    /// the bodies the next evaluates them at (the last end, which the
    /// caller may move).
    pub fn body_predictions(&mut self) -> (&[Vector3<f64>], &mut [BodyState]) {
        (&self.law_loads, &mut self.predicted_bodies)
    }

    /// The end-of-step force enters with weight 1 + α (at t_{n+1+α}).
    pub fn body_weights(&self, dt: f64) -> (f64, f64) {
        let forcing = 1.0 + self.alpha;
        (forcing * self.gamma * dt, forcing * self.beta * dt * dt)
    }

    /// The nominal step's band factor of the effective matrix A and the
    /// weights (w_u, w_v) of `beam_response` on that step: u = w_u A⁻¹ f,
    /// v = w_v A⁻¹ f. None where the solve is not the plain band factor's
    /// (a modal structure, or a fine mesh's two-level solve).
    pub fn nominal_band_response(&self) -> Option<(&crate::band::BandLdlt, f64, f64)> {
        let EffectiveFactor::Band(factor) = &self.nominal.1 else {
            return None;
        };
        let (h, forcing) = (self.nominal.0, 1.0 + self.alpha);
        Some((
            factor,
            forcing * self.beta * h * h,
            forcing * self.gamma * h,
        ))
    }

    /// See `TimeIntegrator::point_compliance`: rowᵀ S⁻¹ row over the
    /// shape's coordinates, weighted as `beam_response` weighs the solve.
    pub fn point_compliance(
        &mut self,
        system: &System,
        shape: &Shape,
        row: &[f64; 4],
        dt: f64,
    ) -> Option<(f64, f64)> {
        if !self.is_nominal(dt) {
            return None;
        }
        let element = shape.element;
        if self.element_inverse.len() <= element {
            self.element_inverse.resize(element + 1, None);
        }
        let block = match self.element_inverse[element] {
            Some(block) => block,
            None => {
                let block = self.element_block(system, &shape.dofs)?;
                self.element_inverse[element] = Some(block);
                block
            }
        };
        let row = Vector4::from(*row);
        let compliance = row.dot(&(block * row));
        let forcing = 1.0 + self.alpha;
        Some((
            forcing * self.beta * dt * dt * compliance,
            forcing * self.gamma * dt * compliance,
        ))
    }

    /// S⁻¹ of the nominal step on an element's four `dofs` (0 where
    /// held), from the inverse within the band (swept at the first call).
    fn element_block(&mut self, system: &System, dofs: &[Option<usize>; 4]) -> Option<Matrix4<f64>> {
        let factor = &self.nominal.1;
        let inverse = self
            .nominal_inverse
            .get_or_insert_with(|| factor.inverse_within_band())
            .as_ref()?;
        let coordinates = dofs.map(|dof| dof.and_then(|d| system.beam.load_coordinate(d)));
        let mut block = Matrix4::zeros();
        for (a, row) in coordinates.iter().enumerate() {
            for (b, column) in coordinates.iter().enumerate() {
                if let (Some(row), Some(column)) = (row, column) {
                    block[(a, b)] = inverse.entry(*row, *column)?;
                }
            }
        }
        Some(block)
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
        copy(&mut a1, load);
        a1.scale_mut(1.0 + self.alpha);
        self.solve_effective(system, dt, &mut a1);
        copy(displacement, &a1);
        displacement.scale_mut(self.beta * dt * dt);
        copy(velocity, &a1);
        velocity.scale_mut(self.gamma * dt);
        self.work = a1;
    }
}
