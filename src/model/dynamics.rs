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
    fn restore(&mut self, state: &Self::State) -> Result<(), String>;
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
        Simulation::restore(self, state)
    }
}
