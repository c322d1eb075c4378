//! Unit tests of the scene format: parsing, defaults, validation
//! messages (field, value, rule) and the built-in scenes.

use super::*;

fn default_scene() -> Scene {
    builtin(DEFAULT_SCENE).expect("the default scene is built in")
}

/// The problems of a scene changed by `edit`, which must be invalid.
fn problems_after(edit: impl FnOnce(&mut Scene)) -> Vec<Problem> {
    let mut scene = default_scene();
    edit(&mut scene);
    match scene.validate() {
        Err(SceneError::Invalid { problems }) => problems,
        other => panic!("expected an invalid scene, got {other:?}"),
    }
}

/// Asserts that exactly one problem is reported, at `path`, with `value`,
/// and a rule containing `rule`.
fn assert_single_problem(edit: impl FnOnce(&mut Scene), path: &str, value: &str, rule: &str) {
    let problems = problems_after(edit);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let problem = &problems[0];
    assert_eq!(problem.path, path, "{problem}");
    assert_eq!(problem.value, value, "{problem}");
    assert!(problem.rule.contains(rule), "{problem} lacks {rule:?}");
}

#[test]
fn every_builtin_is_valid_and_round_trips_through_toml() {
    assert_eq!(builtins().len(), 9);
    for &(name, description) in builtins() {
        let scene = builtin(name).unwrap_or_else(|| panic!("{name} is listed but not built"));
        assert_eq!(scene.name, name);
        assert_eq!(scene.description, description);
        scene.validate().unwrap();
        let text = scene.to_toml_string();
        let reread = Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(reread, scene, "{name} changed through TOML:\n{text}");
    }
}

#[test]
fn builtins_are_the_papers_cases() {
    let expect = [
        ("lee1994-wheel-1", BodyKind::Wheel, 1.0, 0.005),
        ("lee1994-wheel-10", BodyKind::Wheel, 10.0, 0.0025),
        ("lee1994-wheel-100", BodyKind::Wheel, 100.0, 0.0025),
        ("lee1994-glider-30", BodyKind::Glider, 30.0, 0.005),
    ];
    for (name, kind, speed, step) in expect {
        let scene = builtin(name).unwrap();
        assert_eq!(scene.vehicles[0].kind, kind, "{name}");
        assert_eq!(scene.vehicles[0].initial_speed, speed, "{name}");
        assert_eq!(scene.solver.step, step, "{name}");
        assert_eq!(scene.beam.elements, 2, "{name}");
        assert_eq!(scene.beam.length, 24.0, "{name}");
        assert_eq!(scene.sensors.len(), 1, "{name}");
        assert_eq!(scene.sensors[0].name, "midspan");
        assert_eq!(scene.sensors[0].position, 12.0);
    }
    assert_eq!(DEFAULT_SCENE, "lee1994-wheel-10");
    assert!(builtin("lee1994-wheel-2").is_none());
}

#[test]
fn a_minimal_scene_gets_the_documented_defaults() {
    let text = r#"
        name = "minimal"
        [beam]
        length = 10
        mass_per_length = 100
        bending_stiffness = 1e6
        surface_offset = 0
        elements = 4
        [body]
        name = "puck"
        kind = "glider"
        mass = 10
        initial_speed = 5
    "#;
    let scene = Scene::from_toml_str(text).unwrap();
    assert_eq!(scene.beam.length, 10.0, "integers are read as numbers");
    assert_eq!(scene.beam.supports, SupportsSpec::default());
    assert_eq!(scene.solver, SolverSpec::default());
    assert_eq!(scene.solver.step, 0.0025);
    assert_eq!(scene.solver.velocity_tolerance, 1e-7);
    assert_eq!(scene.solver.gap_tolerance, 1e-5);
    assert_eq!(scene.solver.max_iterations, 50);
    assert!(scene.sensors.is_empty());
    assert_eq!(scene.vehicles[0].initial_position, 0.0);
    assert_eq!(
        (scene.vehicles[0].force_x, scene.vehicles[0].force_y),
        (0.0, 0.0)
    );
    assert_eq!(scene.description, "");
}

// ---- validation rules, one test each ----

#[test]
fn beam_length_must_be_positive() {
    assert_single_problem(|s| s.beam.length = 0.0, "beam.length", "0.0", "> 0");
}

#[test]
fn beam_mass_per_length_must_be_positive() {
    assert_single_problem(
        |s| s.beam.mass_per_length = -1250.0,
        "beam.mass_per_length",
        "-1250.0",
        "> 0",
    );
}

