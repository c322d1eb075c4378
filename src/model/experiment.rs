//! The default experiment a scene's FMU declares: from the start to the
//! last exit from the structure plus a time of free vibration (or the
//! scene's `solver.end_time`), in steps of the solver's.

use crate::scene::Scene;
use crate::simulation::run_end::{exit_time, run_end, RunEnd};

/// Free vibration after the last exit, in periods of the fundamental mode
/// of the longest span.
pub const FREE_VIBRATION_PERIODS: f64 = 3.0;

/// Stop time of the default experiment: `solver.end_time` if the scene sets
/// one; else the last exit from the beam at the vehicles' initial speeds
/// plus `FREE_VIBRATION_PERIODS` periods of the longest span's fundamental
/// mode (simply supported: T₁ = 2 L² / π · √(m / EI)); 1 s where no vehicle
/// moves.
/// Moving forces step on their fixed grid only (`variable_communication_steps`):
/// there the stop time is the first grid point at or after it.
pub fn default_stop_time(scene: &Scene) -> f64 {
    let stop = match run_end(scene) {
        RunEnd::EndTime(t) => t,
        RunEnd::LastExit { distance, speed } => {
            exit_time((distance, speed)) + FREE_VIBRATION_PERIODS * fundamental_period(scene)
        }
        RunEnd::NoExit => 1.0,
    };
    if variable_communication_steps(scene) {
        return stop;
    }
    let step = scene.solver.step;
    (stop / step - 1e-9).ceil() * step
}

/// Whether the FMU takes communication steps of any size: a vehicle's
/// does (its last internal step is shortened to the point); moving forces
/// are stepped on the fixed grid of `solver.step` (Newmark's matrix is
/// factored once for it), so their communication steps are fixed
/// multiples of it (`canHandleVariableCommunicationStepSize = false`).
pub fn variable_communication_steps(scene: &Scene) -> bool {
    !crate::moving_load::is_moving_force_scene(scene)
}

/// Fundamental period (s) of the longest span between supports, taken as
/// simply supported.
pub fn fundamental_period(scene: &Scene) -> f64 {
    let beam = &scene.beam;
    let mut supports = vec![0.0];
    supports.extend(&beam.supports.intermediate);
    supports.push(beam.length);
    let span = supports.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    2.0 * span * span / std::f64::consts::PI
        * (beam.mass_per_length / beam.bending_stiffness).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::BodyKind;

    #[test]
    fn the_default_scene_stops_three_periods_after_its_exit() {
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        // L = 24 m, m = 1250 kg/m, EI = 1e9 N m²: T1 = 0.4099 s
        let period = fundamental_period(&scene);
        assert!((period - 2.0 * 576.0 / std::f64::consts::PI * 1.25e-6f64.sqrt()).abs() < 1e-12);
        assert!((period - 0.41).abs() < 1e-3, "{period}");
        let stop = default_stop_time(&scene);
        assert!((stop - (2.4 + 3.0 * period)).abs() < 1e-12, "{stop}");
    }

    /// The HSLM template at 50 m/s: 25 m plus the train's length, then
    /// three periods, rounded up to its 1 ms grid.
    #[test]
    fn moving_forces_stop_on_their_grid() {
        let scene = crate::scene::builtin("bridge25-hslm").unwrap();
        let train = crate::moving_load::hslm("HSLM-A1").unwrap();
        let exact = (25.0 + train.length()) / 50.0 + 3.0 * fundamental_period(&scene);
        let stop = default_stop_time(&scene);
        assert!(stop >= exact && stop < exact + 0.001, "{stop} {exact}");
        assert_eq!(stop, (stop / 0.001).round() * 0.001);
        assert!(!variable_communication_steps(&scene));
    }

    #[test]
    fn end_time_wins_and_a_vehicle_at_rest_gives_one_second() {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        scene.solver.end_time = Some(0.7);
        assert_eq!(default_stop_time(&scene), 0.7);
        scene.solver.end_time = None;
        scene.vehicles[0].initial_speed = 0.0;
        assert_eq!(default_stop_time(&scene), 1.0);
        // moving left from x = 6 m at 3 m/s: out at 2 s
        scene.vehicles[0].initial_speed = -3.0;
        scene.vehicles[0].initial_position = 6.0;
        let stop = default_stop_time(&scene);
        assert!((stop - 2.0 - 3.0 * fundamental_period(&scene)).abs() < 1e-12);
    }
}
