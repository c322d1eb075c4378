//! The events located inside a step, as methods of the step's view
//! (`stepper::Step`) over the system and the state: the active set of the
//! contacts (`active_set`), landings and impacts (`landing`), track
//! boundaries (`track`), lift-offs under HHT-α (`lift_off`), switches of
//! surface and the implicit scheme's restart (`switch`), the massless
//! followers (`follower`); here, the locator they share (regula falsi on
//! the step's length) and the contact frames and velocity errors now.

use nalgebra::Vector2;

use crate::contact::ContactForce;
use crate::integrate::DynamicState;
use crate::iteration::StepSolution;
use crate::solver::stepper::{SolverError, Step};

mod active_set;
mod follower;
mod landing;
mod lift_off;
mod switch;
mod track;

impl Step<'_> {
    /// Shorten the step until `miss`, a signed distance read from the
    /// solved state and solution (`start` at the step's start, or at the
    /// step length given with it, `end` at its end), is within
    /// `tolerance`: regula falsi on the step length,
    /// Illinois variant. `None` when 60 passes do not get there.
    pub(crate) fn locate(
        &mut self,
        forces: &[ContactForce],
        dt: f64,
        ((lo, start), end): ((f64, f64), f64),
        tolerance: f64,
        miss: impl Fn(&Step, &StepSolution) -> f64,
    ) -> Result<Option<(StepSolution, f64)>, SolverError> {
        let (mut lo, mut f_lo) = (lo, start);
        let (mut hi, mut f_hi) = (dt, end);
        let mut side = 0;
        for _ in 0..60 {
            let tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let solution = self.solve(forces, tau)?;
            let f = miss(self, &solution);
            if f.abs() <= tolerance || (hi - lo) <= 1e-15 * dt {
                return Ok(Some((solution, tau)));
            }
            if (f > 0.0) == (f_hi > 0.0) {
                (hi, f_hi) = (tau, f);
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            } else {
                (lo, f_lo) = (tau, f);
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            }
        }
        Ok(None)
    }

    /// The contact frames of state `d`, each contact on the part of the
    /// track it is on now.
    pub(crate) fn frames_of(
        &self,
        d: &DynamicState,
    ) -> Result<Vec<crate::contact::ContactFrame>, crate::integrate::IntegrationError> {
        let memo = self.work.iteration.frame_memo();
        memo.frames_of(self.system, d, &self.state.parts)
    }

    /// The contact frames of the current state.
    pub(crate) fn frames_now(&self) -> Result<Vec<crate::contact::ContactFrame>, SolverError> {
        self.frames_of(&self.state.dynamic)
            .map_err(|e| SolverError {
                time: self.state.time,
                message: crate::iteration::StepError::from(e).to_string(),
            })
    }

    /// Contact `c`'s normal velocity error now (m/s): negative approaches.
    pub(crate) fn normal_velocity_error(&self, c: usize) -> Result<f64, SolverError> {
        let frames = self.frames_now()?;
        Ok(self.velocity_errors(&frames)[c].y)
    }

    /// Every contact's velocity error (tangential, normal) at `frames`.
    pub(crate) fn velocity_errors(
        &self,
        frames: &[crate::contact::ContactFrame],
    ) -> Vec<Vector2<f64>> {
        let d = &self.state.dynamic;
        let beam = &self.system.beam;
        self.system
            .contacts
            .iter()
            .zip(frames)
            .map(|(contact, frame)| {
                let point = contact.point(&d.bodies[contact.body]);
                frame.velocity_error(beam, contact.radius(), &point, &d.beam_velocity)
            })
            .collect()
    }
}