#[test]
fn bending_stiffness_must_be_positive() {
    assert_single_problem(
        |s| s.beam.bending_stiffness = 0.0,
        "beam.bending_stiffness",
        "0.0",
        "> 0",
    );
}

#[test]
fn surface_offset_must_not_be_negative_but_may_be_zero() {
    assert_single_problem(
        |s| s.beam.surface_offset = -0.1,
        "beam.surface_offset",
        "-0.1",
        ">= 0",
    );
    let mut scene = default_scene();
    scene.beam.surface_offset = 0.0;
    scene.validate().unwrap();
}

#[test]
fn beam_needs_at_least_one_element() {
    assert_single_problem(|s| s.beam.elements = 0, "beam.elements", "0", ">= 1");
    assert_single_problem(
        |s| s.beam.elements = MAX_ELEMENTS + 1,
        "beam.elements",
        &(MAX_ELEMENTS + 1).to_string(),
        "<=",
    );
}

#[test]
fn numbers_must_be_finite() {
    assert_single_problem(
        |s| s.beam.bending_stiffness = f64::NAN,
        "beam.bending_stiffness",
        "NaN",
        "finite",
    );
    assert_single_problem(
        |s| s.vehicles[0].force_y = f64::NEG_INFINITY,
        "body.force_y",
        "-inf",
        "finite",
    );
    assert_single_problem(
        |s| s.vehicles[0].force_x = f64::NAN,
        "body.force_x",
        "NaN",
        "finite",
    );
    assert_single_problem(
        |s| s.sensors[0].position = f64::INFINITY,
        "sensors[0].position",
        "inf",
        "finite",
    );
}

#[test]
fn intermediate_supports_lie_strictly_inside_and_increase() {
    let mut scene = default_scene();
    scene.beam.supports.intermediate = vec![8.0, 16.0];
    scene.validate().unwrap();

    assert_single_problem(
        |s| s.beam.supports.intermediate = vec![0.0],
        "beam.supports.intermediate[0]",
        "0.0",
        "strictly inside",
    );
    assert_single_problem(
        |s| s.beam.supports.intermediate = vec![8.0, 24.0],
        "beam.supports.intermediate[1]",
        "24.0",
        "strictly inside",
    );
    assert_single_problem(
        |s| s.beam.supports.intermediate = vec![16.0, 8.0],
        "beam.supports.intermediate[1]",
        "8.0",
        "greater than the support before",
    );
    assert_single_problem(
        |s| s.beam.supports.intermediate = vec![f64::NAN],
        "beam.supports.intermediate[0]",
        "NaN",
        "finite",
    );
}

#[test]
fn supports_must_hold_the_beam() {
    let problems = problems_after(|s| {
        s.beam.supports.left = EndSupport::Free;
        s.beam.supports.right = EndSupport::Free;
    });
    assert_eq!(problems.len(), 1);
    assert_eq!(problems[0].path, "beam.supports");
    assert!(problems[0].rule.contains("rigid motion"));

    // A cantilever and a propped free end are held.
    let mut scene = default_scene();
    scene.beam.supports.left = EndSupport::Clamped;
    scene.beam.supports.right = EndSupport::Free;
    scene.validate().unwrap();
    scene.beam.supports.left = EndSupport::Pinned;
    scene.beam.supports.intermediate = vec![12.0];
    scene.validate().unwrap();
}

#[test]
fn body_name_is_an_identifier_and_not_reserved() {
    assert_single_problem(
        |s| s.vehicles[0].name = "front wheel".into(),
        "body.name",
        "\"front wheel\"",
        "identifier",
    );
    assert_single_problem(
        |s| s.vehicles[0].name = "1wheel".into(),
        "body.name",
        "\"1wheel\"",
        "identifier",
    );
    assert_single_problem(
        |s| s.vehicles[0].name = "energy".into(),
        "body.name",
        "\"energy\"",
        "reserved",
    );
}

#[test]
fn body_mass_must_be_positive() {
    assert_single_problem(|s| s.vehicles[0].mass = 0.0, "body.mass", "0.0", "> 0");
}

#[test]
fn wheel_requires_positive_inertia_and_radius() {
    assert_single_problem(
        |s| s.vehicles[0].inertia = None,
        "body.inertia",
        "missing",
        "a wheel needs",
    );
    assert_single_problem(
        |s| s.vehicles[0].radius = Some(-0.3),
        "body.radius",
        "-0.3",
        "> 0",
    );
    assert_single_problem(
        |s| s.vehicles[0].radius = None,
        "body.radius",
        "missing",
        "> 0",
    );
    assert_single_problem(
        |s| s.vehicles[0].inertia = Some(0.0),
        "body.inertia",
        "0.0",
        "> 0",
    );
}

