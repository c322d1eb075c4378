//! The physics as the model layer sees it: build from a scene, step, read
//! outputs, save and restore state.
//!
//! `Simulation` is the one real implementation. The trait exists so that the
//! model and the FMI layer can be tested against a small fake (see
//! `model::fake`) independently of the physics.

use crate::scene::Scene;
use crate::simulation::{Advance, OutputInfo, SimState, Simulation, SolverError};
use serde::{de::DeserializeOwned, Serialize};

pub trait Dynamics: Sized {
    /// Everything needed to continue a run bit-identically.
    type State: Clone + Serialize + DeserializeOwned;

    /// Build the model a (valid) scene asks for.
    fn build(scene: &Scene) -> Result<Self, String>;
    fn time(&self) -> f64;
    /// The outputs of this scene, in a fixed order.
    fn outputs(&self) -> &[OutputInfo];
    /// Current output values, in the order of `outputs()`.
    fn output_values(&self, values: &mut [f64]);
    fn set_body_force(&mut self, fx: f64, fy: f64);
    /// Advance to `t`; on error the state is that at the start of the failing
    /// internal step (the caller rolls back further if it needs to).
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError>;
    fn exit_time(&self) -> Option<f64>;
    fn state(&self) -> Self::State;
    fn restore(&mut self, state: &Self::State) -> Result<(), String>;
}

impl Dynamics for Simulation {
    type State = SimState;

    fn build(scene: &Scene) -> Result<Self, String> {
        Simulation::new(scene)
    }
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn outputs(&self) -> &[OutputInfo] {
        Simulation::outputs(self)
    }
    fn output_values(&self, values: &mut [f64]) {
        Simulation::output_values(self, values)
    }
    fn set_body_force(&mut self, fx: f64, fy: f64) {
        Simulation::set_body_force(self, fx, fy)
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        Simulation::advance_to(self, t)
    }
    fn exit_time(&self) -> Option<f64> {
        Simulation::exit_time(self)
    }
    fn state(&self) -> SimState {
        Simulation::state(self)
    }
    fn restore(&mut self, state: &SimState) -> Result<(), String> {
        Simulation::restore(self, state)
    }
}
