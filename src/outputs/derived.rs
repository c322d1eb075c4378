//! The quantities of a state that the outputs read but the state does not
//! hold: the contact frames now, the bodies' accelerations under the last
//! forces, the beam's dynamics under the last contact forces, and what the
//! outputs need beside the system and the state to compute them (`Probes`).

use nalgebra::{DVector, Vector3};
use std::borrow::Cow;

use crate::contact::{ContactForce, ContactFrame};
use crate::integrate::{loads, EndForces, FrameMemo};
use crate::state::SimState;
use crate::structure::acceleration_rows::AccelerationRows;
use crate::structure::section_forces::BeamDynamics;
use crate::system::System;

/// What the outputs read beside the system and the state: where the
/// sensors and sections are, the frames of the last step (recalled, not
/// searched again), whether the energy books were kept, and the constant
/// forces before the first step (after it the state holds them).
pub struct Probes<'a> {
    /// Abscissae of the deflection sensors (m).
    pub sensors: &'a [f64],
    /// Abscissae of the sections whose moment and shear are outputs (m).
    pub sections: &'a [f64],
    pub frames: &'a FrameMemo,
    /// K u + C v of the last step's end, where the integrator kept them.
    pub end_forces: Option<&'a EndForces>,
    /// The rows that give the accelerations the design outputs read
    /// without a solve, where they are cheaper (`AccelerationRows`).
    pub acceleration_rows: Option<&'a AccelerationRows>,
    /// False where a step was solved without the energy bookkeeping: the
    /// energy totals no longer hold, and are reported as NaN.
    pub booked: bool,
    /// The constant generalized force on each body, used while the state
    /// has no step's forces (`SimState::last_applied` empty); else empty.
    pub start_applied: Vec<Vector3<f64>>,
}

impl Probes<'_> {
    /// The outputs' route to the beam's accelerations: their rows' only.
    pub fn route(&self) -> AccelerationRoute<'_> {
        AccelerationRoute {
            end_forces: self.end_forces,
            rows: self.acceleration_rows,
            whole: false,
        }
    }

    /// `total`, one of the energy totals the steps book, or NaN where the
    /// books were not kept.
    pub fn booked(&self, total: f64) -> f64 {
        if self.booked {
            total
        } else {
            f64::NAN
        }
    }
}

/// The contact frames of `state` (each contact on the part of the track it
/// is on): lent by `memo` where they are the last step's, else searched.
pub fn frames_now<'m>(
    system: &System,
    state: &SimState,
    memo: &'m FrameMemo,
) -> Result<Cow<'m, [ContactFrame]>, crate::integrate::IntegrationError> {
    let d = &state.dynamic;
    let located = (d.contact_x.as_slice(), state.parts.as_slice());
    let configuration = (&d.beam_displacement, d.bodies.as_slice());
    if let Some(kept) = memo.recall(configuration, located) {
        return Ok(Cow::Borrowed(kept));
    }
    let mut frames = Vec::new();
    let u = &d.beam_displacement;
    crate::integrate::contact_frames(system, u, &d.bodies, located, &mut frames)?;
    Ok(Cow::Owned(frames))
}

/// The contact forces of the last step.
fn last_forces(state: &SimState) -> Vec<ContactForce> {
    state.force_history.iter().map(|h| h[0]).collect()
}

/// Each body's (ẍ, ÿ, θ̈) in `state` under the last forces; NaN where a
/// contact point cannot be located.
pub fn body_accelerations(system: &System, state: &SimState, probes: &Probes) -> Vec<Vector3<f64>> {
    let frames = frames_now(system, state, probes.frames).ok();
    body_accelerations_at(system, state, probes, frames.as_deref())
}

/// `body_accelerations` at the state's `frames` (`frames_now`; `None`
/// where a contact point cannot be located: NaN).
pub fn body_accelerations_at(
    system: &System,
    state: &SimState,
    probes: &Probes,
    frames: Option<&[ContactFrame]>,
) -> Vec<Vector3<f64>> {
    let d = &state.dynamic;
    let Some(frames) = frames else {
        return vec![Vector3::repeat(f64::NAN); system.bodies.len()];
    };
    let mut beam_load = DVector::zeros(d.beam_displacement.len());
    let mut body_loads = vec![Vector3::zeros(); system.bodies.len()];
    let forces = last_forces(state);
    let applied = match state.last_applied.len() {
        0 => &probes.start_applied,
        _ => &state.last_applied,
    };
    loads(
        system,
        frames,
        &forces,
        applied,
        &d.bodies,
        &d.beam_velocity,
        &mut beam_load,
        &mut body_loads,
    );
    system
        .bodies
        .iter()
        .zip(&body_loads)
        .map(|(body, load)| body.acceleration(load))
        .collect()
}