#[test]
fn glider_must_not_have_inertia_or_radius() {
    let mut glider = builtin("lee1994-glider-30").unwrap();
    glider.validate().unwrap();
    glider.vehicles[0].inertia = Some(135.0);
    glider.vehicles[0].radius = Some(0.3);
    let Err(SceneError::Invalid { problems }) = glider.validate() else {
        panic!("a glider with a radius must be invalid");
    };
    let paths: Vec<&str> = problems.iter().map(|p| p.path.as_str()).collect();
    assert_eq!(paths, ["body.inertia", "body.radius"]);
    assert!(problems.iter().all(|p| p.rule.contains("glider")));
}

#[test]
fn start_must_lie_on_the_beam() {
    assert_single_problem(
        |s| s.vehicles[0].initial_position = -1.0,
        "body.initial_position",
        "-1.0",
        "0 <= x < beam.length = 24.0",
    );
    assert_single_problem(
        |s| s.vehicles[0].initial_position = 24.0,
        "body.initial_position",
        "24.0",
        "0 <= x < beam.length",
    );
    let mut scene = default_scene();
    scene.vehicles[0].initial_position = 23.9;
    scene.validate().unwrap();
}

#[test]
fn initial_speed_must_be_finite_and_may_be_zero() {
    assert_single_problem(
        |s| s.vehicles[0].initial_speed = f64::NAN,
        "body.initial_speed",
        "NaN",
        "finite",
    );
    let mut scene = default_scene();
    scene.vehicles[0].initial_speed = 0.0;
    scene.validate().unwrap();
}

#[test]
fn sensors_lie_on_the_beam_with_unique_identifier_names() {
    assert_single_problem(
        |s| s.sensors[0].position = 24.5,
        "sensors[0].position",
        "24.5",
        "0 <= x <= beam.length",
    );
    let mut scene = default_scene();
    scene.sensors[0].position = 24.0;
    scene.validate().unwrap();

    assert_single_problem(
        |s| s.sensors[0].name = "mid.span".into(),
        "sensors[0].name",
        "\"mid.span\"",
        "identifier",
    );
    assert_single_problem(
        |s| s.sensors.push(s.sensors[0].clone()),
        "sensors[1].name",
        "\"midspan\"",
        "unique",
    );
}

#[test]
fn solver_settings_must_be_positive() {
    assert_single_problem(|s| s.solver.step = 0.0, "solver.step", "0.0", "> 0");
    assert_single_problem(
        |s| s.solver.velocity_tolerance = -1e-7,
        "solver.velocity_tolerance",
        "-1e-7",
        "> 0",
    );
    assert_single_problem(
        |s| s.solver.gap_tolerance = 0.0,
        "solver.gap_tolerance",
        "0.0",
        "> 0",
    );
    assert_single_problem(
        |s| s.solver.max_iterations = 0,
        "solver.max_iterations",
        "0",
        "between 1 and 1000",
    );
    assert_single_problem(
        |s| s.solver.end_time = Some(-2.0),
        "solver.end_time",
        "-2.0",
        "> 0",
    );
}

#[test]
fn description_is_one_line() {
    assert_single_problem(
        |s| s.description = "two\nlines".into(),
        "description",
        "\"two\\nlines\"",
        "one line",
    );
}

#[test]
fn scene_name_is_usable_as_a_file_name() {
    assert_single_problem(|s| s.name = String::new(), "name", "\"\"", "non-empty");
    assert_single_problem(|s| s.name = "a/b".into(), "name", "\"a/b\"", "letters");
}

#[test]
fn every_problem_is_reported_each_on_its_own_line() {
    let mut scene = default_scene();
    scene.beam.bending_stiffness = -1e9;
    scene.vehicles[0].mass = 0.0;
    scene.solver.step = f64::NAN;
    scene.sensors[0].position = 30.0;
    let error = scene.validate().unwrap_err();
    let paths: Vec<String> = error.problems().into_iter().map(|p| p.path).collect();
    assert_eq!(
        paths,
        [
            "beam.bending_stiffness",
            "body.mass",
            "sensors[0].position",
            "solver.step"
        ]
    );
    let text = error.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 5, "{text}");
    assert!(lines[0].contains("4 problems"));
    assert_eq!(
        lines[1].trim(),
        "beam.bending_stiffness = -1000000000.0: must be > 0"
    );
    assert!(lines[4].contains("solver.step = NaN"));
}

