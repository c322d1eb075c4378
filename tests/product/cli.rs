//! The `guideway` binary, run as a user would.

use crate::common;
use common::cli::{guideway, refusal, stderr, stdout};
use guideway::scene::{builtin, builtins};
use guideway::Scene;
use std::path::Path;
use std::process::Command;

#[test]
fn scenes_lists_every_builtin_with_its_description() {
    let output = guideway(&["scenes"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for (name, description) in builtins() {
        let line = text
            .lines()
            .find(|line| line.starts_with(name) && line.contains(description))
            .unwrap_or_else(|| panic!("{name} not listed in\n{text}"));
        assert!(line.len() > name.len());
    }
}

#[test]
fn scenes_show_prints_a_loadable_scene_file() {
    for (name, _) in builtins() {
        let output = guideway(&["scenes", "--show", name]);
        assert!(output.status.success(), "{}", stderr(&output));
        let scene = Scene::from_toml_str(&stdout(&output)).unwrap();
        assert_eq!(Some(scene), builtin(name));
    }
}

#[test]
fn scenes_takes_the_name_as_run_does_or_with_show_but_not_both() {
    let shown = guideway(&["scenes", "--show", "lee1994-glider-30"]);
    let named = guideway(&["scenes", "lee1994-glider-30"]);
    assert!(named.status.success(), "{}", stderr(&named));
    assert_eq!(stdout(&named), stdout(&shown));
    let both = guideway(&["scenes", "lee1994-wheel-10", "--show", "lee1994-glider-30"]);
    assert_eq!(both.status.code(), Some(2));
    assert!(stderr(&both).contains("--show"), "{}", stderr(&both));
    let unknown = guideway(&["scenes", "lee1994-wheel-7"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(
        stderr(&unknown).contains("lee1994-glider-30"),
        "{}",
        stderr(&unknown)
    );
}

#[test]
fn scenes_show_of_an_unknown_name_lists_the_builtins() {
    let output = guideway(&["scenes", "--show", "lee1994-wheel-7"]);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("lee1994-wheel-7"), "{message}");
    assert!(message.contains("lee1994-glider-30"), "{message}");
}

/// The default scene's TOML with `from` replaced by `to`, written to a file.
fn edited_scene_file(dir: &Path, from: &str, to: &str) -> String {
    let text = builtin("lee1994-wheel-10").unwrap().to_toml_string();
    assert!(text.contains(from));
    let path = dir.join("edited.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn a_bad_scene_lists_every_problem_and_exits_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(
        dir.path(),
        "bending_stiffness = 1000000000.0\nsurface_offset = 0.6\nelements = 2",
        "bending_stiffness = -5.0\nsurface_offset = 0.6\nelements = 0",
    );
    let never = dir.path().join("never.csv");
    let output = guideway(&["run", &file, "--out", never.to_str().unwrap(), "--quiet"]);
    let message = refusal(&output, "");
    assert!(
        message.contains("beam.bending_stiffness = -5.0: must be > 0"),
        "{message}"
    );
    assert!(
        message.contains("beam.elements = 0: must be >= 1"),
        "{message}"
    );
    assert!(
        message.contains("edited.toml: scene is not valid (2 problems)"),
        "{message}"
    );
    assert!(!message.contains("panicked"), "{message}");
    assert!(!never.exists(), "nothing is written for a bad scene");
}

#[test]
fn an_unknown_field_is_named_and_exits_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "mass = 3000.0", "mass = 3000.0\nmas = 1.0");
    let output = guideway(&["run", &file]);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("body.mas: unknown field"), "{message}");
}

#[test]
fn a_wrong_type_is_named_and_exits_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "step = 0.0025", "step = \"fast\"");
    let output = guideway(&["scenes", "--show", &file]);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(message.contains("solver.step: invalid type"), "{message}");
}

#[test]
fn a_run_that_could_never_end_is_refused_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "initial_speed = 10.0", "initial_speed = 0.0");
    let output = guideway(&["run", &file, "--quiet"]);
    let message = refusal(&output, "");
    assert!(message.contains("body.initial_speed = 0.0"), "{message}");
    assert!(message.contains("solver.end_time"), "{message}");
}

