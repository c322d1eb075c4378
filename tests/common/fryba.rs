//! Frýba's moving-force case (1972, "Vibration of solids and structures
//! under moving loads", ch. 1): a constant force crossing a simply supported,
//! undamped beam at constant speed. Its numbers and the series that several
//! tests check guideway's runs against.

use std::f64::consts::PI;

/// Span (m).
pub const LENGTH: f64 = 24.0;
/// Mass per length (kg/m).
pub const MASS: f64 = 1250.0;
/// Bending stiffness (N m²).
pub const EI: f64 = 1e9;
/// The crossing force (N).
pub const FORCE: f64 = 600e3;

/// The beam's first circular frequency ω₁ = (π / L)² √(EI / μ) (rad/s).
pub fn omega1() -> f64 {
    (PI / LENGTH).powi(2) * (EI / MASS).sqrt()
}

/// The speed (m/s) at α = c / c_cr, with c_cr = ω₁ L / π.
pub fn speed(alpha: f64) -> f64 {
    alpha * omega1() * LENGTH / PI
}

/// Frýba's v₀ = 2 P L³ / (π⁴ EI), the first mode's static midspan
/// deflection (1.5 % under P L³ / 48 EI), the unit of the series.
pub fn v0() -> f64 {
    2.0 * FORCE * LENGTH.powi(3) / (PI.powi(4) * EI)
}

/// Midspan deflection over v₀ (down positive) at `t` of the force crossing
/// at `alpha` (≠ 1) and of the beam's free vibration after it has left at
/// L / c, 200 modes.
pub fn series_midspan_with_free_vibration(alpha: f64, t: f64) -> f64 {
    let (w1, exit) = (omega1(), LENGTH / speed(alpha));
    let omega = alpha * w1;
    (1..=200)
        .map(|j| {
            let jf = j as f64;
            let mode = libm::sin(jf * PI / 2.0);
            let wj = jf * jf * w1;
            let d = jf * jf * (jf * jf - alpha * alpha);
            let q = |t: f64| (libm::sin(jf * omega * t) - alpha / jf * libm::sin(wj * t)) / d;
            let q_dot = |t: f64| {
                (jf * omega * libm::cos(jf * omega * t) - alpha / jf * wj * libm::cos(wj * t)) / d
            };
            let value = if t <= exit {
                q(t)
            } else {
                let s = t - exit;
                q(exit) * libm::cos(wj * s) + q_dot(exit) / wj * libm::sin(wj * s)
            };
            value * mode
        })
        .sum()
}
