//! The FMI 3.0 layer against the FMI 2.0 one on the same scene: the same
//! variables and start values, the same outputs after the same steps (to
//! the bit), and its own refusals.

use super::exports::*;
use super::instance::Instance;
use super::logging::Logger;
use super::model_description::time_value_reference;
use super::unsupported::*;
use crate::fmi2::instance::Instance as Instance2;
use crate::model::ExportedModel as Physics;
use crate::model::{Causality, VarType};
use crate::scene::{BodyKind, Scene};
use fmi_sys::fmi3::*;

fn scene() -> Scene {
    Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025)
}

fn instance3(scene: &Scene) -> Instance<Physics> {
    let token = super::describe::<Physics>(scene.clone()).unwrap().guid;
    let logger = Logger::new(None, std::ptr::null_mut(), false);
    Instance::new(scene.clone(), &token, logger).unwrap_or_else(|(_, e)| panic!("{e}"))
}

fn instance2(scene: &Scene) -> Instance2<Physics> {
    let guid = crate::fmi2::describe::<Physics>(scene.clone())
        .unwrap()
        .guid;
    let logger = crate::fmi2::logging::Logger::new(None, std::ptr::null_mut(), "t", false);
    Instance2::new(scene.clone(), &guid, logger).unwrap_or_else(|(_, e)| panic!("{e}"))
}

#[test]
fn the_description_declares_every_table_variable_and_time() {
    let scene = scene();
    let d3 = super::describe::<Physics>(scene.clone()).unwrap();
    let d2 = crate::fmi2::describe::<Physics>(scene.clone()).unwrap();
    crate::fmu::check_well_formed(&d3.xml).unwrap();
    assert!(d3.xml.contains("fmiVersion=\"3.0\""));
    assert_ne!(
        d3.guid, d2.guid,
        "an FMI 3.0 description is another description"
    );
    assert_eq!(d3.table, d2.table);
    let time = time_value_reference(&d3.table);
    assert!(d3.xml.contains(&format!(
        "<Float64 name=\"time\" valueReference=\"{time}\" description=\"simulation time\" causality=\"independent\" variability=\"continuous\" unit=\"s\"/>"
    )));
    for v in d3.table.variables() {
        let element = match v.ty {
            VarType::Real => "Float64",
            VarType::Integer => "Int32",
            VarType::Boolean => "Boolean",
        };
        let opening = format!(
            "<{element} name=\"{}\" valueReference=\"{}\"",
            v.name, v.value_reference
        );
        assert!(d3.xml.contains(&opening), "{opening}");
        if v.causality == Causality::Output {
            let output = format!("<Output valueReference=\"{}\"", v.value_reference);
            assert!(d3.xml.contains(&output), "{output}");
        }
    }
    assert_eq!(
        super::describe::<Physics>(scene.clone()).unwrap().guid,
        d3.guid
    );
}

#[test]
fn steps_give_the_fmi2_outputs_to_the_bit() {
    let scene = scene();
    let (mut a, mut b) = (instance3(&scene), instance2(&scene));
    let table = crate::fmi2::describe::<Physics>(scene.clone())
        .unwrap()
        .table;
    let outputs: Vec<u32> = table
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.value_reference)
        .collect();
    a.setup_experiment(0.0, None).unwrap();
    a.enter_initialization_mode().unwrap();
    a.exit_initialization_mode().unwrap();
    b.setup_experiment(0.0, None).unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    let (mut x3, mut x2) = (vec![0.0; outputs.len()], vec![0.0; outputs.len()]);
    let h = 0.01;
    for k in 0..50 {
        let report = a.do_step(k as f64 * h, h).unwrap();
        assert_eq!(report.status, fmi3Status_fmi3OK);
        b.do_step(k as f64 * h, h).unwrap();
        a.get_reals(&outputs, &mut x3).unwrap();
        b.get_reals(&outputs, &mut x2).unwrap();
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&x3), bits(&x2), "step {k}");
    }
    let mut t = [0.0];
    a.get_reals(&[time_value_reference(&table)], &mut t)
        .unwrap();
    assert!((t[0] - 0.5).abs() < 1e-12);
}

#[test]
fn a_state_round_trips_through_serialization() {
    let scene = scene();
    let mut a = instance3(&scene);
    a.setup_experiment(0.0, None).unwrap();
    a.enter_initialization_mode().unwrap();
    a.exit_initialization_mode().unwrap();
    a.do_step(0.0, 0.01).unwrap();
    let key = a.get_state(0).unwrap();
    let bytes = a.serialize_state(key).unwrap();
    a.do_step(0.01, 0.01).unwrap();
    let vr = [0u32];
    let mut after = [0.0];
    a.get_reals(&vr, &mut after).unwrap();
    let restored = a.deserialize_state(&bytes).unwrap();
    a.set_state(restored).unwrap();
    a.do_step(0.01, 0.01).unwrap();
    let mut again = [0.0];
    a.get_reals(&vr, &mut again).unwrap();
    assert_eq!(after[0].to_bits(), again[0].to_bits());
    // Another model's bytes are refused.
    let mut other = scene.clone();
    other.beam.length = 25.0;
    let mut b = instance3(&other);
    assert!(b.deserialize_state(&bytes).is_err());
}

