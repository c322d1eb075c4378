//! Export an FMU of a scene and run it with an independent importer, the
//! `fmi` crate, comparing with the same model run in-process.

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use guideway::model::{Model, StepOutcome, Value, VarType};
use guideway::scene::{BodyKind, Scene};
use guideway::Simulation;

fn export(scene: &Scene, dir: &std::path::Path) -> std::path::PathBuf {
    let out = dir.join("scene.fmu");
    let cdylib = guideway::fmu::default_cdylib().expect("the cdylib is built with the tests");
    guideway::fmu::export(scene, &out, &cdylib).unwrap();
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&out).unwrap()).unwrap();
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("modelDescription.xml").unwrap(), &mut xml)
        .unwrap();
    guideway::fmu::check_well_formed(&xml).expect("modelDescription.xml is well-formed");
    out
}

#[test]
fn the_fmi_crate_runs_the_exported_fmu_like_the_native_model() {
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let dir = tempfile::tempdir().unwrap();
    let import: Fmi2Import = fmi::import::from_path(export(&scene, dir.path())).unwrap();
    let mut inst = import.instantiate_cs("wheel", false, true).unwrap();

    let mut native = Model::<Simulation>::new(scene.clone()).unwrap();
    let table = native.table().clone();
    let vr = |name: &str| table.by_name(name).unwrap().value_reference;
    let outputs: Vec<u32> = table
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.value_reference)
        .collect();

    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    native.initialize().unwrap();

    let h = 0.05;
    let mut values = vec![0.0; outputs.len()];
    let on_beam = vr("contact.on_beam");
    let mut exit = None;
    // Past the exit (an event, not the end of the run) to 3 s.
    for steps in 0..60 {
        let t = steps as f64 * h;
        let fmu = inst.do_step(t, h, true);
        let nat = native.do_step(native.time(), h).unwrap();
        inst.get_real(&outputs, &mut values).unwrap();
        let want: Vec<f64> = native
            .get(VarType::Real, &outputs)
            .unwrap()
            .into_iter()
            .map(|v| match v {
                Value::Real(x) => x,
                v => panic!("{v:?}"),
            })
            .collect();
        assert_eq!(values, want, "outputs differ after step {steps}");
        match (fmu, nat) {
            (Ok(_), StepOutcome::Completed) => {}
            (f, n) => panic!("FMU {f:?} vs native {n:?} at step {steps}"),
        }
        let mut on = [0];
        inst.get_integer(&[on_beam], &mut on).unwrap();
        if on[0] == 0 && exit.is_none() {
            exit = Some(t + h);
        }
    }
    let exit = exit.expect("the wheel left the beam");
    assert!(exit > 2.0 && exit < 2.5, "exit at {exit}");
    let mut x = [0.0];
    inst.get_real(&[vr("contact.position")], &mut x).unwrap();
    assert!(x[0] > 30.0, "{}", x[0]);

    // parameters through the importer: a refused value is an error, the
    // instance goes on
    inst.reset().unwrap();
    assert!(inst.set_real(&[vr("wheel.mass")], &[-1.0]).is_err());
    inst.set_real(&[vr("wheel.initial_speed")], &[20.0])
        .unwrap();
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.do_step(0.0, 0.1, true).unwrap();
    inst.get_real(&[vr("wheel.x")], &mut x).unwrap();
    assert!((x[0] - 2.0).abs() < 0.05, "x = {}", x[0]);
}
