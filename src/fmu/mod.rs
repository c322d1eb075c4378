//! Packaging: assemble an FMI 2.0 co-simulation FMU (a zip) from the static
//! parts in `fmu_template/`, the generated modelDescription.xml and
//! documentation page, the built cdylib and the scene.
//!
//! Layout of the archive:
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/<modelIdentifier>.so    copy of libguideway.so
//! resources/scene.toml                     the scene the FMU simulates
//! documentation/index.html                 generated from the variable table
//! documentation/style.css, licenses/       from fmu_template/
//! ```

pub mod cross_check;
mod documentation;
pub mod release;
pub mod ssp;

use crate::fmi2::instance::SCENE_FILE;
use crate::fmi2::{describe, Physics};
use crate::scene::Scene;
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// Static files copied into every FMU (path in the archive, content).
const TEMPLATE: &[(&str, &[u8])] = &[
    (
        "documentation/style.css",
        include_bytes!("../../fmu_template/documentation/style.css"),
    ),
    (
        "documentation/licenses/LICENSE.txt",
        include_bytes!("../../fmu_template/documentation/licenses/LICENSE.txt"),
    ),
];

/// What `export` wrote.
#[derive(Debug, Clone)]
pub struct Exported {
    pub path: PathBuf,
    pub model_identifier: String,
    pub guid: String,
}

/// The cdylib to put into FMUs: `$GUIDEWAY_CDYLIB` if set, else
/// `libguideway.so` next to the running executable (cargo builds the binary
/// and the cdylib into the same `target/<profile>/`).
pub fn default_cdylib() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("GUIDEWAY_CDYLIB") {
        return Ok(PathBuf::from(p));
    }
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate the executable: {e}"))?;
    let dir = exe.parent().ok_or("the executable has no directory")?;
    // test binaries live one level deeper, in target/<profile>/deps
    for d in [dir, dir.parent().unwrap_or(dir)] {
        let p = d.join("libguideway.so");
        if p.is_file() {
            return Ok(p);
        }
    }
    Err(format!(
        "libguideway.so not found next to {}: build it with `cargo build` (same profile) or set GUIDEWAY_CDYLIB",
        exe.display()
    ))
}

/// Export `scene` as an FMU at `out`, with the binary `cdylib`
/// (`libguideway.so`). Fails with a message if the scene is invalid or a
/// file cannot be read or written.
pub fn export(scene: &Scene, out: &Path, cdylib: &Path) -> Result<Exported, String> {
    // The FMU reads its scene back from TOML; describe the scene as it will
    // read it, so the GUID it computes at instantiation is the same.
    let scene_text = scene.to_toml_string();
    let scene = Scene::from_toml_str(&scene_text).map_err(|e| e.to_string())?;
    let d = describe::<Physics>(&scene)?;
    let binary = std::fs::read(cdylib)
        .map_err(|e| format!("cannot read the FMU binary {}: {e}", cdylib.display()))?;
    let html = documentation::index_html(&scene, &d);

    let mut files: Vec<(String, &[u8], u32)> = vec![
        ("modelDescription.xml".into(), d.xml.as_bytes(), 0o644),
        (
            format!("binaries/linux64/{}.so", d.model_identifier),
            &binary,
            0o755,
        ),
        (
            format!("resources/{SCENE_FILE}"),
            scene_text.as_bytes(),
            0o644,
        ),
        ("documentation/index.html".into(), html.as_bytes(), 0o644),
    ];
    files.extend(TEMPLATE.iter().map(|&(p, b)| (p.to_string(), b, 0o644)));
    // Reproducible archives: entries in name order, each with the same
    // timestamp (the zip epoch, 1980-01-01 00:00) and fixed permissions, so
    // packaging the same scene and binary twice gives the same bytes.
    files.sort_by(|a, b| a.0.cmp(&b.0));

    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let io = |e: std::io::Error| format!("cannot write {}: {e}", out.display());
    let zerr = |e: zip::result::ZipError| format!("cannot write {}: {e}", out.display());
    let file = std::fs::File::create(out).map_err(io)?;
    let mut zip = zip::ZipWriter::new(file);
    for (name, bytes, mode) in files {
        let options = SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default())
            .unix_permissions(mode);
        zip.start_file(name, options).map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    zip.finish().map_err(zerr)?;
    Ok(Exported {
        path: out.to_path_buf(),
        model_identifier: d.model_identifier,
        guid: d.guid,
    })
}

/// Write the cross-check reference files `<modelIdentifier>_ref.csv` and
/// `<modelIdentifier>_ref.opt` of `scene` into `dir`.
pub fn write_cross_check(scene: &Scene, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let id = crate::fmi2::model_description::model_identifier(&scene.name);
    cross_check::write::<Physics>(scene, &id, dir)
}
