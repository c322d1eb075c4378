//! A release: the FMUs of every built-in scene for the crate's version, with
//! their FMI cross-check files, release notes and checksums.
//!
//! Layout of `<out>/<version>/`:
//!
//! ```text
//! <model>.fmu                      one per built-in scene
//! cross-check/fmus/2.0/cs/linux64/guideway/<version>/<model>/
//!     <model>.fmu, <model>_ref.csv, <model>_ref.opt, ReadMe.txt
//! README.md                        what is in the release, which FMU to pick
//! RELEASE_NOTES.md                 the version's section of CHANGELOG.md
//! SHA256SUMS                       of every other file (`sha256sum -c`)
//! ```
//!
//! Every file is a function of the version, the scenes, the changelog and
//! the cdylib, so building a release twice from one build gives the same
//! bytes.

use crate::fmi_common::description::model_identifier;
use crate::scene::{builtin, fmu_builtins, BodyKind, Scene};
use sha2::{Digest, Sha256};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The version released: the crate's (`Cargo.toml`), as the FMUs' model
/// descriptions state it.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The FMI cross-check tree's path from the release directory to the
/// directories of the models (one per FMU).
pub fn cross_check_models_dir() -> PathBuf {
    [
        "cross-check",
        "fmus",
        "2.0",
        "cs",
        "linux64",
        "guideway",
        VERSION,
    ]
    .iter()
    .collect()
}

/// What `build` wrote.
#[derive(Debug, Clone)]
pub struct Release {
    /// `<out>/<version>`.
    pub dir: PathBuf,
    /// The FMUs at the top of `dir`.
    pub fmus: Vec<PathBuf>,
}

/// The section of a Keep-a-Changelog file for `version`: from its heading
/// `## [version]` up to the next `## ` heading (trimmed). Fails if there is
/// none or it is empty: a release needs notes.
pub fn release_notes(changelog: &str, version: &str) -> Result<String, String> {
    let heading = format!("## [{version}]");
    let mut lines = changelog.lines();
    let first = lines.find(|l| l.starts_with(&heading)).ok_or_else(|| {
        format!("CHANGELOG.md has no section `{heading}`: add one before releasing")
    })?;
    let body: Vec<&str> = lines.take_while(|l| !l.starts_with("## ")).collect();
    let body = body.join("\n");
    if body.trim().is_empty() {
        return Err(format!("CHANGELOG.md's section `{heading}` is empty"));
    }
    Ok(format!(
        "# guideway {version}\n\n{}\n\n{}\n",
        first.trim(),
        body.trim()
    ))
}

/// Build the release for `VERSION` into `<out>/<version>/`, packaging
/// `cdylib` (libguideway.so). Refuses to write into an existing release
/// directory unless `replace` (then it is removed first).
pub fn build(out: &Path, cdylib: &Path, changelog: &str, replace: bool) -> Result<Release, String> {
    let notes = release_notes(changelog, VERSION)?;
    let dir = out.join(VERSION);
    if dir.exists() {
        if !replace {
            return Err(format!(
                "{} exists: remove it, or rebuild it with --replace",
                dir.display()
            ));
        }
        std::fs::remove_dir_all(&dir)
            .map_err(|e| format!("cannot remove {}: {e}", dir.display()))?;
    }
    let scenes: Vec<Scene> = fmu_builtins()
        .map(|(name, _)| builtin(name).expect("a listed built-in exists"))
        .collect();
    let mut fmus = Vec::new();
    for scene in &scenes {
        let id = model_identifier(&scene.name);
        let fmu = dir.join(format!("{id}.fmu"));
        super::export(scene, &fmu, cdylib)?;
        let model_dir = dir.join(cross_check_models_dir()).join(&id);
        super::write_cross_check(scene, &model_dir)?;
        copy(&fmu, &model_dir.join(format!("{id}.fmu")))?;
        write(&model_dir.join("ReadMe.txt"), &cross_check_readme(scene))?;
        fmus.push(fmu);
        if let Some(coupled) = coupling_variant(scene) {
            let id = model_identifier(&coupled.name);
            let fmu = dir.join("coupling").join(format!("{id}.fmu"));
            std::fs::create_dir_all(dir.join("coupling"))
                .map_err(|e| format!("cannot create {}/coupling: {e}", dir.display()))?;
            super::export(&coupled, &fmu, cdylib)?;
            fmus.push(fmu);
        }
    }
    write(&dir.join("README.md"), &readme(&scenes))?;
    write(&dir.join("RELEASE_NOTES.md"), &notes)?;
    write(&dir.join("SHA256SUMS"), &sha256sums(&dir)?)?;
    Ok(Release { dir, fmus })
}

