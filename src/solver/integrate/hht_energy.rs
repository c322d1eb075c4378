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

use nalgebra::{DVector, Vector3};

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

/// Work buffers of the beam's share, one per vector (reused every step).
pub struct Buffers {
    mean_u: DVector<f64>,
    mean_v: DVector<f64>,
    vector: DVector<f64>,
    product: DVector<f64>,
    scratch: DVector<f64>,
}

impl Buffers {
    pub fn new(free_dofs: usize) -> Buffers {
        let z = || DVector::zeros(free_dofs);
        Buffers {
            mean_u: z(),
            mean_v: z(),
            vector: z(),
            product: z(),
            scratch: z(),
        }
    }
}

/// D of the step from `start` to `end` (J): the beam's and every body's;
/// `step_means` has filled `buffers`' means.
/// `tractive` holds each driven body's tractive force at the step's end as
/// the balance books it (zero for free bodies).
pub fn step_dissipation(
    system: &System,
    w: Weights,
    dt: f64,
    (start, end): (&DynamicState, &DynamicState),
    tractive: &[f64],
    buffers: &mut Buffers,
) -> f64 {
    let beam = beam_dissipation(system, w, dt, (start, end), buffers);
    let bodies: f64 = (0..system.bodies.len())
        .map(|b| body_dissipation(system, b, w, dt, (start, end), tractive[b]))
        .sum();
    beam + bodies
}

/// The step's mean displacement and velocity, (u₀ + u₁)/2 and
/// (v₀ + v₁)/2, into `buffers` (one pass): `step_dissipation` reads them,
/// and the structural damping's power is taken at the mean velocity.
pub fn step_means<'a>(
    (start, end): (&DynamicState, &DynamicState),
    b: &'a mut Buffers,
) -> &'a DVector<f64> {
    // On slices: nalgebra's element iterators cost several times the sums.
    let (u0, u1) = (
        start.beam_displacement.as_slice(),
        end.beam_displacement.as_slice(),
    );
    for (mean, (u0, u1)) in b.mean_u.as_mut_slice().iter_mut().zip(u0.iter().zip(u1)) {
        *mean = (u0 + u1) * 0.5;
    }
    let (v0, v1) = (start.beam_velocity.as_slice(), end.beam_velocity.as_slice());
    for (mean, (v0, v1)) in b.mean_v.as_mut_slice().iter_mut().zip(v0.iter().zip(v1)) {
        *mean = (v0 + v1) * 0.5;
    }
    &b.mean_v
}

/// The beam's share; `step_means` has filled the buffers' means. Each
/// vector expression is one pass, with the bits of nalgebra's operations
/// one after the other.
fn beam_dissipation(
    system: &System,
    w: Weights,
    dt: f64,
    (start, end): (&DynamicState, &DynamicState),
    b: &mut Buffers,
) -> f64 {
    let beam = &system.beam;
    let (u0, a0) = (&start.beam_displacement, &start.beam_acceleration);
    let (u1, a1) = (&end.beam_displacement, &end.beam_acceleration);
    // F̄ − M a_γ = f̄ − (K ū + C v̄) − M a_γ (the internal forces are linear).
    beam.internal_forces(&b.mean_u, &b.mean_v, &mut b.scratch, &mut b.product);
    let (one_minus_gamma, gamma) = (1.0 - w.gamma, w.gamma);
    let (a0, a1) = (a0.as_slice(), a1.as_slice());
    for (x, (a0, a1)) in b.vector.as_mut_slice().iter_mut().zip(a0.iter().zip(a1)) {
        *x = gamma * a1 + a0 * one_minus_gamma;
    }
    beam.mass_times(&b.vector, &mut b.scratch);
    let loads = start
        .beam_load
        .as_slice()
        .iter()
        .zip(end.beam_load.as_slice());
    let forces = b
        .product
        .as_mut_slice()
        .iter_mut()
        .zip(b.scratch.as_slice());
    for (x, ((l0, l1), (p, s))) in b.vector.as_mut_slice().iter_mut().zip(loads.zip(forces)) {
        *p += s;
        *x = (l0 + l1) * 0.5 - *p;
    }
    let (u0, u1) = (u0.as_slice(), u1.as_slice());
    for (p, (u0, u1)) in b.product.as_mut_slice().iter_mut().zip(u0.iter().zip(u1)) {
        *p = u1 - u0;
    }
    let work = b.product.dot(&b.vector);
    // Δa, for the quadratic terms.
    for (x, (a0, a1)) in b.vector.as_mut_slice().iter_mut().zip(a0.iter().zip(a1)) {
        *x = a1 - a0;
    }
    let (a0, a1) = (&start.beam_acceleration, &end.beam_acceleration);
    let (delta, kappa) = (w.delta(), w.kappa());
    let h2 = dt * dt;
    let acceleration_energy = beam.kinetic_energy(a1) - beam.kinetic_energy(a0);
    let increment = 2.0 * beam.kinetic_energy(&b.vector);
    let mut damping = 0.0;
    if beam.is_damped() && delta != 0.0 {
        b.mean_u.fill(0.0);
        beam.internal_forces(&b.mean_u, &b.mean_v, &mut b.scratch, &mut b.product);
        damping = b.vector.dot(&b.product);
    }
    work + delta * h2 * (acceleration_energy + kappa * increment + damping)
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
