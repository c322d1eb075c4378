//! `guideway export SCENE -o NAME.fmu [--fmi 2|3] [--cross-check DIR]
//! [--ssp SYSTEM.ssp [--ssp-version 1|2] --vehicle VEHICLE.fmu --connect FROM=TO ...]`.

use super::{check_outputs, load_scene_with_inputs, ExportArgs, Failure, Inputs};
use guideway::fmu::ssp::{Experiment, SspVersion, System, SystemError};
use guideway::fmu::{self, ExportError, FmiVersion};
use guideway::scene::Scene;
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
    let fmi = if args.fmi == "3" {
        FmiVersion::V3
    } else {
        FmiVersion::V2
    };
    // A bad --connect is a usage error found before anything is written.
    let system = match (&args.ssp, &args.vehicle) {
        (Some(_), Some(vehicle)) => Some(check_system(&args, &scene, vehicle, fmi)?),
        _ => None,
    };
    let (cdylib, warning) = fmu::export_cdylib().map_err(Failure::Run)?;
    let exported = fmu::export_as(&scene, &args.out, &cdylib, fmi).map_err(|e| match e {
        // The same scene problem gives the same exit code as `run`.
        ExportError::Scene(m) => {
            Failure::Scene(format!("scene `{}` cannot be exported: {m}", scene.name))
        }
        ExportError::Io(m) => Failure::Run(m),
    })?;
    // Said once the FMU is written, so that it never hides a refusal.
    if let Some(w) = warning {
        eprintln!("warning: {w}");
    }
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
    if let (Some(ssp), Some(system)) = (&args.ssp, system) {
        system.write(&args.out, ssp).map_err(Failure::Run)?;
        println!("{}", ssp.display());
    }
    Ok(())
}

/// The `--ssp` system (SSP `--ssp-version`), its connections checked
/// against the model description the FMU (of FMI `fmi`) will have and the
/// vehicle FMU.
fn check_system(
    args: &ExportArgs,
    scene: &Scene,
    vehicle: &Path,
    fmi: FmiVersion,
) -> Result<System, Failure> {
    let xml = fmu::model_description_as(scene, fmi)
        .map_err(|e| Failure::Scene(format!("scene `{}` cannot be exported: {e}", scene.name)))?;
    let experiment = Experiment {
        stop_time: guideway::model::experiment::default_stop_time(scene),
        step_size: scene.solver.step,
    };
    let version = SspVersion::parse(&args.ssp_version).unwrap_or_default();
    fmu::ssp::check_connections(
        &scene.name,
        version,
        &xml,
        vehicle,
        &args.connect,
        experiment,
    )
    .map_err(|e| match e {
        SystemError::Connection(m) => Failure::Usage(m),
        SystemError::Io(m) => Failure::Run(m),
    })
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
