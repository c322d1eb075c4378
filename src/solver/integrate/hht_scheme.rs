//! HHT-α behind the integrator seam: its answers to `TimeIntegrator`
//! (implicit, second order, stable at any step, carrying its step's end,
//! lagging its force laws) and the forwarding of each call to `Hht`'s own
//! methods (hht.rs).

use super::{
    BodyState, ContactForce, DynamicState, ForceProfile, Hht, IntegrationError, StepStart,
    TimeIntegrator, Vector3,
};
use crate::system::System;
use nalgebra::DVector;

impl TimeIntegrator for Hht {
    const NAME: &'static str = "hht";
    const TITLE: &'static str = "implicit HHT-α";
    const CARRIES_STEP_END: bool = true;
    // Its unknown is the end-of-step force: a shape would be ignored.
    const FITS_FORCE_SHAPE: bool = false;
    const LAGS_FORCE_LAWS: bool = true;
    const STEPS_TRACK_ON_DECK: bool = true;
    const HOLDS_FORCES_AT_END: bool = true;

    fn build(system: &System, step: f64, damping: f64) -> Result<(Hht, String), String> {
        let hht = Hht::new(system, damping, step)?;
        Ok((hht, format!("hht (implicit HHT-α, α = {})", 0.0 - damping)))
    }

    fn stable_step(_system: &System) -> Option<f64> {
        None
    }

    fn order(_profile: ForceProfile) -> f64 {
        2.0
    }

    fn begin_step(&mut self, system: &System, dt: f64) -> Result<(), IntegrationError> {
        Hht::begin_step(self, system, dt)
    }

    fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError> {
        Hht::step(self, system, from, forces, end)
    }

    fn finish_step(&mut self, system: &System, from: &StepStart, end: &mut DynamicState) {
        Hht::finish_step(self, system, from, end)
    }

    fn keep_energy_books(&mut self, on: bool) {
        Hht::keep_energy_books(self, on)
    }

    fn keeps_energy_books(&self) -> bool {
        Hht::keeps_energy_books(self)
    }

    fn hold_followers(&mut self, held: &[bool]) {
        Hht::hold_followers(self, held)
    }

    fn seed_prediction(&mut self, end: Option<(&DynamicState, f64)>) {
        Hht::seed_prediction(self, end)
    }

    fn seeded_bodies(&self) -> Option<&[BodyState]> {
        Hht::seeded_bodies(self)
    }

    fn predict_with_accelerations(&mut self, on: bool) {
        self.predicts_accelerations = on;
    }

    fn held_follower_forces(&self) -> &[ContactForce] {
        self.follower_forces_used()
    }

    fn end_forces(&self) -> Option<&super::EndForces> {
        Some(Hht::end_forces(self))
    }

    fn body_predictions(&mut self) -> Option<(&[Vector3<f64>], &mut [BodyState])> {
        Some(Hht::body_predictions(self))
    }

    fn know_prediction(&mut self, known: super::KnownAtPrediction) {
        Hht::know_prediction(self, known)
    }

    fn body_weights(&self, dt: f64) -> (f64, f64) {
        Hht::body_weights(self, dt)
    }

    fn nominal_band_response(&self) -> Option<(&crate::band::BandLdlt, f64, f64)> {
        Hht::nominal_band_response(self)
    }

    fn point_compliance(
        &mut self,
        system: &System,
        shape: &crate::beam::Shape,
        row: &[f64; 4],
        dt: f64,
    ) -> Option<(f64, f64)> {
        Hht::point_compliance(self, system, shape, row, dt)
    }

    fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    ) {
        Hht::beam_response(self, system, load, dt, displacement, velocity)
    }
}
