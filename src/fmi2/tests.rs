//! The instance state machine, on the stand-in physics.

use super::instance::{resource_path, Instance, Mode};
use super::logging::Logger;
use super::model_description::generate;
use crate::model::fake::FakeDynamics;
use crate::model::{FmuModel, Model, Value, VarType};
use crate::scene::{BodyKind, Scene};
use fmi_sys::fmi2::*;

fn scene() -> Scene {
    Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025)
}

fn guid(scene: &Scene) -> String {
    let m = Model::<FakeDynamics>::new(scene.clone()).unwrap();
    generate(&m.info(), m.table()).1
}

fn instance() -> Instance<Model<FakeDynamics>> {
    let s = scene();
    let g = guid(&s);
    Instance::new(s, &g, Logger::new(None, std::ptr::null_mut(), "t", false))
        .unwrap_or_else(|(_, e)| panic!("{e}"))
}

fn vr(i: &Instance<Model<FakeDynamics>>, name: &str) -> u32 {
    i.model().table().by_name(name).unwrap().value_reference
}

#[test]
fn wrong_guid_is_refused() {
    let logger = Logger::new(None, std::ptr::null_mut(), "t", false);
    let e = Instance::<Model<FakeDynamics>>::new(scene(), "{nope}", logger)
        .err()
        .unwrap()
        .1;
    assert!(e.contains("{nope}") && e.contains("GUID"), "{e}");
}

#[test]
fn model_exchange_is_refused() {
    let logger = Logger::new(None, std::ptr::null_mut(), "t", false);
    let r = Instance::<Model<FakeDynamics>>::instantiate(
        fmi2Type_fmi2ModelExchange,
        "g",
        "file:///tmp",
        logger,
    );
    assert!(r.err().unwrap().1.contains("co-simulation"));
}

#[test]
fn resource_locations_in_both_file_forms_are_decoded() {
    assert_eq!(
        resource_path("file:///tmp/a%20b/resources")
            .unwrap()
            .to_str(),
        Some("/tmp/a b/resources")
    );
    assert_eq!(
        resource_path("file:/tmp/x/").unwrap().to_str(),
        Some("/tmp/x/")
    );
    assert!(resource_path("http://example.org/r").is_err());
    assert!(resource_path("not a uri").is_err());
}

#[test]
fn calls_in_the_wrong_state_are_refused_and_change_nothing() {
    let mut i = instance();
    let x = vr(&i, "wheel.x");
    let e = i.get("fmi2GetReal", VarType::Real, &[x]).unwrap_err();
    assert!(
        e.contains("fmi2GetReal") && e.contains("Instantiated"),
        "{e}"
    );
    assert!(i.do_step(0.0, 0.1).unwrap_err().contains("Instantiated"));
    assert!(i.exit_initialization_mode().is_err());
    assert!(i.terminate().is_err());
    assert_eq!(i.mode(), Mode::Instantiated);
    i.enter_initialization_mode().unwrap();
    assert!(i.setup_experiment(0.0, None).is_err());
    i.get("fmi2GetReal", VarType::Real, &[x]).unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(i.mode(), Mode::StepComplete);
    assert_eq!(i.do_step(0.0, 0.1).unwrap().status, fmi2Status_fmi2OK);
    i.terminate().unwrap();
    assert!(i.do_step(0.1, 0.1).is_err());
    i.get("fmi2GetReal", VarType::Real, &[x]).unwrap();
    i.reset().unwrap();
    assert_eq!(i.mode(), Mode::Instantiated);
}

#[test]
fn refused_parameter_leaves_the_instance_usable() {
    let mut i = instance();
    let el = vr(&i, "beam.elements");
    let e = i
        .set("fmi2SetInteger", &[el], &[Value::Integer(0)])
        .unwrap_err();
    assert!(e.contains("beam.elements") && e.contains('0'), "{e}");
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(i.do_step(0.0, 0.1).unwrap().status, fmi2Status_fmi2OK);
}

