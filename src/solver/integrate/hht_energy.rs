//! The energy HHT-α's numerical damping removes in one step, from the
//! scheme's own discrete energy identity (not from the balance).
//!
//! Newmark's updates, which HHT-α shares, give for any mass M exactly
//!   Δu = Δt v̄ + δ Δt² Δa,   Δv = Δt a_γ,
//! with v̄ the step's mean velocity, a_γ = (1 − γ) a₀ + γ a₁, δ = β − γ/2
//! and κ = γ − ½; multiplying the second by M v̄ and using the first:
//!   Δ(½ vᵀ M v) = Δuᵀ M a_γ − δ Δt² Δ(½ aᵀ M a) − κ δ Δt² Δaᵀ M Δa.
//! The masses move under M a_γ, the α-weighted forces the scheme applied;
//! the energy balance books the work of the physical forces at the step's
//! two ends by the trapezoidal rule, Δuᵀ F̄ (exact for the beam's strain
//! energy, gravity and constant forces), and the structural damping as
//! Δt v̄ᵀ C v̄. What the scheme removes beyond that is
//!   D = Δuᵀ (F̄ − M a_γ) + δ Δt² Δ(½ aᵀ M a) + κ δ Δt² Δaᵀ M Δa
//!       + δ Δt² Δaᵀ C v̄,
//! each term a product of the step's increments. For HHT-α (δ = α²/4,
//! κ = −α) it vanishes at α = 0, where the scheme is the trapezoidal rule.
//! The contact forces enter F̄ and M a_γ on beam and body alike, with the
//! same weights, so their share of D is their work on the contact's
//! relative motion, as the balance's.
//!
//! The beam's terms are sums over its entries of products taken at the
//! step's two ends only (K u + C v, C v, M a: `StepEnds`), each end's
//! computed once and recalled as the next step's start: K ū + C v̄ and
//! M a_γ are the same linear combinations of the ends' products.

use nalgebra::{DVector, Vector3};

use super::step_end::{same_bits, EndForces};
use super::DynamicState;
use crate::system::System;

/// The scheme's constants: (δ, κ) = (β − γ/2, γ − ½).
#[derive(Debug, Clone, Copy)]
pub struct Weights {
    pub beta: f64,
    pub gamma: f64,
}

impl Weights {
    fn delta(&self) -> f64 {
        self.beta - 0.5 * self.gamma
    }

    fn kappa(&self) -> f64 {
        self.gamma - 0.5
    }
}

/// M a and ½ aᵀ M a at one acceleration a, with a's copy to recognise
/// it by.
#[derive(Debug, Clone, Default)]
struct Inertia {
    acceleration: DVector<f64>,
    product: DVector<f64>,
    energy: f64,
    kept: bool,
}

impl Inertia {
    fn keep(&mut self, system: &System, a: &DVector<f64>) {
        for x in [&mut self.acceleration, &mut self.product] {
            if x.len() != a.len() {
                *x = DVector::zeros(a.len());
            }
        }
        self.acceleration.copy_from(a);
        system.beam.mass_times(a, &mut self.product);
        self.energy = 0.5 * a.dot(&self.product);
        self.kept = true;
    }

    fn is_of(&self, a: &DVector<f64>) -> bool {
        self.kept && same_bits(&self.acceleration, a)
    }
}

/// The structure's products at a step's two ends, from which the books
/// take every term: K u + C v and C v (`EndForces`), M a and ½ aᵀ M a
/// (`Inertia`). A step's end is the next step's start, so each step
/// computes its end's alone (three products: K u, C v, M a) and recalls
/// its start's; HHT-α's own C v₀ + K u₀ is recalled too (`end_forces`).
#[derive(Debug, Clone, Default)]
pub struct StepEnds {
    end: EndForces,
    start: EndForces,
    end_inertia: Inertia,
    start_inertia: Inertia,
}

impl StepEnds {
    /// K u + C v at the last accepted step's end, where kept.
    pub fn end_forces(&self) -> &EndForces {
        &self.end
    }

    /// Keep K u + C v at the end of a step whose books are not kept
    /// (HHT-α's next start reads them), or forget the last (`keep` false).
    pub fn keep_end_forces(
        &mut self,
        system: &System,
        end: &DynamicState,
        keep: bool,
        scratch: &mut DVector<f64>,
    ) {
        match keep {
            true => {
                let state = (&end.beam_displacement, &end.beam_velocity);
                self.end.keep(system, state, false, scratch);
            }
            false => self.end.forget(),
        }
    }

