//! Moving forces: point loads crossing the beam at constant speed, with no
//! body and no contact iteration: the classical model of code checks
//! (Frýba's moving force) and of the standard trains (HSLM, EN 1991-2).
//!
//! The beam alone is integrated with Newmark's average acceleration (HHT-α
//! at α = 0: unconditionally stable, second order, no numerical damping),
//! the loads placed at their exact positions at each step's end through
//! the Hermite shape functions (consistent nodal loads).

mod crossing;
mod run;
mod trains;

pub use crate::vehicle::hslm::{hslm, HslmTrain, HSLM_TRAINS};
pub use crossing::{exit_time, run_end, static_peak, Crossing, Peaks};
pub use run::{crossing_times, AxleEvent, ForceRun, ForceState, ForceVehicle, FORCES_ON_BEAM};
pub use trains::RealTrain;

use crate::scene::{BodySpec, Scene};
pub use crate::vehicle::presets::is_moving_force_scene;

/// One point force: its abscissa at t = 0 (m), its speed (m/s) and its
/// vertical component (N, y up: a downward load is negative).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axle {
    pub position: f64,
    pub speed: f64,
    pub force: f64,
}

impl Axle {
    /// Abscissa at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        self.position + self.speed * t
    }
}

/// The axles of one moving-force vehicle: its train's, the first at
/// `initial_position` and the others behind it, or a single force of the
/// body's weight plus its applied `force_y`.
pub fn vehicle_axles(spec: &BodySpec, gravity: f64) -> Vec<Axle> {
    let speed = spec.initial_speed;
    match spec.train.as_deref().and_then(hslm) {
        Some(train) => train
            .axles()
            .into_iter()
            .map(|(offset, force)| Axle {
                position: spec.initial_position - offset,
                speed,
                force,
            })
            .collect(),
        None => vec![Axle {
            position: spec.initial_position,
            speed,
            force: spec.force_y - spec.mass * gravity,
        }],
    }
}

/// Every axle of a moving-force scene ([body] and [[vehicles]]).
pub fn scene_axles(scene: &Scene) -> Vec<Axle> {
    scene
        .vehicles
        .iter()
        .flat_map(|spec| vehicle_axles(spec, scene.gravity))
        .collect()
}
