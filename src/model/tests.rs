//! Unit tests of the FMU model: the variable table, the call rules,
//! stepping and roll-back, over a fake physics and the real scenes.

use super::fake::{FakeDynamics, FAIL_FORCE, FINE_FORCE, FINE_STEP};
use super::*;
use crate::scene::BodyKind;

fn model(kind: BodyKind) -> Model<FakeDynamics> {
    Model::new(Scene::lee1994(kind, 10.0, 0.0025)).unwrap()
}

fn vr(m: &Model<FakeDynamics>, name: &str) -> u32 {
    m.table().by_name(name).unwrap().value_reference
}

fn real(m: &mut Model<FakeDynamics>, name: &str) -> f64 {
    let vr = vr(m, name);
    match m.get(VarType::Real, &[vr]).unwrap()[0] {
        Value::Real(x) => x,
        v => panic!("{v:?}"),
    }
}

#[test]
fn parameters_take_effect_at_initialization() {
    let mut m = model(BodyKind::Glider);
    let speed = vr(&m, "glider.initial_speed");
    m.set(&[speed], &[Value::Real(20.0)]).unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    assert!((real(&mut m, "glider.x") - 2.0).abs() < 1e-12);
}

#[test]
fn bad_parameter_is_refused_naming_variable_value_and_rule() {
    let mut m = model(BodyKind::Wheel);
    let mass = vr(&m, "wheel.mass");
    let e = m.set(&[mass], &[Value::Real(-3.0)]).unwrap_err().0;
    assert!(
        e.contains("wheel.mass") && e.contains("-3") && e.contains("> 0"),
        "{e}"
    );
    // still usable, value unchanged
    assert_eq!(real(&mut m, "wheel.mass"), 3000.0);
    m.initialize().unwrap();
}

#[test]
fn cross_field_rule_is_checked_when_initialization_is_left() {
    let mut m = model(BodyKind::Wheel);
    let pos = vr(&m, "wheel.initial_position");
    m.set(&[pos], &[Value::Real(30.0)]).unwrap();
    let e = m.initialize().unwrap_err().0;
    assert!(
        e.contains("wheel.initial_position") && e.contains("30"),
        "{e}"
    );
}

/// Found by scripts/fuzz_fmi.py: each parameter finite and valid, but an
/// output overflowed to inf (a subnormal radius: ω = V/r). The declared
/// bounds now carry the scene's magnitude limit, so such a radius is
/// refused when set, naming the variable and the limit, and the model is
/// left as it was.
#[test]
fn a_parameter_beyond_the_magnitude_limit_is_refused_when_set() {
    let mut m = model(BodyKind::Wheel);
    let radius = vr(&m, "wheel.radius");
    let e = m.set(&[radius], &[Value::Real(5e-324)]).unwrap_err().0;
    assert!(
        e.contains("wheel.radius = 5e-324") && e.contains("magnitude limit"),
        "{e}"
    );
    let w = vr(&m, "wheel.angular_velocity");
    let values = m.get(VarType::Real, &[w]).unwrap();
    assert!(matches!(values[0], Value::Real(x) if x.is_finite()));
    m.initialize().unwrap();
}

/// Found while fuzzing: a subnormal solver.step (valid: > 0) made one
/// fmi2DoStep take 1e321 internal steps, a hang in the importer's process.
/// (A subnormal step is now refused by the magnitude limit; 1e-12 s passes
/// it and still needs 1e10 internal steps for 0.01 s.)
#[test]
fn a_step_needing_too_many_internal_steps_is_refused_and_changes_nothing() {
    let mut m = model(BodyKind::Wheel);
    let step = vr(&m, "solver.step");
    let v0 = vr(&m, "wheel.initial_speed");
    // at rest, with no stop time, the run's length is unknown: only the
    // per-call limit can refuse it (1e-12 s: the least step the scene's
    // magnitude limit allows is far above the subnormals that found this)
    m.set(&[step, v0], &[Value::Real(1e-12), Value::Real(0.0)])
        .unwrap();
    m.initialize().unwrap();
    let e = m.do_step(0.0, 0.01).unwrap_err().0;
    assert!(
        e.contains("solver.step") && e.contains("internal steps"),
        "{e}"
    );
    assert_eq!(m.time(), 0.0);

    let mut m = model(BodyKind::Wheel);
    m.initialize().unwrap();
    let limit = MAX_INTERNAL_STEPS_PER_CALL * m.scene().solver.step;
    let e = m.do_step(0.0, 1.01 * limit).unwrap_err().0;
    assert!(e.contains("communicationStepSize"), "{e}");
    assert_eq!(m.time(), 0.0);
    // the largest allowed step is not refused
    m.do_step(0.0, limit).unwrap();
}

#[test]
fn parameters_are_fixed_after_initialization_but_inputs_are_not() {
    let mut m = model(BodyKind::Wheel);
    m.initialize().unwrap();
    let len = vr(&m, "beam.length");
    assert!(m
        .set(&[len], &[Value::Real(30.0)])
        .unwrap_err()
        .0
        .contains("fixed"));
    let fx = vr(&m, "wheel.force_x");
    m.set(&[fx], &[Value::Real(1000.0)]).unwrap();
    let out = vr(&m, "wheel.x");
    assert!(m
        .set(&[out], &[Value::Real(1.0)])
        .unwrap_err()
        .0
        .contains("output"));
}

