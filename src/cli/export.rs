//! `guideway export SCENE -o NAME.fmu [--cross-check DIR]
//! [--ssp SYSTEM.ssp --vehicle VEHICLE.fmu --connect FROM=TO ...]`.

use super::{load_scene, ExportArgs, Failure};
use guideway::fmu;

pub(super) fn export(args: ExportArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    let cdylib = fmu::default_cdylib().map_err(Failure::Run)?;
    let exported = fmu::export(&scene, &args.out, &cdylib).map_err(Failure::Run)?;
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
