//! Which integrator a scene runs, and why (for `auto`).

use super::{Hht, Integrator, IntegratorKind, Rk4, TimeIntegrator};
use crate::solver::spec::SolverSpec;
use crate::system::System;
use nalgebra::Complex;

/// An integrator and what runs in words, or why it cannot run.
pub(super) type Built = Result<(Integrator, String), String>;

type Complex64 = Complex<f64>;

/// The largest step explicit RK4 is stable at for this beam (s): its
/// stability region reaches 2√2 on the imaginary axis (undamped). With
/// Rayleigh damping the eigenvalues λ = ω(−ζ ± i√(1 − ζ²)) leave that axis,
/// and stiffness-proportional damping (ζ = βω/2 large at the highest modes)
/// moves them out along the negative real axis, where the region ends at
/// −2.785: the limit is then taken over a spread of frequencies up to ω_max.
pub fn rk4_step_limit(system: &System) -> f64 {
    // Support dampers: a decay rate up to `damper_rate_bound` on the
    // negative real axis, where the region ends at −2.785.
    let dampers = system.beam.damper_rate_bound();
    let damper_limit = if dampers > 0.0 {
        2.785 / dampers
    } else {
        f64::INFINITY
    };
    rk4_beam_limit(system).min(damper_limit)
}

fn rk4_beam_limit(system: &System) -> f64 {
    let omega_max = system.beam.highest_frequency();
    let damping = system.beam.damping();
    let modal_ratio = system.beam.modal_ratio();
    if damping.is_zero() && modal_ratio.is_none() {
        return 2.0 * std::f64::consts::SQRT_2 / omega_max;
    }
    let extra = modal_ratio.unwrap_or(0.0);
    // 200 frequencies from ω_max / 10⁴ to ω_max, geometrically spaced.
    (0..=200)
        .map(|k| omega_max * libm::pow(10f64, -4.0 * k as f64 / 200.0))
        .map(|omega| damped_mode_limit(omega, damping.ratio(omega) + extra))
        .fold(f64::INFINITY, f64::min)
}

/// Largest step for which RK4 is stable on the damped oscillator ω, ζ.
fn damped_mode_limit(omega: f64, zeta: f64) -> f64 {
    let eigenvalues: Vec<Complex64> = if zeta < 1.0 {
        vec![omega * Complex64::new(-zeta, (1.0 - zeta * zeta).sqrt())]
    } else {
        let root = (zeta * zeta - 1.0).sqrt();
        vec![
            Complex64::new(omega * (-zeta - root), 0.0),
            Complex64::new(omega * (-zeta + root), 0.0),
        ]
    };
    eigenvalues
        .iter()
        .map(|&lambda| ray_limit(lambda / lambda.norm()) / lambda.norm())
        .fold(f64::INFINITY, f64::min)
}

/// Radius of a half-disk, Re z ≤ 0, inside RK4's stability region: |R| ≤ 1
/// on the imaginary axis up to 2√2, and on the arc |z| = 2.5 of the left
/// half-plane |R| ≤ 0.873 (sampled at 200,000 points, where |R| varies by
/// under 1e-3 between samples), hence inside by the maximum principle.
const LEFT_HALF_DISK: f64 = 2.5;

/// How far RK4's stability region |1 + z + z²/2 + z³/6 + z⁴/24| ≤ 1 reaches
/// along the ray z = s·`direction` (|direction| = 1): the first s where it
/// leaves, by a scan then bisection. In the left half-plane the scan starts
/// at `LEFT_HALF_DISK` (it costs a damped scene's start-up 201 rays).
fn ray_limit(direction: Complex64) -> f64 {
    // |R|² > 1: no square root (hypot) in the scan.
    let leaves = |s: f64| {
        let z = direction * s;
        (1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))).norm_sqr() > 1.0
    };
    // The region lies within |z| < 3 in every direction.
    let steps = 3000;
    let from = if direction.re <= 0.0 {
        (LEFT_HALF_DISK / 3.0 * steps as f64) as usize + 1
    } else {
        1
    };
    let Some(first) = (from..=steps).find(|&k| leaves(3.0 * k as f64 / steps as f64)) else {
        return 3.0;
    };
    let (mut lower, mut upper) = (
        3.0 * (first - 1) as f64 / steps as f64,
        3.0 * first as f64 / steps as f64,
    );
    for _ in 0..50 {
        let middle = 0.5 * (lower + upper);
        if leaves(middle) {
            upper = middle;
        } else {
            lower = middle;
        }
    }
    lower
}

/// The least numerical damping `auto` runs HHT-α with.
pub const AUTO_MIN_DAMPING: f64 = 0.1;

/// The integrator of `solver` for `system`, and what runs in words.
pub fn choose_integrator(system: &System, solver: &SolverSpec) -> Built {
    let (step, damping) = (solver.step, solver.numerical_damping);
    match solver.integrator.build(system, step, damping) {
        Some(built) => built,
        None => auto(system, step, damping),
    }
}