#[test]
fn a_step_beyond_the_stability_limit_is_refused_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "elements = 2", "elements = 128");
    let output = guideway(&["run", &file, "--quiet"]);
    let message = refusal(&output, "");
    assert!(message.contains("cannot be simulated"), "{message}");
    assert!(message.contains("solver.step"), "{message}");
}

#[test]
fn an_output_into_a_missing_directory_fails_before_the_run() {
    let output = guideway(&["run", "--summary", "no/such/dir/summary.json"]);
    assert_eq!(output.status.code(), Some(1));
    let message = stderr(&output);
    assert!(
        message.contains("cannot write no/such/dir/summary.json"),
        "{message}"
    );
    assert!(
        stdout(&output).is_empty(),
        "nothing ran: {}",
        stdout(&output)
    );
}

#[test]
fn a_solver_failure_exits_with_1_and_keeps_the_steps_before_it() {
    // One contact iteration per stage cannot reach the velocity tolerance:
    // the solver stops with a diagnostic.
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "max_iterations = 50", "max_iterations = 1");
    let csv = dir.path().join("partial.csv");
    let output = guideway(&["run", &file, "--out", csv.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let message = stderr(&output);
    assert!(message.contains("the solver failed at t = "), "{message}");
    // Kept apart from the path asked for, which only a finished run fills.
    assert!(message.contains("partial.csv.incomplete"), "{message}");
    assert!(!csv.exists());
    let text = std::fs::read_to_string(dir.path().join("partial.csv.incomplete")).unwrap();
    assert!(text.starts_with("time,"), "{text}");
    assert!(
        text.lines().count() >= 2,
        "header and initial state: {text}"
    );
}

#[test]
fn a_missing_scene_file_exits_with_2() {
    let output = guideway(&["run", "no/such/scene.toml"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("cannot read scene file `no/such/scene.toml`"));
}

#[test]
fn run_of_the_default_scene_writes_csv_summary_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("results.csv");
    let summary = dir.path().join("summary.json");
    let plot = dir.path().join("results.png");
    let output = guideway(&[
        "run",
        "--out",
        csv.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("exit speed V"),
        "{}",
        stdout(&output)
    );

    let csv = std::fs::read_to_string(csv).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "time");
    for name in [
        "wheel.nominal_speed",
        "sensor.midspan.deflection",
        "energy.balance",
    ] {
        assert!(header.contains(&name), "{name} not in {header:?}");
    }
    let times: Vec<f64> = lines
        .map(|line| line.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times[0], 0.0);
    assert_eq!(times[1], 0.0025);
    assert!(times.windows(2).all(|w| w[1] > w[0]), "times increase");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(summary).unwrap()).unwrap();
    assert_eq!(summary["scene"], "lee1994-wheel-10");
    assert_eq!(summary["steps"].as_u64().unwrap() as usize, times.len() - 1);
    assert_eq!(
        summary["exit_time"].as_f64().unwrap(),
        *times.last().unwrap()
    );
    let exit_speed = summary["exit_nominal_speed"].as_f64().unwrap();
    assert!((exit_speed - 9.96).abs() < 0.01, "exit speed {exit_speed}");
    assert!(
        summary["peak_sensor_deflection"]["midspan"]
            .as_f64()
            .unwrap()
            < 0.0
    );
    assert!(summary["max_energy_drift"].as_f64().unwrap() < 2.9e-5);
    assert!(summary["iterations"].as_u64().unwrap() >= summary["steps"].as_u64().unwrap());
    assert!(summary["wall_time_s"].as_f64().unwrap() > 0.0);

    let png = std::fs::read(plot).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
}

#[test]
fn export_writes_an_fmu_and_the_cross_check_files() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("glider.fmu");
    let cross_check = dir.path().join("cross-check");
    // `cargo test` builds the cdylib next to the test binaries, in deps/,
    // not next to the guideway binary where `export` looks by default.
    let cdylib = guideway::fmu::default_cdylib().expect("the cdylib is built with the tests");
    let output = Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args([
            "export",
            "lee1994-glider-30",
            "-o",
            fmu.to_str().unwrap(),
            "--cross-check",
            cross_check.to_str().unwrap(),
        ])
        .env("GUIDEWAY_CDYLIB", cdylib)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("lee1994_glider_30"),
        "{}",
        stdout(&output)
    );
    let bytes = std::fs::read(&fmu).unwrap();
    assert!(bytes.starts_with(b"PK\x03\x04"), "an FMU is a zip archive");
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("modelDescription.xml").unwrap(), &mut xml)
        .unwrap();
    guideway::fmu::check_well_formed(&xml).expect("modelDescription.xml is well-formed");
    for file in ["lee1994_glider_30_ref.csv", "lee1994_glider_30_ref.opt"] {
        assert!(cross_check.join(file).is_file(), "{file} missing");
    }
}

