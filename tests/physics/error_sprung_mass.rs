//! Acceptance of `guideway run --error` (issue 25) on a sprung mass: the
//! estimated step error of each summary figure of a moving oscillator
//! crossing a simply supported beam, against its true error from an
//! independent reference written here: the classical coupled equations in
//! modal coordinates (sine modes), integrated finely with this file's own
//! classical RK4 (Yang & Yau 1997's sprung mass: L = 25 m, EI = 8.5347e10
//! N m², m̄ = 2303 kg/m, M_v = 5750 kg, k_v = 1595 kN/m, 100 km/h, g).

use guideway::scene::Scene;
use guideway::study::convergence::Estimate;
use guideway::study::refine::{error_study, Refinement};
use std::f64::consts::PI;

use crate::common::yang_yau::{EI, LENGTH, MASS_PER_LENGTH, SPEED, SPRUNG, STIFFNESS, UNSPRUNG};
use crate::common::GRAVITY;

const MODES: usize = 30;

/// The scene at `step` (s): 20 elements, midspan sensor, run to the exit.
fn scene(step: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "sprung-mass"
gravity = {GRAVITY:?}
[beam]
length = {LENGTH:?}
mass_per_length = {MASS_PER_LENGTH:?}
bending_stiffness = {EI:?}
surface_offset = 0.0
elements = 20
[body]
name = "car"
kind = "sprung_mass"
mass = {SPRUNG:?}
initial_speed = {SPEED:?}
[body.suspension]
stiffness = {STIFFNESS:?}
damping = 0.0
unsprung_mass = {UNSPRUNG:?}
[[sensors]]
name = "midspan"
position = {:?}
[solver]
step = {step:?}
integrator = "hht"
"#,
        LENGTH / 2.0
    ))
    .expect("valid scene")
}

fn wavenumber(n: usize) -> f64 {
    (n + 1) as f64 * PI / LENGTH
}

/// Rates of y = (q, q̇, u, u̇) at t, with the modal accelerations q̈:
/// q̈ₙ + ωₙ² qₙ = −(2 / m̄L) φₙ(Vt) N, N = m_u (ẅ_c + g) + F_s, the
/// unsprung mass riding the deflected beam (ẅ_c = φ·q̈ + 2V φ'·q̇ + V² φ''·q),
/// F_s = M_v g − k (u − w_c); the sprung mass M_v ü = −k (u − w_c).
fn rates(t: f64, y: &[f64]) -> Vec<f64> {
    let m = MODES;
    let (q, qd) = (&y[..m], &y[m..2 * m]);
    let x = SPEED * t;
    let phi: Vec<f64> = (0..m).map(|n| libm::sin(wavenumber(n) * x)).collect();
    let dphi: Vec<f64> = (0..m)
        .map(|n| wavenumber(n) * libm::cos(wavenumber(n) * x))
        .collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let w_c = dot(&phi, q);
    let curvature_term: f64 = (0..m).map(|n| -wavenumber(n).powi(2) * phi[n] * q[n]).sum();
    let delta = y[2 * m] - w_c;
    let spring = SPRUNG * GRAVITY - STIFFNESS * delta;
    let convective = 2.0 * SPEED * dot(&dphi, qd) + SPEED * SPEED * curvature_term;
    let a = 2.0 / (MASS_PER_LENGTH * LENGTH);
    let omega2 = |n: usize| wavenumber(n).powi(4) * EI / MASS_PER_LENGTH;
    let b: Vec<f64> = (0..m)
        .map(|n| -omega2(n) * q[n] - a * phi[n] * (UNSPRUNG * (convective + GRAVITY) + spring))
        .collect();
    // q̈ = b − a m_u φ (φ·q̈): a rank-one system, solved for φ·q̈.
    let phi_qdd = dot(&phi, &b) / (1.0 + a * UNSPRUNG * dot(&phi, &phi));
    let mut rates = vec![0.0; 2 * m + 2];
    rates[..m].copy_from_slice(qd);
    for n in 0..m {
        rates[m + n] = b[n] - a * UNSPRUNG * phi[n] * phi_qdd;
    }
    rates[2 * m] = y[2 * m + 1];
    rates[2 * m + 1] = -STIFFNESS * delta / SPRUNG;
    rates
}