/// `auto`: RK4 where the step is within its stability limit, HHT-α (damped
/// at least `AUTO_MIN_DAMPING`) otherwise.
fn auto(system: &System, step: f64, damping: f64) -> Built {
    let limit = rk4_step_limit(system);
    if step <= limit {
        let (rk4, words) = Rk4::build(system, step, damping)?;
        let why = format!("; auto: the step is within RK4's stability limit {limit:.3e} s");
        return Ok((Integrator::Rk4(Box::new(rk4)), words + &why));
    }
    // Undamped HHT lets the contact force oscillate from step to step at
    // high speed (a spurious early lift-off at 150 m/s on 8 elements,
    // report/stress.md): auto damps at least a little.
    let (hht, words) = Hht::build(system, step, damping.max(AUTO_MIN_DAMPING))?;
    let why = format!("; auto: RK4 would need a step of at most {limit:.3e} s for this mesh");
    Ok((Integrator::Hht(Box::new(hht)), words + &why))
}

/// The integrator and numerical damping `auto` ran a run with, from its
/// description `words` (the scene's `damping` otherwise): what a
/// companion run pins so that it runs the same scheme.
pub fn auto_pick(words: &str, damping: f64) -> (IntegratorKind, f64) {
    match IntegratorKind::described_in(words).unwrap_or_default() {
        IntegratorKind::Hht => (IntegratorKind::Hht, damping.max(AUTO_MIN_DAMPING)),
        kind => (kind, damping),
    }
}

/// `S` for `system`, refused where `step` is beyond its stability limit.
pub(super) fn build_within_limit<S: TimeIntegrator>(
    system: &System,
    step: f64,
    damping: f64,
) -> Result<(S, String), String> {
    match S::stable_step(system) {
        Some(limit) if step > limit => Err(beyond_limit(system, step, limit, S::TITLE)),
        _ => S::build(system, step, damping),
    }
}

fn beyond_limit(system: &System, step: f64, limit: f64, title: &str) -> String {
    // What sets the highest frequency, and so what the user can change:
    // the mesh's shortest element, or the highest mode a modal run keeps.
    let (cause, remedy) = match system.beam.modal() {
        Some(basis) => (
            format!("the highest of the {} modes kept has a", basis.modes()),
            "keep fewer modes (solver.modes, solver.max_frequency)",
        ),
        None => (
            format!(
                "elements of {:.4} m give the beam a highest",
                system.beam.min_element_length()
            ),
            "use fewer elements",
        ),
    };
    format!(
        "solver.step = {step} s is beyond the stability limit of {title} \
         for this mesh: {cause} frequency of \
         {:.1} rad/s (Rayleigh damping alpha = {:e}, beta = {:e}), so the step must \
         not exceed {limit:.3e} s; shorten solver.step, \
         {remedy}, or set solver.integrator = \"hht\" or \"auto\"",
        system.beam.highest_frequency(),
        system.beam.damping().mass,
        system.beam.damping().stiffness,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_region_reaches_its_known_axis_points() {
        // Imaginary axis: 2√2; negative real axis: 2.7853 (where R(−s) = 1).
        let imaginary = ray_limit(Complex64::new(0.0, 1.0));
        assert!((imaginary - 2.0 * std::f64::consts::SQRT_2).abs() < 1e-9);
        let real = ray_limit(Complex64::new(-1.0, 0.0));
        assert!((real - 2.785_293_563).abs() < 1e-6, "{real}");
    }

    #[test]
    fn the_left_half_disk_is_inside_the_region() {
        // |R| ≤ 1 on its boundary (the arc and the imaginary axis), sampled
        // here more coarsely than for the constant's comment.
        let r = |z: Complex64| (1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))).norm();
        for k in 0..=20_000 {
            let angle = std::f64::consts::PI * (0.5 + k as f64 / 20_000.0);
            let on_arc = Complex64::from_polar(LEFT_HALF_DISK, angle);
            assert!(r(on_arc) < 0.88, "|R| = {} at {on_arc}", r(on_arc));
            let on_axis = Complex64::new(0.0, LEFT_HALF_DISK * k as f64 / 20_000.0);
            assert!(
                r(on_axis) <= 1.0 + 1e-15,
                "|R| = {} at {on_axis}",
                r(on_axis)
            );
        }
        // And the scan from it finds what a scan from 0 finds.
        for k in 0..=100 {
            let angle = std::f64::consts::PI * (0.5 + k as f64 / 100.0);
            let direction = Complex64::from_polar(1.0, angle);
            let limit = ray_limit(direction);
            assert!(limit > LEFT_HALF_DISK && limit <= 3.0, "{limit} at {angle}");
            assert!(r(direction * (limit + 1e-9)) > 1.0 - 1e-12);
        }
    }

    #[test]
    fn heavy_damping_shortens_the_limit_below_the_undamped_one() {
        let omega = 1000.0;
        let undamped = damped_mode_limit(omega, 0.0);
        assert!((undamped * omega - 2.0 * std::f64::consts::SQRT_2).abs() < 1e-9);
        // ζ = 5: the fast real eigenvalue ω(−ζ − √(ζ² − 1)) governs.
        let zeta: f64 = 5.0;
        let fast = omega * (zeta + (zeta * zeta - 1.0).sqrt());
        let limit = damped_mode_limit(omega, zeta);
        assert!((limit * fast - 2.785_293_563).abs() < 1e-6);
    }
}
