//! Rigid planar bodies: position (x, y), pitch θ, mass and pitch inertia.
//! A wheel is a body with J > 0; a glider or a car body without pitch
//! inertia (J = 0) does not turn.

use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// Inertia of a rigid planar body.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// Prefix of the body's outputs (`wheel`, `vehicle1.car`, ...).
    pub name: String,
    pub mass: f64,
    /// Centroidal moment of inertia J; zero for a body that does not turn.
    pub inertia: f64,
    /// The horizontal acceleration ẍ imposed over the current step on a body
    /// driven at a prescribed speed (a tractive force holds it); `None` for a
    /// body that moves freely.
    pub drive: Option<f64>,
}

impl RigidBody {
    /// Whether the body turns under a torque (J > 0).
    pub fn turns(&self) -> bool {
        self.inertia > 0.0
    }

    /// 1 / J, or 0 for a body that does not turn.
    pub fn inverse_inertia(&self) -> f64 {
        if self.turns() {
            1.0 / self.inertia
        } else {
            0.0
        }
    }

    /// (ẍ, ÿ, θ̈) under the generalized force (F_x, F_y, torque); a driven
    /// body's ẍ is its imposed one.
    pub fn acceleration(&self, generalized: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.drive.unwrap_or(generalized.x / self.mass),
            generalized.y / self.mass,
            if self.turns() {
                generalized.z / self.inertia
            } else {
                0.0
            },
        )
    }

    /// The horizontal tractive force that gives a driven body its imposed
    /// ẍ under `generalized` (N); zero for a free body.
    pub fn tractive_force(&self, generalized: &Vector3<f64>) -> f64 {
        self.drive.map_or(0.0, |ax| self.mass * ax - generalized.x)
    }

    /// `a · M⁻¹ b` over (x, y): how the body's velocity along `a` answers a
    /// force along `b`; a driven body does not answer horizontally.
    pub fn compliance(&self, a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
        let horizontal = if self.drive.is_some() { 0.0 } else { a.x * b.x };
        (horizontal + a.y * b.y) / self.mass
    }

    pub fn kinetic_energy(&self, state: &BodyState) -> f64 {
        0.5 * self.mass * state.velocity.norm_squared()
            + 0.5 * self.inertia * state.angular_velocity * state.angular_velocity
    }
}

/// Whether `local` is a body's centre (0, 0), either zero's sign.
#[inline]
pub fn is_centre(local: &Vector2<f64>) -> bool {
    local.x == 0.0 && local.y == 0.0
}

/// The sines and cosines of the bodies' angles met in one pass over
/// contacts of one configuration, each computed once: a vehicle's
/// followers share a few bodies, and a sine and cosine per attachment
/// point was a fifth of a train's run (the force elements' sweeps keep
/// theirs in their plan, `element_sweep`). Direct-mapped on the body index
/// in `SLOTS` slots, so no allocation: one for a pass over contacts
/// (`ContactRotations`), where a body's followers are neighbours and every
/// slot costs its stores on every pass.
pub struct Rotations<const SLOTS: usize>([(usize, f64, f64); SLOTS]);

impl<const SLOTS: usize> Default for Rotations<SLOTS> {
    #[inline]
    fn default() -> Rotations<SLOTS> {
        Rotations([(usize::MAX, 0.0, 0.0); SLOTS])
    }
}

impl<const SLOTS: usize> Rotations<SLOTS> {
    /// World offset from the centre of body `b` (in `state`) of its point
    /// `local`: `BodyState::offset_of`'s bits, with the rotation
    /// remembered. Valid while every `b` asked for is in one configuration.
    #[inline]
    pub fn offset_of(&mut self, b: usize, state: &BodyState, local: &Vector2<f64>) -> Vector2<f64> {
        if is_centre(local) {
            return Vector2::zeros();
        }
        let slot = &mut self.0[b % SLOTS];
        if slot.0 != b {
            let (sin, cos) = libm::sincos(state.angle);
            *slot = (b, sin, cos);
        }
        rotated((slot.1, slot.2), local)
    }
}

/// The rotations a pass over contacts keeps (see `Rotations`).
pub type ContactRotations = Rotations<1>;

/// `local` rotated by the angle whose (sine, cosine) is `sin_cos`.
#[inline]
pub fn rotated((sin, cos): (f64, f64), local: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(cos * local.x - sin * local.y, sin * local.x + cos * local.y)
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

impl BodyState {
    /// Every number of the state, in field order (for the state checks).
    pub fn numbers(&self) -> [f64; 6] {
        [
            self.position.x,
            self.position.y,
            self.velocity.x,
            self.velocity.y,
            self.angle,
            self.angular_velocity,
        ]
    }

    /// (ẋ, ẏ, θ̇).
    pub fn generalized_velocity(&self) -> Vector3<f64> {
        Vector3::new(self.velocity.x, self.velocity.y, self.angular_velocity)
    }

    /// World offset from the centre of a point fixed in the body at `local`.
    pub fn offset_of(&self, local: &Vector2<f64>) -> Vector2<f64> {
        // A body's centre (where a suspension meets a wheelset) needs no
        // rotation: the sine and cosine were a tenth of a train's run.
        if is_centre(local) {
            return Vector2::zeros();
        }
        rotated(libm::sincos(self.angle), local)
    }

    /// State advanced by `h` with rates (velocity, angular velocity) and
    /// accelerations `acceleration` = (ẍ, ÿ, θ̈): an explicit stage update.
    pub fn advanced(&self, h: f64, rates: &BodyState, acceleration: &Vector3<f64>) -> BodyState {
        BodyState {
            position: self.position + h * rates.velocity,
            velocity: self.velocity + h * acceleration.xy(),
            angle: self.angle + h * rates.angular_velocity,
            angular_velocity: self.angular_velocity + h * acceleration.z,
        }
    }
}
