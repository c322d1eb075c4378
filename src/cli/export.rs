//! `guideway export SCENE -o NAME.fmu [--cross-check DIR]`.

use super::{ExportArgs, Failure};
use guideway::fmu;
use guideway::Scene;

pub(super) fn export(args: ExportArgs) -> Result<(), Failure> {
    let scene = Scene::load(&args.scene)?;
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
    Ok(())
}
