//! Rigid moving bodies: a rolling wheel, or a glider (r = 0, J = 0).

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::scene::{BodyKind, BodySpec};

/// Inertia and geometry of a moving body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBody {
    pub mass: f64,
    /// Centroidal moment of inertia J; zero for a glider.
    pub inertia: f64,
    /// Rim radius r; zero for a glider.
    pub radius: f64,
    /// Whether the body rotates and carries a tangential contact force.
    pub rolls: bool,
}

impl RigidBody {
    pub fn from_spec(spec: &BodySpec) -> RigidBody {
        match spec.kind {
            BodyKind::Wheel => RigidBody {
                mass: spec.mass,
                inertia: spec.inertia.unwrap_or(0.0),
                radius: spec.radius.unwrap_or(0.0),
                rolls: true,
            },
            BodyKind::Glider => RigidBody {
                mass: spec.mass,
                inertia: 0.0,
                radius: 0.0,
                rolls: false,
            },
        }
    }

    pub fn kinetic_energy(&self, state: &BodyState) -> f64 {
        0.5 * self.mass * state.velocity.norm_squared()
            + 0.5 * self.inertia * state.angular_velocity * state.angular_velocity
    }
}

/// Position and velocity of a body's centre, and its rotation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    pub position: Vector2<f64>,
    pub velocity: Vector2<f64>,
    /// Rotation θ, counter-clockwise positive (rad).
    pub angle: f64,
    pub angular_velocity: f64,
}
