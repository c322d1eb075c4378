//! A sprung mass (moving oscillator) crossing a simply supported beam at
//! constant speed, against an independent modal-superposition solution
//! written here: the sprung-mass example of Yang & Yau (1997) (L = 25 m,
//! EI = 2.943e10 N/m² × 2.90 m⁴, m̄ = 2303 kg/m, M_v = 5750 kg,
//! k_v = 1595 kN/m, V = 100 km/h, gravity 9.81 m/s²), with an unsprung
//! contact mass of 1 % of M_v (the literature's contact point is massless).

use guideway::{Advance, Scene, Simulation};

use crate::common::yang_yau::{EI, LENGTH, MASS_PER_LENGTH, SPEED, SPRUNG, STIFFNESS, UNSPRUNG};
use crate::common::{largest_difference, peak, GRAVITY};

const STEP: f64 = 1.25e-5;

fn scene(damping: f64) -> Scene {
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
damping = {damping:?}
unsprung_mass = {UNSPRUNG:?}
[[sensors]]
name = "midspan"
position = {:?}
[solver]
step = {STEP:?}
"#,
        LENGTH / 2.0
    ))
    .expect("valid scene")
}

/// Sampled histories: time, midspan deflection, sprung-mass acceleration.
struct History {
    time: Vec<f64>,
    midspan: Vec<f64>,
    acceleration: Vec<f64>,
}

fn guideway_history(scene: &Scene) -> History {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (midspan, ay) = (at("sensor.midspan.deflection"), at("car.ay"));
    let mut values = vec![0.0; names.len()];
    let mut history = History {
        time: Vec::new(),
        midspan: Vec::new(),
        acceleration: Vec::new(),
    };
    for k in 1.. {
        let advance = sim.advance_to(k as f64 * STEP).expect("no solver error");
        if advance != Advance::Reached {
            break;
        }
        sim.output_values(&mut values);
        history.time.push(sim.time());
        history.midspan.push(values[midspan]);
        history.acceleration.push(values[ay]);
    }
    history
}

/// Modal superposition with `modes` sine modes, classical RK4 at `h`:
/// q̈ₙ + ωₙ² qₙ = −(2 / m̄L) φₙ(Vt) N, with the contact force
/// N = m_u (ẅ_c + g) + F_s carrying the unsprung mass along the deflected
/// beam (ẅ_c = φ·q̈ + 2V φ'·q̇ + V² φ''·q) and the suspension force
/// F_s = M_v g − k δ − c δ̇, δ = u − w_c; the sprung mass: M_v ü = −k δ − c δ̇.
struct Modal {
    modes: usize,
    damping: f64,
}

impl Modal {
    fn omega(&self, n: usize) -> f64 {
        let k = (n + 1) as f64 * std::f64::consts::PI / LENGTH;
        k * k * (EI / MASS_PER_LENGTH).sqrt()
    }

    /// φ, φ', φ'' of every mode at x.
    fn shapes(&self, x: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut phi = vec![0.0; self.modes];
        let mut dphi = vec![0.0; self.modes];
        let mut ddphi = vec![0.0; self.modes];
        for n in 0..self.modes {
            let k = (n + 1) as f64 * std::f64::consts::PI / LENGTH;
            phi[n] = libm::sin(k * x);
            dphi[n] = k * libm::cos(k * x);
            ddphi[n] = -k * k * libm::sin(k * x);
        }
        (phi, dphi, ddphi)
    }

    /// Rates of y = (q, q̇, u, u̇) at time t; also the sprung acceleration.
    fn rates(&self, t: f64, y: &[f64]) -> (Vec<f64>, f64) {
        let m = self.modes;
        let (q, qd) = (&y[..m], &y[m..2 * m]);
        let (u, ud) = (y[2 * m], y[2 * m + 1]);
        let (phi, dphi, ddphi) = self.shapes(SPEED * t);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let w_c = dot(&phi, q);
        let wd_c = dot(&phi, qd) + SPEED * dot(&dphi, q);
        let (delta, delta_rate) = (u - w_c, ud - wd_c);
        let spring = SPRUNG * GRAVITY - STIFFNESS * delta - self.damping * delta_rate;
        let convective = 2.0 * SPEED * dot(&dphi, qd) + SPEED * SPEED * dot(&ddphi, q);
        let a = 2.0 / (MASS_PER_LENGTH * LENGTH);
        // q̈ = b − a m_u φ (φ·q̈), solved for φ·q̈ (a rank-one update).
        let b: Vec<f64> = (0..m)
            .map(|n| {
                -self.omega(n).powi(2) * q[n]
                    - a * phi[n] * (UNSPRUNG * (convective + GRAVITY) + spring)
            })
            .collect();
        let phi_qdd = dot(&phi, &b) / (1.0 + a * UNSPRUNG * dot(&phi, &phi));
        let sprung_acceleration = (-STIFFNESS * delta - self.damping * delta_rate) / SPRUNG;
        let mut rates = vec![0.0; 2 * m + 2];
        rates[..m].copy_from_slice(qd);
        for n in 0..m {
            rates[m + n] = b[n] - a * UNSPRUNG * phi[n] * phi_qdd;
        }
        rates[2 * m] = ud;
        rates[2 * m + 1] = sprung_acceleration;
        (rates, sprung_acceleration)
    }

