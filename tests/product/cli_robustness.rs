//! Issue 13's defects of `guideway run` and `guideway export`, each run as a
//! user (or an attacker) would: bounded work and memory, Ctrl-C, non-finite
//! values, XML-illegal text, name and size limits, output files, exit codes.

use crate::common;
use common::cli::{arg, guideway, refusal, stderr};
use common::model_description;
use guideway::scene::builtin;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

fn default_toml() -> String {
    builtin("lee1994-wheel-10").unwrap().to_toml_string()
}

/// The default scene with `from` replaced by `to`, written to `dir/name`.
fn scene_file(dir: &Path, name: &str, from: &str, to: &str) -> String {
    let text = default_toml();
    assert!(text.contains(from), "{from} not in\n{text}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_str().unwrap().to_string()
}

// ---- 1: bounded work and memory, Ctrl-C -------------------------------------------

#[test]
fn a_run_needing_more_steps_than_the_limit_is_refused_before_running() {
    // The default scene takes 910 steps; its stop time if it never left
    // the beam, 10 × 24 m / 10 m/s, is 9600 steps.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("r.csv");
    let output = guideway(&["run", "--max-steps", "100", "--out", arg(&csv), "--quiet"]);
    let message = refusal(&output, "");
    assert!(
        message.contains("more than the limit of 100 steps"),
        "{message}"
    );
    assert!(message.contains("--max-steps"), "{message}");
    assert!(!csv.exists());
    let output = guideway(&["run", "--max-steps", "9600", "--quiet"]);
    assert!(output.status.success(), "{}", stderr(&output));
}

#[test]
fn speeds_that_never_reach_the_exit_are_refused_naming_the_steps() {
    let dir = tempfile::tempdir().unwrap();
    for speed in ["5e-324", "1e-300", "1e-30", "1e-3"] {
        let file = scene_file(
            dir.path(),
            "slow.toml",
            "initial_speed = 10.0",
            &format!("initial_speed = {speed}"),
        );
        // (the explicit default makes a binary without the limit fail at
        // once instead of running for ever)
        let output = guideway(&["run", &file, "--max-steps", "1000000", "--quiet"]);
        let message = refusal(&output, speed);
        assert!(
            message.contains("limit of 1000000 steps") || message.contains("magnitude limit"),
            "{speed}: {message}"
        );
    }
}

#[test]
fn a_stop_time_below_the_time_resolution_is_refused_not_run_for_nothing() {
    // 10 × 24 m / 1e14 m/s = 2.4e-12 s, below 1e-9 of the step: on main the
    // run took no real step and exited 0.
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "fast.toml",
        "initial_speed = 10.0",
        "initial_speed = 1e14",
    );
    let output = guideway(&["run", &file, "--quiet"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("no step would be taken"),
        "{}",
        stderr(&output)
    );
}

/// Exit code and peak resident memory (kB) of the guideway binary: the
/// largest VmHWM read from /proc while it runs. (`wait4`'s ru_maxrss would
/// include the test process's own memory, which the child shares until
/// its exec.)
fn run_measuring_memory(args: &[&str]) -> (Option<i32>, i64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    let status = loop {
        let hwm = std::fs::read_to_string(&status_file).ok().and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
            line.split_whitespace().nth(1)?.parse::<i64>().ok()
        });
        peak = peak.max(hwm.unwrap_or(0));
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    };
    (status.code(), peak)
}

