//! A constant force crossing a simply supported beam at constant speed,
//! undamped (issue 11 item 4): guideway's moving force against the series
//! solution of Frýba (1972), "Vibration of solids and structures under
//! moving loads", chapter 1.
//!
//! With v₀ = 2PL³/(π⁴EI), ω = πc/L, ω_j = j²π²/L² √(EI/μ) and α = c/c_cr
//! = ω/ω₁, the deflection (down positive) from rest is
//!
//!   v(x, t) = v₀ Σ_j [sin jωt − (α/j) sin ω_j t] / (j²(j² − α²)) · sin(jπx/L),
//!
//! the j = 1 term at α = 1 being its limit ½(sin ωt − ωt cos ωt). At α = 1
//! every term vanishes at t = L/c except the first: v(L/2, L/c) = (π/2) v₀.

use guideway::beam::Beam;
use guideway::moving_load::{Axle, Crossing};
use guideway::scene::BeamSpec;
use std::f64::consts::PI;

use crate::common::fryba::{omega1, v0, EI, FORCE, LENGTH, MASS};

/// Fine mesh and step: 40 elements, 4000 steps per crossing.
const ELEMENTS: usize = 40;
const STEPS: usize = 4000;

fn beam() -> Beam {
    Beam::new(&BeamSpec {
        length: LENGTH,
        mass_per_length: MASS,
        bending_stiffness: EI,
        surface_offset: 0.0,
        elements: ELEMENTS,
        ..BeamSpec::default()
    })
    .expect("beam builds")
}

/// Frýba's series at midspan (down positive), 200 terms.
fn series_midspan(alpha: f64, t: f64) -> f64 {
    let w1 = omega1();
    let omega = alpha * w1;
    (1..=200)
        .map(|j| {
            let jf = j as f64;
            let mode = libm::sin(jf * PI / 2.0);
            if mode.abs() < 1e-12 {
                return 0.0;
            }
            let term = if j == 1 && (alpha - 1.0).abs() < 1e-12 {
                0.5 * (libm::sin(omega * t) - omega * t * libm::cos(omega * t))
            } else {
                (libm::sin(jf * omega * t) - alpha / jf * libm::sin(jf * jf * w1 * t))
                    / (jf * jf * (jf * jf - alpha * alpha))
            };
            term * mode
        })
        .sum::<f64>()
        * v0()
}

/// guideway's midspan deflection (down positive) at every step of the
/// crossing at α; the last sample is at t = L/c.
fn crossing_midspan(alpha: f64) -> Vec<f64> {
    let beam = beam();
    let speed = alpha * omega1() * LENGTH / PI;
    let axles = [Axle {
        position: 0.0,
        speed,
        force: -FORCE,
    }];
    let crossing_time = LENGTH / speed;
    let mut crossing = Crossing::new(&beam, &axles, crossing_time / STEPS as f64).expect("builds");
    (0..STEPS)
        .map(|_| {
            crossing.step();
            -crossing.deflection(LENGTH / 2.0)
        })
        .collect()
}

#[test]
fn at_the_critical_speed_the_force_leaves_a_deflection_of_pi_over_two_v0() {
    let samples = crossing_midspan(1.0);
    let at_exit = *samples.last().unwrap();
    let expected = PI / 2.0 * v0();
    let error = (at_exit - expected).abs() / expected;
    eprintln!(
        "alpha = 1: midspan at exit {at_exit:.6} m, (pi/2) v0 = {expected:.6} m, error {error:.2e}"
    );
    assert!(error <= 0.005, "error {error:.3e}");
}

#[test]
fn the_largest_deflection_over_the_crossing_matches_the_series() {
    for alpha in [0.1, 0.5, 1.0] {
        let computed = crossing_midspan(alpha).into_iter().fold(0.0, f64::max);
        let crossing_time = PI / (alpha * omega1());
        let series = (0..=20_000)
            .map(|k| series_midspan(alpha, crossing_time * k as f64 / 20_000.0))
            .fold(0.0, f64::max);
        let error = (computed - series).abs() / series;
        eprintln!(
            "alpha = {alpha}: largest midspan deflection {computed:.6} m, series {series:.6} m \
             ({:.4} v0), error {error:.2e}",
            series / v0()
        );
        assert!(error <= 0.005, "alpha = {alpha}: error {error:.3e}");
    }
}