#[test]
fn unknown_and_mistyped_value_references_are_refused() {
    let mut m = model(BodyKind::Wheel);
    assert!(m
        .get(VarType::Real, &[9999])
        .unwrap_err()
        .0
        .contains("9999"));
    let el = vr(&m, "beam.elements");
    assert!(m
        .get(VarType::Real, &[el])
        .unwrap_err()
        .0
        .contains("Integer"));
    assert_eq!(
        m.get(VarType::Integer, &[el]).unwrap(),
        vec![Value::Integer(2)]
    );
}

#[test]
fn exit_stops_the_step_at_the_exit_time() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let mut t = 0.0;
    let outcome = loop {
        match m.do_step(t, 0.5).unwrap() {
            StepOutcome::Completed => t += 0.5,
            o => break o,
        }
    };
    let StepOutcome::Exited { time } = outcome else {
        panic!("{outcome:?}")
    };
    assert!((time - 2.4).abs() < 1e-9, "{time}");
    assert_eq!(m.exit_time(), Some(time));
    assert_eq!(real(&mut m, "glider.x"), 24.0);
}

#[test]
fn solver_failure_rolls_back_the_whole_step() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    let before = real(&mut m, "glider.x");
    let fy = vr(&m, "glider.force_y");
    m.set(&[fy], &[Value::Real(-2.0 * FAIL_FORCE)]).unwrap();
    let o = m.do_step(0.1, 0.1).unwrap();
    assert!(matches!(o, StepOutcome::Failed { .. }), "{o:?}");
    assert_eq!(real(&mut m, "glider.x"), before);
    assert!((m.time() - 0.1).abs() < 1e-15);
}

#[test]
fn communication_point_mismatch_beyond_rounding_is_refused() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    m.do_step(0.1 + 1e-15, 0.1).unwrap();
    assert!(m
        .do_step(0.3, 0.1)
        .unwrap_err()
        .0
        .contains("does not match"));
    assert!(m.do_step(0.2, 0.0).is_err());
    assert!(m.do_step(0.2, f64::NAN).is_err());
}

#[test]
fn snapshot_restore_and_serialization_continue_identically() {
    let mut m = model(BodyKind::Wheel);
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    let snap = m.snapshot();
    let bytes = Model::<FakeDynamics>::serialize(&snap, "guid").unwrap();
    m.do_step(0.1, 0.1).unwrap();
    let a = real(&mut m, "wheel.x");

    m.restore(&snap).unwrap();
    m.do_step(0.1, 0.1).unwrap();
    assert_eq!(real(&mut m, "wheel.x").to_bits(), a.to_bits());

    let mut other = model(BodyKind::Wheel);
    let back = Model::<FakeDynamics>::deserialize(&bytes, "guid").unwrap();
    other.restore(&back).unwrap();
    assert_eq!(other.phase(), Phase::Running);
    other.do_step(0.1, 0.1).unwrap();
    assert_eq!(real(&mut other, "wheel.x").to_bits(), a.to_bits());
    assert!(Model::<FakeDynamics>::deserialize(&bytes, "other").is_err());
}

#[test]
fn reset_returns_to_start_values() {
    let mut m = model(BodyKind::Wheel);
    let len = vr(&m, "beam.length");
    m.set(&[len], &[Value::Real(30.0)]).unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    m.reset();
    assert_eq!(m.phase(), Phase::Configuring);
    assert_eq!(real(&mut m, "beam.length"), 24.0);
    assert_eq!(real(&mut m, "wheel.x"), 0.0);
}

#[test]
fn a_start_time_offsets_communication_times_only() {
    let mut a = model(BodyKind::Glider);
    a.initialize().unwrap();
    a.do_step(0.0, 0.1).unwrap();
    let mut b = model(BodyKind::Glider);
    b.set_experiment(10.0, None).unwrap();
    b.initialize().unwrap();
    assert_eq!(b.time(), 10.0);
    assert!(b.do_step(0.0, 0.1).is_err());
    b.do_step(10.0, 0.1).unwrap();
    // same motion; the offset only rounds the target time (10.1 - 10)
    let (xa, xb) = (real(&mut a, "glider.x"), real(&mut b, "glider.x"));
    assert!((xa - xb).abs() <= 1e-12 * xa.abs(), "{xa} vs {xb}");
    assert!((b.time() - 10.1).abs() < 1e-12);
}

/// The real physics: the contact force at t = 0 is what the inputs set in
/// initialization mode make it, not the exported scene's.
#[test]
fn start_outputs_follow_inputs_set_before_initialization() {
    use crate::Simulation;
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    let vr = |m: &Model<Simulation>, n: &str| m.table().by_name(n).unwrap().value_reference;
    let (fy, normal) = (vr(&m, "wheel.force_y"), vr(&m, "contact.normal_force"));
    let read = |m: &mut Model<Simulation>| match m.get(VarType::Real, &[normal]).unwrap()[0] {
        Value::Real(x) => x,
        v => panic!("{v:?}"),
    };
    assert_eq!(read(&mut m), 600e3);
    m.set(&[fy], &[Value::Real(-250e3)]).unwrap();
    assert_eq!(read(&mut m), 250e3);
    m.initialize().unwrap();
    assert_eq!(read(&mut m), 250e3);
    // After initialization an input acts over the next step, not on the
    // outputs at this communication point (dependencies="" in Outputs).
    m.set(&[fy], &[Value::Real(-100e3)]).unwrap();
    assert_eq!(read(&mut m), 250e3);
}

// ---- issue 13: bounded runs, failures a retry cannot cure ------------------------

