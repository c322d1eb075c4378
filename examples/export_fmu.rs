//! Export an FMU without the CLI (used by scripts/test.sh):
//!
//!     cargo run --example export_fmu -- <scene.toml | built-in name> \
//!         -o Name.fmu [--cross-check DIR]
//!
//! `guideway export` (src/main.rs) is the user-facing command; this example
//! calls the same `guideway::fmu::export`.

use guideway::scene::Scene;
use std::path::PathBuf;

fn scene(arg: &str) -> Result<Scene, String> {
    Scene::load(arg).map_err(|e| e.to_string())
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut scene_arg = None;
    let mut out = None;
    let mut cross = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "-o" => out = it.next().map(PathBuf::from),
            "--cross-check" => cross = it.next().map(PathBuf::from),
            s => scene_arg = Some(s.to_string()),
        }
    }
    let scene = scene(&scene_arg.ok_or("no scene given")?)?;
    let out = out.ok_or("no -o OUTPUT.fmu given")?;
    let cdylib = guideway::fmu::default_cdylib()?;
    let e = guideway::fmu::export(&scene, &out, &cdylib)?;
    println!(
        "{} ({}, GUID {})",
        e.path.display(),
        e.model_identifier,
        e.guid
    );
    if let Some(dir) = cross {
        for p in guideway::fmu::write_cross_check(&scene, &dir)? {
            println!("{}", p.display());
        }
    }
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
