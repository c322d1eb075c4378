//! Export an FMU without the CLI (used by scripts/test.sh):
//!
//!     cargo run --example export_fmu -- <scene.toml | lee1994-wheel-10 | lee1994-glider-20> \
//!         -o Name.fmu [--cross-check DIR]
//!
//! `guideway export` (src/main.rs) is the user-facing command; this example
//! calls the same `guideway::fmu::export`.

use guideway::scene::{BodyKind, Scene};
use std::path::PathBuf;

fn scene(arg: &str) -> Result<Scene, String> {
    if arg.ends_with(".toml") {
        let text = std::fs::read_to_string(arg).map_err(|e| format!("{arg}: {e}"))?;
        return toml::from_str(&text).map_err(|e| format!("{arg}: {e}"));
    }
    let parts: Vec<&str> = arg.split('-').collect();
    let (kind, speed) = match parts.as_slice() {
        ["lee1994", "wheel", v] => (BodyKind::Wheel, v),
        ["lee1994", "glider", v] => (BodyKind::Glider, v),
        _ => {
            return Err(format!(
                "unknown scene {arg}: give a .toml file or lee1994-<wheel|glider>-<speed>"
            ))
        }
    };
    let speed: f64 = speed.parse().map_err(|e| format!("{arg}: speed: {e}"))?;
    Ok(Scene::lee1994(kind, speed, 0.0025))
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
