//! `guideway modes SCENE [--count N] [--out CSV]`: the beam's natural
//! frequencies, and its mode shapes as CSV.

use std::fmt::Write as _;

use super::{check_outputs, load_scene_with_inputs, Failure, ModesArgs};
use guideway::beam::{Beam, Modes};

pub(super) fn modes(args: ModesArgs) -> Result<(), Failure> {
    let (scene, inputs) = load_scene_with_inputs(&args.scene)?;
    if let Some(out) = &args.out {
        check_outputs(&inputs, &[("--out", out.as_path())])?;
    }
    let beam = Beam::new(&scene.beam).map_err(Failure::Scene)?;
    let modes = beam.modes(args.count).map_err(Failure::Scene)?;
    let damping = beam.damping();
    // One ratio for every mode (`beam.damping = { ratio }`) adds to each.
    let modal_ratio = match scene.beam.damping {
        Some(guideway::scene::DampingSpec::Modal { ratio }) => ratio,
        _ => 0.0,
    };
    println!("mode  f (Hz)        omega (rad/s)  damping ratio");
    for (k, &omega) in modes.omega.iter().enumerate() {
        println!(
            "{:>4}  {:<12.6}  {:<13.6}  {:.6}",
            k + 1,
            omega / std::f64::consts::TAU,
            omega,
            damping.ratio(omega) + modal_ratio
        );
    }
    if let Some(path) = &args.out {
        std::fs::write(path, shapes_csv(&beam, &modes))
            .map_err(|e| Failure::Run(format!("{}: {e}", path.display())))?;
        println!("mode shapes: {}", path.display());
    }
    Ok(())
}

/// One row per node: x and each mode's deflection, scaled so that its
/// largest |w| is 1 and positive.
fn shapes_csv(beam: &Beam, modes: &Modes) -> String {
    let count = modes.omega.len();
    let columns: Vec<Vec<f64>> = (0..count)
        .map(|k| {
            let shape = modes.shapes.column(k).into_owned();
            let w: Vec<f64> = beam
                .node_x
                .iter()
                .map(|&x| beam.deflection(&shape, x))
                .collect();
            let peak = w
                .iter()
                .copied()
                .fold(0.0, |a: f64, b| if b.abs() > a.abs() { b } else { a });
            let scale = if peak == 0.0 { 1.0 } else { 1.0 / peak };
            w.iter().map(|v| v * scale).collect()
        })
        .collect();
    let mut text = String::from("x");
    for k in 0..count {
        let _ = write!(text, ",mode_{}", k + 1);
    }
    text.push('\n');
    for (i, x) in beam.node_x.iter().enumerate() {
        let _ = write!(text, "{x}");
        for column in &columns {
            let _ = write!(text, ",{}", column[i]);
        }
        text.push('\n');
    }
    text
}