/// Peak memory (kB) of a run of the wheel at rest on the support until
/// `end` s (400 rows a second), with `extra` arguments.
fn peak_memory_at_rest(dir: &Path, end: &str, extra: &[&str]) -> i64 {
    let file = scene_file(
        dir,
        &format!("rest{end}.toml"),
        "initial_speed = 10.0",
        "initial_speed = 0.0",
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let text = text.replace("[solver]\n", &format!("[solver]\nend_time = {end}\n"));
    std::fs::write(&file, text).unwrap();
    let csv = dir.join(format!("rest{end}.csv"));
    let mut args = vec!["run", &file, "--out", arg(&csv), "--quiet"];
    args.extend(extra);
    let (code, kb) = run_measuring_memory(&args);
    assert_eq!(code, Some(0));
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    let steps: f64 = end.parse::<f64>().unwrap() * 400.0;
    assert_eq!(
        rows,
        steps as usize + 2,
        "header, initial state, every step"
    );
    kb
}

#[test]
fn memory_does_not_grow_with_the_length_of_the_run() {
    // Kept in memory, 100 000 more rows of 21 outputs are 17 MB more. (Both
    // runs are long enough for their memory to be sampled while they run.)
    let dir = tempfile::tempdir().unwrap();
    let long = peak_memory_at_rest(dir.path(), "250", &[]);
    let longer = peak_memory_at_rest(dir.path(), "500", &[]);
    assert!(long > 0, "sampled");
    assert!(
        longer < long + 5_000,
        "peak {long} kB for 100 000 rows, {longer} kB for 200 000"
    );
    // The plot keeps a thinned copy of bounded size: once the run is
    // longer than that bound, doubling it costs nothing.
    let plot = dir.path().join("p.png");
    let long = peak_memory_at_rest(dir.path(), "250", &["--plot", arg(&plot)]);
    let longer = peak_memory_at_rest(dir.path(), "500", &["--plot", arg(&plot)]);
    assert!(
        longer < long + 5_000,
        "peak {long} kB for 100 000 rows, {longer} kB for 200 000"
    );
}

#[test]
fn ctrl_c_keeps_the_rows_written_so_far_marked_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "long.toml",
        "initial_speed = 10.0",
        "initial_speed = 0.0",
    );
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replace("[solver]\n", "[solver]\nend_time = 2000.0\n"),
    )
    .unwrap();
    let csv = dir.path().join("r.csv");
    std::fs::write(&csv, "the previous results\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args([
            "run",
            &file,
            "--out",
            arg(&csv),
            "--max-steps",
            "1000000",
            "--quiet",
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The staged CSV appears once the handler is installed; wait until it
    // holds more than the 1000 rows asserted below, then interrupt. The
    // run stops at the next step (the handler only sets a flag), so what
    // is on disk now is kept. (Counted in lines, not bytes: a row's width
    // grows with the catalogue of outputs.)
    let rows_on_disk = |path: &std::path::Path| {
        std::fs::read(path).map_or(0, |bytes| bytes.iter().filter(|&&b| b == b'\n').count())
    };
    let staged = loop {
        let found = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(Result::ok)
            .find(|e| {
                e.file_name().to_string_lossy().starts_with(".r.csv.")
                    && rows_on_disk(&e.path()) > 1001
            });
        if let Some(entry) = found {
            break entry.path();
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before Ctrl-C"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    // SAFETY: sending SIGINT to our own child.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let status = child.wait().unwrap();
    let mut message = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut message)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{message}");
    assert!(message.contains("interrupted"), "{message}");
    assert!(message.contains("r.csv.incomplete"), "{message}");
    assert!(!staged.exists(), "the staged file was moved");
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        "the previous results\n"
    );
    let incomplete = std::fs::read_to_string(dir.path().join("r.csv.incomplete")).unwrap();
    let lines: Vec<&str> = incomplete.lines().collect();
    assert!(lines[0].starts_with("time,"));
    assert!(lines.len() > 1000, "{} lines", lines.len());
    // whole rows only: every line has as many fields as the header
    let fields = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == fields));
}

// ---- 5: non-finite values ------------------------------------------------------------

#[test]
fn values_that_overflow_an_output_are_refused_as_the_fmu_refuses_them() {
    let dir = tempfile::tempdir().unwrap();
    for (from, to, field) in [
        ("inertia = 135.0", "inertia = 1e308", "body.inertia"),
        ("radius = 0.3", "radius = 1e-300", "body.radius"),
        (
            "initial_speed = 10.0",
            "initial_speed = 2e218",
            "body.initial_speed",
        ),
        (
            "initial_speed = 10.0",
            "initial_speed = 1e308",
            "body.initial_speed",
        ),
    ] {
        let file = scene_file(dir.path(), "big.toml", from, to);
        let csv = dir.path().join("big.csv");
        let output = guideway(&["run", &file, "--out", arg(&csv), "--quiet"]);
        let message = refusal(&output, to);
        assert!(
            message.contains(field) && message.contains("magnitude limit"),
            "{message}"
        );
        assert!(!csv.exists(), "{to}: nothing written");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no stray files"
        );
    }
}

// ---- 6, 7, 8: text that reaches the XML, names, sizes ----------------------------------

#[test]
fn a_description_with_characters_xml_cannot_carry_is_refused_by_run_and_export() {
    let dir = tempfile::tempdir().unwrap();
    for c in ['\u{0}', '\u{7}', '\u{1b}', '\u{FFFE}'] {
        let mut scene = builtin("lee1994-wheel-10").unwrap();
        scene.description = format!("bad {c} text");
        let file = dir.path().join("ctrl.toml");
        std::fs::write(&file, scene.to_toml_string()).unwrap();
        let fmu = dir.path().join("ctrl.fmu");
        for args in [
            vec!["export", arg(&file), "-o", arg(&fmu)],
            vec!["run", arg(&file), "--quiet"],
        ] {
            let output = guideway(&args);
            let message = refusal(&output, &format!("{args:?}"));
            let code = format!("U+{:04X}", c as u32);
            assert!(
                message.contains("description") && message.contains(&code),
                "{message}"
            );
        }
        assert!(!fmu.exists());
    }
}

