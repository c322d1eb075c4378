//! The force elements' lag in HHT-α's contact iteration, anticipated.
//!
//! HHT-α evaluates the force elements at the end configuration of the
//! previous integration of the step (the first at a constant-velocity
//! prediction), so each correction of the contact forces reaches the
//! suspensions one integration late. Measured on the 8-coach train, the
//! correction then left 5 % of the error after the first correction and
//! about ρ = (1 + α)(γ Δt c + β Δt² k) / m (0.8 % for its wheelsets) after
//! each later one: four integrations a step where two would do. Before a
//! correction is applied, the bodies' end state it will produce is
//! predicted (their rigid response to the corrected forces), the force
//! elements are evaluated there, the error the change of their loads will
//! cause is added to the error corrected, and the next integration is given
//! that predicted state. What is left is second order in ρ. The converged
//! step is the same fixed point as before; only the way there changes.

use nalgebra::Vector3;

use super::ContactIteration;
use crate::body::{BodyState, RigidBody};
use crate::force_element::add_element_forces;
use crate::integrate::DynamicState;
use crate::system::System;

/// A body's generalized acceleration under a generalized force; a driven
/// body's horizontal motion is imposed, so it does not answer.
pub(super) fn response(body: &RigidBody, q: &Vector3<f64>) -> Vector3<f64> {
    let x = if body.drive.is_some() {
        0.0
    } else {
        q.x / body.mass
    };
    Vector3::new(x, q.y / body.mass, q.z * body.inverse_inertia())
}

/// Workspace of the anticipation, one entry per body.
#[derive(Default)]
pub(super) struct LawLag {
    /// The contact forces' change of each body's generalized force.
    contact_change: Vec<Vector3<f64>>,
    /// The force elements' generalized forces in the last integration and
    /// at the predicted end.
    used: Vec<Vector3<f64>>,
    anticipated: Vec<Vector3<f64>>,
    predicted: Vec<BodyState>,
}

impl ContactIteration {
    /// Whether the integrator lags the force elements (HHT-α on a system
    /// with force elements).
    pub(super) fn lags_laws(&mut self, system: &System, dt: f64) -> bool {
        let full_step = crate::solver::parameters::is_nominal_step(dt, self.nominal_step);
        !system.force_elements.is_empty()
            && full_step
            && !self
                .open
                .iter()
                .zip(&self.followers)
                .any(|(&o, &f)| o && !f)
            && self.integrator.body_predictions().is_some()
    }

    /// Each body's generalized force from the contact force changes `-dp`
    /// (the stacked correction), applied at the end frames.
    fn contact_change(&mut self, system: &System, dp: &nalgebra::DVector<f64>) {
        let change = &mut self.law_lag.contact_change;
        change.clear();
        change.resize(system.bodies.len(), Vector3::zeros());
        for (c, contact) in system.contacts.iter().enumerate() {
            if self.open[c] {
                continue;
            }
            let (bt, bn) = self.end_frames[c].body_rows(contact.radius());
            let offset = self.offsets[c];
            let q = if contact.rolls() {
                -(dp[offset] * bt + dp[offset + 1] * bn)
            } else {
                -dp[offset] * bn
            };
            change[contact.body] += q;
        }
    }

    /// The bodies' end state after a change `q` of each one's generalized
    /// force at the end of the step, from `end`, into `out`.
    pub(super) fn moved(
        system: &System,
        (velocity_weight, position_weight): (f64, f64),
        end: &[BodyState],
        q: impl Fn(usize) -> Vector3<f64>,
        out: &mut [BodyState],
    ) {
        for (b, (body, state)) in system.bodies.iter().zip(end).enumerate() {
            let a = response(body, &q(b));
            out[b] = BodyState {
                position: state.position + position_weight * a.xy(),
                velocity: state.velocity + velocity_weight * a.xy(),
                angle: state.angle + position_weight * a.z,
                angular_velocity: state.angular_velocity + velocity_weight * a.z,
            };
        }
    }

    /// Add to `self.error` what the force elements' change between the
    /// last integration's prediction and the end the correction
    /// `self.correction` leads to will add to it.
    pub(super) fn anticipate_laws(&mut self, system: &System, dt: f64, end: &DynamicState) {
        let weights = self.integrator.body_weights(dt);
        let correction = std::mem::take(&mut self.correction);
        self.contact_change(system, &correction);
        self.correction = correction;
        let lag = &mut self.law_lag;
        lag.predicted.clear();
        lag.predicted.extend_from_slice(&end.bodies);
        let change = &lag.contact_change;
        Self::moved(
            system,
            weights,
            &end.bodies,
            |b| change[b],
            &mut lag.predicted,
        );
        lag.anticipated.clear();
        lag.anticipated
            .resize(system.bodies.len(), Vector3::zeros());
        add_element_forces(&system.force_elements, &lag.predicted, &mut lag.anticipated);
        lag.used.clear();
        if let Some((used, _)) = self.integrator.body_predictions() {
            lag.used.extend_from_slice(used);
        }
        for (c, contact) in system.contacts.iter().enumerate() {
            if self.open[c] {
                continue;
            }
            let b = contact.body;
            let dv = weights.0 * response(&system.bodies[b], &(lag.anticipated[b] - lag.used[b]));
            let (mt, mn) = self.end_frames[c].body_rows(contact.radius());
            let offset = self.offsets[c];
            if contact.rolls() {
                self.error[offset] += mt.dot(&dv);
                self.error[offset + 1] += mn.dot(&dv);
            } else {
                self.error[offset] += mn.dot(&dv);
            }
        }
    }

    /// Give the next integration the bodies' end state the applied
    /// correction `self.correction` and the anticipated force elements
    /// lead to.
    pub(super) fn predict_bodies(&mut self, system: &System, dt: f64, end: &DynamicState) {
        let weights = self.integrator.body_weights(dt);
        let correction = std::mem::take(&mut self.correction);
        self.contact_change(system, &correction);
        self.correction = correction;
        let lag = &self.law_lag;
        let q = |b: usize| lag.contact_change[b] + lag.anticipated[b] - lag.used[b];
        if let Some((_, next)) = self.integrator.body_predictions() {
            Self::moved(system, weights, &end.bodies, q, next);
        }
    }
}