#[test]
fn a_run_needing_an_absurd_number_of_steps_is_refused_before_it_starts() {
    let mut m = model(BodyKind::Wheel);
    let step = vr(&m, "solver.step");
    m.set(&[step], &[Value::Real(1e-12)]).unwrap();
    let e = m.initialize().unwrap_err().0;
    assert!(
        e.contains("2.4e12 internal steps") && e.contains("1e8"),
        "{e}"
    );
    assert_eq!(m.phase(), Phase::Configuring);
    // a stop time bounds the run instead of the exit
    let mut m = model(BodyKind::Wheel);
    m.set(&[step], &[Value::Real(1e-6)]).unwrap();
    m.set_experiment(0.0, Some(1.0)).unwrap();
    m.initialize().unwrap();
    let mut m = model(BodyKind::Wheel);
    m.set(&[step], &[Value::Real(1e-6)]).unwrap();
    let v0 = vr(&m, "wheel.initial_speed");
    m.set(&[v0], &[Value::Real(1e-3)]).unwrap();
    m.set_experiment(0.0, Some(1000.0)).unwrap();
    assert!(m.initialize().unwrap_err().0.contains("to the stop time"));
    // the exit comes first: a far stop time does not matter
    let mut m = model(BodyKind::Wheel);
    m.set(&[step], &[Value::Real(1e-6)]).unwrap();
    m.set_experiment(0.0, Some(1e300)).unwrap();
    m.initialize().unwrap();
}

/// A train's run lasts until its last vehicle leaves (`run_end`): beside
/// the paper's wheel at 10 m/s (960 steps of 2.5 ms to leave), a second
/// one at x₀ = 1 m crawling at 2e-5 m/s leaves after (L − x₀) / V =
/// 23 / 2e-5 s, more than 1e8 steps.
#[test]
fn the_run_length_counts_to_the_last_vehicle_to_leave() {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut slow = scene.vehicles[0].clone();
    slow.name = "slow".to_string();
    (slow.initial_position, slow.initial_speed) = (1.0, 2e-5);
    scene.vehicles.push(slow);
    let mut m = Model::<FakeDynamics>::new(scene).unwrap();
    let steps = ((24.0 - 1.0) / 2e-5 / 0.0025_f64).ceil();
    assert!(steps > MAX_RUN_STEPS);
    let e = m.initialize().unwrap_err().0;
    assert!(
        e.contains(&format!("{steps:e} internal steps")) && e.contains("last vehicle's exit"),
        "{e}"
    );
    // The scene's end time, not the exit, ends a run that sets one.
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.solver.end_time = Some(1e6);
    let e = (Model::<FakeDynamics>::new(scene).unwrap().initialize()).unwrap_err();
    assert!(
        e.0.contains("4e8 internal steps") && e.0.contains("to solver.end_time"),
        "{e:?}"
    );
}

#[test]
fn a_step_below_the_resolution_of_the_time_is_refused() {
    let mut m = model(BodyKind::Glider);
    m.set_experiment(1e15, None).unwrap();
    m.initialize().unwrap();
    let e = m.do_step(1e15, 0.01).unwrap_err().0;
    assert!(e.contains("below the resolution"), "{e}");
    assert_eq!(m.time(), 1e15);
    // a step the time can carry is taken
    assert_eq!(m.do_step(1e15, 0.5).unwrap(), StepOutcome::Completed);
}

fn failed(o: StepOutcome) -> (String, bool) {
    match o {
        StepOutcome::Failed { message, curable } => (message, curable),
        o => panic!("not a failure: {o:?}"),
    }
}

#[test]
fn a_failure_no_step_size_cures_is_marked_so() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let fy = vr(&m, "glider.force_y");
    m.set(&[fy], &[Value::Real(2.0 * FAIL_FORCE)]).unwrap();
    let (message, curable) = failed(m.do_step(0.0, 0.1).unwrap());
    assert!(!curable, "{message}");
    assert!(message.contains("no step size cures this"), "{message}");
    assert_eq!(m.time(), 0.0);
}

#[test]
fn a_failure_a_smaller_step_cures_is_discarded_once_then_refused_if_retried_unchanged() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let fy = vr(&m, "glider.force_y");
    m.set(&[fy], &[Value::Real(2.0 * FINE_FORCE)]).unwrap();
    let (message, curable) = failed(m.do_step(0.0, 0.1).unwrap());
    assert!(curable && message.contains("succeeds"), "{message}");
    // the same step again: refused, naming the first reason
    let (again, curable) = failed(m.do_step(0.0, 0.1).unwrap());
    assert!(!curable && again.contains("nothing has changed"), "{again}");
    assert!(again.contains("fake solver"), "{again}");
    // a smaller step is taken; so is the old size once something changed
    assert_eq!(m.do_step(0.0, FINE_STEP).unwrap(), StepOutcome::Completed);
    let (_, curable) = failed(m.do_step(FINE_STEP, 0.1).unwrap());
    assert!(curable);
    // (held: otherwise the line from 2e8 down to 0 is extrapolated on)
    m.set(&[fy], &[Value::Real(0.0)]).unwrap();
    m.set_input_derivatives(&[fy], &[1], &[0.0]).unwrap();
    assert_eq!(m.do_step(FINE_STEP, 0.1).unwrap(), StepOutcome::Completed);
}