/// The reference's peaks at midspan over the crossing (0 to L/V), each
/// the value of largest magnitude (sign kept, as the summary keeps it):
/// deflection (the most negative), velocity, acceleration.
fn reference_peaks(substeps: usize) -> [f64; 3] {
    let crossing = LENGTH / SPEED;
    let h = crossing / substeps as f64;
    let m = MODES;
    let mut y = vec![0.0; 2 * m + 2];
    let mid: Vec<f64> = (0..m)
        .map(|n| libm::sin(wavenumber(n) * LENGTH / 2.0))
        .collect();
    let at_mid = |v: &[f64]| mid.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let mut peaks = [0.0f64; 3];
    let keep = |peaks: &mut [f64; 3], t: f64, y: &[f64], deflection: f64| {
        let r = rates(t, y);
        let values = [deflection, at_mid(&y[m..2 * m]), at_mid(&r[m..2 * m])];
        peaks[0] = peaks[0].min(values[0]);
        for k in 1..3 {
            if values[k].abs() > peaks[k].abs() {
                peaks[k] = values[k];
            }
        }
    };
    for step in 0..substeps {
        let t = step as f64 * h;
        let k1 = rates(t, &y);
        let shifted =
            |k: &[f64], s: f64| -> Vec<f64> { y.iter().zip(k).map(|(a, b)| a + s * b).collect() };
        let k2 = rates(t + 0.5 * h, &shifted(&k1, 0.5 * h));
        let k3 = rates(t + 0.5 * h, &shifted(&k2, 0.5 * h));
        let k4 = rates(t + h, &shifted(&k3, h));
        for i in 0..y.len() {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        let deflection = at_mid(&y[..m]);
        keep(&mut peaks, t + h, &y, deflection);
    }
    peaks
}

/// Within [1/3, 10] × the true error: an underestimate is worse than none.
fn assert_brackets(estimate: &Estimate, truth: f64) {
    let error = estimate.error.expect("an error estimate");
    let true_error = (estimate.value - truth).abs();
    let ratio = error / true_error;
    eprintln!(
        "{:48} value {:.6e} reference {truth:.6e} estimate {error:.3e} true {true_error:.3e} \
         ratio {ratio:.2} order {:?} {:?}",
        estimate.name, estimate.value, estimate.order, estimate.not_converged
    );
    assert!(
        (1.0 / 3.0..=10.0).contains(&ratio),
        "{}: estimate {error:e} against true error {true_error:e}",
        estimate.name
    );
}

#[test]
fn sprung_mass_estimates_bracket_the_error_against_modal_superposition() {
    // The reference at two resolutions: their difference bounds its own
    // error, asserted below a tenth of each true error checked.
    let (reference, check) = (reference_peaks(800_000), reference_peaks(400_000));
    eprintln!("reference {reference:?}, at half its resolution {check:?}");
    let study = error_study(&scene(2.5e-4), Refinement::Time, 1_000_000, 2).expect("study runs");
    let of = |name: &str| {
        study
            .estimates
            .iter()
            .find(|e| e.name == name)
            .unwrap_or_else(|| panic!("no figure {name}"))
    };
    let static_midspan = (SPRUNG + UNSPRUNG) * GRAVITY * LENGTH.powi(3) / (48.0 * EI);
    let daf = |peaks: &[f64; 3]| peaks[0].abs() / static_midspan;
    let checks = [
        ("peak_sensor_deflection.midspan", reference[0], check[0]),
        (
            "peak_design.sensor.midspan.deflection",
            reference[0],
            check[0],
        ),
        (
            "peak_design.sensor.midspan.velocity",
            reference[1],
            check[1],
        ),
        (
            "peak_design.sensor.midspan.acceleration",
            reference[2],
            check[2],
        ),
        (
            "dynamic_amplification.sensor.midspan.deflection",
            daf(&reference),
            daf(&check),
        ),
    ];
    for (name, truth, coarser_truth) in checks {
        let estimate = of(name);
        assert_brackets(estimate, truth);
        let own_error = (truth - coarser_truth).abs();
        assert!(
            own_error < 0.1 * (estimate.value - truth).abs(),
            "{name}: reference {own_error:e}"
        );
    }
}
