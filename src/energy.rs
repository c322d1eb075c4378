//! The energy balance of a run, term by term: kinetic, strain and spring
//! energy of the current state plus the energy the steps booked (dampers,
//! structural damping, impacts, HHT-α's numerical damping) minus the work
//! of gravity, of the applied forces and of the drives.

use crate::integrate::EndForces;
use crate::state::SimState;
use crate::system::System;

/// The structure's strain energy in `state` (J): from the K u the last
/// step kept (`end`) where `state` is its end and that gives the bits of
/// `strain_energy` (the rail over the deck), else `strain_energy`.
pub fn structure_strain(system: &System, state: &SimState, end: Option<&EndForces>) -> f64 {
    let d = &state.dynamic;
    let (u, v) = (&d.beam_displacement, &d.beam_velocity);
    let kept = end.and_then(|end| end.strain_energy_at((u, v)));
    kept.unwrap_or_else(|| system.beam.strain_energy(u))
}

/// Kinetic energy of the bodies (J).
pub fn body_kinetic(system: &System, state: &SimState) -> f64 {
    system
        .bodies
        .iter()
        .zip(&state.dynamic.bodies)
        .map(|(body, body_state)| body.kinetic_energy(body_state))
        .sum()
}

/// Potential energy of the force elements and of the followers'
/// suspensions (at their gaps at the end of the last step) (J).
pub fn spring(system: &System, state: &SimState) -> f64 {
    spring_with(system, state, None)
}

/// `spring`, the force elements' share recalled from the last step's
/// kept products `end` where `state` is its end (`EndForces::element_sums_at`,
/// the same bits).
pub fn spring_with(system: &System, state: &SimState, end: Option<&EndForces>) -> f64 {
    let bodies = &state.dynamic.bodies;
    let kept = end.and_then(|end| end.element_sums_at(system, bodies));
    let elements = kept.map_or_else(|| system.spring_energy(bodies), |(_, energy)| energy);
    let followers: f64 = system
        .contacts
        .iter()
        .zip(&state.contacts)
        .filter_map(|(c, status)| c.follower.map(|f| f.potential_energy(status.gap)))
        .sum();
    elements + followers
}

/// Kinetic + strain + spring energy + energy dissipated − work done on
/// the system (J), with `spring` (the spring energy) already known and
/// the last step's kept products `end` (`structure_strain`): zero to
/// round-off less the initial energy when the books are kept.
pub fn balance_with(
    system: &System,
    state: &SimState,
    (spring, end): (f64, Option<&EndForces>),
) -> f64 {
    let energies = StateEnergies {
        body_kinetic: body_kinetic(system, state),
        beam_kinetic: system.beam.kinetic_energy(&state.dynamic.beam_velocity),
        strain: structure_strain(system, state, end),
        spring,
    };
    balance_of(state, energies)
}

/// The energies a state holds (J), each as its own function gives it
/// (`body_kinetic`, `Structure::kinetic_energy`, `structure_strain`,
/// `spring`).
#[derive(Debug, Clone, Copy)]
pub struct StateEnergies {
    pub body_kinetic: f64,
    pub beam_kinetic: f64,
    pub strain: f64,
    pub spring: f64,
}

/// `balance_with` from the state's `energies` already known (the outputs
/// report them too: each taken once a row), summed in the same order.
pub fn balance_of(state: &SimState, energies: StateEnergies) -> f64 {
    let d = &state.dynamic;
    energies.body_kinetic
        + energies.beam_kinetic
        + energies.strain
        + energies.spring
        + d.dissipated
        + d.beam_dissipated
        + d.numerical_dissipation
        + state.impact_loss
        - state.gravity_work
        - state.external_work
        - d.tractive_work
}
