//! Contact between the body and the beam's top surface.
//!
//! The foot point d of the perpendicular from the body's centre on the
//! deformed neutral axis, the contact frame (t, n) there, the gap error g and
//! the velocity error e of METHOD.md.
//!
//! Kinematics and loads form the *exact pair* of METHOD.md: the normal row is
//! the time derivative of the exact gap g = n·(centre − d) − (r + h), so the
//! normal force passes through the neutral axis and puts no moment on the
//! section; the tangential row is the paper's small-deformation surface
//! velocity (eq. 7) rotated into the frame. The beam load is the transpose of
//! the same rows (`ContactFrame::beam_rows`), so the contact does no work
//! whenever e = 0.

use nalgebra::{DVector, Vector2, Vector3};

use crate::beam::{Beam, Shape};
use crate::body::{BodyState, RigidBody};

/// Contact force on the body in the contact frame (N): tangential and normal
/// components. The beam receives the opposite force.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactForce {
    pub tangential: f64,
    pub normal: f64,
}

impl ContactForce {
    pub fn as_vector(&self) -> Vector2<f64> {
        Vector2::new(self.tangential, self.normal)
    }
    pub fn from_vector(v: Vector2<f64>) -> ContactForce {
        ContactForce {
            tangential: v.x,
            normal: v.y,
        }
    }
}

/// The contact frame at the foot point, and the constraint rows there.
#[derive(Debug, Clone, Copy)]
pub struct ContactFrame {
    /// Abscissa x_d of the foot point (m).
    pub x: f64,
    pub shape: Shape,
    /// w(x_d), w'(x_d), w''(x_d) of the deformed neutral axis.
    pub deflection: f64,
    pub slope: f64,
    pub curvature: f64,
    pub cos: f64,
    pub sin: f64,
}

/// Why the foot point could not be found.
#[derive(Debug, Clone, PartialEq)]
pub struct FootPointError {
    pub last_x: f64,
}

impl ContactFrame {
    /// Unit tangent t = (cos φ, sin φ).
    pub fn tangent(&self) -> Vector2<f64> {
        Vector2::new(self.cos, self.sin)
    }
    /// Unit normal n = (−sin φ, cos φ).
    pub fn normal(&self) -> Vector2<f64> {
        Vector2::new(-self.sin, self.cos)
    }

    /// Rows over the element's four DOFs giving the beam surface velocity at
    /// the contact in the frame: (v_ct, v_cn) = (t_row · u̇, n_row · u̇).
    pub fn beam_rows(&self, surface_offset: f64) -> ([f64; 4], [f64; 4]) {
        let s = &self.shape;
        let mut t_row = [0.0; 4];
        let mut n_row = [0.0; 4];
        for k in 0..4 {
            t_row[k] = self.sin * s.n[k] - surface_offset * self.cos * s.dn[k];
            n_row[k] = self.cos * s.n[k];
        }
        (t_row, n_row)
    }

    /// Rows over (ẋ, ẏ, θ̇) giving the rim point's velocity in the frame.
    pub fn body_rows(&self, radius: f64) -> (Vector3<f64>, Vector3<f64>) {
        (
            Vector3::new(self.cos, self.sin, radius),
            Vector3::new(-self.sin, self.cos, 0.0),
        )
    }

    /// Velocity error e = rim velocity − surface velocity, in the frame (m/s).
    pub fn velocity_error(
        &self,
        beam: &Beam,
        body: &RigidBody,
        state: &BodyState,
        beam_velocity: &DVector<f64>,
    ) -> Vector2<f64> {
        let (bt, bn) = self.body_rows(body.radius);
        let q = Vector3::new(state.velocity.x, state.velocity.y, state.angular_velocity);
        let (t_row, n_row) = self.beam_rows(beam.surface_offset);
        Vector2::new(
            bt.dot(&q) - self.shape.dot(&t_row, beam_velocity),
            bn.dot(&q) - self.shape.dot(&n_row, beam_velocity),
        )
    }

    /// Gap error g = n·(centre − d) − (r + h) (m); negative is penetration.
    pub fn gap(&self, beam: &Beam, body: &RigidBody, centre: &Vector2<f64>) -> f64 {
        let d = Vector2::new(self.x, self.deflection);
        self.normal().dot(&(centre - d)) - (body.radius + beam.surface_offset)
    }

    /// Nominal travel speed V = ẋ_centre + (r + h) φ̇ (METHOD.md, eq. 24), with
    /// φ̇ the total rate of the surface angle at the moving foot point.
    pub fn nominal_speed(
        &self,
        beam: &Beam,
        body: &RigidBody,
        state: &BodyState,
        beam_velocity: &DVector<f64>,
    ) -> f64 {
        let s = &self.shape;
        let w_rate = s.dot(&s.n, beam_velocity);
        let slope_rate = s.dot(&s.dn, beam_velocity);
        let height = state.position.y - self.deflection;
        // d/dt of the foot-point condition (X − x) + (Y − w(x)) w'(x) = 0.
        let foot_speed =
            (state.velocity.x + (state.velocity.y - w_rate) * self.slope + height * slope_rate)
                / (1.0 + self.slope * self.slope - height * self.curvature);
        let angle_rate =
            (slope_rate + self.curvature * foot_speed) / (1.0 + self.slope * self.slope);
        state.velocity.x + (body.radius + beam.surface_offset) * angle_rate
    }
}

/// Find the foot of the perpendicular from `centre` on the deformed neutral
/// axis by Newton's method, starting at `guess` and moving across elements.
/// Beyond the beam's ends the end elements' cubics are extended, so that the
/// exit instant can be found by interpolation.
pub fn foot_point(
    beam: &Beam,
    u: &DVector<f64>,
    centre: &Vector2<f64>,
    guess: f64,
) -> Result<ContactFrame, FootPointError> {
    let mut x = guess;
    let max_move = beam.min_element_length();
    for _ in 0..50 {
        let shape = beam.shape(beam.element_at(x), x);
        let w = shape.dot(&shape.n, u);
        let slope = shape.dot(&shape.dn, u);
        let curvature = shape.dot(&shape.ddn, u);
        let height = centre.y - w;
        let residual = (centre.x - x) + height * slope;
        let derivative = -1.0 - slope * slope + height * curvature;
        if !(derivative.is_finite() && residual.is_finite()) || derivative.abs() < 1e-12 {
            return Err(FootPointError { last_x: x });
        }
        let dx = (-residual / derivative).clamp(-max_move, max_move);
        x += dx;
        if dx.abs() <= 1e-14 * beam.length.max(1.0) {
            let shape = beam.shape(beam.element_at(x), x);
            let slope = shape.dot(&shape.dn, u);
            let secant = (1.0 + slope * slope).sqrt();
            return Ok(ContactFrame {
                x,
                shape,
                deflection: shape.dot(&shape.n, u),
                slope,
                curvature: shape.dot(&shape.ddn, u),
                cos: 1.0 / secant,
                sin: slope / secant,
            });
        }
    }
    Err(FootPointError { last_x: x })
}
