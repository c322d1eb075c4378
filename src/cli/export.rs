//! `guideway export SCENE -o NAME.fmu [--cross-check DIR]`.

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
    Ok(())
}
