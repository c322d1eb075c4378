//! The physics as the model layer sees it: build from a scene, step, read
//! outputs, save and restore state.
//!
//! `Simulation` is the one real implementation. The trait exists so that the
//! model and the FMI layer can be tested against a small fake (see
//! `model::fake`) independently of the physics.

use crate::scene::Scene;
use crate::simulation::{SimState, Simulation, Steppable};
use serde::{de::DeserializeOwned, Serialize};

/// `Steppable` (time, outputs, output values, advance) plus what the FMU
/// needs besides: building, inputs, exit, state.
pub trait Dynamics: Steppable + Sized {
    /// Everything needed to continue a run bit-identically.
    type State: Clone + Serialize + DeserializeOwned;

    /// Build the model a (valid) scene asks for.
    fn build(scene: &Scene) -> Result<Self, String>;
    fn set_body_force(&mut self, fx: f64, fy: f64);
    fn exit_time(&self) -> Option<f64>;
    fn state(&self) -> Self::State;
    /// Continue from `state`, which may come from a forged FMU state:
    /// refused (Err naming why) unless it fits these dynamics.
    fn restore(&mut self, state: &Self::State) -> Result<(), String>;
    /// Whether `state` is one `restore` accepts (every state a step reaches
    /// must be: the importer may save and restore it).
    fn check_state(&self, _state: &Self::State) -> Result<(), String> {
        Ok(())
    }
}

impl Dynamics for Simulation {
    type State = SimState;

    fn build(scene: &Scene) -> Result<Self, String> {
        Simulation::new(scene)
    }
    fn set_body_force(&mut self, fx: f64, fy: f64) {
        Simulation::set_body_force(self, fx, fy)
    }
    fn exit_time(&self) -> Option<f64> {
        Simulation::exit_time(self)
    }
    fn state(&self) -> SimState {
        Simulation::state(self)
    }
    fn restore(&mut self, state: &SimState) -> Result<(), String> {
        check_sim_state(state, self.step_size())?;
        Simulation::restore(self, state)
    }
    fn check_state(&self, state: &SimState) -> Result<(), String> {
        check_sim_state(state, self.step_size())
    }
}

/// A state may come from a forged serialized FMU state: every number must be
/// finite, the vectors of the beam alike in length (`Simulation::restore`
/// checks that length against the model), and the time on the state's own
/// grid of `step`.
fn check_sim_state(s: &SimState, step: f64) -> Result<(), String> {
    let d = &s.dynamic;
    let n = d.beam_displacement.len();
    let lengths = [
        d.beam_velocity.len(),
        d.beam_acceleration.len(),
        d.beam_load.len(),
    ];
    if lengths.iter().any(|&m| m != n) {
        return Err(format!(
            "the state's beam vectors differ in length ({n}, {lengths:?})"
        ));
    }
    let scalars = [
        s.time,
        s.external_work,
        s.initial_energy,
        s.last_velocity_error,
        s.last_gap_error,
        d.contact_x,
        d.body.angle,
        d.body.angular_velocity,
        s.exit_time.unwrap_or(0.0),
    ];
    let forces = s
        .force_history
        .iter()
        .flat_map(|f| [f.tangential, f.normal]);
    let all = scalars
        .into_iter()
        .chain(forces)
        .chain(s.step_history)
        .chain(s.body_force)
        .chain(
            d.body
                .position
                .iter()
                .chain(d.body.velocity.iter())
                .copied(),
        )
        .chain(
            d.body_acceleration
                .iter()
                .chain(d.body_load.iter())
                .copied(),
        )
        .chain(d.beam_displacement.iter().copied())
        .chain(d.beam_velocity.iter().copied())
        .chain(d.beam_acceleration.iter().copied())
        .chain(d.beam_load.iter().copied());
    if let Some(x) = all.into_iter().find(|x| !x.is_finite()) {
        return Err(format!("the state holds a non-finite number ({x})"));
    }
    let grid = s.grid_step as f64 * step;
    let slack = 1e-6 * step;
    if !(s.time >= 0.0 && grid - slack <= s.time && s.time <= grid + step + slack) {
        return Err(format!(
            "the state's time {} s is not in its step {} of solver.step = {step} s",
            s.time, s.grid_step
        ));
    }
    Ok(())
}
