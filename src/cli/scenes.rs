//! `guideway scenes [NAME | --show NAME]`.

use super::{load_scene, Failure, ScenesArgs};
use guideway::moving_load::HSLM_TRAINS;
use guideway::scene::{builtins, templates, DEFAULT_SCENE};

pub(super) fn scenes(args: ScenesArgs) -> Result<(), Failure> {
    match args.name.or(args.show) {
        Some(name) => {
            let scene = load_scene(&name)?;
            print!("{}", scene.to_annotated_toml());
        }
        None => {
            let width = builtins()
                .iter()
                .map(|(name, _)| name.len())
                .max()
                .unwrap_or(0);
            for (name, description) in builtins() {
                println!("{name:width$}  {description}");
            }
            let names: Vec<&str> = templates().map(|(name, _)| name).collect();
            println!();
            println!(
                "Bridge templates (`guideway scenes --show NAME > my.toml`): {}",
                names.join(", ")
            );
            let trains: Vec<&str> = HSLM_TRAINS.iter().map(|t| t.name).collect();
            println!();
            println!(
                "Trains for moving forces (kind = \"moving_force\", train = NAME; EN 1991-2 \
                 Annex E): {}",
                trains.join(", ")
            );
            println!();
            println!("`guideway run NAME` runs one ({DEFAULT_SCENE} when none is given);");
            println!("`guideway scenes --show NAME > my.toml` starts a scene file from one.");
        }
    }
    Ok(())
}
