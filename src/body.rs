//! Rigid moving bodies: a rolling wheel, or a glider (r = 0, J = 0).

use nalgebra::{Vector2, Vector3};
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

    /// Whether the body turns under a torque (a wheel with J > 0).
    fn turns(&self) -> bool {
        self.rolls && self.inertia > 0.0
    }

    /// 1 / J, or 0 for a body that does not turn.
    pub fn inverse_inertia(&self) -> f64 {
        if self.turns() {
            1.0 / self.inertia
        } else {
            0.0
        }
    }

    /// (ẍ, ÿ, θ̈) under the generalized force (F_x, F_y, torque).
    pub fn acceleration(&self, generalized: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            generalized.x / self.mass,
            generalized.y / self.mass,
            if self.turns() {
                generalized.z / self.inertia
            } else {
                0.0
            },
        )
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
