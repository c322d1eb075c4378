//! Packaging: assemble an FMI 2.0 or FMI 3.0 co-simulation FMU (a zip) from
//! the static parts in `fmu_template/`, the generated modelDescription.xml
//! and documentation page, the built cdylib (one binary serves both
//! versions) and the scene.
//!
//! Layout of the archive:
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/<modelIdentifier>.so    copy of libguideway.so (FMI 2.0;
//!                                          FMI 3.0: binaries/x86_64-linux/)
//! resources/scene.toml                     the scene the FMU simulates
//! documentation/index.html                 generated from the variable table
//! documentation/style.css, licenses/       from fmu_template/
//! ```

pub mod cross_check;
mod documentation;
pub mod release;
pub mod ssp;

use crate::fmi2::describe;
use crate::fmi_common::Description;
use crate::model::{ExportedDynamics, ExportedModel, SCENE_FILE};
use crate::output_file::Staged;
use crate::scene::Scene;
use std::fmt;
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

/// Why `export` wrote nothing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ExportError {
    /// The scene is not valid or cannot be simulated: nothing to package.
    Scene(String),
    /// A file could not be read or written.
    Io(String),
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExportError::Scene(m) | ExportError::Io(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ExportError {}

impl From<ExportError> for String {
    fn from(e: ExportError) -> String {
        e.to_string()
    }
}

/// Which FMI standard an FMU follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FmiVersion {
    #[default]
    V2,
    V3,
}

impl FmiVersion {
    /// `2.0` or `3.0`.
    pub fn label(self) -> &'static str {
        match self {
            FmiVersion::V2 => "2.0",
            FmiVersion::V3 => "3.0",
        }
    }

    /// The prefix of the standard's functions and status names.
    pub fn prefix(self) -> &'static str {
        match self {
            FmiVersion::V2 => "fmi2",
            FmiVersion::V3 => "fmi3",
        }
    }

    /// What the description's identity attribute is called.
    pub fn token_name(self) -> &'static str {
        match self {
            FmiVersion::V2 => "GUID",
            FmiVersion::V3 => "instantiation token",
        }
    }

    /// The standard's name of a variable type.
    pub fn type_name(self, ty: crate::model::VarType) -> &'static str {
        match (self, ty) {
            (FmiVersion::V2, ty) => ty.as_str(),
            (FmiVersion::V3, crate::model::VarType::Real) => "Float64",
            (FmiVersion::V3, crate::model::VarType::Integer) => "Int32",
            (FmiVersion::V3, crate::model::VarType::Boolean) => "Boolean",
        }
    }

    /// The folder of the Linux x86-64 binary inside the archive.
    fn binary_dir(self) -> &'static str {
        match self {
            FmiVersion::V2 => "binaries/linux64",
            FmiVersion::V3 => "binaries/x86_64-linux",
        }
    }
}

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

/// The glibc 2.17 build of the FMU binary: where the wheel installs it
/// (`pip install guideway`: `<prefix>/bin/guideway` beside
/// `<prefix>/lib/guideway/libguideway.so`, scripts/build_wheel.sh), or where
/// `scripts/build_portable.sh` puts it for the executable in
/// `target/<profile>/`, or beside the executable of that build itself (the
/// one `scripts/test.sh` tests).
fn portable_cdylib() -> Option<PathBuf> {
    const PORTABLE_RELEASE: &str = "portable/x86_64-unknown-linux-gnu/release";
    let exe = std::env::current_exe().ok()?;
    let dir = exe.parent()?;
    let above = dir.parent()?;
    let beside = dir.ends_with(PORTABLE_RELEASE).then(|| dir.to_path_buf());
    let places = [above.join("lib/guideway"), above.join(PORTABLE_RELEASE)];
    (beside.into_iter().chain(places))
        .map(|d| d.join("libguideway.so"))
        .find(|p| p.is_file())
}

/// Why a native build is not shipped (README, "The FMU binary").
const NOT_PORTABLE: &str = "the native build needs the glibc of the machine that built it (2.34 \
     or later on Debian 12), not the 2.17 baseline; build the portable one with \
     `bash scripts/build_portable.sh` or set GUIDEWAY_CDYLIB";