// ---- parse errors ----

fn parse_error(text: &str) -> (String, String) {
    match Scene::from_toml_str(text) {
        Err(error @ SceneError::Parse { .. }) => {
            let SceneError::Parse { ref path, .. } = error else {
                unreachable!()
            };
            (path.clone(), error.to_string())
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// The default scene's TOML with `from` replaced by `to`.
fn edited_default(from: &str, to: &str) -> String {
    let text = default_scene().to_toml_string();
    assert!(text.contains(from), "{from:?} not in\n{text}");
    text.replacen(from, to, 1)
}

#[test]
fn unknown_field_is_named_with_its_path_and_line() {
    let text = edited_default("elements = 2", "elements = 2\nstiffnes = 3");
    let (path, message) = parse_error(&text);
    assert_eq!(path, "beam.stiffnes");
    assert!(
        message.contains("beam.stiffnes: unknown field"),
        "{message}"
    );
    assert!(message.contains("expected one of `length`"), "{message}");
    let line = text
        .lines()
        .position(|l| l.starts_with("stiffnes"))
        .unwrap()
        + 1;
    assert!(
        message.contains(&format!("line {line}, column 1")),
        "{message}"
    );
}

#[test]
fn unknown_top_level_and_sensor_fields_are_named() {
    let (path, _) = parse_error(&edited_default("[beam]", "colour = \"red\"\n[beam]"));
    assert_eq!(path, "colour");
    let (path, _) = parse_error(&edited_default(
        "position = 12.0",
        "position = 12.0\nunit = 1",
    ));
    assert_eq!(path, "sensors[0].unit");
}

#[test]
fn wrong_type_is_named_with_what_was_expected() {
    let (path, message) = parse_error(&edited_default("length = 24.0", "length = \"24 m\""));
    assert_eq!(path, "beam.length");
    assert!(
        message.contains("invalid type: string \"24 m\", expected a number"),
        "{message}"
    );

    let (path, message) = parse_error(&edited_default("elements = 2", "elements = 2.5"));
    assert_eq!(path, "beam.elements");
    assert!(message.contains("expected a whole number"), "{message}");

    let (path, message) = parse_error(&edited_default("elements = 2", "elements = -2"));
    assert_eq!(path, "beam.elements");
    assert!(message.contains("-2"), "{message}");
}

#[test]
fn missing_field_and_unknown_variant_are_named() {
    let (path, message) = parse_error(&edited_default("mass = 3000.0\n", ""));
    assert_eq!(path, "body.mass");
    assert!(message.contains("missing field"), "{message}");

    let (path, message) = parse_error(&edited_default("kind = \"wheel\"", "kind = \"tank\""));
    assert_eq!(path, "body.kind");
    assert!(
        message.contains("`wheel`, `glider`, `sprung_mass`"),
        "{message}"
    );

    let (path, message) = parse_error(&edited_default("left = \"pinned\"", "left = \"hinged\""));
    assert_eq!(path, "beam.supports.left");
    assert!(message.contains("`pinned`, `clamped`, `free`"), "{message}");
}

#[test]
fn malformed_toml_reports_its_location() {
    let (path, message) = parse_error("name = \"x\"\n[beam\n");
    assert_eq!(path, "");
    assert!(message.contains("line 2"), "{message}");
}

#[test]
fn parsed_scenes_are_validated() {
    let text = edited_default(
        "bending_stiffness = 1000000000.0",
        "bending_stiffness = -1.0",
    );
    match Scene::from_toml_str(&text) {
        Err(SceneError::Invalid { problems }) => {
            assert_eq!(problems.len(), 1);
            assert_eq!(problems[0].path, "beam.bending_stiffness");
        }
        other => panic!("expected an invalid scene, got {other:?}"),
    }
}

// ---- loading ----

#[test]
fn load_finds_builtins_and_files() {
    assert_eq!(
        Scene::load("lee1994-glider-30").unwrap().vehicles[0].kind,
        BodyKind::Glider
    );

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mine.toml");
    let mut scene = default_scene();
    scene.name = "mine".into();
    std::fs::write(&path, scene.to_toml_string()).unwrap();
    assert_eq!(Scene::load(path.to_str().unwrap()).unwrap(), scene);
}

#[test]
fn load_reports_missing_files_and_unknown_names() {
    match Scene::load("no/such/scene.toml") {
        Err(SceneError::Read { path, .. }) => assert_eq!(path, "no/such/scene.toml"),
        other => panic!("expected a read error, got {other:?}"),
    }
    let error = Scene::load("lee1994-wheel-7").unwrap_err();
    assert!(matches!(error, SceneError::NotFound { .. }));
    let message = error.to_string();
    assert!(message.contains("lee1994-wheel-7"), "{message}");
    assert!(
        message.contains("lee1994-wheel-10"),
        "lists the built-ins: {message}"
    );
    // Each built-in and template once.
    for (name, _) in builtins().iter().copied().chain(templates()) {
        let listed = message.matches(&format!("{name},")).count()
            + usize::from(message.ends_with(&format!("{name})")));
        assert_eq!(listed, 1, "{name} in {message}");
    }
}

#[test]
fn annotated_toml_reads_back_to_the_same_scene() {
    let mut scenes: Vec<Scene> = builtins()
        .iter()
        .map(|(n, _)| builtin(n).unwrap())
        .collect();
    let mut varied = default_scene();
    varied.solver.end_time = Some(0.25);
    varied.beam.supports.intermediate = vec![8.0, 16.5];
    varied.vehicles[0].force_x = 1.5e-4;
    varied.sensors.push(SensorSpec {
        name: "quarter".into(),
        position: 6.0,
    });
    scenes.push(varied);
    for scene in scenes {
        let text = scene.to_annotated_toml();
        let paper_beam = scene.beam.bending_stiffness == 1e9;
        assert!(
            !paper_beam || text.contains("bending_stiffness = 1e9"),
            "{text}"
        );
        assert!(text.contains("# N m^2, EI > 0"), "{text}");
        let reread = Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(reread, scene, "{text}");
    }
}

/// Issue 13: huge and subnormal values are refused in every real field,
/// naming the field and the magnitude limit.
#[test]
fn every_real_field_has_a_magnitude_limit() {
    type Edit = fn(&mut Scene, f64);
    let fields: [(&str, Edit); 15] = [
        ("beam.length", |s, x| s.beam.length = x),
        ("beam.mass_per_length", |s, x| s.beam.mass_per_length = x),
        ("beam.bending_stiffness", |s, x| {
            s.beam.bending_stiffness = x
        }),
        ("beam.surface_offset", |s, x| s.beam.surface_offset = x),
        ("body.mass", |s, x| s.vehicles[0].mass = x),
        ("body.inertia", |s, x| s.vehicles[0].inertia = Some(x)),
        ("body.radius", |s, x| s.vehicles[0].radius = Some(x)),
        ("body.initial_speed", |s, x| s.vehicles[0].initial_speed = x),
        ("body.force_x", |s, x| s.vehicles[0].force_x = x),
        ("body.force_y", |s, x| s.vehicles[0].force_y = x),
        ("solver.step", |s, x| s.solver.step = x),
        ("solver.velocity_tolerance", |s, x| {
            s.solver.velocity_tolerance = x
        }),
        ("solver.gap_tolerance", |s, x| s.solver.gap_tolerance = x),
        ("solver.end_time", |s, x| s.solver.end_time = Some(x)),
        ("body.initial_position", |s, x| {
            s.vehicles[0].initial_position = x
        }),
    ];
    for (path, edit) in fields {
        let problems = problems_after(|s| edit(s, 1e16));
        assert!(
            problems
                .iter()
                .any(|p| p.path == path && p.rule.contains("magnitude limit")),
            "{path}: {problems:#?}"
        );
    }
    let positive = ["beam.length", "body.mass", "body.radius", "solver.step"];
    for (path, edit) in fields.iter().filter(|(p, _)| positive.contains(p)) {
        let problems = problems_after(|s| edit(s, 5e-324));
        assert_eq!(problems.len(), 1, "{path}: {problems:#?}");
        assert!(problems[0].rule.contains(">= 1e-15"), "{}", problems[0]);
    }
    // at the limits, accepted
    let mut scene = default_scene();
    scene.vehicles[0].force_y = -MAX_MAGNITUDE;
    scene.solver.gap_tolerance = MIN_MAGNITUDE;
    scene.validate().unwrap();
}

#[test]
fn names_and_text_have_length_limits_and_xml_legal_characters() {
    let long = "a".repeat(MAX_NAME_CHARS + 1);
    assert_single_problem(
        |s| s.vehicles[0].name = long.clone(),
        "body.name",
        "\"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\"... (65 characters)",
        "more than the limit of 64",
    );
    let mut scene = default_scene();
    scene.name = "a".repeat(MAX_NAME_CHARS);
    scene.validate().unwrap();
    assert_single_problem(
        |s| s.description = "bell \u{7}".into(),
        "description",
        "\"bell \\u{7}\"",
        "character 5 is U+0007, which XML 1.0 cannot carry",
    );
    assert!(!is_xml_char('\u{FFFF}') && is_xml_char('\t') && is_xml_char('😀'));
    let problems = problems_after(|s| {
        s.sensors = (0..=MAX_SENSORS)
            .map(|i| SensorSpec {
                name: format!("s{i}"),
                position: -1.0,
            })
            .collect()
    });
    assert_eq!(problems.len(), 1, "one problem, not 10 001");
    assert_eq!(
        problems[0].to_string(),
        "sensors = 10001 sensors: must hold at most 10000"
    );
}

#[test]
fn a_long_list_of_problems_is_cut_in_the_message() {
    let problems = problems_after(|s| {
        s.sensors = (0..200)
            .map(|_| SensorSpec {
                name: "a b".into(),
                position: 1.0,
            })
            .collect()
    });
    let message = SceneError::Invalid { problems }.to_string();
    assert!(message.starts_with("scene is not valid (200 problems):"));
    assert!(message.ends_with("... and 150 more"), "{message}");
    assert_eq!(message.lines().count(), 52);
}

#[test]
fn sprung_mass_needs_its_suspension_and_others_refuse_one() {
    let mut scene = default_scene();
    scene.vehicles[0].kind = BodyKind::SprungMass;
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("body.suspension"), "{problems}");
    scene.vehicles[0].suspension = Some(crate::scene::SuspensionSpec {
        stiffness: 1e6,
        damping: -1.0,
        unsprung_mass: 50.0,
    });
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("body.suspension.damping"), "{problems}");
    assert_single_problem(
        |s| {
            s.vehicles[0].suspension = Some(crate::scene::SuspensionSpec {
                stiffness: 1e6,
                damping: 0.0,
                unsprung_mass: 50.0,
            })
        },
        "body.suspension",
        "present",
        "sprung_mass",
    );
}

fn bogie() -> crate::scene::BogieSpec {
    crate::scene::BogieSpec {
        car_inertia: 1.95e6,
        bogie_mass: 2400.0,
        bogie_inertia: 3200.0,
        wheelset_mass: 1400.0,
        bogie_half_distance: 8.75,
        axle_half_distance: 1.25,
        primary_stiffness: 1.18e6,
        primary_damping: 0.0,
        secondary_stiffness: 5.3e5,
        secondary_damping: 0.0,
        wheel_radius: None,
        wheelset_inertia: None,
    }
}

#[test]
fn bogie_vehicle_needs_its_bogie_and_others_refuse_one() {
    let mut scene = default_scene();
    scene.vehicles[0].kind = BodyKind::BogieVehicle;
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("body.bogie"), "{problems}");
    assert!(problems.contains("missing"), "{problems}");
    scene.vehicles[0].initial_position = scene.beam.length / 2.0;
    scene.vehicles[0].bogie = Some(bogie());
    // Wheelsets at 12 ± 10 m on the 24 m beam.
    scene.validate().expect("a valid bogie vehicle");
    let mut bad = bogie();
    bad.primary_damping = -1.0;
    bad.bogie_half_distance = 1.0;
    scene.vehicles[0].bogie = Some(bad);
    let problems = scene.validate().unwrap_err().to_string();
    assert!(
        problems.contains("body.bogie.primary_damping"),
        "{problems}"
    );
    assert!(
        problems.contains("body.bogie.bogie_half_distance"),
        "{problems}"
    );
    assert!(problems.contains("axle_half_distance = 1.25"), "{problems}");
    assert_single_problem(
        |s| s.vehicles[0].bogie = Some(bogie()),
        "body.bogie",
        "present",
        "bogie_vehicle",
    );
}

