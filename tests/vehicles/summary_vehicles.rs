//! The run summary's exit figures per vehicle (issue 26 item 3): each
//! coach's first and last contact off the beam, with or without
//! `solver.end_time`, checked against the recorded kinematics (the contact
//! bodies' x crossing the end of the beam) rather than the event list.

use guideway::report::exits::{vehicle_names, ExitWatch, VehicleExit};
use guideway::report::{drive, Run, RunSummary};
use guideway::scene::{builtin, IntegratorKind};
use guideway::{Scene, Simulation};

/// Run `scene` watching its vehicles' exits; the trace, the summary with
/// the exits set, and the exits.
fn run_watched(scene: &Scene) -> (Run, RunSummary) {
    let mut simulation = Simulation::new(scene).expect("scene builds");
    let mut watch = ExitWatch::new(&mut simulation, &vehicle_names(scene));
    let run = drive(scene, &mut watch, |_| {}).expect("run succeeds");
    let exits = watch.finish();
    let mut summary = run.summary(scene);
    summary.set_vehicles(exits);
    (run, summary)
}

/// Two coaches of the built-in 3-coach train, at a coarser step, past
/// their exit into the free vibration (`end_time` set).
fn two_coaches() -> Scene {
    let mut scene = builtin("train-3-coaches-2x25-5").expect("built-in");
    scene.vehicles.truncate(2);
    scene.solver.step = 1e-3;
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.end_time = Some(19.5);
    scene
}

/// When body `name`'s x first reached `x_end` in the trace, by linear
/// interpolation between the two rows around it.
fn crossing_time(run: &Run, name: &str, x_end: f64) -> f64 {
    let column = run.trace.column(&format!("{name}.x")).expect("body x");
    let k = column.iter().position(|&x| x >= x_end).expect("crosses");
    let (x0, x1) = (column[k - 1], column[k]);
    let (t0, t1) = (run.trace.time[k - 1], run.trace.time[k]);
    t0 + (t1 - t0) * (x_end - x0) / (x1 - x0)
}

#[test]
fn each_coach_has_its_first_and_last_exit_with_end_time_set() {
    let scene = two_coaches();
    let (run, summary) = run_watched(&scene);
    let length = scene.beam.length;
    assert_eq!(summary.vehicles.len(), 2);
    for (coach, exit) in ["coach1", "coach2"].iter().zip(&summary.vehicles) {
        let VehicleExit {
            vehicle, contacts, ..
        } = exit;
        assert_eq!((vehicle.as_str(), *contacts), (*coach, 4));
        // Leading and trailing wheelsets: their centres cross x = L when
        // their contact points do (to the wheel radius times the deck's
        // slope, under 1e-4 m here, i.e. 2e-5 s at 5 m/s).
        let first = crossing_time(&run, &format!("{coach}_wheelset1"), length);
        let last = crossing_time(&run, &format!("{coach}_wheelset4"), length);
        let within = |got: Option<f64>, want: f64| (got.unwrap() - want).abs() < 1e-4;
        assert!(within(exit.first_exit_time, first), "{exit:?} vs {first}");
        assert!(within(exit.last_exit_time, last), "{exit:?} vs {last}");
        // The coach runs free at about its initial 5 m/s.
        for speed in [exit.first_exit_speed, exit.last_exit_speed] {
            assert!((speed.unwrap() - 5.0).abs() < 5e-3, "{exit:?}");
        }
    }
    // The run went on to end_time, past the exit: the summary gives the
    // train's exit, when its last contact (coach2's last wheelset) left,
    // as a run without end_time would have ended (`run_end`).
    assert_eq!(*run.trace.time.last().unwrap(), 19.5);
    let rear_last = crossing_time(&run, "coach2_wheelset4", length);
    assert!((summary.exit_time.unwrap() - rear_last).abs() < 1e-4);
    assert_eq!(summary.exit_time, summary.vehicles[1].last_exit_time);
    assert_eq!(
        summary.exit_nominal_speed,
        summary.vehicles[1].last_exit_speed
    );
    let json = summary.to_json();
    assert!(json.contains("\"last_exit_time\""), "{json}");
    let text = summary.to_string();
    assert!(!text.contains("did not leave"), "{text}");
    assert!(
        text.contains("vehicle exit       coach2: first contact"),
        "{text}"
    );
}

#[test]
fn a_coach_still_on_the_beam_has_no_last_exit() {
    let mut scene = two_coaches();
    // coach2's trailing wheelset is still on the beam at 18.5 s.
    scene.solver.end_time = Some(17.0);
    let (_, summary) = run_watched(&scene);
    let coach2 = &summary.vehicles[1];
    assert!(coach2.first_exit_time.is_some(), "{coach2:?}");
    assert_eq!(
        (coach2.last_exit_time, coach2.last_exit_speed),
        (None, None)
    );
    // The train has not left (coach1 has): the summary gives no exit.
    assert!(summary.vehicles[0].last_exit_time.is_some());
    assert_eq!(
        (summary.exit_time, summary.exit_nominal_speed),
        (None, None)
    );
}

#[test]
fn a_single_wheel_run_to_its_exit_agrees_with_the_run_exit() {
    let scene = builtin("lee1994-wheel-10").expect("built-in");
    let (run, summary) = run_watched(&scene);
    let wheel = &summary.vehicles[0];
    assert_eq!(wheel.first_exit_time, run.exit_time);
    assert_eq!(wheel.last_exit_time, run.exit_time);
    let speed = run.trace.column("wheel.nominal_speed").unwrap();
    assert_eq!(wheel.last_exit_speed, speed.last().copied());
    assert_eq!(summary.exit_nominal_speed, wheel.last_exit_speed);
}