    /// Midspan deflection and sprung acceleration at each time of `times`
    /// (multiples of `STEP`), integrating with `substeps` RK4 steps per STEP.
    fn history(&self, times: &[f64], substeps: usize) -> (Vec<f64>, Vec<f64>) {
        let m = self.modes;
        let mut y = vec![0.0; 2 * m + 2];
        let h = STEP / substeps as f64;
        let mut t = 0.0;
        let (mut midspan, mut acceleration) = (Vec::new(), Vec::new());
        let (phi_mid, _, _) = self.shapes(LENGTH / 2.0);
        for &target in times {
            while t < target - 0.5 * h {
                let (k1, _) = self.rates(t, &y);
                let at = |y: &[f64], k: &[f64], s: f64| -> Vec<f64> {
                    y.iter().zip(k).map(|(a, b)| a + s * b).collect()
                };
                let (k2, _) = self.rates(t + 0.5 * h, &at(&y, &k1, 0.5 * h));
                let (k3, _) = self.rates(t + 0.5 * h, &at(&y, &k2, 0.5 * h));
                let (k4, _) = self.rates(t + h, &at(&y, &k3, h));
                for i in 0..y.len() {
                    y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
                t += h;
            }
            midspan.push(phi_mid.iter().zip(&y[..m]).map(|(p, q)| p * q).sum());
            acceleration.push(self.rates(t, &y).1);
        }
        (midspan, acceleration)
    }
}

fn check_against_modal(damping: f64) {
    let run = guideway_history(&scene(damping));
    // The contact reaches x = L at about L / V = 0.9 s.
    let crossing = LENGTH / SPEED;
    let last = *run.time.last().unwrap();
    assert!((last - crossing).abs() < 0.01 * crossing, "ran to {last} s");
    let modal = Modal { modes: 30, damping };
    let (midspan, acceleration) = modal.history(&run.time, 1);
    let (peak_w, peak_a) = (peak(&midspan), peak(&acceleration));
    // The static midspan deflection under the vehicle's weight, as a sanity
    // check that the modal solution is the intended problem.
    let static_w = (SPRUNG + UNSPRUNG) * GRAVITY * LENGTH.powi(3) / (48.0 * EI);
    assert!(
        (0.8 * static_w..1.5 * static_w).contains(&peak_w),
        "{peak_w} vs {static_w}"
    );
    assert!(peak_a > 0.01, "peak acceleration {peak_a}");
    let dw = largest_difference(&run.midspan, &midspan);
    let da = largest_difference(&run.acceleration, &acceleration);
    eprintln!(
        "damping {damping}: midspan {:.3e} of peak {peak_w:.4e} m; acceleration {:.3e} of \
         peak {peak_a:.4e} m/s2",
        dw / peak_w,
        da / peak_a
    );
    assert!(dw <= 0.01 * peak_w, "midspan: {dw} against peak {peak_w}");
    assert!(
        da <= 0.01 * peak_a,
        "acceleration: {da} against peak {peak_a}"
    );
}

#[test]
fn undamped_sprung_mass_matches_modal_superposition() {
    check_against_modal(0.0);
}

#[test]
fn damped_sprung_mass_matches_modal_superposition() {
    check_against_modal(2.0e4);
}

/// Largest |balance − initial| over the crossing, the largest |work| gravity
/// did on the way, and the energy the damper dissipated.
fn energy_drift(scene: &Scene) -> (f64, f64, f64) {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (balance, gravity, dissipated) = (
        at("energy.balance"),
        at("energy.gravity_work"),
        at("energy.dissipated"),
    );
    let mut values = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let (mut drift, mut work): (f64, f64) = (0.0, 0.0);
    for k in 1.. {
        let advance = sim.advance_to(k as f64 * scene.solver.step).unwrap();
        sim.output_values(&mut values);
        drift = drift.max((values[balance] - e0).abs());
        work = work.max(values[gravity].abs());
        if advance != Advance::Reached {
            break;
        }
    }
    (drift, work, values[dissipated])
}

#[test]
fn energy_balance_holds_with_gravity_springs_and_dampers() {
    // Over the crossing gravity does work as the beam deflects (and takes
    // it back as it recovers); the balance (kinetic + strain + spring + dissipated − work) stays put.
    let (drift, gravity_work, dissipated) = energy_drift(&scene(0.0));
    eprintln!("undamped: drift {drift:.3e} J, gravity work {gravity_work:.4e} J");
    assert!(gravity_work > 1.0, "{gravity_work}");
    assert_eq!(dissipated, 0.0);
    assert!(
        drift < 1e-5 * gravity_work,
        "drift {drift} J of {gravity_work} J"
    );
    let (drift, gravity_work, dissipated) = energy_drift(&scene(2.0e4));
    eprintln!("damped: drift {drift:.3e} J, gravity work {gravity_work:.4e} J, dissipated {dissipated:.4e} J");
    // Left out of the balance, the dissipated energy would show as a drift
    // a hundred times the one measured.
    assert!(dissipated > 100.0 * drift, "{dissipated} vs drift {drift}");
    assert!(
        drift < 1e-5 * gravity_work,
        "drift {drift} J of {gravity_work} J"
    );
}