#[test]
fn the_time_cannot_be_set_and_calls_out_of_order_are_refused() {
    let scene = scene();
    let mut a = instance3(&scene);
    let time = time_value_reference(
        &crate::fmi2::describe::<Physics>(scene.clone())
            .unwrap()
            .table,
    );
    let e = a
        .set("fmi3SetFloat64", &[time], &[crate::model::Value::Real(1.0)])
        .unwrap_err();
    assert!(e.contains("independent variable"), "{e}");
    let e = a.do_step(0.0, 0.01).unwrap_err();
    assert!(e.contains("not allowed in state Instantiated"), "{e}");
}

#[test]
fn null_instances_and_arrays_are_refused() {
    unsafe {
        let (mut a, mut b, mut c, mut t) = (false, false, false, 0.0);
        let status = fmi3DoStep(
            std::ptr::null_mut(),
            0.0,
            0.1,
            true,
            &mut a,
            &mut b,
            &mut c,
            &mut t,
        );
        assert_eq!(status, ERROR);
        fmi3FreeInstance(std::ptr::null_mut());
        let inst = Box::into_raw(Box::new(instance3(&scene()))) as fmi3Instance;
        assert_eq!(
            fmi3EnterInitializationMode(inst, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(
            fmi3GetFloat64(inst, std::ptr::null(), 0, std::ptr::null_mut(), 0),
            OK
        );
        assert_eq!(
            fmi3GetFloat64(inst, std::ptr::null(), 2, std::ptr::null_mut(), 2),
            ERROR
        );
        let vr = [0u32];
        let mut x = [0.0; 2];
        assert_eq!(
            fmi3GetFloat64(inst, vr.as_ptr(), 1, x.as_mut_ptr(), 2),
            ERROR,
            "nValues"
        );
        assert_eq!(fmi3GetFloat64(inst, vr.as_ptr(), 1, x.as_mut_ptr(), 1), OK);
        assert_eq!(
            fmi3GetFloat32(inst, vr.as_ptr(), 1, std::ptr::null_mut(), 1),
            ERROR
        );
        assert_eq!(fmi3EnterEventMode(inst), ERROR);
        fmi3FreeInstance(inst);
    }
}

#[test]
fn an_allowed_early_return_ends_at_the_internal_step_of_the_exit() {
    let scene = scene();
    let step = scene.solver.step;
    let table = crate::fmi2::describe::<Physics>(scene.clone())
        .unwrap()
        .table;
    let on_beam = table.by_name("contact.on_beam").unwrap().value_reference;
    let deflection = table
        .by_name("sensor.midspan.deflection")
        .unwrap()
        .value_reference;
    let start = |early: bool| {
        let mut a = instance3(&scene);
        a.allow_early_return(early);
        a.setup_experiment(0.0, None).unwrap();
        a.enter_initialization_mode().unwrap();
        a.exit_initialization_mode().unwrap();
        a
    };
    let mut early = start(true);
    let report = early.do_step(0.0, 3.0).unwrap();
    assert!(report.early_return && report.status == fmi3Status_fmi3OK);
    let t_event = report.last_successful_time;
    assert!(t_event < 3.0);
    let on = |a: &mut Instance<Physics>| {
        let mut v = 0;
        a.get_each("get", VarType::Integer, &[on_beam], |x| {
            if let crate::model::Value::Integer(n) = x {
                v = n
            }
        })
        .unwrap();
        v
    };
    assert_eq!(on(&mut early), 0, "the contact has left the beam");
    // Reference: the same run in internal steps, without early return. The
    // exit happens in the last of them, and the state there is the same.
    let mut plain = start(false);
    let k = (t_event / step).round() as usize;
    assert!((t_event - k as f64 * step).abs() < 1e-9, "on the grid");
    for i in 0..k - 1 {
        let r = plain.do_step(i as f64 * step, step).unwrap();
        assert!(!r.early_return);
    }
    assert_eq!(on(&mut plain), 1, "still on the beam one step before");
    plain.do_step((k - 1) as f64 * step, step).unwrap();
    assert_eq!(on(&mut plain), 0);
    let (mut a, mut b) = ([0.0], [0.0]);
    early.get_reals(&[deflection], &mut a).unwrap();
    plain.get_reals(&[deflection], &mut b).unwrap();
    assert_eq!(a[0].to_bits(), b[0].to_bits());
    // Without the importer's leave, the same step runs through.
    let report = start(false).do_step(0.0, 3.0).unwrap();
    assert!(!report.early_return && report.last_successful_time == 3.0);
}
