//! The contact force within a step (`solver.force_profile`).
//!
//! The iteration's unknown stays the force's mean over the step, as in the
//! paper: the velocity error at the step's end fixes the impulse. The
//! profile gives the force a shape in time around that mean, a polynomial
//! whose means over this step and the previous ones are the iterate and
//! the converged forces of those steps (histopolation). RK4's stages then
//! see the force at their own times: with the held force the shape's error
//! is the force's rate times Δt and the scheme is second order; with the
//! quadratic one it is O(Δt³) and the coupled step is fourth order.

use nalgebra::{Matrix2, Matrix3, RowVector2, RowVector3, Vector2};
use serde::{Deserialize, Serialize};

use crate::contact::ContactForce;

/// The contact force within a step. The iteration's unknown is always the
/// force's mean over the step; the profile sets its shape from the means of
/// the steps before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ForceProfile {
    /// Constant over the step: the paper's scheme (second order).
    #[default]
    Held,
    /// Linear: its mean over this step and the previous one as found.
    Linear,
    /// Quadratic: its means over this step and the two before as found.
    Quadratic,
}

impl ForceProfile {
    pub fn is_default(&self) -> bool {
        *self == ForceProfile::default()
    }
}

/// RK4's distinct stage times as fractions of the step.
pub const STAGE_FRACTIONS: [f64; 3] = [0.0, 0.5, 1.0];

/// Neighbouring steps longer or shorter than this ratio are not fitted:
/// the polynomial would extrapolate far beyond the data it was fitted to.
const MAX_STEP_RATIO: f64 = 8.0;

/// One contact's force over the step at RK4's stage times (0, ½, 1 of the
/// step): `own[k]` times the step's mean force, plus `history[k]`, the part
/// the previous steps' means contribute (tangential, normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceShape {
    own: [f64; 3],
    history: [Vector2<f64>; 3],
}

impl Default for ForceShape {
    /// Held: the mean at every stage.
    fn default() -> ForceShape {
        ForceShape {
            own: [1.0; 3],
            history: [Vector2::zeros(); 3],
        }
    }
}

impl ForceShape {
    /// The force at stage time `STAGE_FRACTIONS[k]` for the step's `mean`.
    #[inline]
    pub fn at(&self, k: usize, mean: &ContactForce) -> ContactForce {
        ContactForce::from_vector(self.own[k] * mean.as_vector() + self.history[k])
    }

    /// Whether the force is held over the step.
    pub fn is_held(&self) -> bool {
        *self == ForceShape::default()
    }
}

/// The shape of one contact's force over a step of `dt`, from the means of
/// the previous steps `history` (newest first; only the first `usable` are
/// converged forces of closed steps) over steps of `steps` (newest first).
pub fn force_shape(
    profile: ForceProfile,
    history: &[ContactForce; 3],
    steps: &[f64; 2],
    usable: usize,
    dt: f64,
) -> ForceShape {
    let wanted = match profile {
        ForceProfile::Held => 0,
        ForceProfile::Linear => 1,
        ForceProfile::Quadratic => 2,
    };
    // Steps in units of this one; a neighbour too unlike it is not used.
    let ratios = [steps[0] / dt, steps[1] / dt];
    let alike = |r: f64| r.is_finite() && (1.0 / MAX_STEP_RATIO..=MAX_STEP_RATIO).contains(&r);
    let mut fitted = wanted.min(usable);
    if fitted >= 1 && !alike(ratios[0]) {
        fitted = 0;
    }
    if fitted == 2 && !alike(ratios[1] / ratios[0]) {
        fitted = 1;
    }
    let means = |k: usize| history[k].as_vector();
    let mut shape = ForceShape::default();
    match fitted {
        1 => {
            // Cells [0, 1] (this step) and [−r₁, 0]: mean of (1, τ).
            let r1 = ratios[0];
            let cells = Matrix2::new(1.0, 0.5, 1.0, -0.5 * r1);
            let Some(inverse) = cells.try_inverse() else {
                return shape;
            };
            for (k, &tau) in STAGE_FRACTIONS.iter().enumerate() {
                let w = RowVector2::new(1.0, tau) * inverse;
                shape.own[k] = w[0];
                shape.history[k] = w[1] * means(0);
            }
        }
        2 => {
            // Cells [0, 1], [−r₁, 0], [−r₁ − r₂, −r₁]: means of (1, τ, τ²).
            let (r1, r2) = (ratios[0], ratios[1]);
            let row =
                |a: f64, b: f64| RowVector3::new(1.0, 0.5 * (a + b), (a * a + a * b + b * b) / 3.0);
            let cells = Matrix3::from_rows(&[row(0.0, 1.0), row(-r1, 0.0), row(-r1 - r2, -r1)]);
            let Some(inverse) = cells.try_inverse() else {
                return shape;
            };
            for (k, &tau) in STAGE_FRACTIONS.iter().enumerate() {
                let w = RowVector3::new(1.0, tau, tau * tau) * inverse;
                shape.own[k] = w[0];
                shape.history[k] = w[1] * means(0) + w[2] * means(1);
            }
        }
        _ => {}
    }
    shape
}