#[test]
fn a_step_over_its_wall_time_budget_is_rolled_back() {
    let mut m = model(BodyKind::Glider);
    let budget = vr(&m, "solver.wall_time_budget");
    assert_eq!(
        m.get(VarType::Real, &[budget]).unwrap(),
        vec![Value::Real(DEFAULT_WALL_TIME_BUDGET)]
    );
    assert!(m.set(&[budget], &[Value::Real(0.0)]).is_err());
    assert!(m.set(&[budget], &[Value::Real(f64::INFINITY)]).is_err());
    m.set(&[budget], &[Value::Real(1e-300)]).unwrap();
    m.initialize().unwrap();
    let before = real(&mut m, "glider.x");
    let (message, curable) = failed(m.do_step(0.0, 1.0).unwrap());
    assert!(
        curable && message.contains("solver.wall_time_budget"),
        "{message}"
    );
    assert_eq!(real(&mut m, "glider.x"), before);
    assert_eq!(m.time(), 0.0);
    assert!(m.set(&[budget], &[Value::Real(10.0)]).is_err(), "fixed");
}

#[test]
fn chunked_advance_gives_the_same_result_as_one_advance() {
    // The budget is checked between chunks ending on the solver's grid, where
    // an uninterrupted advance passes anyway: the physics' results are
    // bit-identical (an off-grid first step included).
    use crate::simulation::Simulation;
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut m = Model::<Simulation>::new(scene.clone()).unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, 0.0101).unwrap();
    m.do_step(0.0101, 1.5).unwrap();
    let mut sim = Simulation::new_open_ended(&scene).unwrap();
    sim.advance_to(0.0101).unwrap();
    sim.advance_to(0.0101 + 1.5).unwrap();
    let mut want = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut want);
    let real_outputs: Vec<(u32, usize)> = m
        .table()
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| match v.role {
            Role::Output(k) => (v.value_reference, k),
            r => panic!("{r:?}"),
        })
        .collect();
    assert!(real_outputs.len() > 5);
    for (vr, k) in real_outputs {
        let Value::Real(x) = m.get(VarType::Real, &[vr]).unwrap()[0] else {
            panic!()
        };
        assert_eq!(x.to_bits(), want[k].to_bits(), "{}", sim.outputs()[k].name);
    }
}

// ---- issue 13, defect 4: a restored state is untrusted input ----------------------

/// A running wheel model's state with `forge` applied, through the byte
/// form (the checksum recomputed over the forged payload, as an attacker
/// would).
fn forged<D: Dynamics>(
    m: &Model<D>,
    forge: impl FnOnce(&mut Snapshot<D::State>),
) -> Snapshot<D::State> {
    let mut snap = m.snapshot();
    forge(&mut snap);
    let bytes = Model::<D>::serialize(&snap, "guid").unwrap();
    Model::<D>::deserialize(&bytes, "guid").unwrap()
}

#[test]
fn a_restored_state_must_be_a_state_of_this_model() {
    let mut m = model(BodyKind::Wheel);
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    let x = real(&mut m, "wheel.x");
    type Forge = fn(&mut Snapshot<super::fake::FakeState>);
    let cases: [(Forge, &str); 10] = [
        (|s| s.scene.beam.elements = 10_000_000, "beam.elements"),
        (|s| s.scene.beam.elements = usize::MAX, "beam.elements"),
        (|s| s.scene.vehicles[0].mass = -3000.0, "wheel.mass"),
        (
            |s| s.scene.sensors[0].position = 1e9,
            "sensor.midspan.position",
        ),
        (|s| s.scene.sensors.clear(), "sensors"),
        (
            |s| s.scene.vehicles[0].kind = BodyKind::Glider,
            "more than parameters",
        ),
        (
            |s| s.scene.solver.max_iterations = u32::MAX as _,
            "more than parameters",
        ),
        (|s| s.inputs[1] = f64::NAN, "not finite"),
        // what fmi2SetReal refuses (found by the FMI fuzzer: 2^53 + 1 N)
        (|s| s.inputs[1] = 9007199254740993.0, "magnitude limit"),
        (|s| s.sim = None, "missing"),
    ];
    for (forge, named) in cases {
        let snap = forged(&m, forge);
        let e = m.check_snapshot(&snap).unwrap_err().0;
        assert!(e.contains(named), "{named}: {e}");
        assert!(m.restore(&snap).is_err());
        assert_eq!(real(&mut m, "wheel.x"), x, "{named}: model unchanged");
        assert_eq!(m.phase(), Phase::Running);
    }
    // a parameter changed within its rule is a state of this model
    let snap = forged(&m, |s| s.scene.vehicles[0].mass = 6000.0);
    m.restore(&snap).unwrap();
}

#[test]
fn a_forged_physics_state_is_refused_and_the_model_left_as_it_was() {
    use crate::simulation::Simulation;
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    let vr = m.table().by_name("wheel.x").unwrap().value_reference;
    let x = m.get(VarType::Real, &[vr]).unwrap();
    let good = m.snapshot();
    type Forge = fn(&mut Snapshot<crate::simulation::SimState>);
    let cases: [(Forge, &str); 5] = [
        (
            |s| s.sim.as_mut().unwrap().dynamic.beam_load = nalgebra::DVector::zeros(1),
            "length",
        ),
        (
            |s| {
                let d = &mut s.sim.as_mut().unwrap().dynamic;
                d.beam_displacement = nalgebra::DVector::zeros(3);
                d.beam_velocity = nalgebra::DVector::zeros(3);
                d.beam_acceleration = nalgebra::DVector::zeros(3);
                d.beam_load = nalgebra::DVector::zeros(3);
            },
            "DOFs",
        ),
        (
            |s| s.sim.as_mut().unwrap().dynamic.beam_velocity[0] = f64::INFINITY,
            "non-finite",
        ),
        (|s| s.sim.as_mut().unwrap().time = f64::NAN, "non-finite"),
        (
            |s| s.sim.as_mut().unwrap().grid_step = 1000,
            "not in its step",
        ),
    ];
    for (forge, named) in cases {
        let snap = forged(&m, forge);
        let bytes = Model::<Simulation>::serialize(&snap, "guid").unwrap();
        let e = m.deserialize_checked(&bytes, "guid").unwrap_err().0;
        assert!(e.contains(named), "deserialize, {named}: {e}");
        let e = m.restore(&snap).unwrap_err().0;
        assert!(e.contains(named), "{named}: {e}");
        assert_eq!(m.get(VarType::Real, &[vr]).unwrap(), x, "{named}");
        assert_eq!(m.do_step(0.1, 0.1).unwrap(), StepOutcome::Completed);
        m.restore(&good).unwrap();
    }
}