#[test]
fn exit_gives_discard_terminated_and_last_successful_time() {
    let mut i = instance();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert!(!i.get_boolean_status(fmi2StatusKind_fmi2Terminated).unwrap());
    assert_eq!(i.do_step(0.0, 1.0).unwrap().status, fmi2Status_fmi2OK);
    assert_eq!(i.do_step(1.0, 1.0).unwrap().status, fmi2Status_fmi2OK);
    assert_eq!(i.do_step(2.0, 1.0).unwrap().status, fmi2Status_fmi2Discard);
    assert_eq!(i.mode(), Mode::StepFailed);
    assert!(i.get_boolean_status(fmi2StatusKind_fmi2Terminated).unwrap());
    let t = i
        .get_real_status(fmi2StatusKind_fmi2LastSuccessfulTime)
        .unwrap();
    assert!((t - 2.4).abs() < 1e-9, "{t}");
    assert!(i.do_step(t, 0.1).is_err());
    // the last good state is still retrievable
    let s = i.get_state(0).unwrap();
    assert!(!i.serialize_state(s).unwrap().is_empty());
}

#[test]
fn states_are_tracked_and_foreign_handles_refused() {
    let mut i = instance();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    let s = i.get_state(0).unwrap();
    assert_eq!(i.get_state(s).unwrap(), s);
    assert!(i.set_state(12345).is_err());
    assert!(i.get_state(12345).is_err());
    i.free_state(s).unwrap();
    assert!(i.free_state(s).is_err(), "double free is refused");
    assert!(i.set_state(s).is_err());
}

#[test]
fn deserialized_state_continues_in_another_instance() {
    let mut a = instance();
    a.enter_initialization_mode().unwrap();
    a.exit_initialization_mode().unwrap();
    a.do_step(0.0, 0.3).unwrap();
    let s = a.get_state(0).unwrap();
    let bytes = a.serialize_state(s).unwrap();
    a.do_step(0.3, 0.3).unwrap();
    let x = vr(&a, "wheel.x");
    let want = a.get("g", VarType::Real, &[x]).unwrap();

    let mut b = instance();
    let t = b.deserialize_state(&bytes).unwrap();
    b.set_state(t).unwrap();
    assert_eq!(b.mode(), Mode::StepComplete);
    b.do_step(0.3, 0.3).unwrap();
    assert_eq!(b.get("g", VarType::Real, &[x]).unwrap(), want);
    let mut bad = bytes.clone();
    bad[40] ^= 0xff;
    assert!(b.deserialize_state(&bad).is_err());
}

#[test]
fn a_stale_state_handle_is_refused_even_when_its_memory_was_reused() {
    // Issue 13, defect 9: free a, get b (the allocator reuses a's memory),
    // free a's old handle again: that must not free b.
    let mut i = instance();
    let a = i.get_state(0).unwrap();
    i.free_state(a).unwrap();
    let b = i.get_state(0).unwrap();
    let e = i.free_state(a).unwrap_err();
    assert!(e.contains("not a live state"), "{e}");
    i.set_state(b).unwrap();
    i.free_state(b).unwrap();
}

#[test]
fn another_instances_state_handle_is_refused() {
    let mut a = instance();
    let mut b = instance();
    let sa = a.get_state(0).unwrap();
    let sb = b.get_state(0).unwrap();
    assert_ne!(sa, sb);
    assert!(b.set_state(sa).is_err());
    assert!(b.free_state(sa).is_err());
    a.free_state(sa).unwrap();
    b.free_state(sb).unwrap();
}

const D: &str = "fmi2SetRealInputDerivatives";

#[test]
fn input_derivatives_are_taken_while_inputs_may_be_set_and_refused_after_terminate() {
    let mut i = instance();
    let fx = vr(&i, "wheel.force_x");
    i.set_input_derivatives(D, &[fx], &[1], &[10.0]).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i.set_input_derivatives(D, &[fx], &[2], &[1.0]).unwrap();
    let e = i.set_input_derivatives(D, &[fx], &[0], &[1.0]).unwrap_err();
    assert!(
        e.contains("fmi2SetRealInputDerivatives") && e.contains("1 or 2"),
        "{e}"
    );
    i.terminate().unwrap();
    let e = i.set_input_derivatives(D, &[fx], &[1], &[1.0]).unwrap_err();
    assert!(e.contains("Terminated"), "{e}");
}
