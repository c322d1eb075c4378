//! Issue 27 (item 1) and issue 30 (defect 3): every built-in scene's FMU
//! accepts its own start values, restores every state it hands out (get/set
//! and serialize/deserialize, in the same instance and a fresh one), and
//! declares min <= start <= max for every variable.

use guideway::fmi2::instance::Instance;
use guideway::fmi2::logging::Logger;
use guideway::fmi2::model_description::generate;
use guideway::model::{FmuModel, Model, Role, SceneDynamics, Value, VarType};
use guideway::scene::builtins;
use guideway::Scene;

type Fmu = Instance<Model<SceneDynamics>>;

fn instance(scene: &Scene) -> (Fmu, String) {
    let model = Model::<SceneDynamics>::new(scene.clone()).unwrap();
    let (xml, guid) = generate(&model.info(), model.table());
    let logger = Logger::new(None, std::ptr::null_mut(), "own", false);
    let fmu = Instance::new(scene.clone(), &guid, logger).unwrap_or_else(|(_, e)| panic!("{e}"));
    (fmu, xml)
}

/// The built-in scenes and the project's scene files (vehicles and moving
/// forces alike).
fn scenes() -> Vec<Scene> {
    let mut all: Vec<Scene> = builtins()
        .iter()
        .map(|(name, _)| guideway::scene::builtin(name).unwrap())
        .collect();
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        all.push(Scene::load(path.to_str().unwrap()).unwrap());
    }
    assert!(all.len() >= 8, "{} scenes", all.len());
    all
}

/// An attribute's value in one XML element's text.
fn attribute(element: &str, name: &str) -> Option<f64> {
    let key = format!(" {name}=\"");
    let at = element.find(&key)? + key.len();
    let end = element[at..].find('"')?;
    element[at..at + end].parse().ok()
}

#[test]
fn every_declared_start_lies_within_its_declared_bounds() {
    for scene in scenes() {
        let (_, xml) = instance(&scene);
        let mut checked = 0;
        for variable in xml.split("<ScalarVariable").skip(1) {
            let element = &variable[..variable.find("</ScalarVariable>").unwrap()];
            let (Some(start), name) = (attribute(element, "start"), element) else {
                continue;
            };
            if let Some(min) = attribute(element, "min") {
                assert!(
                    min <= start,
                    "{}: min {min} > start {start} in {name}",
                    scene.name
                );
            }
            if let Some(max) = attribute(element, "max") {
                assert!(
                    start <= max,
                    "{}: start {start} > max {max} in {name}",
                    scene.name
                );
            }
            checked += 1;
        }
        assert!(checked > 5, "{}: {checked} starts", scene.name);
    }
}

/// Every parameter set to its own start value, which must be accepted.
fn set_own_starts(fmu: &mut Fmu, scene: &Scene) {
    let table = fmu.model().table().clone();
    for v in table.variables() {
        let (Role::Parameter(_), Some(start)) = (v.role, v.start) else {
            continue;
        };
        fmu.set("fmi2SetReal", &[v.value_reference], &[start])
            .unwrap_or_else(|e| panic!("{}: its own start refused: {e}", scene.name));
    }
}

fn outputs(fmu: &mut Fmu) -> Vec<u64> {
    let vrs: Vec<u32> = fmu
        .model()
        .table()
        .outputs()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.value_reference)
        .collect();
    let mut out = vec![0.0; vrs.len()];
    fmu.get_reals(&vrs, &mut out).unwrap();
    out.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn every_builtin_fmu_accepts_its_starts_and_restores_every_state_it_hands_out() {
    for scene in scenes() {
        let (mut fmu, _) = instance(&scene);
        set_own_starts(&mut fmu, &scene);
        fmu.setup_experiment(0.0, None).unwrap();
        fmu.enter_initialization_mode().unwrap();
        fmu.exit_initialization_mode()
            .unwrap_or_else(|e| panic!("{}: {e}", scene.name));
        let h = 4.0 * scene.solver.step;
        let (mut t, mut saved) = (0.0, Vec::new());
        for _ in 0..3 {
            let key = fmu.get_state(0).unwrap();
            saved.push((t, key, fmu.serialize_state(key).unwrap(), outputs(&mut fmu)));
            fmu.do_step(t, h)
                .unwrap_or_else(|e| panic!("{}: {e}", scene.name));
            t += h;
        }
        let end = outputs(&mut fmu);
        for (t0, key, bytes, at) in &saved {
            let name = &scene.name;
            fmu.set_state(*key)
                .unwrap_or_else(|e| panic!("{name} at {t0}: {e}"));
            assert_eq!(&outputs(&mut fmu), at, "{name}: outputs after set at {t0}");
            let copy = fmu
                .deserialize_state(bytes)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            fmu.set_state(copy)
                .unwrap_or_else(|e| panic!("{name} at {t0}: {e}"));
            assert_eq!(&outputs(&mut fmu), at, "{name}: outputs after deserialize");
            let (mut fresh, _) = instance(&scene);
            let theirs = fresh
                .deserialize_state(bytes)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            fresh
                .set_state(theirs)
                .unwrap_or_else(|e| panic!("{name} fresh at {t0}: {e}"));
            assert_eq!(
                &outputs(&mut fresh),
                at,
                "{name}: outputs in a fresh instance"
            );
        }
        // From the first state again, the same steps reach the same end.
        fmu.set_state(saved[0].1).unwrap();
        for k in 0..3 {
            fmu.do_step(k as f64 * h, h).unwrap();
        }
        assert_eq!(
            outputs(&mut fmu),
            end,
            "{}: bit-identical rerun",
            scene.name
        );
    }
}

