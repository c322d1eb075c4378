//! `guideway sweep`, run as a user would: bad speed ranges are refused with
//! the rule they break; the envelope has one row per speed and train.

use crate::common;
use common::cli::{guideway, refusal, stderr};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bridge25_hslm.toml");

fn refused(speeds: &str, expected: &str) {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("sweep.csv");
    let output = guideway(&[
        "sweep",
        SCENE,
        "--speeds",
        speeds,
        "--out",
        out.to_str().unwrap(),
    ]);
    let message = refusal(&output, &format!("--speeds {speeds}"));
    assert!(
        message.contains(&format!("--speeds \"{speeds}\"")) && message.contains(expected),
        "--speeds {speeds}: {message}"
    );
    assert!(!out.exists(), "no envelope is written for a refused range");
}

#[test]
fn bad_speed_ranges_are_refused_with_the_rule() {
    refused("400:100:5", "stop 100 is below start 400");
    refused("100:400:0", "step 0 must be > 0");
    refused("100:400:-5", "step -5 must be > 0");
    refused("0:400:5", "start 0 must be > 0");
    refused("-100:400:5", "start -100 must be > 0");
    refused("100:400", "want START:STOP:STEP");
    refused("100:fast:5", "stop \"fast\" is not a number");
    refused("100:nan:5", "not a finite speed");
    refused("1:100000:1", "100000 speeds, more than the limit of 10000");
}

#[test]
fn a_bad_unit_or_train_is_refused() {
    let output = guideway(&["sweep", SCENE, "--speeds", "100:200:50", "--unit", "mph"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("want \"m/s\" or \"km/h\""),
        "{}",
        stderr(&output)
    );
    let output = guideway(&[
        "sweep",
        SCENE,
        "--speeds",
        "100:200:50",
        "--trains",
        "HSLM-B1",
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("\"HSLM-B1\" is not a train"),
        "{}",
        stderr(&output)
    );
}

fn envelope(extra: &[&str]) -> Vec<Vec<String>> {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("sweep.csv");
    let plot = dir.path().join("sweep.png");
    let mut args = vec!["sweep", SCENE, "--out", out.to_str().unwrap()];
    args.extend(["--plot", plot.to_str().unwrap()]);
    args.extend(extra);
    let output = guideway(&args);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(std::fs::metadata(&plot).expect("plot written").len() > 1000);
    let text = std::fs::read_to_string(&out).expect("envelope written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "train,speed_km_h,speed_m_s,peak_deflection_m,peak_acceleration_m_s2,\
             peak_acceleration_filtered_m_s2,acceleration_cut_off_hz,daf,\
             sensor.midspan.deflection,sensor.midspan.deflection.daf,sensor.midspan.velocity,\
             sensor.midspan.acceleration,section.midspan.moment,section.midspan.moment.daf,\
             section.midspan.shear,section.midspan.shear.daf,sensor.midspan.acceleration_filtered"
        )
    );
    lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn the_envelope_has_one_row_per_speed_and_train() {
    let rows = envelope(&[
        "--speeds",
        "150:350:100",
        "--unit",
        "km/h",
        "--trains",
        "hslm",
    ]);
    assert_eq!(rows.len(), 30, "10 trains x 3 speeds");
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], format!("HSLM-A{}", i / 3 + 1));
        let speed: f64 = row[1].parse().unwrap();
        assert_eq!(speed, [150.0, 250.0, 350.0][i % 3]);
        let speed_m_s: f64 = row[2].parse().unwrap();
        assert!((speed_m_s - speed / 3.6).abs() < 1e-12);
        let numbers: Vec<f64> = row[3..8].iter().map(|x| x.parse().unwrap()).collect();
        assert!(numbers.iter().all(|x| x.is_finite() && *x > 0.0), "{row:?}");
        let design: Vec<f64> = row[8..].iter().map(|x| x.parse().unwrap()).collect();
        assert!(design.iter().all(|x| x.is_finite()), "{row:?}");
        // Dynamic amplification of a crossing is at least about 1.
        assert!(numbers[4] > 0.95, "{row:?}");
        // f3 = 36 Hz on this bridge: the cut-off of EN 1991-2 6.4.6.5(4)
        assert!((numbers[3] - 36.0).abs() < 0.1, "{row:?}");
    }
}

#[test]
fn without_trains_the_scene_s_own_forces_run_at_each_speed() {
    let rows = envelope(&["--speeds", "200:300:50", "--unit", "km/h", "--threads", "1"]);
    assert_eq!(rows.len(), 3);
    assert!(rows.iter().all(|r| r[0] == "bridge25_hslm"));
    // The scene's train is HSLM-A1: the same as naming it.
    let named = envelope(&[
        "--speeds",
        "200:300:50",
        "--unit",
        "km/h",
        "--trains",
        "HSLM-A1",
    ]);
    for (own, train) in rows.iter().zip(&named) {
        assert_eq!(own[1..], train[1..], "threads and naming change nothing");
    }
}

#[test]
fn a_sweep_beyond_its_step_limit_is_refused_before_running() {
    let output = guideway(&[
        "sweep",
        SCENE,
        "--speeds",
        "100:400:5",
        "--unit",
        "km/h",
        "--trains",
        "hslm",
        "--max-steps",
        "1000000",
    ]);
    assert_eq!(output.status.code(), Some(2));
    let message = stderr(&output);
    assert!(
        message.contains("more than the limit of 1000000 (--max-steps)"),
        "{message}"
    );
}

#[test]
fn every_envelope_column_is_named_once_in_either_unit() {
    for unit in ["m/s", "km/h"] {
        let dir = tempfile::tempdir().expect("temp dir");
        let out = dir.path().join("sweep.csv");
        let output = guideway(&[
            "sweep",
            SCENE,
            "--speeds",
            "60:70:10",
            "--unit",
            unit,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let text = std::fs::read_to_string(&out).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let mut unique = header.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), header.len(), "--unit {unit}: {header:?}");
        // Both speed columns hold the same speed.
        let row: Vec<f64> = text
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .skip(1)
            .take(2)
            .map(|x| x.parse().unwrap())
            .collect();
        assert!(
            (row[0] - 3.6 * row[1]).abs() < 1e-9,
            "--unit {unit}: {row:?}"
        );
    }
}