#[test]
fn every_export_writes_well_formed_xml() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = builtin("lee1994-wheel-10").unwrap();
    // everything XML must escape, and text at the length limits
    scene.description = "<a & \"b\" 'c'> \t é 😀 ".repeat(40);
    scene.name = "n".repeat(guideway::scene::MAX_NAME_CHARS);
    scene.sensors[0].name = "s".repeat(guideway::scene::MAX_NAME_CHARS);
    let file = dir.path().join("edge.toml");
    std::fs::write(&file, scene.to_toml_string()).unwrap();
    let fmu = dir.path().join("edge.fmu");
    let output = guideway(&["export", arg(&file), "-o", arg(&fmu)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let xml = model_description(&fmu);
    guideway::fmu::check_well_formed(&xml).unwrap();
    assert!(xml.contains("&lt;a &amp; &quot;b&quot;"), "escaped");
}

#[test]
fn names_longer_than_64_characters_are_refused_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let long = "a".repeat(300);
    for (from, to, field) in [
        (
            "name = \"lee1994-wheel-10\"",
            format!("name = \"{long}\""),
            "name",
        ),
        (
            "name = \"wheel\"",
            format!("name = \"{long}\""),
            "body.name",
        ),
        (
            "name = \"midspan\"",
            format!("name = \"{long}\""),
            "sensors[0].name",
        ),
    ] {
        let file = scene_file(dir.path(), "long.toml", from, &to);
        let fmu = dir.path().join("long.fmu");
        let output = guideway(&["export", &file, "-o", arg(&fmu)]);
        let message = refusal(&output, field);
        assert!(message.contains(&format!("{field} = \"aaaa")), "{message}");
        assert!(
            message.contains("300 characters, more than the limit of 64"),
            "{message}"
        );
        assert!(message.len() < 1000, "the value is shortened: {message}");
        assert!(!fmu.exists());
    }
}

#[test]
fn more_than_10000_sensors_are_refused_with_one_problem() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = default_toml();
    for i in 0..10_001 {
        text.push_str(&format!("\n[[sensors]]\nname = \"s{i}\"\nposition = 1.0\n"));
    }
    let file = dir.path().join("many.toml");
    std::fs::write(&file, text).unwrap();
    let output = guideway(&["run", arg(&file), "--quiet"]);
    let message = refusal(&output, "");
    assert!(
        message.contains("sensors = 10002 sensors: must hold at most 10000"),
        "{message}"
    );
    assert!(message.contains("(1 problem)"), "{message}");
}

#[test]
fn a_scene_file_over_10_mb_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let text = default_toml().replacen(
        "description = \"",
        &format!("description = \"{}", "x".repeat(10_000_000)),
        1,
    );
    let file = dir.path().join("huge.toml");
    std::fs::write(&file, &text).unwrap();
    let never = dir.path().join("never.fmu");
    for args in [
        vec!["run", arg(&file), "--quiet"],
        vec!["export", arg(&file), "-o", arg(&never)],
    ] {
        let output = guideway(&args);
        let message = refusal(&output, "");
        assert!(
            message.contains(&format!("scene is {} bytes", text.len())),
            "{message}"
        );
        assert!(message.contains("at most 10000000 bytes"), "{message}");
    }
    assert!(!never.exists());
}

#[test]
fn a_description_over_1000_characters_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = builtin("lee1994-wheel-10").unwrap();
    scene.description = "x".repeat(1001);
    let file = dir.path().join("d.toml");
    std::fs::write(&file, scene.to_toml_string()).unwrap();
    let output = guideway(&["run", arg(&file), "--quiet"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("1001 characters, more than the limit of 1000"));
}

// ---- 10: output files -------------------------------------------------------------------

