//! The turn of each contact's frame with the beam's end displacement, in
//! the velocity operator (issue 29).
//!
//! A contact's normal velocity error e_n = n(φ)·q̇ − v_n is measured in the
//! frame of the foot point's slope, φ = atan w′(x_d), which the step's end
//! displacement turns: ∂e_n/∂φ = −(cos φ ẋ + sin φ ẏ), the body's speed
//! along the surface, and ∂φ/∂u = cos²φ N′(x_d). Where the scheme's end
//! displacement answers the end force w_u / w_v times its end velocity
//! (HHT-α: β Δt / γ, `TimeIntegrator::HOLDS_FORCES_AT_END`), measuring the
//! beam's response with the normal row n_row + κ N′, κ = (w_u / w_v) cos²φ
//! (cos φ ẋ + sin φ ẏ), makes the operator the step's Jacobian. Without
//! it, at 300 km/h the first correction left 0.1–0.4 % of the error (a
//! coupling antisymmetric between the two wheelsets of a bogie, found by
//! finite differences of whole integrations), and a third of the steps of
//! the 3 × 25 m train took a third integration. Left out: the surface's
//! own speed along itself (sin φ w′ v, 1e-8 of the body's) and the
//! tangential row's turn, whose factor is e_n itself, zero at convergence.

use crate::body::BodyState;
use crate::contact::ContactFrame;
use crate::system::System;

/// Each contact's κ (s·m/s = m) at an integration's end, in `frames` and
/// `bodies`, with the scheme's body weights `(w_v, w_u)`; zero off the
/// beam.
pub(super) fn turn_rates(
    system: &System,
    (frames, bodies): (&[ContactFrame], &[BodyState]),
    (velocity_weight, position_weight): (f64, f64),
    turns: &mut Vec<f64>,
) {
    let lag = position_weight / velocity_weight;
    turns.clear();
    turns.extend(system.contacts.iter().zip(frames).map(|(contact, frame)| {
        if !frame.on_beam {
            return 0.0;
        }
        let velocity = bodies[contact.body].velocity;
        let along = frame.cos * velocity.x + frame.sin * velocity.y;
        lag * frame.cos * frame.cos * along
    }));
}

/// Add `turn` (κ) times the slope's row at `frame`'s foot point to its
/// normal row `normal` (nothing where κ is zero: the same bits).
pub(super) fn add_turn<'a>(
    normal: impl IntoIterator<Item = &'a mut f64>,
    frame: &ContactFrame,
    turn: f64,
) {
    if turn != 0.0 {
        for (n, dn) in normal.into_iter().zip(&frame.shape.dn) {
            *n += turn * dn;
        }
    }
}
