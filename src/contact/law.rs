//! The compliant contact laws beside Lee's rigid contact: what a contact
//! body with mass feels from the track when the scene chooses a force law
//! instead of the constraint (`[body.contact_law]`).
//!
//! - **Hertz** (wheel on rail): P = C_H δ^{3/2} for a compression δ > 0,
//!   nothing in tension. C_H from the radii by Hertz's theory for two
//!   crossed cylinders (the wheel's rolling radius R_w, the rail head's
//!   transverse radius R_r), taken as the equivalent sphere of radius
//!   R_e = √(R_w R_r) on a plane (Johnson, *Contact Mechanics*, 1985,
//!   §4.2, the ellipticity correction neglected):
//!   C_H = (4/3) E* √R_e with E* = E / (2 (1 − ν²)) for two steel bodies.
//!   R_w = 0.46 m, R_r = 0.3 m, E = 210 GPa, ν = 0.3 give 9.38e10 N/m^1.5.
//! - **EMS magnet** (electromagnetic suspension): the attraction
//!   F = k (i/s)² of an electromagnet at air gap s and current i,
//!   linearised at its operating point (F₀, i₀, s₀):
//!   ΔF = 2F₀ Δi/i₀ − 2F₀ Δs/s₀; a PD gap controller sets
//!   Δi = K_p Δs + K_d Δṡ, so ΔF = k_e Δs + c_e Δṡ with
//!   k_e = 2F₀ (K_p/i₀ − 1/s₀) (the controller must beat the magnet's
//!   negative stiffness) and c_e = 2F₀ K_d/i₀ (Sinha, *Electromagnetic
//!   Suspension: Dynamics and Control*, IEE 1987, ch. 2). The force
//!   saturates at F_max (the iron's flux, the amplifier's voltage) and
//!   cannot push (F ≥ 0): contact is lost only where it saturates at zero.
//!
//! Both are functions of the contact body's gap and gap rate, as a massless
//! follower's suspension is, so they ride on the follower's machinery
//! (`contact::Follower`): evaluated with the loads at every stage, no rows
//! in the iteration, slack (open) where the law would pull.

/// Which law a follower's force obeys.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LawKind {
    /// The massless follower's suspension: P = preload − k (g − rest) − c ġ.
    #[default]
    Suspension,
    /// Hertz: P = C_H (δ₀ + rest − g)^{3/2}, δ₀ = (preload / C_H)^{2/3}, so
    /// that it carries its preload at g = rest (N/m^1.5).
    Hertz { coefficient: f64 },
    /// The linearised EMS magnet: the suspension's law capped at `max_force`
    /// (N); its stiffness and damping are the controller's k_e, c_e; its
    /// nominal air gap s₀ (m) gives the air gap and current outputs.
    Magnet { max_force: f64, nominal_gap: f64 },
}

/// Steel's Young's modulus (Pa) and Poisson's ratio, the default of a
/// Hertz law given by radii.
pub const STEEL: (f64, f64) = (2.1e11, 0.3);

/// Hertz's coefficient C_H (N/m^1.5) of a wheel of rolling radius
/// `wheel_radius` on a rail head of transverse radius `rail_radius` (m),
/// both of modulus `elastic_modulus` (Pa) and Poisson ratio `poisson`.
pub fn hertz_coefficient(
    wheel_radius: f64,
    rail_radius: f64,
    elastic_modulus: f64,
    poisson: f64,
) -> f64 {
    let effective_modulus = elastic_modulus / (2.0 * (1.0 - poisson * poisson));
    let effective_radius = (wheel_radius * rail_radius).sqrt();
    4.0 / 3.0 * effective_modulus * effective_radius.sqrt()
}

/// Compression δ (m) at which a Hertz contact carries `load` (N).
pub fn hertz_compression(coefficient: f64, load: f64) -> f64 {
    (load / coefficient).powf(2.0 / 3.0)
}

/// Hertz's contact stiffness dP/dδ linearised at `load` (N/m):
/// (3/2) C_H^{2/3} P^{1/3}.
pub fn hertz_stiffness(coefficient: f64, load: f64) -> f64 {
    1.5 * coefficient.powf(2.0 / 3.0) * load.cbrt()
}

/// The EMS controller's equivalent stiffness k_e (N/m) and damping c_e
/// (N s/m) at the operating force `load` (N), air gap `nominal_gap` (m)
/// and gains relative to the operating current, K_p/i₀ (1/m) and
/// K_d/i₀ (s/m).
pub fn magnet_equivalent(
    load: f64,
    nominal_gap: f64,
    proportional_gain: f64,
    derivative_gain: f64,
) -> (f64, f64) {
    let stiffness = 2.0 * load * (proportional_gain - 1.0 / nominal_gap);
    let damping = 2.0 * load * derivative_gain;
    (stiffness, damping)
}

/// The magnet's current relative to its operating current, i/i₀, that
/// carries `force` (N) at the air gap deviation `air_gap_change` = s − s₀
/// (m) by the linearised force law ΔF = 2F₀ Δi/i₀ − 2F₀ Δs/s₀ at the
/// operating point (`load` F₀, `nominal_gap` s₀): 1 + ΔF/2F₀ + Δs/s₀.
/// Below saturation that is the controller's 1 + (K_p/i₀) Δs + (K_d/i₀) Δṡ;
/// at the cap, the current the capped force takes.
pub fn magnet_relative_current(
    load: f64,
    nominal_gap: f64,
    force: f64,
    air_gap_change: f64,
) -> f64 {
    1.0 + (force - load) / (2.0 * load) + air_gap_change / nominal_gap
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wheel_on_a_uic60_head_has_the_textbook_hertz_coefficient() {
        // 0.46 m wheel on a 0.3 m head: 9.37e10 N/m^1.5 in the railway
        // literature (the same formula, steel).
        let c = hertz_coefficient(0.46, 0.3, STEEL.0, STEEL.1);
        assert!((c / 9.376e10 - 1.0).abs() < 1e-3, "{c}");
        // The linearised stiffness is the secant's 3/2.
        let load = 7.0e4;
        let delta = hertz_compression(c, load);
        assert!((hertz_stiffness(c, load) * delta / load - 1.5).abs() < 1e-12);
    }

    #[test]
    fn the_controller_must_beat_the_magnets_negative_stiffness() {
        let (k, c) = magnet_equivalent(4.0e4, 0.01, 100.0, 0.5);
        assert_eq!(k, 0.0);
        assert_eq!(c, 4.0e4);
        assert!(magnet_equivalent(4.0e4, 0.01, 160.0, 0.5).0 > 0.0);
    }

    #[test]
    fn the_current_behind_a_force_is_the_controllers_below_saturation() {
        // Static (Δṡ = 0): the controller sets Δi/i₀ = K_p/i₀ Δs, and the
        // force is F₀ + k_e Δs; the current read back from that force and
        // gap is the controller's.
        let (load, gap, kp) = (4.0e4, 0.01, 160.0);
        let (k, _) = magnet_equivalent(load, gap, kp, 0.9);
        let change = 1.0e-4;
        let current = magnet_relative_current(load, gap, load + k * change, change);
        assert!((current - (1.0 + kp * change)).abs() < 1e-12, "{current}");
        assert_eq!(magnet_relative_current(load, gap, load, 0.0), 1.0);
    }
}