/// How `beam_dynamics` finds the accelerations: the kept internal forces
/// of the last step's end, and the rows of the design outputs'
/// coordinates (`AccelerationRows`).
#[derive(Clone, Copy)]
pub struct AccelerationRoute<'a> {
    pub end_forces: Option<&'a EndForces>,
    pub rows: Option<&'a AccelerationRows>,
    /// Every coordinate's acceleration (the node file), not only the
    /// rows' (the others NaN).
    pub whole: bool,
}

/// The beam in `state` under the contact forces of the last step, with
/// the acceleration they give (design outputs); `None` when a contact
/// point cannot be located. With rows, their coordinates' accelerations
/// are theirs, and where not `whole` the others are NaN (no solve); the
/// internal forces K u + C v they read are recalled from `end_forces`
/// where they are this state's, else computed (the same bits: a function
/// of the state either way). Without rows, a whole solve. The state lends
/// u and v (copying them was O(n) a row).
pub fn beam_dynamics<'s>(
    system: &System,
    state: &'s SimState,
    memo: &FrameMemo,
    route: AccelerationRoute,
) -> Option<BeamDynamics<'s>> {
    let frames = frames_now(system, state, memo).ok()?;
    Some(beam_dynamics_at(system, state, &frames, route))
}

/// `beam_dynamics` at the state's `frames` (`frames_now`).
pub fn beam_dynamics_at<'s>(
    system: &System,
    state: &'s SimState,
    frames: &[ContactFrame],
    route: AccelerationRoute,
) -> BeamDynamics<'s> {
    let d = &state.dynamic;
    let beam = &system.beam;
    let loads = crate::contact::loads::contact_loads(beam, frames, &last_forces(state));
    let (u, v) = (&d.beam_displacement, &d.beam_velocity);
    let Some(rows) = route.rows else {
        let readable = beam.accelerations_read_internal_forces();
        let kept = route.end_forces.filter(|_| readable);
        let internal = kept.and_then(|kept| kept.recall((u, v)));
        return BeamDynamics::lent(beam, (u, v), loads, internal);
    };
    let mut acceleration = match route.whole {
        true => BeamDynamics::lent(beam, (u, v), loads.clone(), None)
            .acceleration()
            .clone(),
        false => DVector::from_element(u.len(), f64::NAN),
    };
    match route.end_forces.and_then(|kept| kept.recall((u, v))) {
        Some(internal) => rows.write(beam, &loads, internal, &mut acceleration),
        None => {
            let (mut scratch, mut internal) = (DVector::zeros(u.len()), DVector::zeros(u.len()));
            beam.internal_forces(u, v, &mut scratch, &mut internal);
            rows.write(beam, &loads, &internal, &mut acceleration);
        }
    }
    let state = (Cow::Borrowed(u), Cow::Borrowed(v), Cow::Owned(acceleration));
    BeamDynamics::assembled(beam, state, loads)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BodyKind, Scene};
    use crate::simulation::Simulation;

    #[test]
    fn the_beams_dynamics_borrow_the_states_vectors_and_keep_their_bits() {
        // The paper's wheel mid-crossing: the dynamics lend the state's u
        // and v (an output row copied both, O(n) a row), and give the
        // acceleration of the owned construction bit for bit.
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let mut simulation = Simulation::new(&scene).expect("builds");
        simulation.advance_to(1.0).expect("steps");
        let (system, state) = (simulation.system(), simulation.state());
        let route = AccelerationRoute {
            end_forces: None,
            rows: None,
            whole: true,
        };
        let memo = FrameMemo::default();
        let lent = beam_dynamics(system, &state, &memo, route).expect("located");
        let d = &state.dynamic;
        assert!(std::ptr::eq(lent.displacement(), &d.beam_displacement));
        assert!(std::ptr::eq(lent.velocity(), &d.beam_velocity));
        let frames = frames_now(system, &state, &memo).expect("located");
        let loads =
            crate::contact::loads::contact_loads(&system.beam, &frames, &last_forces(&state));
        assert!(!loads.is_empty());
        let owned = BeamDynamics::new(
            &system.beam,
            (d.beam_displacement.clone(), d.beam_velocity.clone()),
            loads,
            None,
        );
        let bits = |v: &DVector<f64>| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(lent.acceleration()), bits(owned.acceleration()));
        assert!(lent.acceleration().iter().any(|&a| a != 0.0));
    }
}