/// The coupling-ready FMU of a one-body scene (issue 27 item 3): the same
/// scene with its body as a coupling point (`couplings`, docs/coupling.md),
/// so that a vehicle model of the user's own can ride on it. None for
/// scenes of several vehicles or with couplings already.
pub fn coupling_variant(scene: &Scene) -> Option<Scene> {
    let one_body = scene.vehicles.len() == 1 && scene.couplings.is_empty();
    let kind = matches!(scene.vehicles[0].kind, BodyKind::Wheel | BodyKind::Glider);
    (one_body && kind).then(|| {
        let mut coupled = scene.clone();
        coupled.name = format!("{}-coupling", scene.name);
        coupled.couplings = vec![scene.vehicles[0].name.clone()];
        coupled
    })
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn copy(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::copy(from, to)
        .map(|_| ())
        .map_err(|e| format!("cannot copy {} to {}: {e}", from.display(), to.display()))
}

/// `sha256sum` lines (`<hex>  <path>`) of every file under `dir`, paths
/// relative to `dir` with `/`, sorted.
pub fn sha256sums(dir: &Path) -> Result<String, String> {
    let mut files = Vec::new();
    collect_files(dir, dir, &mut files)?;
    files.sort();
    let mut out = String::new();
    for rel in files {
        if rel == "SHA256SUMS" {
            continue;
        }
        let path = dir.join(&rel);
        let bytes =
            std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let hex: String = Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        writeln!(out, "{hex}  {rel}").expect("write to String");
    }
    Ok(out)
}

fn collect_files(root: &Path, dir: &Path, out: &mut Vec<String>) -> Result<(), String> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    for entry in entries {
        let path = entry
            .map_err(|e| format!("cannot list {}: {e}", dir.display()))?
            .path();
        if path.is_dir() {
            collect_files(root, &path, out)?;
        } else {
            let rel = path.strip_prefix(root).expect("under the root");
            let parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            out.push(parts.join("/"));
        }
    }
    Ok(())
}

/// The README's body column: the one vehicle's kind, or a train's count
/// and each vehicle's kind.
fn body_text(scene: &Scene) -> String {
    let kinds: Vec<&str> = (scene.vehicles.iter())
        .map(|v| v.kind.description())
        .collect();
    match kinds.as_slice() {
        [one] => one.to_string(),
        _ => format!("{} vehicles: {}", kinds.len(), kinds.join(", ")),
    }
}

/// The README's V0 column: the vehicles' initial speeds (m/s), each
/// distinct one once, in order.
fn initial_speeds_text(scene: &Scene) -> String {
    let mut speeds: Vec<f64> = Vec::new();
    for v in &scene.vehicles {
        if !speeds.contains(&v.initial_speed) {
            speeds.push(v.initial_speed);
        }
    }
    let texts: Vec<String> = speeds.iter().map(f64::to_string).collect();
    texts.join(", ")
}

/// The cross-check `ReadMe.txt` of one model.
fn cross_check_readme(scene: &Scene) -> String {
    format!(
        "guideway {VERSION}: FMI 2.0 co-simulation FMU of the scene `{}`.\n\
         {}\n\n\
         The reference {id}_ref.csv was computed by guideway's own model code \
         (the code the FMU runs) with communication steps of solver.step = {} s \
         (see {id}_ref.opt), from t = 0 until the last contact leaves the beam.\n\
         Platform: linux64 (x86-64, glibc). No inputs are needed.\n",
        scene.name,
        scene.description,
        scene.solver.step,
        id = model_identifier(&scene.name),
    )
}