/// Found by the state fuzzer: a forged state, finite everywhere, stepped
/// into one with an infinite number outside the outputs (a glider's angle);
/// saved after a later failed step, it could not be restored.
#[test]
fn a_step_into_a_state_that_could_not_be_restored_fails() {
    use crate::simulation::Simulation;
    let scene = Scene::lee1994(BodyKind::Glider, 30.0, 0.005);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, 0.1).unwrap();
    let snap = forged(&m, |s| {
        let body = &mut s.sim.as_mut().unwrap().dynamic.bodies[0];
        body.angle = f64::MAX;
        body.angular_velocity = f64::MAX;
    });
    m.restore(&snap).unwrap();
    let (message, curable) = failed(m.do_step(0.1, 0.1).unwrap());
    assert!(!curable && message.contains("unusable"), "{message}");
    let now = m.snapshot();
    m.restore(&now).unwrap();
}

// ---- issue 12: the end of the structure is an event ------------------------------

#[test]
fn the_fmu_model_steps_past_the_exit_and_reports_it_as_an_event() {
    use crate::simulation::Simulation;
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    m.initialize().unwrap();
    let on_beam = m
        .table()
        .by_name("contact.on_beam")
        .unwrap()
        .value_reference;
    let mut events = Vec::new();
    let mut left_at = None;
    for k in 0..35 {
        let t = k as f64 * 0.1;
        assert_eq!(
            m.do_step(t, 0.1).unwrap(),
            StepOutcome::Completed,
            "t = {t}"
        );
        events.extend(m.take_events());
        let Value::Integer(on) = m.get(VarType::Integer, &[on_beam]).unwrap()[0] else {
            panic!()
        };
        if on == 0 && left_at.is_none() {
            left_at = Some(m.time());
        }
    }
    assert!(
        left_at.is_some_and(|t| (t - 2.3).abs() < 1e-9),
        "{left_at:?}"
    );
    assert_eq!(events.len(), 2, "{events:?}");
    assert!(events[0].starts_with("t = 2.27") && events[0].ends_with("Exit of contact"));
    assert!(events[1].ends_with("LeftTrack of contact"), "{events:?}");
    assert!(m.take_events().is_empty(), "each event is handed out once");
    assert_eq!(m.exit_time(), None);
}

// ---- issue 12: coupling ports ------------------------------------------------------

fn coupled_wheel() -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.couplings = vec!["wheel".into()];
    scene
}

#[test]
fn a_coupling_body_gets_load_inputs_and_motion_outputs_without_direct_dependencies() {
    use crate::simulation::Simulation;
    let m = Model::<Simulation>::new(coupled_wheel()).unwrap();
    let t = m.table();
    for name in [
        "wheel.coupling_force_x",
        "wheel.coupling_force_y",
        "wheel.coupling_moment",
    ] {
        let v = t.by_name(name).unwrap_or_else(|| panic!("{name}"));
        assert_eq!(v.causality, Causality::Input);
        assert_eq!(v.start, Some(Value::Real(0.0)));
    }
    for name in [
        "wheel.x",
        "wheel.y",
        "wheel.pitch",
        "wheel.vx",
        "wheel.vy",
        "wheel.angular_velocity",
        "wheel.ax",
        "wheel.ay",
        "wheel.angular_acceleration",
    ] {
        let v = t.by_name(name).unwrap_or_else(|| panic!("{name}"));
        assert_eq!(v.dependencies.as_deref(), Some(&[][..]), "{name}");
    }
    // a glider does not turn: no moment
    let mut glider = Scene::lee1994(BodyKind::Glider, 30.0, 0.005);
    glider.couplings = vec!["glider".into()];
    let g = Model::<Simulation>::new(glider).unwrap();
    assert!(g.table().by_name("glider.coupling_force_y").is_some());
    assert!(g.table().by_name("glider.coupling_moment").is_none());
}

/// The coupling force is additional to the scene's applied force: on rigid
/// ground (the wheel beyond a zero-length beam's end is not needed: a glider
/// at rest on the beam) adding -F to the coupling port and +F to force_y
/// changes nothing; the reported acceleration follows the loads of the step
/// that ended, not an input set after it.
#[test]
fn coupling_loads_add_to_the_applied_force_and_accelerations_follow_the_last_step() {
    use crate::simulation::Simulation;
    let run = |force_y: f64, coupling_y: f64| {
        let mut m = Model::<Simulation>::new(coupled_wheel()).unwrap();
        let vr = |m: &Model<Simulation>, n: &str| m.table().by_name(n).unwrap().value_reference;
        let (fy, cy) = (vr(&m, "wheel.force_y"), vr(&m, "wheel.coupling_force_y"));
        m.set(&[fy, cy], &[Value::Real(force_y), Value::Real(coupling_y)])
            .unwrap();
        m.initialize().unwrap();
        m.do_step(0.0, 0.1).unwrap();
        let ay = vr(&m, "wheel.ay");
        let y = vr(&m, "sensor.midspan.deflection");
        let before = m.get(VarType::Real, &[ay, y]).unwrap();
        // an input set now does not change what the step ended with
        m.set(&[cy], &[Value::Real(coupling_y - 1e5)]).unwrap();
        assert_eq!(m.get(VarType::Real, &[ay, y]).unwrap(), before);
        before
    };
    let split = run(-3e5, -3e5);
    let whole = run(-6e5, 0.0);
    let (Value::Real(a), Value::Real(b)) = (split[1], whole[1]) else {
        panic!()
    };
    assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
    assert_ne!(run(-6e5, -1e5)[1], whole[1], "the coupling load acts");
}