#[test]
fn bogie_vehicle_wheelsets_must_start_on_the_track() {
    let mut scene = default_scene();
    scene.vehicles[0].kind = BodyKind::BogieVehicle;
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    scene.vehicles[0].bogie = Some(bogie());
    scene.vehicles[0].initial_position = 0.0;
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("body.initial_position"), "{problems}");
    assert!(problems.contains("off the track"), "{problems}");
}

#[test]
fn gravity_and_track_lengths_are_checked() {
    assert_single_problem(|s| s.gravity = -9.81, "gravity", "-9.81", ">= 0");
    assert_single_problem(
        |s| s.track.run_off = f64::NAN,
        "track.run_off",
        "NaN",
        "finite",
    );
    assert_single_problem(
        |s| {
            s.beam.supports.right = EndSupport::Free;
            s.beam.supports.left = EndSupport::Clamped;
            s.track.run_off = 5.0;
        },
        "track.run_off",
        "5.0",
        "free beam end",
    );
    // With an approach, a body may start on it.
    let mut scene = default_scene();
    scene.track.approach = 10.0;
    scene.vehicles[0].initial_position = -10.0;
    scene.validate().unwrap();
    scene.vehicles[0].initial_position = -10.5;
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("-track.approach = -10.0"), "{problems}");
}

