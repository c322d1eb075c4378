//! `guideway export SCENE -o NAME.fmu [--cross-check DIR]
//! [--ssp SYSTEM.ssp --vehicle VEHICLE.fmu --connect FROM=TO ...]`.

use super::{check_outputs, load_scene_with_inputs, ExportArgs, Failure, Inputs};
use guideway::fmu::{self, ExportError};
use std::path::{Path, PathBuf};

pub(super) fn export(args: ExportArgs) -> Result<(), Failure> {
    let (scene, mut inputs) = load_scene_with_inputs(&args.scene)?;
    if let Some(vehicle) = &args.vehicle {
        inputs.push(("--vehicle FMU", vehicle.clone()));
    }
    check_paths(&args, &scene.name, &inputs)?;
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

/// Refuse an FMU, SSP or cross-check file that would overwrite an input
/// (the scene, its tables, the vehicle FMU) or another output.
fn check_paths(args: &ExportArgs, scene_name: &str, inputs: &Inputs) -> Result<(), Failure> {
    let cross_check: Vec<PathBuf> = match &args.cross_check {
        Some(dir) => fmu::cross_check_files(scene_name, dir),
        None => Vec::new(),
    };
    let mut outputs: Vec<(&str, &Path)> = vec![("-o", args.out.as_path())];
    if let Some(ssp) = &args.ssp {
        outputs.push(("--ssp", ssp.as_path()));
    }
    outputs.extend(
        cross_check
            .iter()
            .map(|p| ("--cross-check file", p.as_path())),
    );
    check_outputs(inputs, &outputs)
}
