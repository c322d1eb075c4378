//! The compliant laws' secant path on the rail (issue 24): with the
//! structure's compliance in the first slope and the bodies anticipated,
//! Hertz wheelsets on a rail over the deck settle in fewer integrations,
//! and the outputs stay within the tolerance of the step's fixed point,
//! measured against a run whose iteration is converged 10,000 times
//! tighter; the compliance read from the inverse is a whole solve's, and
//! a restored state continues with the same bits.

use super::coaches_tests::{every_step, two_coaches};
use super::Simulation;
use crate::scene::Scene;

/// Two coaches on 1,400 kg wheelsets with the Hertz wheel–rail preset on
/// a rail over a 20 m span, velocity tolerance `tolerance`.
fn coaches_on_rail(tolerance: f64) -> Scene {
    let track = "[track]\napproach = 50.0\nrun_off = 50.0\n[track.on_deck]\n\
                 stiffness = 6.6e7\ndamping = 9.0e4\nrail_bending_stiffness = 1.28e7\n\
                 rail_mass_per_length = 120.0";
    let solver =
        format!("velocity_tolerance = {tolerance:e}\nmax_iterations = 1000\nend_time = 0.2");
    two_coaches((1400.0, Some("wheel-rail")), track, &solver)
}

/// Every output after every grid step, and the integrations spent.
fn run(scene: &Scene, aided: bool) -> (Vec<Vec<f64>>, u64) {
    let mut sim = Simulation::new(scene).expect("builds");
    sim.stepper.iteration_mut().aid_secant(aided);
    every_step(sim, scene.solver.step, 0.2)
}

/// Per output (but the solver's counts and the energy books, whose
/// bookkeeping takes the laws where the iteration left them): the largest
/// difference from the reference's column, over its peak.
fn apart(names: &[String], reference: &[Vec<f64>], rows: &[Vec<f64>]) -> Vec<(f64, String)> {
    let mut out = Vec::new();
    for (j, name) in names.iter().enumerate() {
        if name.starts_with("solver.") || name.starts_with("energy.") {
            continue;
        }
        let peak = reference.iter().fold(0.0f64, |m, r| m.max(r[j].abs()));
        let apart = reference
            .iter()
            .zip(rows)
            .fold(0.0f64, |m, (a, b)| m.max((a[j] - b[j]).abs()));
        out.push((if peak > 0.0 { apart / peak } else { apart }, name.clone()));
    }
    out
}

#[test]
fn hertz_wheelsets_on_the_rail_settle_in_fewer_integrations_within_the_tolerance() {
    let scene = coaches_on_rail(1e-7);
    let names: Vec<String> = {
        let sim = Simulation::new(&scene).expect("builds");
        assert!(sim.system.contacts.iter().all(|c| c.follower.is_some()));
        sim.outputs().iter().map(|o| o.name.clone()).collect()
    };
    let (reference, _) = run(&coaches_on_rail(1e-11), true);
    let (plain, by_plain) = run(&scene, false);
    let (aided, by_aided) = run(&scene, true);
    eprintln!("integrations: {by_plain} plain, {by_aided} aided");
    assert!(
        (by_aided as f64) < 0.75 * by_plain as f64,
        "{by_aided} against {by_plain}"
    );
    // The bodies' velocities settle to 1e-7 m/s, their accelerations to
    // 1e-7 / Δt = 4e-4 m/s²: every output within 1e-4 of its peak of the
    // converged run (the wheelsets' accelerations peak at a few m/s²), and
    // no farther from it than the plain path's.
    let worst = |rows: &[Vec<f64>]| {
        apart(&names, &reference, rows)
            .into_iter()
            .fold(
                (0.0f64, String::new()),
                |w, x| if x.0 > w.0 { x } else { w },
            )
    };
    let (plain_worst, aided_worst) = (worst(&plain), worst(&aided));
    eprintln!(
        "largest differences from the converged run: plain {plain_worst:?}, aided {aided_worst:?}"
    );
    // Measured 2026-11-28: plain 5.1e-4 of `coach2.vy`'s peak (a car's
    // vertical velocity, peak ~1e-5 m/s), aided 2.3e-5.
    assert!(
        aided_worst.0 <= plain_worst.0,
        "aided {aided_worst:?}, plain {plain_worst:?}"
    );
    for (share, name) in apart(&names, &reference, &aided) {
        assert!(
            share <= 1e-4,
            "{name}: {share:e} of its peak from the converged run"
        );
    }
}

