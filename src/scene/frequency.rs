//! `beam.frequency`: the bending stiffness EI that gives the model the first
//! natural frequency an engineer specifies instead of EI.
//!
//! EI scales K's beam part only: without springs ω₁² is proportional to EI
//! (one eigen-solve at EI = 1, then scale); with elastic supports the
//! springs' share does not scale, so a secant iteration on ω₁²(EI) (nearly
//! linear) finishes the job. Either way the frequency is the model's own
//! (the same mesh and modes the simulation uses), not a closed form.

use super::{Problem, Scene, SceneError, MAX_MAGNITUDE};
use crate::structure::beam::HermiteBeam;
use std::f64::consts::TAU;

/// Secant steps before giving up.
const MAX_SECANT_STEPS: usize = 40;
/// Relative agreement of ω₁² with the target that ends the iteration.
const TOLERANCE: f64 = 1e-12;
/// Relative disagreement accepted when the iteration stalls at round-off.
const ACCEPTED: f64 = 1e-9;

/// Replace `beam.frequency` by the `beam.bending_stiffness` it implies;
/// refuse a scene that gives both or neither.
pub(super) fn resolve(scene: &mut Scene, text: &str) -> Result<(), SceneError> {
    let written = stiffness_written(text);
    let Some(f1) = scene.beam.frequency else {
        if written {
            return Ok(());
        }
        return Err(invalid(
            "beam.bending_stiffness",
            "missing",
            "give the bending stiffness EI (N m^2) or the first natural frequency \
             beam.frequency (Hz)",
        ));
    };
    if written {
        return Err(invalid(
            "beam.frequency",
            &f1.to_string(),
            "give either beam.frequency or beam.bending_stiffness, not both",
        ));
    }
    if !(f1.is_finite() && f1 > 0.0 && f1 <= MAX_MAGNITUDE) {
        return Err(invalid(
            "beam.frequency",
            &f1.to_string(),
            &format!("must be > 0 and <= {MAX_MAGNITUDE:e} (Hz)"),
        ));
    }
    // Check everything else with a placeholder EI before any eigen-solve.
    scene.beam.frequency = None;
    scene.beam.bending_stiffness = 1.0;
    scene.validate()?;
    scene.beam.bending_stiffness = stiffness_for(scene, f1)
        .map_err(|rule| invalid("beam.frequency", &f1.to_string(), &rule))?;
    Ok(())
}

/// Whether the scene's text writes `beam.bending_stiffness` (a written
/// `nan` counts: it must not pass as "left out").
fn stiffness_written(text: &str) -> bool {
    text.parse::<toml::Table>().is_ok_and(|table| {
        table
            .get("beam")
            .and_then(|beam| beam.get("bending_stiffness"))
            .is_some()
    })
}

/// The EI whose model has first natural frequency `f1` (Hz).
fn stiffness_for(scene: &Scene, f1: f64) -> Result<f64, String> {
    let target = (TAU * f1).powi(2);
    let squared = |ei: f64| first_omega_squared(scene, ei);
    let (mut ei_a, mut w_a) = (1.0, squared(1.0)?);
    if w_a <= 0.0 {
        return Err(
            "the structure can move as a rigid body (its first frequency is 0), \
                    which EI cannot change: support it, or give beam.bending_stiffness"
                .into(),
        );
    }
    let mut ei_b = target / w_a;
    let mut w_b = squared(ei_b)?;
    for _ in 0..MAX_SECANT_STEPS {
        if (w_b - target).abs() <= TOLERANCE * target {
            return Ok(ei_b);
        }
        let slope = (w_b - w_a) / (ei_b - ei_a);
        let next = ei_b + (target - w_b) / slope;
        if !(next.is_finite() && next > 0.0) || next == ei_b {
            break;
        }
        (ei_a, w_a) = (ei_b, w_b);
        ei_b = next;
        w_b = squared(ei_b)?;
    }
    if (w_b - target).abs() <= ACCEPTED * target {
        return Ok(ei_b);
    }
    Err(format!(
        "no bending stiffness gives this first frequency (the nearest found, EI = {ei_b:e} \
         N m^2, gives {:.6} Hz): the springs and the mass alone set a bound; give \
         beam.bending_stiffness instead",
        w_b.max(0.0).sqrt() / TAU
    ))
}

/// ω₁² (rad²/s²) of the scene's structure with bending stiffness `ei`.
fn first_omega_squared(scene: &Scene, ei: f64) -> Result<f64, String> {
    let mut spec = scene.beam.clone();
    spec.bending_stiffness = ei;
    spec.damping = None; // no bearing on the undamped frequencies
    let beam = HermiteBeam::new(&spec)?;
    let omega = beam.frequencies(1)?;
    Ok(omega.first().map_or(0.0, |w| w * w))
}

fn invalid(path: &str, value: &str, rule: &str) -> SceneError {
    SceneError::Invalid {
        problems: vec![Problem::new(path, value, rule)],
    }
}