/// The binary `guideway export` packages: `$GUIDEWAY_CDYLIB`, else the
/// portable build if there is one, else the native one with a warning
/// saying what it needs.
pub fn export_cdylib() -> Result<(PathBuf, Option<String>), String> {
    if std::env::var_os("GUIDEWAY_CDYLIB").is_some() {
        return default_cdylib().map(|p| (p, None));
    }
    if let Some(p) = portable_cdylib() {
        return Ok((p, None));
    }
    let native = default_cdylib()?;
    let warning = native_warning(&native, BUILT_FOR_THIS_CPU);
    Ok((native, Some(warning)))
}

/// Whether this build's Rust flags chose a CPU (`-C target-cpu`, or a
/// target feature beyond x86-64's SSE2): every such choice enables SSE3.
/// The native library is built with the command's flags.
const BUILT_FOR_THIS_CPU: bool = cfg!(all(target_arch = "x86_64", target_feature = "sse3"));

/// What `export` says when it packages the native library at `path`.
fn native_warning(path: &Path, built_for_this_cpu: bool) -> String {
    let cpu = if built_for_this_cpu {
        "; and it is built for this CPU's instructions (its Rust flags), so the \
         FMU stops with an illegal instruction on CPUs without them"
    } else {
        ""
    };
    format!("packaging {}: {NOT_PORTABLE}{cpu}", path.display())
}

/// The binary `guideway release` ships: `$GUIDEWAY_CDYLIB`, else the
/// portable build; a native build is refused.
pub fn release_cdylib() -> Result<PathBuf, String> {
    if std::env::var_os("GUIDEWAY_CDYLIB").is_some() {
        return default_cdylib();
    }
    portable_cdylib().ok_or_else(|| {
        format!("a release ships the portable FMU binary, which is not built: {NOT_PORTABLE}")
    })
}

/// Export `scene` as an FMU at `out`, with the binary `cdylib`
/// (`libguideway.so`). The archive is written beside `out` and renamed onto
/// it when complete, so a failure leaves `out` as it was.
pub fn export(scene: &Scene, out: &Path, cdylib: &Path) -> Result<Exported, ExportError> {
    export_as(scene, out, cdylib, FmiVersion::V2)
}