#[test]
fn damping_is_validated_field_by_field() {
    let damp = |d: DampingSpec| move |s: &mut Scene| s.beam.damping = Some(d);
    assert_single_problem(
        damp(DampingSpec::Coefficients {
            alpha: -0.1,
            beta: 0.0,
        }),
        "beam.damping.alpha",
        "-0.1",
        ">= 0",
    );
    assert_single_problem(
        damp(DampingSpec::Modes {
            ratio: 0.02,
            modes: [2, 2],
        }),
        "beam.damping.modes",
        "[2, 2]",
        "two different mode numbers",
    );
    assert_single_problem(
        damp(DampingSpec::Frequencies {
            ratios: [0.05, 0.001],
            frequencies: [1.0, 10.0],
        }),
        "beam.damping.ratios",
        "[0.05, 0.001]",
        "negative Rayleigh coefficients",
    );
}

#[test]
fn damping_round_trips_through_toml_in_each_shape() {
    for damping in [
        DampingSpec::Coefficients {
            alpha: 0.5,
            beta: 2.5e-4,
        },
        DampingSpec::Modes {
            ratio: 0.02,
            modes: [1, 3],
        },
        DampingSpec::Frequencies {
            ratios: [0.01, 0.02],
            frequencies: [2.0, 20.0],
        },
    ] {
        let mut scene = default_scene();
        scene.beam.damping = Some(damping);
        scene.validate().unwrap();
        let reread = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
        assert_eq!(reread, scene);
    }
}

