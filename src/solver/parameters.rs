//! Every tolerance, cap and ratio the solver runs with, in one documented
//! struct (`Default` = the values guideway has always used), and the one
//! rule for "the same instant" and "the nominal step".

use crate::solver::iteration::IterationSettings;

/// Two times closer than this fraction of the step are the same instant
/// (an event within round-off of a grid point, a step within round-off of
/// the nominal one).
pub const SAME_INSTANT: f64 = 1e-9;

/// Whether a step of length `dt` is the nominal step `nominal` (whose
/// factors and unit-load responses are cached), to `SAME_INSTANT`.
pub fn is_nominal_step(dt: f64, nominal: f64) -> bool {
    (dt - nominal).abs() <= SAME_INSTANT * nominal
}

/// The solver's settings for one run: the scene's (`step`, `iteration`,
/// `force_profile_order`) and the fixed ones, named and documented here
/// rather than as literals at their sites.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParameters {
    /// The fixed grid step (s), `solver.step`.
    pub step: f64,
    /// The contact-force iteration's tolerances and cap (`solver.*`).
    pub iteration: IterationSettings,
    /// The first steps of a run with a shaped force profile are the grid
    /// step divided by this.
    pub start_up_divisions: f64,
    /// Events kept per run; later ones are counted, not kept.
    pub max_events: usize,
    /// Largest sum of |weights| an extrapolation of the force history may
    /// have (bounds how much the history's differences are magnified).
    pub max_extrapolation_gain: f64,
    /// A contact whose separation speed after an impact is below this
    /// (m/s) rests instead of bouncing again.
    pub resting_speed: f64,
    /// Trial steps of an implicit restart at most.
    pub restart_passes: usize,
    /// A restart is done when no force changes by more than this fraction
    /// of the largest.
    pub restart_tolerance: f64,
    /// A lift-off is located when its end force is within this fraction of
    /// the force it starts from.
    pub lift_off_tolerance: f64,
    /// The shortest step a lift-off is located in, as a fraction of the step.
    pub lift_off_earliest: f64,
    /// Steps between two grid points at most: events shorten steps, and
    /// contacts that switch back and forth at one instant (Zeno-like
    /// chatter) would otherwise shorten them for ever.
    pub max_steps_in_grid_step: usize,
}

impl SolverParameters {
    /// Today's values, with the scene defaults' step and iteration.
    pub const DEFAULT: SolverParameters = SolverParameters {
        step: 0.0025,
        iteration: IterationSettings {
            velocity_tolerance: 1e-7,
            gap_tolerance: 1e-5,
            max_iterations: 50,
        },
        start_up_divisions: 8.0,
        max_events: crate::state::MAX_EVENTS,
        max_extrapolation_gain: 50.0,
        resting_speed: 1e-2,
        restart_passes: 6,
        restart_tolerance: 1e-9,
        lift_off_tolerance: 1e-6,
        lift_off_earliest: 1e-3,
        max_steps_in_grid_step: 1000,
    };

    /// The fixed values with a scene's step and iteration settings.
    pub fn with_step(step: f64, iteration: IterationSettings) -> SolverParameters {
        SolverParameters {
            step,
            iteration,
            ..SolverParameters::DEFAULT
        }
    }

    /// Times closer than this (s) are the same instant.
    pub fn same_instant(&self) -> f64 {
        SAME_INSTANT * self.step
    }

    /// Whether a step of length `dt` is this run's grid step.
    pub fn is_nominal_step(&self, dt: f64) -> bool {
        is_nominal_step(dt, self.step)
    }
}

impl Default for SolverParameters {
    fn default() -> SolverParameters {
        SolverParameters::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same-instant rule at its edge: a relative difference of half
    /// `SAME_INSTANT` is the nominal step, of twice it is not.
    #[test]
    fn nominal_step_within_the_same_instant_tolerance() {
        let step = 0.0025;
        assert!(is_nominal_step(step * (1.0 + 0.5 * SAME_INSTANT), step));
        assert!(is_nominal_step(step * (1.0 - 0.5 * SAME_INSTANT), step));
        assert!(!is_nominal_step(step * (1.0 + 2.0 * SAME_INSTANT), step));
        assert!(!is_nominal_step(0.5 * step, step));
    }

    /// A scene's step and iteration replace the defaults', nothing else.
    #[test]
    fn with_step_keeps_the_fixed_values() {
        let iteration = IterationSettings {
            velocity_tolerance: 1e-3,
            gap_tolerance: 1e-4,
            max_iterations: 7,
        };
        let params = SolverParameters::with_step(1e-3, iteration);
        assert_eq!(params.step, 1e-3);
        assert_eq!(params.iteration, iteration);
        let fixed = SolverParameters {
            step: SolverParameters::DEFAULT.step,
            iteration: SolverParameters::DEFAULT.iteration,
            ..params
        };
        assert_eq!(fixed, SolverParameters::default());
        assert_eq!(params.same_instant(), SAME_INSTANT * 1e-3);
    }
}