/// `export` following the standard `fmi`.
pub fn export_as(
    scene: &Scene,
    out: &Path,
    cdylib: &Path,
    fmi: FmiVersion,
) -> Result<Exported, ExportError> {
    let (scene_text, scene, d) = describe_as_packaged(scene, fmi)?;
    let binary = std::fs::read(cdylib).map_err(|e| {
        ExportError::Io(format!(
            "cannot read the FMU binary {}: {e}",
            cdylib.display()
        ))
    })?;
    let html = documentation::index_html(&scene, &d, fmi);

    let mut files: Vec<(String, &[u8], u32)> = vec![
        ("modelDescription.xml".into(), d.xml.as_bytes(), 0o644),
        (
            format!("{}/{}.so", fmi.binary_dir(), d.model_identifier),
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
            .map_err(|e| ExportError::Io(format!("cannot create {}: {e}", dir.display())))?;
    }
    let staged = Staged::new(out).map_err(ExportError::Io)?;
    write_zip(&staged, files).map_err(ExportError::Io)?;
    staged.commit().map_err(ExportError::Io)?;
    Ok(Exported {
        path: out.to_path_buf(),
        model_identifier: d.model_identifier,
        guid: d.guid,
    })
}

/// The scene as the FMU will read it back (its TOML text, parsed), and the
/// description of that scene, checked well-formed.
fn describe_as_packaged(
    scene: &Scene,
    fmi: FmiVersion,
) -> Result<(String, Scene, Description), ExportError> {
    // The FMU reads its scene back from TOML; describe the scene as it will
    // read it, so the GUID it computes at instantiation is the same.
    let scene_text = scene.to_toml_string();
    let scene = Scene::from_toml_str(&scene_text).map_err(|e| ExportError::Scene(e.to_string()))?;
    let d = match fmi {
        FmiVersion::V2 => describe::<ExportedModel>(scene.clone()),
        FmiVersion::V3 => crate::fmi3::describe::<ExportedModel>(scene.clone()),
    }
    .map_err(ExportError::Scene)?;
    check_well_formed(&d.xml).map_err(ExportError::Scene)?;
    Ok((scene_text, scene, d))
}

/// The modelDescription.xml `export` would write for `scene` (to check an
/// SSP's connections before anything is written).
pub fn model_description(scene: &Scene) -> Result<String, ExportError> {
    model_description_as(scene, FmiVersion::V2)
}

/// The same, for an FMU of standard `fmi`.
pub fn model_description_as(scene: &Scene, fmi: FmiVersion) -> Result<String, ExportError> {
    describe_as_packaged(scene, fmi).map(|(_, _, d)| d.xml)
}

fn write_zip(staged: &Staged, files: Vec<(String, &[u8], u32)>) -> Result<(), String> {
    let out = staged.path();
    let io = |e: std::io::Error| format!("cannot write {}: {e}", out.display());
    let zerr = |e: zip::result::ZipError| format!("cannot write {}: {e}", out.display());
    let mut zip = zip::ZipWriter::new(staged.file()?);
    for (name, bytes, mode) in files {
        let options = SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default())
            .unix_permissions(mode);
        zip.start_file(name, options).map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    zip.finish().map_err(zerr)?.sync_all().map_err(io)
}

/// Refuse to package a modelDescription.xml that an XML parser would
/// reject (the scene's rules should make this impossible; this is the last
/// guard before an importer sees it).
pub fn check_well_formed(xml: &str) -> Result<(), String> {
    let broken =
        |e: String| format!("the generated modelDescription.xml is not well-formed XML: {e}");
    if let Some((at, c)) = xml
        .char_indices()
        .find(|&(_, c)| !crate::scene::is_xml_char(c))
    {
        return Err(broken(format!(
            "character U+{:04X} at byte {at} is not allowed in XML 1.0",
            c as u32
        )));
    }
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut depth = 0usize;
    let mut roots = 0usize;
    loop {
        match reader.read_event() {
            Ok(quick_xml::events::Event::Eof) => break,
            Ok(quick_xml::events::Event::Start(e)) => {
                roots += usize::from(depth == 0);
                depth += 1;
                check_attributes(&e).map_err(broken)?;
            }
            Ok(quick_xml::events::Event::Empty(e)) => {
                roots += usize::from(depth == 0);
                check_attributes(&e).map_err(broken)?;
            }
            Ok(quick_xml::events::Event::End(_)) => depth = depth.saturating_sub(1),
            Ok(_) => {}
            Err(e) => return Err(broken(format!("{e} at byte {}", reader.buffer_position()))),
        }
    }
    if depth != 0 || roots != 1 {
        return Err(broken(format!("{roots} root elements, {depth} left open")));
    }
    Ok(())
}

/// Every attribute parses and its value unescapes.
fn check_attributes(e: &quick_xml::events::BytesStart) -> Result<(), String> {
    for attribute in e.attributes() {
        let attribute = attribute.map_err(|e| e.to_string())?;
        attribute
            .normalized_value(quick_xml::XmlVersion::Implicit1_0)
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Write the cross-check reference files `<modelIdentifier>_ref.csv` and
/// `<modelIdentifier>_ref.opt` of `scene` into `dir`.
pub fn write_cross_check(scene: &Scene, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let id = crate::fmi_common::description::model_identifier(&scene.name);
    cross_check::write::<ExportedDynamics>(scene, &id, dir)
}

/// The paths `write_cross_check` writes for a scene named `scene_name`.
pub fn cross_check_files(scene_name: &str, dir: &Path) -> Vec<PathBuf> {
    let id = crate::fmi_common::description::model_identifier(scene_name);
    cross_check::files(&id, dir).to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_native_warning_names_the_cpu_only_for_a_build_for_one() {
        let path = Path::new("/t/libguideway.so");
        let portable = native_warning(path, false);
        assert!(
            portable.starts_with("packaging /t/libguideway.so: the native build needs the glibc")
        );
        assert!(!portable.contains("CPU"));
        let for_cpu = native_warning(path, true);
        assert!(for_cpu.starts_with(&portable));
        assert!(for_cpu.contains("illegal instruction on CPUs without them"));
    }
}