/// A load set on a coupling port during initialization is carried by the
/// coupled body's contact at t = 0, as `force_y` is: a glider at rest
/// under a car ten times its mass reads no acceleration at the start, and
/// its contact carries the static sum of both weights. (It read −10 g: the
/// car's weight over the glider's mass.)
#[test]
fn a_coupling_load_set_during_initialization_is_carried_at_t_0() {
    use crate::simulation::Simulation;
    let mut scene = Scene::lee1994(BodyKind::Glider, 30.0, 0.005);
    scene.couplings = vec!["glider".into()];
    // (the paper's scene loads the glider by its force, not by gravity)
    let (mass, g) = (scene.vehicles[0].mass, 9.81);
    let car = 10.0 * mass * g;
    let mut m = Model::<Simulation>::new(scene).unwrap();
    let vr = |m: &Model<Simulation>, n: &str| m.table().by_name(n).unwrap().value_reference;
    let (cy, ay) = (vr(&m, "glider.coupling_force_y"), vr(&m, "glider.ay"));
    let normal = vr(&m, "contact.normal_force");
    let reals = |m: &mut Model<Simulation>| {
        let values = m.get(VarType::Real, &[ay, normal]).unwrap();
        values
            .iter()
            .map(|v| match v {
                Value::Real(x) => *x,
                _ => panic!("{v:?}"),
            })
            .collect::<Vec<f64>>()
    };
    let alone = reals(&mut m); // built before the input is set
    m.set(&[cy], &[Value::Real(-car)]).unwrap();
    m.initialize().unwrap();
    let start = reals(&mut m);
    assert!(start[0].abs() <= 1e-9 * g, "ay at t = 0: {}", start[0]);
    let carried = alone[1] + car;
    assert!(
        (start[1] - carried).abs() <= 1e-9 * carried,
        "{} vs {carried}",
        start[1]
    );
    // Set again once running, before the first step (libcosim and Ecos
    // set inputs there): carried the same way.
    m.set(&[cy], &[Value::Real(-2.0 * car)]).unwrap();
    let again = reals(&mut m);
    assert!(again[0].abs() <= 1e-9 * g, "ay at t = 0: {}", again[0]);
    assert!((again[1] - carried - car).abs() <= 1e-9 * carried);
}

// ---- the per-step path: roll-back copies kept between steps, Real getters --------

/// The state a failed step goes back to is the one the last completed step
/// reached, also when the steps before it took no copy of their own (their
/// copies come from the check of the step before).
#[test]
fn a_failed_step_after_completed_ones_rolls_back_to_the_last_of_them() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let fy = vr(&m, "glider.force_y");
    m.set(&[fy], &[Value::Real(2.0 * FINE_FORCE)]).unwrap();
    let mut t = 0.0;
    for _ in 0..3 {
        assert_eq!(m.do_step(t, FINE_STEP).unwrap(), StepOutcome::Completed);
        t += FINE_STEP;
    }
    let before = m.snapshot().sim.unwrap();
    let x = real(&mut m, "glider.x");
    let (_, curable) = failed(m.do_step(t, 0.1).unwrap());
    assert!(curable);
    assert_eq!(m.snapshot().sim.unwrap(), before);
    assert_eq!(real(&mut m, "glider.x"), x);
    // and on from there as if it had not failed
    assert_eq!(m.do_step(t, FINE_STEP).unwrap(), StepOutcome::Completed);
    let (_, curable) = failed(m.do_step(t + FINE_STEP, 0.1).unwrap());
    assert!(curable);
    assert!((m.time() - (t + FINE_STEP)).abs() < 1e-15);
}

/// The same with the real physics, whose copy for the next step is taken
/// as the state a step reaches is checked (`SimState::copy_checked_from`).
#[test]
fn the_simulation_rolls_back_to_the_state_the_last_step_reached() {
    use crate::simulation::Simulation;
    let scene = Scene::lee1994(BodyKind::Glider, 30.0, 0.005);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    m.initialize().unwrap();
    for k in 0..5 {
        m.do_step(k as f64 * 0.1, 0.1).unwrap();
    }
    let reached = m.snapshot();
    // Behind the model's back (so that it keeps the copy it took): a state
    // whose next step overflows.
    let sim = m.sim.as_mut().unwrap();
    let mut state = sim.state();
    state.dynamic.bodies[0].angle = f64::MAX;
    state.dynamic.bodies[0].angular_velocity = f64::MAX;
    sim.restore(&state).unwrap();
    let (message, curable) = failed(m.do_step(0.5, 0.1).unwrap());
    assert!(!curable && message.contains("unusable"), "{message}");
    // Back to the copy taken when the last step was checked.
    assert_eq!(m.snapshot().sim, reached.sim);
    assert_eq!(m.do_step(0.5, 0.1).unwrap(), StepOutcome::Completed);
}

