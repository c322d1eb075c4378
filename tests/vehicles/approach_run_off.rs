//! A wheel rolling from rigid approach ground onto the beam and off onto the
//! run-off: entry and exit are events, the run goes on to the end time with
//! the beam vibrating freely.

use guideway::scene::BodyKind;
use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

fn scene(end_time: Option<f64>) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.track.approach = 10.0;
    scene.track.run_off = 30.0;
    scene.vehicles[0].initial_position = -5.0;
    scene.solver.end_time = end_time;
    scene.validate().expect("valid");
    scene
}

struct Sampled {
    time: Vec<f64>,
    normal: Vec<f64>,
    midspan: Vec<f64>,
    beam_energy: Vec<f64>,
}

fn run(sim: &mut Simulation, end: f64) -> (Sampled, Advance) {
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (normal, midspan) = (at("contact.normal_force"), at("sensor.midspan.deflection"));
    let (kinetic, strain) = (at("energy.beam_kinetic"), at("energy.beam_strain"));
    let mut values = vec![0.0; names.len()];
    let mut s = Sampled {
        time: vec![],
        normal: vec![],
        midspan: vec![],
        beam_energy: vec![],
    };
    let dt = sim.step_size();
    let mut advance = Advance::Reached;
    for k in 1..=(end / dt).round() as u64 {
        advance = sim.advance_to(k as f64 * dt).expect("no solver error");
        sim.output_values(&mut values);
        s.time.push(sim.time());
        s.normal.push(values[normal]);
        s.midspan.push(values[midspan]);
        s.beam_energy.push(values[kinetic] + values[strain]);
        if advance != Advance::Reached {
            break;
        }
    }
    (s, advance)
}

#[test]
fn wheel_rolls_on_and_off_and_the_beam_vibrates_freely_until_the_end_time() {
    let mut sim = Simulation::new(&scene(Some(4.0))).unwrap();
    let (s, advance) = run(&mut sim, 4.0);
    assert_eq!(advance, Advance::Reached);
    assert!((sim.time() - 4.0).abs() < 1e-12, "{}", sim.time());
    let events = sim.events().to_vec();
    assert_eq!(events.len(), 2, "{events:?}");
    assert_eq!(events[0].kind, EventKind::Entry);
    assert_eq!(events[1].kind, EventKind::Exit);
    // Entry at x = 0 after 5 m at 10 m/s on rigid ground.
    assert!((events[0].time - 0.5).abs() < 1e-9, "{:?}", events[0]);
    let (entry, exit) = (events[0].time, events[1].time);
    // The paper's crossing takes 2.275 s from x = 0.
    assert!(
        (exit - entry - 2.2749).abs() < 0.01,
        "crossing {}",
        exit - entry
    );

    // Before the entry the beam is at rest and the wheel carries its load.
    let before: Vec<usize> = (0..s.time.len()).filter(|&i| s.time[i] < entry).collect();
    assert!(before.iter().all(|&i| s.midspan[i] == 0.0));
    assert!(before
        .iter()
        .all(|&i| (s.normal[i] - 6e5).abs() < 1e-6 * 6e5));

    // After the exit: free vibration, present and bounded (undamped: the
    // beam's energy stays what it was when the wheel left).
    let after: Vec<usize> = (0..s.time.len())
        .filter(|&i| s.time[i] > exit + 0.01)
        .collect();
    assert!(after.len() > 400);
    let amplitude = after
        .iter()
        .map(|&i| s.midspan[i].abs())
        .fold(0.0, f64::max);
    let peak = s.midspan.iter().map(|w| w.abs()).fold(0.0, f64::max);
    assert!(
        amplitude > 0.05 * peak,
        "free vibration {amplitude} vs {peak}"
    );
    assert!(amplitude < peak, "{amplitude} vs {peak}");
    // RK4 damps the free vibration slightly (its amplitude error at
    // ω Δt); it never feeds energy in.
    let e0 = s.beam_energy[after[0]];
    let mut lowest = e0;
    for &i in &after {
        let e = s.beam_energy[i];
        assert!(
            e <= e0 * (1.0 + 1e-12),
            "beam energy {e} vs {e0} at {}",
            s.time[i]
        );
        lowest = lowest.min(e);
    }
    eprintln!("beam energy after the exit: {e0} J, lowest {lowest} J");
    assert!(lowest > 0.99 * e0, "{lowest} vs {e0}");
    // On the run-off the wheel carries its load again.
    assert!(after
        .iter()
        .all(|&i| (s.normal[i] - 6e5).abs() < 1e-6 * 6e5));

    // The contact force is continuous from step to step away from the exit
    // step (see README: the jump there is the beam end's surface velocity).
    let mut largest_change: f64 = 0.0;
    for i in 1..s.time.len() {
        if (s.time[i.saturating_sub(2)]..=s.time[i]).contains(&exit) {
            continue;
        }
        largest_change = largest_change.max((s.normal[i] - s.normal[i - 1]).abs());
    }
    assert!(
        largest_change < 0.01 * 6e5,
        "normal force changes by {largest_change} N in a step"
    );
}

#[test]
fn without_an_end_time_the_run_stops_when_the_wheel_leaves_the_beam() {
    let mut sim = Simulation::new(&scene(None)).unwrap();
    let (_, advance) = run(&mut sim, 10.0);
    let Advance::Exited { time } = advance else {
        panic!("{advance:?}");
    };
    let exit = sim.events().last().unwrap();
    assert_eq!(exit.kind, EventKind::Exit);
    assert_eq!(exit.time, time);
    assert!((time - 0.5 - 2.2749).abs() < 0.01, "{time}");
}

#[test]
fn on_the_approach_the_wheel_rolls_as_on_level_ground() {
    // 0.3 s on the approach: no beam motion, constant speed, the load
    // carried by the ground.
    let mut sim = Simulation::new(&scene(Some(0.3))).unwrap();
    let (s, _) = run(&mut sim, 0.3);
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    let vx = values[names.iter().position(|n| n == "wheel.vx").unwrap()];
    assert!((vx - 10.0).abs() < 1e-9, "{vx}");
    assert!(s.midspan.iter().all(|w| *w == 0.0));
    assert!(sim.events().is_empty());
}