/// A valid bogie vehicle at midspan of the default beam.
fn bogie_scene(edit: impl FnOnce(&mut crate::scene::BogieSpec)) -> Scene {
    let mut scene = default_scene();
    scene.vehicles[0].kind = BodyKind::BogieVehicle;
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    scene.vehicles[0].initial_position = scene.beam.length / 2.0;
    let mut b = bogie();
    edit(&mut b);
    scene.vehicles[0].bogie = Some(b);
    scene
}

#[test]
fn wheel_wheelsets_need_radius_and_inertia_together() {
    bogie_scene(|b| {
        b.wheel_radius = Some(0.45);
        b.wheelset_inertia = Some(700.0);
    })
    .validate()
    .expect("wheel wheelsets");
    for (radius, inertia, path, value) in [
        (Some(0.45), None, "body.bogie.wheelset_inertia", "missing"),
        (None, Some(700.0), "body.bogie.wheel_radius", "missing"),
        (Some(-0.45), Some(700.0), "body.bogie.wheel_radius", "-0.45"),
        (Some(0.45), Some(0.0), "body.bogie.wheelset_inertia", "0"),
    ] {
        let scene = bogie_scene(|b| {
            b.wheel_radius = radius;
            b.wheelset_inertia = inertia;
        });
        let problems = scene.validate().unwrap_err().to_string();
        assert!(problems.contains(path), "{problems}");
        assert!(problems.contains(value), "{problems}");
    }
}

fn maglev() -> crate::scene::MaglevSpec {
    crate::scene::MaglevSpec {
        car_inertia: 1.5e6,
        magnets: 4,
        magnet_spacing: 3.0,
        magnet_mass: 600.0,
        stiffness: 8e5,
        damping: 0.0,
    }
}