#[test]
fn an_output_equal_to_the_scene_or_to_another_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(dir.path(), "s.toml", "mass = 3000.0", "mass = 3000.0");
    let scene_before = std::fs::read_to_string(&file).unwrap();
    let same = dir.path().join(".").join("s.toml");
    let x = dir.path().join("x.csv");
    let cases: Vec<Vec<&str>> = vec![
        vec!["run", &file, "--out", arg(&same)],
        vec!["run", &file, "--summary", &file],
        vec!["run", &file, "--plot", &file],
        vec!["export", &file, "-o", arg(&same)],
        vec!["run", &file, "--out", arg(&x), "--summary", arg(&x)],
        vec!["run", &file, "--out", arg(&x), "--plot", arg(&x)],
    ];
    for args in cases {
        let output = guideway(&args);
        let message = refusal(&output, &format!("{args:?}"));
        assert!(
            message.contains("would overwrite") || message.contains("would be overwritten"),
            "{message}"
        );
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            scene_before,
            "{args:?}"
        );
        assert!(!x.exists(), "{args:?}");
    }
    // the cross-check files may not be the FMU either
    let fmu = dir.path().join("lee1994_wheel_10_ref.csv");
    let output = guideway(&[
        "export",
        &file,
        "-o",
        arg(&fmu),
        "--cross-check",
        arg(dir.path()),
    ]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
}

#[test]
fn a_failed_run_leaves_the_previous_results_and_keeps_its_rows_apart() {
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "up.toml",
        "max_iterations = 50",
        "max_iterations = 1",
    );
    let csv = dir.path().join("r.csv");
    let summary = dir.path().join("s.json");
    std::fs::write(&csv, "previous good results\n").unwrap();
    std::fs::write(&summary, "{}\n").unwrap();
    let output = guideway(&["run", &file, "--out", arg(&csv), "--summary", arg(&summary)]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        "previous good results\n"
    );
    assert_eq!(std::fs::read_to_string(&summary).unwrap(), "{}\n");
    let message = stderr(&output);
    assert!(message.contains("r.csv.incomplete"), "{message}");
    let partial = std::fs::read_to_string(dir.path().join("r.csv.incomplete")).unwrap();
    assert!(partial.starts_with("time,") && partial.lines().count() >= 2);
    assert!(!partial.contains("NaN") && !partial.contains("inf"));
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 4, "no temporary file left: {names:?}");
}

#[test]
fn an_unwritable_output_fails_before_the_run() {
    // The run would fail (one iteration cannot converge); the output is
    // refused first.
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "up.toml",
        "max_iterations = 50",
        "max_iterations = 1",
    );
    let output = guideway(&["run", &file, "--out", "/proc/x.csv"]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let message = stderr(&output);
    assert!(message.contains("cannot write /proc/x.csv"), "{message}");
    assert!(!message.contains("solver failed"), "nothing ran: {message}");
}

/// Not a defect of main (it failed before creating the file here), but the
/// staging's guarantee for the FMU: a failed export leaves no file behind.
#[test]
fn a_failed_export_leaves_the_previous_fmu() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("m.fmu");
    std::fs::write(&fmu, "previous FMU").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args(["export", "-o", arg(&fmu)])
        .env("GUIDEWAY_CDYLIB", dir.path().join("missing.so"))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert_eq!(std::fs::read_to_string(&fmu).unwrap(), "previous FMU");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

// ---- 11: one exit-code convention, bounded iterations ---------------------------------

#[test]
fn export_and_run_give_the_same_exit_code_for_a_scene_that_cannot_be_simulated() {
    let dir = tempfile::tempdir().unwrap();
    // beyond RK4's stability limit: valid field by field, refused when built
    let file = scene_file(dir.path(), "fine.toml", "elements = 2", "elements = 128");
    let fmu = dir.path().join("fine.fmu");
    let run = guideway(&["run", &file, "--quiet"]);
    let export = guideway(&["export", &file, "-o", arg(&fmu)]);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    assert_eq!(export.status.code(), Some(2), "{}", stderr(&export));
    assert!(
        stderr(&export).contains("solver.step"),
        "{}",
        stderr(&export)
    );
    assert!(!fmu.exists());
}

#[test]
fn a_cross_check_needing_too_many_steps_is_refused_before_anything_is_written() {
    // 1.25 × 24 m / 1e-4 m/s = 3e5 s: 1.2e8 steps, not refused on main.
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "slow.toml",
        "initial_speed = 10.0",
        "initial_speed = 1e-4",
    );
    let fmu = dir.path().join("slow.fmu");
    let cross_check = dir.path().join("cc");
    let output = guideway(&[
        "export",
        &file,
        "-o",
        arg(&fmu),
        "--cross-check",
        arg(&cross_check),
    ]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("more than the limit of 1000000"),
        "{}",
        stderr(&output)
    );
    assert!(!fmu.exists() && !cross_check.exists());
}

#[test]
fn max_iterations_has_an_upper_bound() {
    let dir = tempfile::tempdir().unwrap();
    let file = scene_file(
        dir.path(),
        "it.toml",
        "max_iterations = 50",
        "max_iterations = 1000000",
    );
    let output = guideway(&["run", &file, "--quiet"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("solver.max_iterations = 1000000: must be between 1 and 1000"));
}