#[test]
fn export_of_a_bad_scene_exits_with_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_scene_file(dir.path(), "mass = 3000.0", "mass = -3000.0");
    let fmu = dir.path().join("bad.fmu");
    let output = guideway(&["export", &file, "-o", fmu.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("body.mass = -3000.0: must be > 0"));
    assert!(!fmu.exists());
}

#[test]
fn modes_prints_the_frequencies_and_writes_the_shapes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = edited_scene_file(dir.path(), "elements = 2", "elements = 20");
    let csv = dir.path().join("modes.csv");
    let output = guideway(&[
        "modes",
        &scene,
        "--count",
        "3",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    // Simply supported: f_n = n² π / (2 L²) √(EI / ρA).
    let f1 = std::f64::consts::PI / (2.0 * 24.0 * 24.0) * (1e9f64 / 1250.0).sqrt();
    let printed: Vec<f64> = stdout(&output)
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1)?.parse().ok())
        .collect();
    assert_eq!(printed.len(), 3, "{}", stdout(&output));
    for (n, f) in printed.iter().enumerate() {
        let exact = f1 * ((n + 1) * (n + 1)) as f64;
        assert!(
            (f / exact - 1.0).abs() < 1e-4,
            "mode {}: {f} vs {exact}",
            n + 1
        );
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("x,mode_1,mode_2,mode_3\n"));
    // A header and the 21 nodes.
    assert_eq!(text.lines().count(), 22);
}

#[test]
fn run_prints_the_natural_frequencies_or_why_not() {
    let dir = tempfile::tempdir().unwrap();
    // 20 elements (HHT for the step): the first five f_n = n² f₁ to 1e-3.
    let scene = edited_scene_file(dir.path(), "elements = 2", "elements = 20");
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(
        text.contains("integrator = \"rk4\"")
            && text.trim_end().ends_with("numerical_damping = 0.0")
    );
    std::fs::write(
        &scene,
        text.replace("integrator = \"rk4\"", "integrator = \"hht\""),
    )
    .unwrap();
    let output = guideway(&["run", &scene]);
    assert!(output.status.success(), "{}", stderr(&output));
    let out = stdout(&output);
    let line = out
        .lines()
        .find(|l| l.starts_with("frequencies (Hz)"))
        .unwrap_or_else(|| panic!("{out}"));
    let hz: Vec<f64> = line["frequencies (Hz)".len()..]
        .split(" (")
        .next()
        .unwrap()
        .split(',')
        .map(|f| f.trim().parse().unwrap())
        .collect();
    assert_eq!(hz.len(), 5, "{line}");
    let f1 = std::f64::consts::PI / (2.0 * 24.0 * 24.0) * (1e9f64 / 1250.0).sqrt();
    for (n, f) in hz.iter().enumerate() {
        let exact = f1 * ((n + 1) * (n + 1)) as f64;
        assert!(
            (f / exact - 1.0).abs() < 1e-3,
            "mode {}: {f} vs {exact}",
            n + 1
        );
    }

    // 400 elements: 800 free DOFs, beyond the 600 a run prints them for.
    let big = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("elements = 20", "elements = 400")
        .replace("name = \"lee1994-wheel-10\"", "name = \"big\"");
    std::fs::write(&scene, big.trim_end().to_string() + "\nend_time = 0.01\n").unwrap();
    let output = guideway(&["run", &scene]);
    assert!(output.status.success(), "{}", stderr(&output));
    let out = stdout(&output);
    assert!(
        out.lines()
            .any(|l| l.starts_with("frequencies        - (the beam has 800 free DOFs")),
        "{out}"
    );
}
