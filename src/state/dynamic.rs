//! The dynamic part of a run's state: positions, velocities and
//! accelerations of beam and bodies, the loads of the last step's end, each
//! contact's foot point and the energy the steps removed: what an
//! integrator advances over a step.

use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};

use crate::body::BodyState;

/// Positions and velocities of everything that moves, plus each contact's
/// foot point (kept as the warm start of the next foot-point search).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicState {
    pub beam_displacement: DVector<f64>,
    pub beam_velocity: DVector<f64>,
    /// Beam accelerations at the end of the last step, and each body's
    /// (ẍ, ÿ, θ̈): the implicit scheme carries them (RK4 does not use them).
    pub beam_acceleration: DVector<f64>,
    pub body_accelerations: Vec<Vector3<f64>>,
    /// The loads at the end of the last step: the contact load vector on the
    /// beam's free DOFs, and each body's generalized force (F_x, F_y,
    /// torque), applied forces and force elements included. HHT-α weighs
    /// them against the next step's (its forces act at t_{n+1+α}).
    pub beam_load: DVector<f64>,
    pub body_loads: Vec<Vector3<f64>>,
    pub bodies: Vec<BodyState>,
    pub contact_x: Vec<f64>,
    /// Energy dissipated by the force elements' dampers since t = 0 (J),
    /// integrated with the step.
    pub dissipated: f64,
    /// Energy dissipated by the beam's structural damping since t = 0 (J),
    /// integrated with the step.
    #[serde(default)]
    pub beam_dissipated: f64,
    /// Work of the tractive forces that hold the driven bodies' speeds since
    /// t = 0 (J), integrated with the step.
    #[serde(default)]
    pub tractive_work: f64,
    /// Energy removed by the integrator's numerical damping since t = 0
    /// (J), step by step: HHT-α's from the scheme's discrete energy
    /// identity, RK4's from the beam's energy against the work of its loads
    /// (see `rk4::beam_dissipation`).
    #[serde(default)]
    pub numerical_dissipation: f64,
}