#[cfg(test)]
mod tests {
    use super::*;

    fn force(n: f64) -> ContactForce {
        ContactForce {
            tangential: 0.1 * n,
            normal: n,
        }
    }

    /// Mean of f over [a, b] by Simpson's rule (exact for cubics).
    fn mean(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
        (f(a) + 4.0 * f(0.5 * (a + b)) + f(b)) / 6.0
    }

    #[test]
    fn quadratic_reproduces_a_quadratic_force_from_its_means() {
        // f(t) = 3 + 2t − 5t² over steps of 0.02, 0.01 and this one, 0.01.
        let f = |t: f64| 3.0 + 2.0 * t - 5.0 * t * t;
        let dt = 0.01;
        let history = [
            force(mean(f, -dt, 0.0)),
            force(mean(f, -3.0 * dt, -dt)),
            ContactForce::default(),
        ];
        let shape = force_shape(ForceProfile::Quadratic, &history, &[dt, 2.0 * dt], 2, dt);
        let own = force(mean(f, 0.0, dt));
        for (k, &tau) in STAGE_FRACTIONS.iter().enumerate() {
            let at = shape.at(k, &own);
            assert!((at.normal - f(tau * dt)).abs() < 1e-12, "{k}: {at:?}");
            assert!((at.tangential - 0.1 * f(tau * dt)).abs() < 1e-12);
        }
        // Simpson's weights of the stages give back the mean.
        let simpson = (shape.own[0] + 4.0 * shape.own[1] + shape.own[2]) / 6.0;
        assert!((simpson - 1.0).abs() < 1e-12);
    }

    #[test]
    fn linear_reproduces_a_linear_force_and_held_is_flat() {
        let f = |t: f64| 7.0 - 40.0 * t;
        let dt = 0.0025;
        let history = [force(mean(f, -dt, 0.0)), force(1.0), force(1.0)];
        let own = force(mean(f, 0.0, dt));
        let linear = force_shape(ForceProfile::Linear, &history, &[dt, dt], 2, dt);
        for (k, &tau) in STAGE_FRACTIONS.iter().enumerate() {
            assert!((linear.at(k, &own).normal - f(tau * dt)).abs() < 1e-12);
        }
        let held = force_shape(ForceProfile::Held, &history, &[dt, dt], 2, dt);
        assert!(held.is_held());
        assert_eq!(held.at(2, &own), own);
    }

    #[test]
    fn falls_back_without_usable_history_or_alike_steps() {
        let history = [force(2.0), force(1.0), force(0.0)];
        let dt = 0.0025;
        assert!(force_shape(ForceProfile::Quadratic, &history, &[dt, dt], 0, dt).is_held());
        // One usable mean: linear.
        let one = force_shape(ForceProfile::Quadratic, &history, &[dt, dt], 1, dt);
        let linear = force_shape(ForceProfile::Linear, &history, &[dt, dt], 1, dt);
        assert_eq!(one, linear);
        assert!(!one.is_held());
        // A step a hundred times shorter than the one before: held.
        assert!(force_shape(ForceProfile::Quadratic, &history, &[dt, dt], 2, dt / 100.0).is_held());
    }
}
