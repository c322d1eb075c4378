//! Time integration of beam and body over one step with the contact force
//! held: the paper's explicit RK4, or HHT-α (implicit, unconditionally
//! stable for the beam) for stiff meshes. Both serve the same contact-force
//! iteration through `Integrator`.

mod hht;
mod rk4;

use nalgebra::{DVector, Vector2};
use serde::{Deserialize, Serialize};

use crate::contact::{ContactForce, ContactFrame};
use crate::system::System;

pub use hht::Hht;
pub use rk4::Rk4;

/// Positions and velocities of everything that moves, plus the foot point
/// (kept as the warm start of the next foot-point search).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicState {
    pub beam_displacement: DVector<f64>,
    pub beam_velocity: DVector<f64>,
    /// Beam accelerations at the end of the last step, and the body's
    /// (ẍ, ÿ, θ̈): the implicit scheme carries them (RK4 does not use them).
    pub beam_acceleration: DVector<f64>,
    pub body_acceleration: nalgebra::Vector3<f64>,
    /// The loads at the end of the last step: the contact load vector on the
    /// beam's free DOFs, and the body's generalized force (F_x, F_y, torque)
    /// including the external force. HHT-α weighs them against the next
    /// step's (its forces act at t_{n+1+α}).
    pub beam_load: DVector<f64>,
    pub body_load: nalgebra::Vector3<f64>,
    pub body: crate::body::BodyState,
    pub contact_x: f64,
}

/// What one step starts from: the state, its contact frame (the same for
/// every iteration of the step), the external force on the body's centre
/// (held over the step) and the step length.
#[derive(Debug, Clone, Copy)]
pub struct StepStart<'a> {
    pub state: &'a DynamicState,
    pub frame: &'a ContactFrame,
    pub external: Vector2<f64>,
    pub dt: f64,
}

/// Failure of one integration.
#[derive(Debug, Clone, PartialEq)]
pub enum IntegrationError {
    /// No foot point: the body is far from the beam or the beam is wildly deformed.
    LostContact { x: f64 },
}

/// The contact's loads for `force` at `frame`: the beam's load vector into
/// `beam_load` (overwritten) and the body's generalized force (F_x, F_y,
/// torque), `external` included.
pub fn contact_loads(
    system: &System,
    frame: &ContactFrame,
    force: ContactForce,
    external: Vector2<f64>,
    beam_load: &mut DVector<f64>,
) -> nalgebra::Vector3<f64> {
    let (t_row, n_row) = frame.beam_rows(system.beam.surface_offset);
    beam_load.fill(0.0);
    frame.shape.scatter(&t_row, -force.tangential, beam_load);
    frame.shape.scatter(&n_row, -force.normal, beam_load);
    let on_body = frame.tangent() * force.tangential + frame.normal() * force.normal + external;
    let torque = if system.body.rolls {
        force.tangential * system.body.radius
    } else {
        0.0
    };
    nalgebra::Vector3::new(on_body.x, on_body.y, torque)
}

/// The time integrator of a simulation.
pub enum Integrator {
    Rk4(Rk4),
    Hht(Box<Hht>),
}

impl Integrator {
    /// Called once before the iterations of each step.
    pub fn begin_step(&mut self) {
        if let Integrator::Hht(hht) = self {
            hht.begin_step();
        }
    }

    /// Advance from `from` over its step with `force` held, into `end`.
    pub fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        force: ContactForce,
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        match self {
            Integrator::Rk4(rk4) => rk4.step(system, from, force, end),
            Integrator::Hht(hht) => hht.step(system, from, force, end),
        }
    }

    /// How the body's end-of-step velocity and position respond to the
    /// force at the end of the step, per unit of acceleration it causes:
    /// (Δt, Δt²/2) for RK4's held force, (γ Δt, β Δt²) for HHT-α.
    pub fn body_weights(&self, dt: f64) -> (f64, f64) {
        match self {
            Integrator::Rk4(_) => (dt, 0.5 * dt * dt),
            Integrator::Hht(hht) => hht.body_weights(dt),
        }
    }

    /// Displacement and velocity of the beam alone after `dt` under a
    /// constant `load`, from rest: the step's response to a unit contact
    /// load, from which the iteration builds its Delassus operator.
    pub fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    ) {
        match self {
            Integrator::Rk4(rk4) => rk4.beam_response(system, load, dt, displacement, velocity),
            Integrator::Hht(hht) => hht.beam_response(system, load, dt, displacement, velocity),
        }
    }
}
