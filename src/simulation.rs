//! Simulation: state of beam and body, fixed-step advance, outputs, energy.
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// How an output is typed when exported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    Real,
    Integer,
}

/// One named output of the simulation, in the order of `output_values`.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputInfo {
    pub name: String,
    pub unit: &'static str,
    pub description: String,
    pub kind: OutputKind,
}

/// Result of `advance_to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    /// The requested time was reached.
    Reached,
    /// The contact point reached the end of the beam at `time`; the state is
    /// the exit state.
    Exited { time: f64 },
}

/// A failure inside a step. The simulation is left at the start of the
/// failing internal step.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverError {
    pub time: f64,
    pub message: String,
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "at t = {} s: {}", self.time, self.message)
    }
}
impl std::error::Error for SolverError {}

/// Everything needed to continue a run bit-identically.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimState {}

pub struct Simulation {}

impl Simulation {
    /// Build the model a scene asks for. The scene must be valid.
    pub fn new(_scene: &Scene) -> Result<Simulation, String> {
        todo!()
    }
    pub fn time(&self) -> f64 {
        todo!()
    }
    /// The outputs this scene has, in a fixed order.
    pub fn outputs(&self) -> &[OutputInfo] {
        todo!()
    }
    /// Current output values, in the order of `outputs()`.
    pub fn output_values(&self, _values: &mut [f64]) {
        todo!()
    }
    /// Set the external force on the body's centre (N), held until changed.
    pub fn set_body_force(&mut self, _fx: f64, _fy: f64) {
        todo!()
    }
    /// Advance to `t` with internal steps of `solver.step`, the last one
    /// shortened to land on `t`; stops early at the exit.
    pub fn advance_to(&mut self, _t: f64) -> Result<Advance, SolverError> {
        todo!()
    }
    /// Exit time, once the body has left the beam.
    pub fn exit_time(&self) -> Option<f64> {
        todo!()
    }
    pub fn state(&self) -> SimState {
        todo!()
    }
    pub fn restore(&mut self, _state: &SimState) -> Result<(), String> {
        todo!()
    }
}
