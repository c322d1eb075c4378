//! Where a coarse run's error comes from: the local error of every step.
//!
//! A fine reference runs the scene at Δt / `fine` with the quadratic force
//! profile. At every grid point of Δt the coarse simulation is restored to
//! the reference's state (its force history the reference's own means
//! over the last coarse steps, so that a shaped profile is fitted to the
//! same data as in a coarse run) and takes one step; its difference from
//! the reference at the step's end is that step's local error. The
//! global error is what these errors become after propagation, so a step
//! whose local error stands out (a node crossing, the entry) shows here.

use nalgebra::Vector2;
use rustfft::num_complex::Complex;
use rustfft::FftPlannerScalar;

use crate::contact::ContactForce;
use crate::outputs::QuantityKind;
use crate::scene::{ForceProfile, Scene};
use crate::{Advance, Simulation};

/// Fine steps per coarse step are refused beyond this (the reference's
/// step count grows with it).
pub const MAX_FINE: usize = 1024;

/// The local error of one coarse step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepError {
    /// The step's end (s).
    pub time: f64,
    /// The first contact's abscissa at the step's end (m).
    pub position: f64,
    /// Coarse minus reference nominal speed of the first body (m/s).
    pub speed: f64,
    /// Coarse minus reference energy balance, per initial energy.
    pub energy: f64,
}

/// The local errors of the steps of `scene.solver.step` along its run
/// (single-contact scenes without events before the exit), against a
/// reference `fine` times finer. The first two steps, which a coarse run
/// takes without a fitted history, are left out.
pub fn local_errors(scene: &Scene, fine: usize) -> Result<Vec<StepError>, String> {
    if !(1..=MAX_FINE).contains(&fine) {
        return Err(format!("fine = {fine}: must be 1 to {MAX_FINE}"));
    }
    let dt = scene.solver.step;
    let mut reference_scene = scene.clone();
    reference_scene.solver.force_profile = ForceProfile::Quadratic;
    reference_scene.solver.step = dt / fine as f64;
    let mut reference = Simulation::new(&reference_scene)?;
    let mut coarse = Simulation::new(scene)?;
    let speed = column(&coarse, QuantityKind::NominalSpeed)?;
    let energy = column(&coarse, QuantityKind::Balance)?;
    let initial_energy = reference.initial_energy();
    if reference.current().force_history.len() != 1 {
        return Err("local errors are measured on single-contact scenes".into());
    }
    let mut means = [ContactForce::default(); 3];
    let mut errors = Vec::new();
    for k in 0u64.. {
        let start = reference.state();
        let Some(mean) = advance_summing(&mut reference, k, fine)? else {
            break;
        };
        if k >= 2 {
            let mut from = start;
            from.grid_step = k;
            from.steps = k;
            from.step_history = [dt, dt];
            from.force_history = vec![means];
            from.last_position_iterations = 0;
            coarse.restore(&from)?;
            let end = (k + 1) as f64 * dt;
            if coarse.advance_to(end).map_err(|e| e.to_string())? == Advance::Reached {
                errors.push(StepError {
                    time: reference.time(),
                    position: reference.current().dynamic.contact_x[0],
                    speed: value(&coarse, speed) - value(&reference, speed),
                    energy: (value(&coarse, energy) - value(&reference, energy)) / initial_energy,
                });
            }
        }
        means = [mean, means[0], means[1]];
    }
    Ok(errors)
}

/// Advance the reference over coarse step `k` (`fine` steps); the mean of
/// its contact force over them, or `None` once the run is over.
fn advance_summing(
    reference: &mut Simulation,
    k: u64,
    fine: usize,
) -> Result<Option<ContactForce>, String> {
    let h = reference.step_size();
    let mut sum = Vector2::zeros();
    for j in 1..=fine as u64 {
        let to = (k * fine as u64 + j) as f64 * h;
        if let Advance::Exited { .. } = reference.advance_to(to).map_err(|e| e.to_string())? {
            return Ok(None);
        }
        sum += reference.current().force_history[0][0].as_vector();
    }
    Ok(Some(ContactForce::from_vector(sum / fine as f64)))
}

/// The first output of `sim` reporting `wanted` (the live catalogue's).
fn column(sim: &Simulation, wanted: QuantityKind) -> Result<usize, String> {
    sim.quantities()
        .iter()
        .position(|q| q.kind() == wanted)
        .ok_or_else(|| "the scene has no such output".to_string())
}

fn value(sim: &Simulation, index: usize) -> f64 {
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    values[index]
}

/// The angular frequency (rad/s) at which `samples`, taken every `dt`,
/// have the largest amplitude (the mean left out): which motion the
/// errors follow.
pub fn dominant_frequency(samples: &[f64], dt: f64) -> f64 {
    let n = samples.len();
    if n < 2 {
        return 0.0;
    }
    let mean = samples.iter().sum::<f64>() / n as f64;
    let mut buffer: Vec<Complex<f64>> = samples
        .iter()
        .map(|&s| Complex::new(s - mean, 0.0))
        .collect();
    FftPlannerScalar::new()
        .plan_fft_forward(n)
        .process(&mut buffer);
    let peak = (1..=n / 2)
        .max_by(|&a, &b| buffer[a].norm().total_cmp(&buffer[b].norm()))
        .unwrap_or(0);
    2.0 * std::f64::consts::PI * peak as f64 / (n as f64 * dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominant_frequency_finds_a_sine_among_others() {
        let dt = 0.0025;
        let samples: Vec<f64> = (0..900)
            .map(|i| {
                let t = i as f64 * dt;
                0.3 + libm::sin(300.0 * t) + 0.4 * libm::cos(60.0 * t)
            })
            .collect();
        let omega = dominant_frequency(&samples, dt);
        // The bin width is 2π / (n Δt) = 2.8 rad/s.
        assert!((omega - 300.0).abs() < 3.0, "{omega}");
    }

    #[test]
    fn a_fine_count_out_of_range_is_refused() {
        let scene = crate::scene::builtin("lee1994-wheel-10").expect("built in");
        let error = local_errors(&scene, 0).unwrap_err();
        assert!(error.contains("fine = 0"), "{error}");
        assert!(local_errors(&scene, MAX_FINE + 1).is_err());
    }
}