    /// Keep the force elements' power and energy at the last step's end
    /// `bodies` (`EndForces::keep_element_sums`).
    pub fn keep_element_sums(&mut self, system: &System, bodies: &[crate::body::BodyState]) {
        self.end.keep_element_sums(system, bodies);
    }

    /// The products of the step from `start` to `end`: the start's
    /// recalled where it is the last end's state, the end's computed.
    fn prepare(
        &mut self,
        system: &System,
        (start, end): (&DynamicState, &DynamicState),
        scratch: &mut DVector<f64>,
    ) {
        let damped = system.beam.is_damped();
        let (u0, v0) = (&start.beam_displacement, &start.beam_velocity);
        let recalled = self.end.recall((u0, v0)).is_some();
        match recalled && (self.end.damping().is_some() || !damped) {
            true => std::mem::swap(&mut self.start, &mut self.end),
            false => self.start.keep(system, (u0, v0), damped, scratch),
        }
        if self.end_inertia.is_of(&start.beam_acceleration) {
            std::mem::swap(&mut self.start_inertia, &mut self.end_inertia);
        } else {
            self.start_inertia.keep(system, &start.beam_acceleration);
        }
        let state = (&end.beam_displacement, &end.beam_velocity);
        self.end.keep(system, state, damped, scratch);
        self.end_inertia.keep(system, &end.beam_acceleration);
    }
}

/// The step's energies: what the beam's structural damping removes,
/// Δt v̄ᵀ C v̄, and D (J) of the step from `start` to `end`, the beam's and
/// every body's. `tractive` holds each driven body's tractive force at the
/// step's end as the balance books it (zero for free bodies).
pub fn step_dissipation(
    system: &System,
    w: Weights,
    (dt, tractive): (f64, &[f64]),
    (start, end): (&DynamicState, &DynamicState),
    (ends, scratch): (&mut StepEnds, &mut DVector<f64>),
) -> (f64, f64) {
    ends.prepare(system, (start, end), scratch);
    let (damping, beam) = beam_dissipation(w, dt, (start, end), ends);
    let bodies: f64 = (0..system.bodies.len())
        .map(|b| body_dissipation(system, b, w, dt, (start, end), tractive[b]))
        .sum();
    (dt * damping, beam + bodies)
}

/// The sums of the beam's share over its entries: Δuᵀ (F̄ − M a_γ),
/// Δaᵀ M Δa, Δaᵀ C v̄ and v̄ᵀ C v̄.
#[derive(Default)]
struct Sums {
    work: f64,
    increment: f64,
    damping: f64,
    power: f64,
}

/// The beam's (v̄ᵀ C v̄, share of D), in one pass over the entries from
/// the products at the two ends (`ends`, prepared): K ū + C v̄ is the
/// mean of the ends' internal forces and M a_γ the weighted sum of their
/// inertia forces, the matrices being constant.
fn beam_dissipation(
    w: Weights,
    dt: f64,
    (start, end): (&DynamicState, &DynamicState),
    ends: &StepEnds,
) -> (f64, f64) {
    let (i0, i1) = (ends.start.internal(), ends.end.internal());
    let (m0, m1) = (&ends.start_inertia, &ends.end_inertia);
    let sums = match (ends.start.damping(), ends.end.damping()) {
        (Some(c0), Some(c1)) => sums(w, (start, end), (i0, i1), (m0, m1), Some((c0, c1))),
        _ => sums(w, (start, end), (i0, i1), (m0, m1), None),
    };
    let (delta, kappa) = (w.delta(), w.kappa());
    let acceleration_energy = m1.energy - m0.energy;
    let quadratic = acceleration_energy + kappa * sums.increment + sums.damping;
    (sums.power, sums.work + delta * dt * dt * quadratic)
}

/// `Sums` over the entries, with C v at the ends where the beam is damped.
fn sums<'a>(
    w: Weights,
    (start, end): (&'a DynamicState, &'a DynamicState),
    (i0, i1): (&'a DVector<f64>, &'a DVector<f64>),
    (m0, m1): (&'a Inertia, &'a Inertia),
    damping: Option<(&'a DVector<f64>, &'a DVector<f64>)>,
) -> Sums {
    let n = start.beam_displacement.len();
    // Slices cut to one length: the loop indexes them without checks.
    let of = |x: &'a DVector<f64>| &x.as_slice()[..n];
    let ends = |x: &'a DVector<f64>, y: &'a DVector<f64>| [of(x), of(y)];
    let entries = Entries {
        u: ends(&start.beam_displacement, &end.beam_displacement),
        a: ends(&start.beam_acceleration, &end.beam_acceleration),
        f: ends(&start.beam_load, &end.beam_load),
        p: ends(&m0.product, &m1.product),
        i: ends(i0, i1),
        v: ends(&start.beam_velocity, &end.beam_velocity),
        // Not read where the beam is undamped.
        c: damping.map_or([&[][..]; 2], |(c0, c1)| ends(c0, c1)),
    };
    match damping {
        Some(_) => sums_pass::<true>(w, &entries),
        None => sums_pass::<false>(w, &entries),
    }
}

