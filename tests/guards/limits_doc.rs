//! Every bound in the code is in the limits table: each `MAX_*`/`MIN_*`
//! constant under `src/` is named in docs/limits.md, or listed here as
//! numerical tuning with the reason it bounds no input.

use std::fs;
use std::path::Path;

/// Constants that tune an algorithm and bound no input, memory or time.
const TUNING: &[(&str, &str)] = &[
    (
        "MAX_ROW_MODES",
        "modes up to which the design outputs are read as rows over the modes; past it through the DOFs, the same values",
    ),
    (
        "MAX_ROW_ENTRIES",
        "probes x modes up to which the design outputs are read as rows (32 MB); past it through the DOFs, the same values",
    ),
    (
        "MAX_INFLUENCE_ENTRIES",
        "entries of K⁻¹'s rows (16 MiB) up to which the static envelope reads its outputs through influence rows; past it a solve per load position, the same values up to rounding",
    ),
    (
        "MAX_ROW_COORDINATES",
        "coordinates up to which the design outputs' accelerations are read through rows of M⁻¹ (`AccelerationRows`); past it a mass solve a row, the same values up to rounding",
    ),
    (
        "MAX_SECANT_STEPS",
        "secant steps of beam.frequency's EI search on springs; past them the scene is refused naming the field",
    ),
    (
        "MAX_COORDINATES",
        "the foot-point memo keeps nothing above it: a speed choice",
    ),
    (
        "MAX_CURVES",
        "curves drawn in one converge figure; the CSV has all",
    ),
    (
        "MAX_EXTRAPOLATION_GAIN",
        "a numerical damping of the force extrapolation",
    ),
    (
        "MAX_STEP_RATIO",
        "neighbouring steps fitted by the profile polynomial",
    ),
    (
        "MAX_SWEEPS",
        "Gauss–Seidel sweeps of the track-on-deck Hertz forces; past them the step returns an error",
    ),
];

/// Names of `const MAX_...`/`const MIN_...` items in one source text.
fn bound_names(source: &str) -> Vec<String> {
    let mut names = Vec::new();
    for (at, _) in source.match_indices("const ") {
        let rest = &source[at + "const ".len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_')
            .collect();
        if name.starts_with("MAX_") || name.starts_with("MIN_") {
            names.push(name);
        }
    }
    names
}

fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push((
                path.display().to_string(),
                fs::read_to_string(&path).unwrap(),
            ));
        }
    }
}

#[test]
fn every_bound_constant_is_in_the_limits_table_or_named_as_tuning() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let limits = fs::read_to_string(root.join("docs/limits.md")).unwrap();
    let mut files = Vec::new();
    sources(&root.join("src"), &mut files);
    let mut missing = Vec::new();
    let mut seen = 0;
    for (file, text) in &files {
        for name in bound_names(text) {
            seen += 1;
            let tuning = TUNING.iter().any(|(n, _)| *n == name);
            if !tuning && !limits.contains(&format!("`{name}`")) {
                missing.push(format!("{name} ({file})"));
            }
        }
    }
    assert!(
        seen > 30,
        "only {seen} bound constants found: the scan is broken"
    );
    assert!(
        missing.is_empty(),
        "bounds in the code missing from docs/limits.md: {missing:?}"
    );
}

#[test]
fn the_tuning_list_names_only_constants_that_exist_and_are_not_documented_bounds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let limits = fs::read_to_string(root.join("docs/limits.md")).unwrap();
    let mut files = Vec::new();
    sources(&root.join("src"), &mut files);
    for (name, _) in TUNING {
        let found = files
            .iter()
            .any(|(_, t)| bound_names(t).iter().any(|n| n == name));
        assert!(found, "{name} is listed as tuning but no longer in src/");
        assert!(
            !limits.contains(name),
            "{name} is both tuning and a documented bound"
        );
    }
}
