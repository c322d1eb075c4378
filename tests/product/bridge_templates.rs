//! The bridge templates (issue 26 item 8): the shipped `scenes/` files a
//! bridge engineer starts from are built-ins, listed by `guideway scenes`,
//! shown by `--show`, and they run (the sweep template with `sweep`).

use crate::common;
use common::cli::guideway_ok;
use guideway::scene::{builtin, builtins, template_file, templates, Scene};

#[test]
fn each_template_is_the_shipped_file_and_is_listed() {
    let listing = String::from_utf8(guideway_ok(&["scenes"]).stdout).expect("UTF-8");
    let mut count = 0;
    for (name, description) in templates() {
        let file = format!(
            "{}/{}",
            env!("CARGO_MANIFEST_DIR"),
            template_file(name).expect("a template's file")
        );
        assert!(
            builtins().iter().any(|(b, _)| *b == name),
            "{name} built in"
        );
        let mut shipped = Scene::load(&file).expect("shipped scene loads");
        // (named and described as listed)
        shipped.name = name.to_string();
        shipped.description = description.to_string();
        assert_eq!(builtin(name), Some(shipped), "{name}");
        assert!(
            listing.lines().any(|l| l.starts_with(name)),
            "{name} listed"
        );
        let shown = String::from_utf8(guideway_ok(&["scenes", "--show", name]).stdout).unwrap();
        assert_eq!(
            Scene::from_toml_str(&shown).expect("shown scene reads"),
            builtin(name).unwrap()
        );
        count += 1;
    }
    assert!(count >= 2);
}

#[test]
fn the_hslm_template_sweeps_by_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("sweep.csv");
    let out = out.to_str().unwrap();
    guideway_ok(&[
        "sweep",
        "bridge25-hslm",
        "--speeds",
        "50:60:10",
        "--out",
        out,
    ]);
    let rows = std::fs::read_to_string(out).expect("CSV").lines().count();
    assert_eq!(rows, 3, "a header and one row per speed");
}

#[test]
fn the_train_template_runs_by_name_past_the_span() {
    let dir = tempfile::tempdir().expect("temp dir");
    let summary = dir.path().join("summary.json");
    let summary = summary.to_str().unwrap();
    let csv = dir.path().join("run.csv");
    let name = "train-8-coaches-20m-300-hertz";
    guideway_ok(&[
        "run",
        name,
        "-q",
        "--summary",
        summary,
        "--out",
        csv.to_str().unwrap(),
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(summary).unwrap()).unwrap();
    // The last wheelset leaves the 20 m span no sooner than the span's
    // length at the nominal 300 km/h after the start.
    let exit = json["exit_time"]
        .as_f64()
        .expect("the train leaves the span");
    assert!(exit >= 20.0 / (300.0 / 3.6), "exit at {exit} s");
}

/// Its former name (the file's) still loads it.
#[test]
fn the_hslm_template_keeps_its_former_name() {
    let (mut former, now) = (
        builtin("bridge25_hslm").unwrap(),
        builtin("bridge25-hslm").unwrap(),
    );
    assert_eq!(former.name, "bridge25_hslm");
    former.name = now.name.clone();
    former.description = now.description.clone();
    assert_eq!(former, now);
}

/// `guideway run` of the moving-force template from the binary alone.
#[test]
fn the_hslm_template_runs_by_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("run.csv");
    guideway_ok(&["run", "bridge25-hslm", "-q", "--out", csv.to_str().unwrap()]);
    let text = std::fs::read_to_string(csv).expect("CSV");
    assert!(text
        .lines()
        .next()
        .unwrap()
        .contains("sensor.midspan.deflection"));
    assert!(
        text.lines().count() > 1000,
        "a row per step of the crossing"
    );
}
