//! The co-simulation's open-ended track (`Simulation::new_open_ended`, what
//! the FMU runs): leaving the structure is an event, not the end of the run.
//! Beyond the end of the track the body goes on over level ground that the
//! structure does not feel, and the beam vibrates freely.

use guideway::scene::BodyKind;
use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};

fn output(sim: &Simulation, name: &str) -> f64 {
    let k = sim
        .outputs()
        .iter()
        .position(|o| o.name == name)
        .unwrap_or_else(|| panic!("no output {name}"));
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    values[k]
}

fn beam_energy(sim: &Simulation) -> f64 {
    output(sim, "energy.beam_kinetic") + output(sim, "energy.beam_strain")
}

/// The default scene has no run-off: the paper's run ends at the exit, the
/// open-ended one goes on with the wheel on the ground beyond the beam.
#[test]
fn without_run_off_the_wheel_leaves_the_structure_and_the_run_goes_on() {
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut closed = Simulation::new(&scene).unwrap();
    let Advance::Exited { time: exit } = closed.advance_to(4.0).unwrap() else {
        panic!("the paper's run ends at the exit")
    };
    let mut sim = Simulation::new_open_ended(&scene).unwrap();
    assert_eq!(output(&sim, "contact.on_beam"), 1.0);
    assert_eq!(sim.advance_to(exit).unwrap(), Advance::Reached);
    let energy_at_exit = beam_energy(&sim);
    assert_eq!(sim.advance_to(4.0).unwrap(), Advance::Reached);
    assert_eq!(sim.time(), 4.0);
    assert_eq!(sim.exit_time(), None);
    let kinds: Vec<EventKind> = sim.events().iter().map(|e| e.kind).collect();
    assert_eq!(kinds, vec![EventKind::Exit, EventKind::LeftTrack]);
    // Found to the event location's tolerance (the open run also stops at
    // `exit` itself, so its steps differ there).
    for e in sim.events() {
        assert!((e.time - exit).abs() < 1e-9, "{} vs {exit}", e.time);
    }
    assert_eq!(output(&sim, "contact.on_beam"), 0.0);
    // On the ground the wheel carries its load, level with the supports.
    let load = -scene.vehicles[0].force_y;
    assert!((output(&sim, "contact.normal_force") - load).abs() < 1e-6 * load);
    let (r, h) = (0.3, scene.beam.surface_offset);
    let y = output(&sim, "wheel.y");
    println!("wheel.y {y}, vy {}", output(&sim, "wheel.vy"));
    // to the gap tolerance
    assert!((y - (r + h)).abs() < scene.solver.gap_tolerance, "{y}");
    assert!(output(&sim, "contact.position") > 24.0 + 10.0 * (4.0 - exit) * 0.9);
    // The beam vibrates freely: its energy stays (RK4 loses a little).
    let energy = beam_energy(&sim);
    println!("beam energy at the exit {energy_at_exit} J, at 4 s {energy} J");
    assert!(energy_at_exit > 1.0);
    assert!(energy <= energy_at_exit && energy > 0.99 * energy_at_exit);
}

/// With run-off the contact rolls onto it (exit event) and, at its end,
/// leaves the track (event) and goes on.
#[test]
fn with_run_off_both_the_exit_and_the_end_of_the_track_are_events() {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.track.run_off = 5.0;
    let mut sim = Simulation::new_open_ended(&scene).unwrap();
    assert_eq!(sim.advance_to(4.0).unwrap(), Advance::Reached);
    let kinds: Vec<EventKind> = sim.events().iter().map(|e| e.kind).collect();
    assert_eq!(kinds, vec![EventKind::Exit, EventKind::LeftTrack]);
    let (exit, left) = (sim.events()[0].time, sim.events()[1].time);
    assert!((left - exit - 0.5).abs() < 0.01, "{exit} {left}");
    assert_eq!(output(&sim, "contact.on_beam"), 0.0);
}
