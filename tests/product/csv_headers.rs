//! Every CSV the product writes (run, sweep, converge, modes, check) names
//! each column once and has as many fields in every row as in its header
//! (issue 26 item 6: pandas renames a repeated column, `csv.DictReader`
//! keeps only the last).

use crate::common;
use common::cli::guideway_ok;
use std::collections::HashSet;
use std::path::Path;

/// The fields of one CSV line (RFC 4180 quotes; no field spans lines in
/// these files). Hand-written: a dozen lines, where the `csv` crate would
/// be a new dependency for one test.
fn fields(line: &str) -> Vec<String> {
    let (mut out, mut field, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    out.push(field);
    out
}

/// Check one CSV; returns its column count.
fn check_csv(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).expect("CSV written");
    let mut lines = text.lines();
    let header = fields(lines.next().expect("a header"));
    let mut seen = HashSet::new();
    for name in &header {
        assert!(!name.is_empty(), "{}: an unnamed column", path.display());
        assert!(
            seen.insert(name),
            "{}: column `{name}` twice",
            path.display()
        );
    }
    for (i, line) in lines.enumerate() {
        let count = fields(line).len();
        assert_eq!(
            count,
            header.len(),
            "{} row {}: {line}",
            path.display(),
            i + 1
        );
    }
    header.len()
}

#[test]
fn every_csv_names_each_column_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let bridge = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bridge25_hslm.toml");
    let runs: &[(&str, Vec<String>)] = &[
        ("run.csv", vec!["run".into(), "lee1994-wheel-10".into()]),
        (
            "train.csv",
            vec!["run".into(), "train-2-coaches-2x40-100".into()],
        ),
        ("modes.csv", vec!["modes".into(), "lee1994-wheel-10".into()]),
        (
            "sweep_m_s.csv",
            vec![
                "sweep".into(),
                bridge.into(),
                "--speeds".into(),
                "50:60:10".into(),
            ],
        ),
        (
            "sweep_km_h.csv",
            vec![
                "sweep".into(),
                bridge.into(),
                "--speeds".into(),
                "200:210:10".into(),
                "--unit".into(),
                "km/h".into(),
                "--trains".into(),
                "HSLM-A1,HSLM-A2".into(),
            ],
        ),
        (
            "converge.csv",
            vec![
                "converge".into(),
                "lee1994-wheel-10".into(),
                "--rungs".into(),
                "3".into(),
            ],
        ),
    ];
    for (file, args) in runs {
        let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
        let path = out(file);
        args.extend(["--out", &path]);
        guideway_ok(&args);
        assert!(check_csv(Path::new(&path)) > 1, "{file}");
    }
    let report = out("check");
    guideway_ok(&["check", "bridge20", "--out", &report, "--threads", "1"]);
    let mut checked = 0;
    for entry in std::fs::read_dir(&report).expect("report dir") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "csv") {
            check_csv(&path);
            checked += 1;
        }
    }
    assert!(checked >= 2, "check wrote {checked} CSVs");
}