/// The compliance `point_compliance` reads from the effective matrix's
/// inverse within its band is the response a whole solve gives
/// (`beam_response`, the structure after one step under the unit load),
/// on the rail over the deck (the wide band) and on the bare deck.
#[test]
fn the_compliance_under_a_contact_is_that_of_a_whole_solve() {
    let mut bare = coaches_on_rail(1e-7);
    bare.track = Default::default();
    for scene in [coaches_on_rail(1e-7), bare] {
        let mut sim = Simulation::new(&scene).expect("builds");
        let dt = scene.solver.step;
        let system = &sim.system;
        let beam = &system.beam;
        let integrator = sim.stepper.iteration_mut().integrator_mut();
        let n = beam.coordinates();
        let (mut load, mut du, mut dv) = (
            nalgebra::DVector::zeros(n),
            nalgebra::DVector::zeros(n),
            nalgebra::DVector::zeros(n),
        );
        let (start, end) = (beam.node_x[0], beam.node_x[beam.elements()]);
        for share in [0.03, 0.31, 0.5, 0.77, 0.98] {
            let x = start + share * (end - start);
            let shape = beam.shape(beam.element_at(x), x);
            let row = shape.n;
            let read = integrator
                .point_compliance(system, &shape, &row, dt)
                .expect("a band factor on the nominal step");
            load.fill(0.0);
            beam.scatter(&shape, &row, 1.0, &mut load);
            integrator.beam_response(system, &load, dt, &mut du, &mut dv);
            let solved = (beam.dot(&shape, &row, &du), beam.dot(&shape, &row, &dv));
            for (r, s) in [(read.0, solved.0), (read.1, solved.1)] {
                assert!(
                    s > 0.0 && (r - s).abs() <= 1e-10 * s,
                    "at {x} m: {r:e} against {s:e}"
                );
            }
        }
        assert!(integrator
            .point_compliance(
                system,
                &beam.shape(0, start),
                &[1.0, 0.0, 0.0, 0.0],
                0.5 * dt
            )
            .is_none());
    }
}

/// A state handed out mid-run and restored into a fresh FMU model
/// continues with the same bits: the first slopes and the anticipated
/// bodies are functions of the state and the factor alone, nothing kept
/// from earlier steps.
#[test]
fn a_restored_state_on_the_rail_continues_with_the_same_bits() {
    use crate::model::Model;
    let names = [
        "coach1_wheelset1.normal_force",
        "coach2_wheelset4.normal_force",
        "coach1_wheelset2.vy",
        "coach2_bogie1.vy",
        "coach1.vy",
    ];
    let fresh = || {
        let mut m = Model::<Simulation>::new(coaches_on_rail(1e-7)).expect("a model");
        m.initialize().expect("initializes");
        m
    };
    let read = |m: &mut Model<Simulation>| {
        let vrs: Vec<u32> = (names.iter())
            .map(|n| m.table().by_name(n).expect("an output").value_reference)
            .collect();
        let mut out = vec![0.0; vrs.len()];
        m.get_reals(&vrs, &mut out).expect("reads");
        out.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
    };
    let mut first = fresh();
    first.do_step(0.0, 0.06).expect("steps");
    let bytes = Model::<Simulation>::serialize(&first.snapshot(), "guid").expect("serializes");
    first.do_step(0.06, 0.03).expect("steps");
    let mut second = fresh();
    let snapshot = Model::<Simulation>::deserialize(&bytes, "guid").expect("deserializes");
    second.restore(&snapshot).expect("restores");
    second.do_step(0.06, 0.03).expect("steps");
    assert_eq!(read(&mut first), read(&mut second));
}