#[test]
fn a_train_starting_on_the_approach_takes_any_start_on_the_approach() {
    let scene = guideway::scene::builtin("train-3-coaches-2x25-5").unwrap();
    let (mut fmu, _) = instance(&scene);
    let vr = fmu
        .model()
        .table()
        .by_name("coach1.initial_position")
        .unwrap()
        .value_reference;
    assert!(fmu.set("fmi2SetReal", &[vr], &[Value::Real(-11.0)]).is_ok());
    assert!(fmu.set("fmi2SetReal", &[vr], &[Value::Real(-70.0)]).is_ok());
    let e = fmu
        .set("fmi2SetReal", &[vr], &[Value::Real(-70.5)])
        .unwrap_err();
    assert!(e.contains("-70.5") && e.contains("must be >= -70"), "{e}");
}

// ---- issue 30, defect 5: forged multi-body states are refused whole ---------------

/// The payload of a serialized state as JSON, and its header up to the
/// checksum.
fn open_state(bytes: &[u8]) -> (Vec<u8>, serde_json::Value) {
    let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let head = bytes[..16 + n].to_vec();
    let payload = &bytes[16 + n + 40..];
    (head, rmp_serde::from_slice(payload).unwrap())
}

/// Framed again with the right length and checksum.
fn close_state(head: &[u8], value: &serde_json::Value) -> Vec<u8> {
    use sha2::Digest;
    let payload = rmp_serde::to_vec_named(value).unwrap();
    let mut out = head.to_vec();
    out.extend_from_slice(&sha2::Sha256::digest(&payload));
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

#[test]
fn forged_train_states_are_refused_at_deserialization() {
    let scene = guideway::scene::builtin("train-3-coaches-2x25-5").unwrap();
    let (mut fmu, _) = instance(&scene);
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    fmu.do_step(0.0, 0.01).unwrap();
    let key = fmu.get_state(0).unwrap();
    let bytes = fmu.serialize_state(key).unwrap();
    let (head, good) = open_state(&bytes);
    assert!(
        fmu.deserialize_state(&close_state(&head, &good)).is_ok(),
        "re-framed own state"
    );
    let forge = |change: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good.clone();
        change(&mut v);
        close_state(&head, &v)
    };
    // The car body (body 0) and its first wheelset swapped: 1.5 m apart.
    let swapped = forge(&|v| {
        let bodies = v["sim"]["dynamic"]["bodies"].as_array_mut().unwrap();
        bodies.swap(0, 3);
    });
    let e = fmu.deserialize_state(&swapped).unwrap_err();
    assert!(e.contains("not where the contacts say"), "{e}");
    let exit_before_start = forge(&|v| v["sim"]["exit_time"] = (-1.0).into());
    let e = fmu.deserialize_state(&exit_before_start).unwrap_err();
    assert!(e.contains("exit time -1 s lies outside"), "{e}");
    let one_body_less = forge(&|v| {
        v["sim"]["dynamic"]["bodies"].as_array_mut().unwrap().pop();
    });
    assert!(fmu
        .deserialize_state(&one_body_less)
        .unwrap_err()
        .contains("bodies"));
    // The instance is unchanged by the refusals and its own state restores.
    fmu.set_state(key).unwrap();
}

// ---- issue 30, defect 6: the wall-time budget holds inside one internal step ------

#[test]
fn one_internal_step_past_the_budget_is_refused_not_finished() {
    let scene = guideway::scene::builtin("train-3-coaches-2x25-5").unwrap();
    let (mut fmu, _) = instance(&scene);
    let budget = fmu
        .model()
        .table()
        .by_name("solver.wall_time_budget")
        .unwrap();
    let vr = budget.value_reference;
    fmu.set("fmi2SetReal", &[vr], &[Value::Real(1e-300)])
        .unwrap();
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    // One internal step: on 86becc7 it ran to its end and returned OK.
    let e = fmu.do_step(0.0, scene.solver.step).unwrap_err();
    assert!(
        e.contains("one internal step") && e.contains("1e-300"),
        "{e}"
    );
    assert!(e.len() < 600, "a short message: {e}");
}