#[test]
fn maglev_vehicle_needs_its_magnets_on_the_track() {
    let mut scene = default_scene();
    scene.vehicles[0].kind = BodyKind::MaglevVehicle;
    scene.vehicles[0].inertia = None;
    scene.vehicles[0].radius = None;
    scene.vehicles[0].initial_position = 12.0;
    let problems = scene.validate().unwrap_err().to_string();
    assert!(problems.contains("body.maglev"), "{problems}");
    scene.vehicles[0].maglev = Some(maglev());
    scene.validate().expect("a valid maglev vehicle");
    for (edit, path, value) in [
        (
            (|m: &mut crate::scene::MaglevSpec| m.magnets = 0) as fn(&mut _),
            "body.maglev.magnets",
            "0",
        ),
        (
            |m| m.magnet_spacing = -3.0,
            "body.maglev.magnet_spacing",
            "-3",
        ),
        (|m| m.damping = -1.0, "body.maglev.damping", "-1"),
        // Magnets at 12 ± 15 m leave the 24 m beam.
        (|m| m.magnets = 11, "body.initial_position", "12"),
    ] {
        let mut m = maglev();
        edit(&mut m);
        scene.vehicles[0].maglev = Some(m);
        let problems = scene.validate().unwrap_err().to_string();
        assert!(problems.contains(path), "{problems}");
        assert!(problems.contains(value), "{problems}");
    }
    assert_single_problem(
        |s| s.vehicles[0].maglev = Some(maglev()),
        "body.maglev",
        "present",
        "maglev_vehicle",
    );
}

// ---- issue 12: couplings ------------------------------------------------------------

#[test]
fn couplings_must_name_bodies_of_the_scene_once() {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.couplings = vec!["wheel".into()];
    scene.validate().unwrap();
    scene.couplings = vec!["wheel".into(), "lorry".into(), "wheel".into()];
    let text = scene.validate().unwrap_err().to_string();
    assert!(
        text.contains("couplings[1] = \"lorry\": must name a body of the scene (one of wheel)"),
        "{text}"
    );
    assert!(
        text.contains("couplings[2] = \"wheel\": must be unique"),
        "{text}"
    );
}

#[test]
fn body_names_are_the_assembled_systems() {
    let wheel = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut sprung = Scene::lee1994(BodyKind::SprungMass, 10.0, 0.0025);
    sprung.vehicles[0].name = "car".into();
    sprung.vehicles[0].suspension = Some(SuspensionSpec {
        stiffness: 1e6,
        damping: 0.0,
        unsprung_mass: 50.0,
    });
    let mut bogie = Scene::lee1994(BodyKind::BogieVehicle, 10.0, 0.0025);
    bogie.vehicles[0].name = "coach".into();
    bogie.vehicles[0].initial_position = 12.0;
    bogie.vehicles[0].bogie = Some(BogieSpec {
        car_inertia: 1e6,
        bogie_mass: 2000.0,
        bogie_inertia: 3000.0,
        wheelset_mass: 1000.0,
        bogie_half_distance: 5.0,
        axle_half_distance: 1.0,
        primary_stiffness: 1e6,
        primary_damping: 0.0,
        secondary_stiffness: 5e5,
        secondary_damping: 0.0,
        wheel_radius: None,
        wheelset_inertia: None,
    });
    for scene in [wheel, sprung, bogie] {
        scene.validate().unwrap();
        let system = crate::assemble::assemble(&scene).unwrap().system;
        let assembled: Vec<String> = system.bodies.iter().map(|b| b.name.clone()).collect();
        assert_eq!(scene.body_names(), assembled);
    }
}

#[test]
fn a_shaped_force_profile_is_refused_with_hht_and_kept_with_auto() {
    assert_single_problem(
        |s| {
            s.solver.integrator = IntegratorKind::Hht;
            s.solver.force_profile = ForceProfile::Quadratic;
        },
        "solver.force_profile",
        "quadratic",
        "HHT-α",
    );
    let mut scene = default_scene();
    scene.solver.integrator = IntegratorKind::Auto;
    scene.solver.force_profile = ForceProfile::Linear;
    scene.validate().unwrap();
}

/// A file's `[body]` is vehicle 0 of the one list, each `[[vehicles]]`
/// entry the next (issue 23); the scene writes back the same blocks, and
/// a scene without vehicles is refused at `body`.
#[test]
fn the_body_block_is_vehicle_zero_of_one_list() {
    let mut scene = default_scene();
    let mut second = scene.vehicles[0].clone();
    second.name = "second".into();
    second.initial_position = 6.0;
    scene.vehicles.push(second);
    let text = scene.to_toml_string();
    assert_eq!(text.matches("[body]").count(), 1, "{text}");
    assert_eq!(text.matches("[[vehicles]]").count(), 1, "{text}");
    let body_at = text.find("[body]").unwrap();
    assert!(text[body_at..].contains(&format!("name = \"{}\"", scene.vehicles[0].name)));
    let reread = Scene::from_toml_str(&text).unwrap();
    assert_eq!(reread, scene);
    let names: Vec<&str> = reread.vehicles.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, [scene.vehicles[0].name.as_str(), "second"]);
    assert_single_problem(|s| s.vehicles.clear(), "body", "missing", "needs a vehicle");
}