/// The release's README: what is in it and which FMU to pick.
fn readme(scenes: &[Scene]) -> String {
    let mut s = format!(
        "# guideway {VERSION}: FMI 2.0 co-simulation FMUs (linux64)\n\n\
         One FMU per built-in scene of guideway {VERSION}. Each is self-contained \
         (binary, scene, documentation/index.html listing every variable) and \
         every parameter of the scene (beam, body, sensor position, solver step) \
         can be changed with start values, so pick the FMU by the *body* and the \
         *time step* you need, then set the rest:\n\n\
         | FMU | body | V0 (m/s) | solver.step (s) | scene |\n|---|---|---:|---:|---|\n"
    );
    for scene in scenes {
        writeln!(
            s,
            "| `{}.fmu` | {} | {} | {} | {} |",
            model_identifier(&scene.name),
            body_text(scene),
            initial_speeds_text(scene),
            scene.solver.step,
            scene.description
        )
        .expect("write to String");
    }
    s += "\n- A wheel or a glider: the body kind is fixed in the FMU (a glider has \
          no radius, inertia or tangential force).\n\
          - The number of beam elements and the step are parameters \
          (`beam.elements`, `solver.step`); a step beyond RK4's stability limit \
          for the mesh is refused at initialization, naming the limit.\n\
          - Inputs `<body>.force_x` and `<body>.force_y` (N) may change between \
          communication steps.\n\n\
          `coupling/` holds, for each of them, the same model with its body as a \
          coupling point (`<body>.coupling_force_x`, `.coupling_force_y` and, on a \
          wheel, `.coupling_moment` inputs; its motion as outputs) for a vehicle \
          model of your own to ride on (see the documentation's coupling page).\n\n\
          Other files: `cross-check/` holds the FMI cross-check tree \
          (`fmus/2.0/cs/linux64/guideway/<version>/<model>/` with the FMU, \
          `_ref.csv`, `_ref.opt`, `ReadMe.txt`), `RELEASE_NOTES.md` the changes \
          in this version, `SHA256SUMS` the checksums (`sha256sum -c SHA256SUMS`).\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const CHANGELOG: &str = "# Changelog\n\n## [Unreleased]\n\n- next\n\n\
        ## [0.2.0] - 2027-01-01\n\n### Added\n- two\n\n## [0.1.0] - 2026-11-21\n\n### Added\n- one\n";

    #[test]
    fn notes_are_the_versions_section_only() {
        let n = release_notes(CHANGELOG, "0.2.0").unwrap();
        assert!(n.starts_with("# guideway 0.2.0\n\n## [0.2.0] - 2027-01-01"));
        assert!(n.contains("- two"));
        assert!(!n.contains("- one") && !n.contains("- next"));
        assert!(release_notes(CHANGELOG, "0.1.0").unwrap().contains("- one"));
    }

    #[test]
    fn a_version_without_notes_is_refused() {
        let e = release_notes(CHANGELOG, "0.3.0").unwrap_err();
        assert!(e.contains("## [0.3.0]"), "{e}");
        let e = release_notes("## [0.3.0]\n\n## [0.2.0]\n- x\n", "0.3.0").unwrap_err();
        assert!(e.contains("empty"), "{e}");
    }

    #[test]
    fn the_changelog_has_notes_for_this_version() {
        let changelog = include_str!("../../CHANGELOG.md");
        assert!(release_notes(changelog, VERSION).is_ok());
    }

    #[test]
    fn every_released_one_body_scene_has_a_valid_coupling_variant() {
        for (name, _) in fmu_builtins() {
            let scene = builtin(name).unwrap();
            let coupled = coupling_variant(&scene).expect("a wheel or glider scene");
            coupled.validate().unwrap();
            assert_eq!(
                coupled.couplings,
                std::slice::from_ref(&scene.vehicles[0].name)
            );
            assert_ne!(
                model_identifier(&coupled.name),
                model_identifier(&scene.name)
            );
        }
    }

    #[test]
    fn readme_names_every_builtin_fmu() {
        let scenes: Vec<Scene> = fmu_builtins().map(|(n, _)| builtin(n).unwrap()).collect();
        let text = readme(&scenes);
        for (name, _) in fmu_builtins() {
            assert!(text.contains(&format!("`{}.fmu`", model_identifier(name))));
        }
        // A train's row names every vehicle and each distinct speed.
        let mut train = builtin("lee1994-wheel-10").unwrap();
        let mut rear = train.vehicles[0].clone();
        rear.initial_speed = 12.5;
        train.vehicles.extend([train.vehicles[0].clone(), rear]);
        let row = format!(
            "| 3 vehicles: {0}, {0}, {0} | 10, 12.5 |",
            body_text(&scenes[0])
        );
        assert!(readme(&[train]).contains(&row), "{row}");
    }
}