fn reals(m: &mut Model<FakeDynamics>, vrs: &[u32]) -> Result<Vec<f64>, ModelError> {
    let mut out = vec![0.0; vrs.len()];
    m.get_reals(vrs, &mut out).map(|()| out)
}

#[test]
fn the_real_getter_reads_what_the_general_getter_does() {
    let mut m = model(BodyKind::Wheel);
    let names = [
        "wheel.x",
        "wheel.mass",
        "wheel.force_y",
        "wheel.vx",
        "wheel.angular_velocity",
        "solver.wall_time_budget",
    ];
    let all: Vec<u32> = names.iter().map(|n| vr(&m, n)).collect();
    let outputs = [all[0], all[3], all[4]];
    let general = |m: &mut Model<FakeDynamics>, vrs: &[u32]| -> Vec<f64> {
        m.get(VarType::Real, vrs)
            .unwrap()
            .into_iter()
            .map(|v| match v {
                Value::Real(x) => x,
                v => panic!("{v:?}"),
            })
            .collect()
    };
    m.initialize().unwrap();
    for step in 0..3 {
        m.do_step(step as f64 * 0.1, 0.1).unwrap();
        // outputs only (remembered after the first read), then a mixed
        // list, then the outputs reversed: each read as `get` reads it
        for vrs in [
            &outputs[..],
            &outputs[..],
            &all[..],
            &[all[4], all[3], all[0]],
        ] {
            assert_eq!(reals(&mut m, vrs).unwrap(), general(&mut m, vrs), "{vrs:?}");
        }
    }
    assert_eq!(reals(&mut m, &[]).unwrap(), Vec::<f64>::new());
    let iterations = vr(&m, "solver.iterations");
    for bad in [vec![all[0], 9999], vec![all[0], iterations]] {
        assert!(reals(&mut m, &bad).is_err(), "{bad:?}");
    }
    assert!(m.get_reals(&outputs, &mut [0.0; 2]).is_err());
}

/// The fake glider's velocity gain after `n` communication steps of `h`
/// with force_x = `rate` · t set at each communication point, the
/// derivative `rate` also sent when `with_derivative`.
fn velocity_gain_under_a_force_ramp(rate: f64, h: f64, n: usize, with_derivative: bool) -> f64 {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let fx = vr(&m, "glider.force_x");
    let v0 = real(&mut m, "glider.vx");
    for k in 0..n {
        let t = k as f64 * h;
        m.set(&[fx], &[Value::Real(rate * t)]).unwrap();
        if with_derivative {
            m.set_input_derivatives(&[fx], &[1], &[rate]).unwrap();
        }
        assert_eq!(m.do_step(t, h).unwrap(), StepOutcome::Completed);
    }
    real(&mut m, "glider.vx") - v0
}

#[test]
fn inputs_are_extrapolated_along_their_last_two_communication_points() {
    // Under F = a t the impulse up to T is a T²/2 (closed form). Held
    // inputs give the left Riemann sum a T (T - H)/2; the line through the
    // last two points is exact for a line, except over the first step,
    // which has no history and holds F(0) = 0: a (T² - H²)/2.
    let (a, h, n) = (1000.0, 0.05, 8);
    let t_end = h * n as f64;
    let mass = match model(BodyKind::Glider).scene().vehicles[0].mass {
        m if m > 0.0 => m,
        m => panic!("mass {m}"),
    };
    let gained = velocity_gain_under_a_force_ramp(a, h, n, false);
    let expected = a * (t_end * t_end - h * h) / 2.0 / mass;
    assert!(
        (gained - expected).abs() < 1e-12 * expected,
        "{gained} vs {expected}"
    );
    let held = a * t_end * (t_end - h) / 2.0 / mass;
    assert!((gained - held).abs() > 1e-3 * expected);
}

#[test]
fn input_derivatives_sent_by_the_master_make_the_first_step_exact_too() {
    let (a, h, n) = (1000.0, 0.05, 8);
    let t_end = h * n as f64;
    let mass = model(BodyKind::Glider).scene().vehicles[0].mass;
    let gained = velocity_gain_under_a_force_ramp(a, h, n, true);
    let expected = a * t_end * t_end / 2.0 / mass;
    assert!(
        (gained - expected).abs() < 1e-12 * expected,
        "{gained} vs {expected}"
    );
}

#[test]
fn bad_input_derivatives_are_refused_naming_variable_order_and_rule() {
    let mut m = model(BodyKind::Glider);
    let fx = vr(&m, "glider.force_x");
    let x = vr(&m, "glider.x");
    let e = m.set_input_derivatives(&[fx], &[3], &[1.0]).unwrap_err().0;
    assert!(e.contains("glider.force_x") && e.contains("1 or 2"), "{e}");
    let e = m.set_input_derivatives(&[x], &[1], &[1.0]).unwrap_err().0;
    assert!(e.contains("not an input"), "{e}");
    let e = m
        .set_input_derivatives(&[fx], &[1], &[f64::NAN])
        .unwrap_err()
        .0;
    assert!(e.contains("finite"), "{e}");
}

#[test]
fn a_restored_state_continues_its_extrapolation_identically() {
    let mut m = model(BodyKind::Glider);
    m.initialize().unwrap();
    let fx = vr(&m, "glider.force_x");
    let h = 0.05;
    for k in 0..3 {
        m.set(&[fx], &[Value::Real(100.0 * k as f64)]).unwrap();
        m.do_step(k as f64 * h, h).unwrap();
    }
    let bytes = Model::<FakeDynamics>::serialize(&m.snapshot(), "g").unwrap();
    let continue_once = |m: &mut Model<FakeDynamics>| {
        m.set(&[fx], &[Value::Real(300.0)]).unwrap();
        m.do_step(3.0 * h, h).unwrap();
        real(m, "glider.vx")
    };
    let first = continue_once(&mut m);
    let snap = m.deserialize_checked(&bytes, "g").unwrap();
    m.restore(&snap).unwrap();
    assert_eq!(continue_once(&mut m).to_bits(), first.to_bits());
}