#[test]
fn a_subnormal_budget_is_printed_short() {
    let scene = guideway::scene::builtin("lee1994-wheel-10").unwrap();
    let (mut fmu, _) = instance(&scene);
    let vr = fmu
        .model()
        .table()
        .by_name("solver.wall_time_budget")
        .unwrap()
        .value_reference;
    fmu.set("fmi2SetReal", &[vr], &[Value::Real(5e-324)])
        .unwrap();
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    let e = fmu.do_step(0.0, 100.0 * scene.solver.step).unwrap_err();
    assert!(e.contains("= 5e-324 s"), "{e}");
    assert!(e.len() < 600, "{} characters: {e}", e.len());
}

/// A step whose contact operator needs more beam integrations than can fit
/// in the budget, by a lower bound from counts, is refused before they
/// start, and the refusal says so; on main at 0f0edf8 it ran to the
/// deadline. A grid step of HHT-α now builds the operator from the band of
/// its inverse with no beam integration (issue 29), so the step asked for
/// is half a grid step: one integration per magnet on the beam, 400 of
/// 50,000 elements, at least 0.4 s against a budget of 0.1 s.
#[test]
fn a_step_known_to_outlast_the_budget_is_refused_up_front() {
    let text = "name = \"fleet\"\ngravity = 9.81\n[beam]\nlength = 100.0\n\
        mass_per_length = 2303.0\nbending_stiffness = 8.5e10\nsurface_offset = 0.0\n\
        elements = 50000\n[solver]\nstep = 5e-4\nintegrator = \"hht\"\n\
        [body]\nname = \"car\"\nkind = \"maglev_vehicle\"\nmass = 30000.0\n\
        initial_position = 60.0\ninitial_speed = 10.0\n[body.maglev]\ncar_inertia = 1.5e6\n\
        magnets = 400\nmagnet_spacing = 0.01\nmagnet_mass = 600.0\nstiffness = 8.0e5\n";
    let scene = guideway::Scene::from_toml_str(text).unwrap();
    let (mut fmu, _) = instance(&scene);
    let vr = fmu
        .model()
        .table()
        .by_name("solver.wall_time_budget")
        .unwrap()
        .value_reference;
    fmu.set("fmi2SetReal", &[vr], &[Value::Real(0.1)]).unwrap();
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    let e = fmu.do_step(0.0, 0.5 * scene.solver.step).unwrap_err();
    assert!(
        e.contains("refused up front") && e.contains("elements"),
        "{e}"
    );
}

// ---- issue 26 item 4: a moving-force FMU's forged states are refused ------------

#[test]
fn forged_moving_force_states_are_refused_naming_why() {
    let scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/bridge25_hslm.toml"
    ))
    .unwrap();
    let (mut fmu, _) = instance(&scene);
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    fmu.do_step(0.0, 0.05).unwrap();
    let key = fmu.get_state(0).unwrap();
    let bytes = fmu.serialize_state(key).unwrap();
    let (head, good) = open_state(&bytes);
    assert_eq!(good["sim"]["steps"], 50, "{good}");
    let forge = |change: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good.clone();
        change(&mut v);
        close_state(&head, &v)
    };
    let short = forge(&|v| {
        v["sim"]["velocity"].as_array_mut().unwrap().pop();
    });
    let e = fmu.deserialize_state(&short).unwrap_err();
    assert!(e.contains("velocity has") && e.contains("free DOFs"), "{e}");
    let off_its_step = forge(&|v| v["sim"]["time"] = 0.2.into());
    let e = fmu.deserialize_state(&off_its_step).unwrap_err();
    assert!(e.contains("time 0.2 s is not that of its step 50"), "{e}");
    // (a vehicle's state handed to moving forces)
    let train = guideway::scene::builtin("lee1994-wheel-10").unwrap();
    let (mut wheel, _) = instance(&train);
    wheel.setup_experiment(0.0, None).unwrap();
    wheel.enter_initialization_mode().unwrap();
    wheel.exit_initialization_mode().unwrap();
    let wheel_key = wheel.get_state(0).unwrap();
    let theirs = wheel.serialize_state(wheel_key).unwrap();
    let (_, vehicle) = open_state(&theirs);
    let wheel_inside = forge(&|v| v["sim"] = vehicle["sim"].clone());
    let e = fmu.deserialize_state(&wheel_inside).unwrap_err();
    assert!(e.contains("not one of this model"), "{e}");
    // The instance is unchanged by the refusals and its own state restores.
    fmu.set_state(key).unwrap();
    // A communication point off the grid of solver.step is refused before
    // anything runs; the grid's next point is then reached as ever.
    let e = fmu.do_step(0.05, 0.0105).unwrap_err();
    assert!(e.contains("must be a multiple of it"), "{e}");
    fmu.do_step(0.05, 0.05).unwrap();
    assert_eq!(fmu.model().time(), 0.1);
}