/// The vectors at a step's two ends that `sums` reads, each cut to the
/// beam's length (C v empty where the beam is undamped).
struct Entries<'a> {
    u: [&'a [f64]; 2],
    a: [&'a [f64]; 2],
    f: [&'a [f64]; 2],
    p: [&'a [f64]; 2],
    i: [&'a [f64]; 2],
    v: [&'a [f64]; 2],
    c: [&'a [f64]; 2],
}

/// `sums` in one pass over the entries; with `DAMPED`, the damping's two
/// sums beside the others (each sum's terms in the entries' order, as two
/// passes took them: the same bits, the four chains of additions side by
/// side).
#[inline(always)]
fn sums_pass<const DAMPED: bool>(w: Weights, e: &Entries) -> Sums {
    let (one_minus_gamma, gamma) = (1.0 - w.gamma, w.gamma);
    let ([u0, u1], [a0, a1], [f0, f1]) = (e.u, e.a, e.f);
    let ([p0, p1], [i0, i1], [v0, v1], [c0, c1]) = (e.p, e.i, e.v, e.c);
    let n = u0.len();
    let mut s = Sums::default();
    for i in 0..n {
        let (du, da) = (u1[i] - u0[i], a1[i] - a0[i]);
        let load = 0.5 * (f0[i] + f1[i]);
        let internal = 0.5 * (i0[i] + i1[i]);
        s.work += du * (load - internal - (one_minus_gamma * p0[i] + gamma * p1[i]));
        s.increment += da * (p1[i] - p0[i]);
        if DAMPED {
            let mean_v = 0.5 * (v0[i] + v1[i]);
            let c_mean_v = 0.5 * (c0[i] + c1[i]);
            s.damping += da * c_mean_v;
            s.power += mean_v * c_mean_v;
        }
    }
    s
}

/// Body `b`'s share, over (x, y) and, for a body that turns, θ. A driven
/// body's horizontal force includes the tractive force, at the step's
/// start as the start's acceleration implies and at its end as booked.
fn body_dissipation(
    system: &System,
    b: usize,
    w: Weights,
    dt: f64,
    (start, end): (&DynamicState, &DynamicState),
    tractive: f64,
) -> f64 {
    let body = &system.bodies[b];
    let (s, e) = (&start.bodies[b], &end.bodies[b]);
    let increment = Vector3::new(
        e.position.x - s.position.x,
        e.position.y - s.position.y,
        e.angle - s.angle,
    );
    let mass = Vector3::new(
        body.mass,
        body.mass,
        if body.turns() { body.inertia } else { 0.0 },
    );
    let (a0, a1) = (start.body_accelerations[b], end.body_accelerations[b]);
    let (mut f0, mut f1) = (start.body_loads[b], end.body_loads[b]);
    if body.drive.is_some() {
        f0.x = body.mass * a0.x;
        f1.x += tractive;
    }
    if !body.turns() {
        (f0.z, f1.z) = (0.0, 0.0);
    }
    let applied = (1.0 - w.gamma) * a0 + w.gamma * a1;
    let mean_force = 0.5 * (f0 + f1);
    let work = increment.dot(&(mean_force - mass.component_mul(&applied)));
    let da = a1 - a0;
    let energy = |a: &Vector3<f64>| 0.5 * mass.dot(&a.component_mul(a));
    let (delta, kappa) = (w.delta(), w.kappa());
    work + delta * dt * dt * (energy(&a1) - energy(&a0) + 2.0 * kappa * energy(&da))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two states of the built-in `scene`'s system whose beam vectors
    /// are smooth fields of unrelated shapes (no step relates them).
    fn two_states(scene: &str) -> (crate::Simulation, DynamicState, DynamicState) {
        let scene = super::super::step_end::scene_named(scene);
        let sim = crate::Simulation::new(&scene).unwrap();
        let mut start = sim.state().dynamic;
        let mut end = start.clone();
        let field = |scale: f64, k: f64| {
            move |i: usize| scale * (libm::sin(k * i as f64) + 0.3 * libm::cos(0.7 * k * i as f64))
        };
        for (state, k) in [(&mut start, 0.13), (&mut end, 0.29)] {
            let fill = |x: &mut DVector<f64>, f: &dyn Fn(usize) -> f64| {
                x.iter_mut().enumerate().for_each(|(i, v)| *v = f(i))
            };
            fill(&mut state.beam_displacement, &field(1e-3, k));
            fill(&mut state.beam_velocity, &field(2e-2, 1.3 * k));
            fill(&mut state.beam_acceleration, &field(3.0, 1.7 * k));
            fill(&mut state.beam_load, &field(4e4, 0.5 * k));
        }
        (sim, start, end)
    }

    /// D's beam share and v̄ᵀ C v̄ by the products of the step's means
    /// (K ū + C v̄, M a_γ, ½ aᵀ M a of a₀, a₁ and Δa, C v̄), as the books
    /// took them before they read the ends' products.
    fn by_the_means(
        system: &System,
        w: Weights,
        dt: f64,
        (s, e): (&DynamicState, &DynamicState),
    ) -> (f64, f64) {
        let beam = &system.beam;
        let mean = |a: &DVector<f64>, b: &DVector<f64>| (a + b) * 0.5;
        let (u, v) = (
            mean(&s.beam_displacement, &e.beam_displacement),
            mean(&s.beam_velocity, &e.beam_velocity),
        );
        let n = u.len();
        let (mut internal, mut scratch, mut c_v) =
            (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
        beam.internal_forces(&u, &v, &mut scratch, &mut internal);
        beam.internal_forces(&DVector::zeros(n), &v, &mut scratch, &mut c_v);
        let applied = &s.beam_acceleration * (1.0 - w.gamma) + &e.beam_acceleration * w.gamma;
        let mut inertia = DVector::zeros(n);
        beam.mass_times(&applied, &mut inertia);
        let forces = mean(&s.beam_load, &e.beam_load) - internal - inertia;
        let work = (&e.beam_displacement - &s.beam_displacement).dot(&forces);
        let da = &e.beam_acceleration - &s.beam_acceleration;
        let energy = |a: &DVector<f64>| beam.kinetic_energy(a);
        let quadratic = energy(&e.beam_acceleration) - energy(&s.beam_acceleration)
            + w.kappa() * 2.0 * energy(&da)
            + da.dot(&c_v);
        (v.dot(&c_v), work + w.delta() * dt * dt * quadratic)
    }

    #[test]
    fn the_ends_products_give_the_means_books_up_to_rounding() {
        let alpha: f64 = -0.1;
        let w = Weights {
            beta: 0.25 * (1.0 - alpha) * (1.0 - alpha),
            gamma: 0.5 - alpha,
        };
        let dt = 2.5e-4;
        for scene in [
            "train-8-coaches-20m-300-rail",
            "train-8-coaches-20m-300-hertz",
        ] {
            let (sim, start, end) = two_states(scene);
            let system = sim.system();
            let (power, beam) = by_the_means(system, w, dt, (&start, &end));
            let mut ends = StepEnds::default();
            let mut scratch = DVector::zeros(start.beam_displacement.len());
            ends.prepare(system, (&start, &end), &mut scratch);
            let (new_power, new_beam) = beam_dissipation(w, dt, (&start, &end), &ends);
            assert!(power > 0.0 && beam.abs() > 0.0, "{scene}: {power}, {beam}");
            assert!(
                (new_power - power).abs() <= 1e-12 * power,
                "{scene}: {new_power} against {power}"
            );
            assert!(
                (new_beam - beam).abs() <= 1e-12 * beam.abs(),
                "{scene}: {new_beam} against {beam}"
            );
            // The next step recalls this end's products as its start's.
            let mut next = end.clone();
            next.beam_displacement *= 1.1;
            ends.prepare(system, (&end, &next), &mut scratch);
            let (recalled, kept) = (ends.start.internal().clone(), &ends.start_inertia.product);
            let mut internal = DVector::zeros(scratch.len());
            system.beam.internal_forces(
                &end.beam_displacement,
                &end.beam_velocity,
                &mut scratch,
                &mut internal,
            );
            assert_eq!(recalled, internal, "{scene}");
            let mut inertia = DVector::zeros(scratch.len());
            system.beam.mass_times(&end.beam_acceleration, &mut inertia);
            assert_eq!(kept, &inertia, "{scene}");
        }
    }

    #[test]
    fn hht_constants_give_the_known_delta_and_kappa() {
        for alpha in [0.0, -0.05, -0.1, -1.0 / 3.0] {
            let w = Weights {
                beta: 0.25 * (1.0 - alpha) * (1.0 - alpha),
                gamma: 0.5 - alpha,
            };
            assert!((w.delta() - alpha * alpha / 4.0).abs() < 1e-15);
            assert!((w.kappa() + alpha).abs() < 1e-15);
        }
    }
}