/// Issue 27 item 2: before, only the first vehicle's speed was a
/// parameter (setting it left the others at the scene's speed, and
/// `coach2.initial_speed` was refused). The train's speed, and then one
/// vehicle's own, are what each vehicle runs at.
#[test]
fn a_train_speed_and_each_vehicle_s_own_reach_the_dynamics() {
    use crate::simulation::Simulation;
    let scene = Scene::load("train-3-coaches-2x25-5").unwrap();
    let mut m = Model::<Simulation>::new(scene).unwrap();
    let set = |m: &mut Model<Simulation>, name: &str, x: f64| {
        let vr = m.table().by_name(name).unwrap().value_reference;
        m.set(&[vr], &[Value::Real(x)]).unwrap();
    };
    set(&mut m, "train.initial_speed", 4.0);
    set(&mut m, "coach3.initial_speed", 3.0);
    m.initialize().unwrap();
    m.do_step(0.0, 0.01).unwrap();
    for (name, speed) in [("coach1.vx", 4.0), ("coach2.vx", 4.0), ("coach3.vx", 3.0)] {
        let vr = m.table().by_name(name).unwrap().value_reference;
        let Value::Real(vx) = m.get(VarType::Real, &[vr]).unwrap()[0] else {
            panic!("{name} is a Real")
        };
        // on the approach, 10 ms after the start at rest on the track
        assert!(
            (vx - speed).abs() < 1e-3 * speed,
            "{name}: {vx} m/s, set {speed}"
        );
    }
}

/// Every vehicle has its own force inputs (issue 23), started at its
/// scene's forces: on rigid ground a glider (no tangential contact force)
/// pushed by `second.force_x` = F gains F t / m of speed, the other
/// vehicle none.
#[test]
fn every_vehicle_s_force_inputs_push_that_vehicle_only() {
    use crate::Simulation;
    let mut scene = Scene::lee1994(BodyKind::Glider, 10.0, 0.0025);
    scene.track.approach = 2000.0;
    scene.vehicles[0].initial_position = -1500.0;
    let mut second = scene.vehicles[0].clone();
    second.name = "second".into();
    second.initial_position = -1000.0;
    second.force_y = -500e3;
    scene.vehicles.push(second);
    let mut m = Model::<Simulation>::new(scene).unwrap();
    let vr = |m: &Model<Simulation>, n: &str| m.table().by_name(n).unwrap().value_reference;
    let start = |m: &Model<Simulation>, n: &str| m.table().by_name(n).unwrap().start;
    assert_eq!(start(&m, "second.force_y"), Some(Value::Real(-500e3)));
    assert_eq!(start(&m, "glider.force_y"), Some(Value::Real(-600e3)));
    let (push, mass, time) = (1500.0, 3000.0, 0.5);
    m.set(&[vr(&m, "second.force_x")], &[Value::Real(push)])
        .unwrap();
    m.initialize().unwrap();
    m.do_step(0.0, time).unwrap();
    let speeds = [vr(&m, "glider.vx"), vr(&m, "second.vx")];
    let read = m.get(VarType::Real, &speeds).unwrap();
    let [Value::Real(first), Value::Real(pushed)] = read[..] else {
        panic!("{read:?}")
    };
    assert!((first - 10.0).abs() < 1e-9, "{first}");
    let expected = 10.0 + push / mass * time;
    assert!(
        (pushed - expected).abs() < 1e-9,
        "{pushed} against {expected}"
    );
}

/// A forged multi-body state with a non-finite body, or with two bodies
/// swapped under force laws (Hertz wheelsets, which have no gap to check),
/// is refused whole before it is restored. A NaN compared false with every
/// bound of the consistency check: on a train both passed.
#[test]
fn forged_states_with_a_nan_body_or_swapped_followers_are_refused() {
    use crate::model::{SceneDynamics, SceneState};
    let forged = |name: &str, forge: &dyn Fn(&mut crate::state::SimState)| {
        let scene = crate::scene::builtin(name).unwrap();
        let mut m = Model::<SceneDynamics>::new(scene).unwrap();
        m.initialize().unwrap();
        m.do_step(0.0, 0.01).unwrap();
        let mut snap = m.snapshot();
        assert!(m.check_whole(&snap).is_ok(), "{name}: its own state");
        if let Some(SceneState::Vehicles(s)) = &mut snap.sim {
            forge(s);
        }
        let bytes = Model::<SceneDynamics>::serialize(&snap, "g").unwrap();
        let back = Model::<SceneDynamics>::deserialize(&bytes, "g").unwrap();
        m.check_whole(&back).unwrap_err().0
    };
    let e = forged("train-3-coaches-2x25-5", &|s| {
        s.dynamic.bodies[3].position.x = f64::NAN
    });
    assert!(e.contains("non-finite number (NaN)"), "{e}");
    // The car body and its first wheelset, 1.5 m apart, on Hertz contacts.
    let e = forged("train-8-coaches-3x25-300", &|s| s.dynamic.bodies.swap(0, 3));
    assert!(
        e.contains("(a force law)")
            && e.contains("not where the contacts say")
            && !e.contains("  "),
        "{e}"
    );
}
