//! Templates that give physics (issue 24 item 4): the built-in eight-coach
//! benchmark, its 1,400 kg wheelsets on the Hertz wheel–rail contact,
//! converges. Its peak filtered deck acceleration and peak wheel force
//! move by less than 2 % at half the step and at twice the elements, no
//! wheelset lifts off, and no force exceeds twice the static wheel load.
//! On Lee's rigid contact at 1 ms the same train lifted off and landed
//! with 223 kN, and its filtered peak moved by 7.8 % at half the step
//! (docs/vehicles.md, "Which model for which question").

use crate::common;

use guideway::report::{drive, RunSummary, SummaryEvent};
use guideway::scene::builtin;
use guideway::{Scene, Simulation};

/// The run's summary and its lift-off count.
fn run(scene: &Scene) -> (RunSummary, usize) {
    let mut simulation = Simulation::new(scene).expect("scene builds");
    let run = drive(scene, &mut simulation, |_| {}).expect("run succeeds");
    let lift_offs = SummaryEvent::list(&simulation)
        .iter()
        .filter(|e| e.kind == "lift_off")
        .count();
    (run.summary(scene), lift_offs)
}

/// Peak |filtered deck acceleration| over the sensors and peak contact
/// force over the contacts.
fn peaks(summary: &RunSummary) -> (f64, f64) {
    let acceleration = summary
        .peak_design
        .iter()
        .filter(|(name, _)| name.ends_with(".acceleration_filtered"))
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max);
    let force = summary
        .peak_contact_force
        .values()
        .fold(0.0, |m: f64, v| m.max(*v));
    (acceleration, force)
}

#[test]
fn the_eight_coach_benchmark_on_hertz_contacts_converges_without_lift_off() {
    let scene = builtin("train-8-coaches-3x25-300").expect("built-in");
    let mut half = scene.clone();
    half.solver.step *= 0.5;
    let mut finer = scene.clone();
    finer.beam.elements *= 2;
    let static_load = common::static_wheelset_load(&scene);
    let (base, base_lifts) = run(&scene);
    let (acceleration, force) = peaks(&base);
    println!("Δt: filtered deck acceleration {acceleration:.5} m/s², force {force:.1} N, static {static_load:.1} N");
    assert_eq!(base_lifts, 0, "lift-offs at the scene's step");
    assert!(
        force < 2.0 * static_load,
        "{force} N against {static_load} N"
    );
    for (what, refined) in [("Δt/2", &half), ("2n elements", &finer)] {
        let (summary, lifts) = run(refined);
        let (a, f) = peaks(&summary);
        let (da, df) = (a / acceleration - 1.0, f / force - 1.0);
        println!(
            "{what}: {a:.5} m/s² ({:+.2} %), {f:.1} N ({:+.2} %), {lifts} lift-offs",
            100.0 * da,
            100.0 * df
        );
        assert_eq!(lifts, 0, "lift-offs at {what}");
        assert!(
            da.abs() < 0.02,
            "filtered deck acceleration at {what}: {da:+e}"
        );
        assert!(df.abs() < 0.02, "peak wheel force at {what}: {df:+e}");
    }
}
