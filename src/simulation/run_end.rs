//! One rule for when a run ends, read by the CLI's run loop
//! (`report::stop_time`) and by the FMU's default experiment
//! (`model::experiment`): at `solver.end_time` where the scene sets one;
//! else when the last contact leaves the structure, which at the vehicles'
//! initial speeds happens at `RunEnd::LastExit`.

use crate::scene::{BodySpec, Scene};

/// When a scene's run ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunEnd {
    /// At `solver.end_time` (s).
    EndTime(f64),
    /// When the last contact leaves the beam [0, L]: that of the vehicle
    /// whose last contact, at its initial speed, leaves last, after
    /// `distance` (m) at `speed` (m/s, > 0) (an estimate: forces change
    /// the speeds).
    LastExit { distance: f64, speed: f64 },
    /// No end time and no vehicle moves: nothing ends the run.
    NoExit,
}

/// The rule: `solver.end_time`, else the last vehicle's exit.
pub fn run_end(scene: &Scene) -> RunEnd {
    if let Some(t) = scene.solver.end_time {
        return RunEnd::EndTime(t);
    }
    match last_to_leave(scene) {
        Some((_, (distance, speed))) => RunEnd::LastExit { distance, speed },
        None => RunEnd::NoExit,
    }
}

/// The vehicle whose last contact leaves the beam last at the initial
/// speeds (the first of those that leave together), with how far that
/// contact travels and at what speed; `None` when no vehicle moves.
pub fn last_to_leave(scene: &Scene) -> Option<(usize, (f64, f64))> {
    let exits = (scene.vehicles.iter().enumerate())
        .filter_map(|(k, v)| Some((k, travel_to_exit(v, scene.beam.length)?)));
    exits.reduce(|a, b| {
        if exit_time(b.1) > exit_time(a.1) {
            b
        } else {
            a
        }
    })
}

/// When a vehicle that travels `distance` at `speed` leaves (s, not
/// before the start).
pub fn exit_time((distance, speed): (f64, f64)) -> f64 {
    (distance / speed).max(0.0)
}

/// How far the last contact of vehicle `v` travels to leave the beam
/// [0, L], and at what speed (its initial speed's magnitude); `None` at rest.
fn travel_to_exit(v: &BodySpec, length: f64) -> Option<(f64, f64)> {
    let speed = v.initial_speed;
    // The contacts' spread about `initial_position` (a bogie vehicle's
    // wheelsets and a maglev's magnets lie about its centre, a moving
    // force's train trails behind it): the preset's reach.
    let reach = v.kind.reach(v).unwrap_or_default();
    let x = v.initial_position;
    if speed > 0.0 {
        Some((length - (x - reach.behind), speed))
    } else if speed < 0.0 {
        Some((x + reach.ahead, -speed))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::BodyKind;

    /// The paper's wheel on its 24 m beam at 10 m/s, and a second wheel
    /// 6 m behind it: the run ends when the second one has travelled
    /// 24 + 6 m (closed form (L − x₀) / V of the rear wheel).
    #[test]
    fn the_last_vehicle_to_leave_ends_the_run() {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        assert_eq!(scene.vehicles[0].initial_position, 0.0);
        let mut rear = scene.vehicles[0].clone();
        rear.initial_position = -6.0;
        scene.vehicles.push(rear);
        let end = run_end(&scene);
        assert_eq!(
            end,
            RunEnd::LastExit {
                distance: 30.0,
                speed: 10.0
            }
        );
        assert_eq!(exit_time((30.0, 10.0)), 3.0);
        // Both callers read it: the CLI's cap and the FMU's experiment.
        assert_eq!(crate::report::stop_time(&scene), Ok(10.0 * 30.0 / 10.0));
        let vibration = crate::model::experiment::FREE_VIBRATION_PERIODS
            * crate::model::experiment::fundamental_period(&scene);
        assert_eq!(
            crate::model::experiment::default_stop_time(&scene),
            3.0 + vibration
        );
        scene.solver.end_time = Some(0.5);
        assert_eq!(run_end(&scene), RunEnd::EndTime(0.5));
    }

    /// A vehicle running towards x = 0 leaves after x₀ / |V|; at rest none
    /// leaves.
    #[test]
    fn a_vehicle_running_back_leaves_at_the_start_and_one_at_rest_never() {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        scene.vehicles[0].initial_position = 12.0;
        scene.vehicles[0].initial_speed = -4.0;
        assert_eq!(
            run_end(&scene),
            RunEnd::LastExit {
                distance: 12.0,
                speed: 4.0
            }
        );
        scene.vehicles[0].initial_speed = 0.0;
        assert_eq!(run_end(&scene), RunEnd::NoExit);
        assert!(crate::report::stop_time(&scene).is_err());
    }

    /// A maglev car of 4 magnets 3 m apart, centred at x₀ = 6 m at 10 m/s
    /// on the 24 m beam: its rear magnet, 4.5 m behind the centre, leaves
    /// last, after L − (x₀ − 4.5) = 22.5 m (the reach validation places
    /// the magnets by; before the one rule the run ended at 18 m).
    #[test]
    fn a_maglev_car_leaves_when_its_rear_magnet_does() {
        let mut scene = Scene::lee1994(BodyKind::Glider, 10.0, 0.0025);
        scene.vehicles[0].kind = BodyKind::MaglevVehicle;
        scene.vehicles[0].initial_position = 6.0;
        scene.vehicles[0].maglev = Some(crate::scene::MaglevSpec {
            car_inertia: 1.5e6,
            magnets: 4,
            magnet_spacing: 3.0,
            magnet_mass: 600.0,
            stiffness: 8e5,
            damping: 0.0,
        });
        scene.validate().unwrap();
        let rear = 6.0 - 0.5 * (4.0 - 1.0) * 3.0;
        assert_eq!(
            run_end(&scene),
            RunEnd::LastExit {
                distance: 24.0 - rear,
                speed: 10.0
            }
        );
        // Running back, the front magnet leaves last, after x₀ + 4.5 m.
        scene.vehicles[0].initial_speed = -10.0;
        assert_eq!(
            run_end(&scene),
            RunEnd::LastExit {
                distance: 6.0 + 4.5,
                speed: 10.0
            }
        );
    }
}
