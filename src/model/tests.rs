use super::fake::{FakeDynamics, FAIL_FORCE};
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
/// output overflowed to inf and was read with status OK.
#[test]
fn parameters_that_overflow_an_output_are_refused_when_outputs_are_read() {
    let mut m = model(BodyKind::Wheel);
    let radius = vr(&m, "wheel.radius");
    m.set(&[radius], &[Value::Real(5e-324)]).unwrap();
    let w = vr(&m, "wheel.angular_velocity");
    let e = m.get(VarType::Real, &[w]).unwrap_err().0;
    assert!(
        e.contains("wheel.angular_velocity") && e.contains("inf"),
        "{e}"
    );
    let e = m.initialize().unwrap_err().0;
    assert!(e.contains("wheel.angular_velocity"), "{e}");
    // a sensible radius makes the model usable again
    m.set(&[radius], &[Value::Real(0.3)]).unwrap();
    m.initialize().unwrap();
}

/// Found while fuzzing: a subnormal solver.step (valid: > 0) made one
/// fmi2DoStep take 1e321 internal steps, a hang in the importer's process.
#[test]
fn a_step_needing_too_many_internal_steps_is_refused_and_changes_nothing() {
    let mut m = model(BodyKind::Wheel);
    let step = vr(&m, "solver.step");
    m.set(&[step], &[Value::Real(5e-324)]).unwrap();
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
    b.set_start_time(10.0).unwrap();
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
