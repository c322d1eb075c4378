//! `guideway export SCENE -o NAME.fmu [--cross-check DIR]
//! [--ssp SYSTEM.ssp --vehicle VEHICLE.fmu --connect FROM=TO ...]`.

use super::{load_scene, ExportArgs, Failure};
use guideway::fmu::{self, ExportError};
use guideway::output_file::check_distinct;
use std::path::{Path, PathBuf};

pub(super) fn export(args: ExportArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    check_paths(&args, &scene.name)?;
    if args.cross_check.is_some() {
        fmu::cross_check::check_length(&scene).map_err(|m| {
            Failure::Scene(format!(
                "scene `{}` cannot be cross-checked: {m}",
                scene.name
            ))
        })?;
    }
    let cdylib = fmu::default_cdylib().map_err(Failure::Run)?;
    let exported = fmu::export(&scene, &args.out, &cdylib).map_err(|e| match e {
        // The same scene problem gives the same exit code as `run`.
        ExportError::Scene(m) => {
            Failure::Scene(format!("scene `{}` cannot be exported: {m}", scene.name))
        }
        ExportError::Io(m) => Failure::Run(m),
    })?;
    println!(
        "{} (model identifier {}, GUID {})",
        exported.path.display(),
        exported.model_identifier,
        exported.guid
    );
    if let Some(dir) = &args.cross_check {
        for path in fmu::write_cross_check(&scene, dir).map_err(Failure::Run)? {
            println!("{}", path.display());
        }
    }
    if let (Some(ssp), Some(vehicle)) = (&args.ssp, &args.vehicle) {
        fmu::ssp::write(&scene.name, &args.out, vehicle, &args.connect, ssp)
            .map_err(Failure::Run)?;
        println!("{}", ssp.display());
    }
    Ok(())
}

/// Refuse an FMU or cross-check file that would overwrite the scene file or
/// another output.
fn check_paths(args: &ExportArgs, scene_name: &str) -> Result<(), Failure> {
    let scene_file = Path::new(&args.scene);
    let inputs: Vec<(&str, &Path)> = if scene_file.is_file() {
        vec![("scene file", scene_file)]
    } else {
        Vec::new()
    };
    let cross_check: Vec<PathBuf> = match &args.cross_check {
        Some(dir) => fmu::cross_check_files(scene_name, dir),
        None => Vec::new(),
    };
    let mut outputs: Vec<(&str, &Path)> = vec![("-o", args.out.as_path())];
    outputs.extend(
        cross_check
            .iter()
            .map(|p| ("--cross-check file", p.as_path())),
    );
    check_distinct(&inputs, &outputs).map_err(Failure::Usage)
}
