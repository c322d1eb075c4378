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
//!
//! A law is one place, this file: its line in `contact_laws!` (its name in
//! a scene, its presets, its fields; `law_spec.rs` makes the scene's
//! `[body.contact_law]` table of them), the function that checks its
//! fields into a `ResolvedLaw` variant, that variant's follower, and its
//! `LawKind` variant with its force and energy.

use serde::{Deserialize, Serialize};

use super::law_spec::{needed, positive, LawProblem};
use super::Follower;

contact_laws! {
    law_note: "rigid (Lee's constraint, the default), hertz or ems (docs/contact-laws.md)",
    preset_note:
        "wheel-rail (Hertz, 0.46 m wheel on a 0.3 m rail head) or ems (10 mm gap, PD control)",
    "rigid" => rigid, presets {}, fields {};
    "hertz" => hertz,
    presets { "wheel-rail" { wheel_radius: 0.46, rail_radius: 0.3 } },
    fields {
        /// Hertz: C_H (N/m^1.5), or from the radii below.
        coefficient ["N/m^1.5", "N/m^1.5, Hertz C_H > 0, or from the radii"],
        /// Hertz: the wheel's rolling radius and the rail head's transverse
        /// radius (m), and their material (Pa; steel if left out).
        wheel_radius ["m", "m, > 0, Hertz: rolling radius"],
        rail_radius ["m", "m, > 0, Hertz: rail head transverse radius"],
        elastic_modulus ["Pa", "Pa, > 0, Hertz: steel if left out"],
        poisson_ratio ["", "in [0, 0.5), Hertz: steel if left out"],
    };
    "ems" => ems,
    presets { "ems" { nominal_gap: 0.01, proportional_gain: 160.0, derivative_gain: 0.9 } },
    fields {
        /// EMS: the nominal air gap s₀ (m), the controller's gains over the
        /// operating current K_p/i₀ (1/m) and K_d/i₀ (s/m), and the force the
        /// magnet saturates at (N; twice its static load if left out).
        nominal_gap ["m", "m, > 0, EMS: the air gap held"],
        proportional_gain ["1/m", "1/m, EMS: K_p / i0"],
        derivative_gain ["s/m", "s/m, EMS: K_d / i0"],
        max_force ["N", "N, > 0, EMS: saturation; twice the static load if left out"],
    };
}

/// Lee's rigid contact: no fields.
fn rigid(_spec: &ContactLawSpec) -> Result<ResolvedLaw, LawProblem> {
    Ok(ResolvedLaw::Rigid)
}

/// Hertz's coefficient, given or from the radii and the material.
fn hertz(spec: &ContactLawSpec) -> Result<ResolvedLaw, LawProblem> {
    let coefficient = match (spec.coefficient, spec.wheel_radius, spec.rail_radius) {
        (Some(c), _, _) => positive("coefficient", c)?,
        (None, Some(rw), Some(rr)) => {
            let (e, nu) = STEEL;
            let e = positive("elastic_modulus", spec.elastic_modulus.unwrap_or(e))?;
            let nu = spec.poisson_ratio.unwrap_or(nu);
            if !(0.0..0.5).contains(&nu) {
                return Err((
                    "poisson_ratio",
                    nu.to_string(),
                    "must lie in [0, 0.5)".into(),
                ));
            }
            let (rw, rr) = (positive("wheel_radius", rw)?, positive("rail_radius", rr)?);
            hertz_coefficient(rw, rr, e, nu)
        }
        _ => {
            let rule = "a hertz law needs coefficient, or wheel_radius and rail_radius";
            return Err(("coefficient", "missing".into(), rule.into()));
        }
    };
    Ok(ResolvedLaw::Hertz { coefficient })
}

/// The EMS magnet: its gap, a controller that beats the magnet's negative
/// stiffness, a damping gain >= 0, a cap if given.
fn ems(spec: &ContactLawSpec) -> Result<ResolvedLaw, LawProblem> {
    let rule = "an ems law needs nominal_gap, proportional_gain and derivative_gain";
    let nominal_gap = positive(
        "nominal_gap",
        needed("nominal_gap", spec.nominal_gap, rule)?,
    )?;
    let proportional_gain = needed("proportional_gain", spec.proportional_gain, rule)?;
    if !(proportional_gain.is_finite() && proportional_gain > 1.0 / nominal_gap) {
        let rule = format!(
            "must exceed 1 / nominal_gap = {} 1/m: the controller must overcome the \
             magnet's negative stiffness",
            1.0 / nominal_gap
        );
        return Err(("proportional_gain", proportional_gain.to_string(), rule));
    }
    let derivative_gain = needed("derivative_gain", spec.derivative_gain, rule)?;
    if !(derivative_gain.is_finite() && derivative_gain >= 0.0) {
        let rule = "must be finite and >= 0".to_string();
        return Err(("derivative_gain", derivative_gain.to_string(), rule));
    }
    let max_force = spec
        .max_force
        .map(|f| positive("max_force", f))
        .transpose()?;
    Ok(ResolvedLaw::Ems {
        nominal_gap,
        proportional_gain,
        derivative_gain,
        max_force,
    })
}

/// Which law a follower's force obeys: each variant's force and energy
/// are side by side in `impl LawKind` below.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LawKind {
    /// The massless follower's suspension: P = preload − k (g − rest) − c ġ.
    #[default]
    Suspension,
    /// Hertz: P = C_H (δ₀ + rest − g)^{3/2}, δ₀ = (preload / C_H)^{2/3}, so
    /// that it carries its preload at g = rest (N/m^1.5).
    /// `compression_at`: δ₀ for a preload, (preload, δ₀), kept so that a
    /// force evaluation takes no power for it (`hertz_offset`).
    Hertz {
        coefficient: f64,
        compression_at: (f64, f64),
    },
    /// The linearised EMS magnet: the suspension's law capped at `max_force`
    /// (N); its stiffness and damping are the controller's k_e, c_e; its
    /// nominal air gap s₀ (m) gives the air gap and current outputs.
    Magnet { max_force: f64, nominal_gap: f64 },
}

/// A contact law as a scene resolves it, ready to build: Lee's rigid
/// constraint, or a compliant law that becomes a follower's `LawKind`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResolvedLaw {
    Rigid,
    Hertz {
        coefficient: f64,
    },
    Ems {
        nominal_gap: f64,
        proportional_gain: f64,
        derivative_gain: f64,
        max_force: Option<f64>,
    },
}

/// A compliant law's follower parameters for a contact body carrying
/// `share` (N): its law, stiffness, damping, rest gap, and how far the
/// body starts sunk below its rigid place (m).
pub struct CompliantFollower {
    pub kind: LawKind,
    pub stiffness: f64,
    pub damping: f64,
    pub rest: f64,
    pub sunk: f64,
}

impl ResolvedLaw {
    /// The follower of a contact body of radius `radius` carrying
    /// `share` (N); None for the rigid contact; an error naming the field
    /// where the law cannot carry it.
    pub fn follower(&self, share: f64, radius: f64) -> Result<Option<CompliantFollower>, String> {
        Ok(Some(match *self {
            ResolvedLaw::Rigid => return Ok(None),
            ResolvedLaw::Hertz { coefficient } => {
                let sunk = hertz_compression(coefficient, share);
                let kind = LawKind::hertz(coefficient, share);
                (kind, 0.0, 0.0, radius - sunk, sunk).into()
            }
            ResolvedLaw::Ems {
                nominal_gap,
                proportional_gain,
                derivative_gain,
                max_force,
            } => {
                let max_force = max_force.unwrap_or(2.0 * share);
                // NaN-safe: a cap that is not above the load is refused.
                if max_force.partial_cmp(&share) != Some(std::cmp::Ordering::Greater) {
                    return Err(format!(
                        "contact_law.max_force = {max_force} N must exceed the magnet's static \
                         load {share} N"
                    ));
                }
                let (k, c) =
                    magnet_equivalent(share, nominal_gap, proportional_gain, derivative_gain);
                let kind = LawKind::Magnet {
                    max_force,
                    nominal_gap,
                };
                (kind, k, c, radius, 0.0).into()
            }
        }))
    }
}

impl From<(LawKind, f64, f64, f64, f64)> for CompliantFollower {
    fn from((kind, stiffness, damping, rest, sunk): (LawKind, f64, f64, f64, f64)) -> Self {
        CompliantFollower {
            kind,
            stiffness,
            damping,
            rest,
            sunk,
        }
    }
}

impl LawKind {
    /// Hertz's law of coefficient C_H (N/m^1.5), its δ₀ kept for `preload`.
    pub fn hertz(coefficient: f64, preload: f64) -> LawKind {
        LawKind::Hertz {
            coefficient,
            compression_at: (preload, hertz_compression(coefficient, preload)),
        }
    }

    /// The same law with what it keeps for its preload brought to
    /// `preload` (after the static start has changed it).
    pub fn at_preload(self, preload: f64) -> LawKind {
        match self {
            LawKind::Hertz { coefficient, .. } => LawKind::hertz(coefficient, preload),
            other => other,
        }
    }

    /// Normal force (N, compression positive) of `follower` at gap `gap`
    /// and rate `rate`, before the cut at zero: negative where the law
    /// would pull (the follower is slack, its contact open).
    pub fn force(&self, follower: &Follower, gap: f64, rate: f64) -> f64 {
        let f = follower;
        let linear = f.preload - f.stiffness * (gap - f.rest) - f.damping * rate;
        match *self {
            LawKind::Suspension => linear,
            LawKind::Magnet { max_force, .. } => linear.min(max_force),
            LawKind::Hertz {
                coefficient,
                compression_at,
            } => {
                // Signed, so that the slack side is negative (a lift-off's
                // instant is where it crosses zero).
                let offset = hertz_offset(coefficient, compression_at, f.preload);
                let compression = offset + f.rest - gap;
                // δ √δ for δ^{3/2}: within a rounding of the power, at a
                // fifth of its instructions (the law is evaluated twice an
                // integration for every wheel).
                let depth = compression.abs();
                compression.signum() * coefficient * (depth * depth.sqrt()) - f.damping * rate
            }
        }
    }

    /// Potential energy of `follower`'s spring at gap `gap` (J), zero at
    /// rest: that of ½ k δ² − preload δ (δ = gap − rest) up to where the
    /// spring goes slack, constant beyond.
    pub fn potential_energy(&self, follower: &Follower, gap: f64) -> f64 {
        let f = follower;
        match *self {
            LawKind::Suspension => {
                let delta = (gap - f.rest).min(f.preload / f.stiffness);
                0.5 * f.stiffness * delta * delta - f.preload * delta
            }
            LawKind::Hertz {
                coefficient,
                compression_at,
            } => {
                // ∫ C_H δ^{3/2} dδ from the undeformed contact.
                let offset = hertz_offset(coefficient, compression_at, f.preload);
                let compression = (offset + f.rest - gap).max(0.0);
                0.4 * coefficient * libm::pow(compression, 2.5)
            }
            LawKind::Magnet { max_force, .. } => {
                // The linear spring's energy, continued linearly where the
                // force is held at its cap (δ below the saturation's δ_s).
                let saturation = (f.preload - max_force) / f.stiffness;
                let delta = (gap - f.rest).min(f.preload / f.stiffness);
                let held = delta.max(saturation);
                0.5 * f.stiffness * held * held - f.preload * held - max_force * (delta - held)
            }
        }
    }

    /// The law's stiffness −∂P/∂g at gap `gap` (N/m): the spring's, zero
    /// where Hertz's contact is open; a magnet's held below its cap.
    pub fn stiffness(&self, follower: &Follower, gap: f64) -> f64 {
        match *self {
            LawKind::Hertz {
                coefficient,
                compression_at,
            } => {
                let offset = hertz_offset(coefficient, compression_at, follower.preload);
                let compression = (offset + follower.rest - gap).max(0.0);
                1.5 * coefficient * compression.sqrt()
            }
            _ => follower.stiffness,
        }
    }

    /// The spring's force alone at gap `gap` (no damper), whose excess
    /// over the force is the damper's dissipation.
    pub fn elastic_force(&self, follower: &Follower, gap: f64) -> f64 {
        match *self {
            LawKind::Suspension => follower.preload - follower.stiffness * (gap - follower.rest),
            _ => self.force(follower, gap, 0.0),
        }
    }
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
    libm::pow(load / coefficient, 2.0 / 3.0)
}

/// `hertz_compression(coefficient, preload)`, from `compression_at` =
/// (its preload, its δ₀) where that preload is this one: the same bits
/// without one of the law's two powers (4 % of the built-in eight-coach
/// train's instructions, docs/performance-log.md).
fn hertz_offset(coefficient: f64, (kept_for, kept): (f64, f64), preload: f64) -> f64 {
    if kept_for == preload {
        kept
    } else {
        hertz_compression(coefficient, preload)
    }
}

/// Hertz's contact stiffness dP/dδ linearised at `load` (N/m):
/// (3/2) C_H^{2/3} P^{1/3}.
pub fn hertz_stiffness(coefficient: f64, load: f64) -> f64 {
    1.5 * libm::pow(coefficient, 2.0 / 3.0) * libm::cbrt(load)
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
    fn hertzs_stiffness_at_a_gap_is_the_linearised_one_at_its_force_and_zero_when_open() {
        // A follower of Hertz's law carrying 6e4 N at rest; at the gap where
        // it carries 9e4 N, −∂P/∂g is (3/2) C_H^{2/3} P^{1/3} at 9e4 N, and
        // the force there is δ^{3/2}'s to a rounding.
        let c = hertz_coefficient(0.46, 0.3, STEEL.0, STEEL.1);
        let (preload, load) = (6.0e4, 9.0e4);
        let follower = crate::contact::Follower {
            stiffness: 0.0,
            damping: 0.0,
            preload,
            rest: 0.45,
            attachment: nalgebra::Vector2::zeros(),
            kind: LawKind::hertz(c, preload),
        };
        let gap = 0.45 + hertz_compression(c, preload) - hertz_compression(c, load);
        let k = follower.kind.stiffness(&follower, gap);
        assert!((k / hertz_stiffness(c, load) - 1.0).abs() < 1e-12, "{k}");
        assert!((follower.force(gap, 0.0) / load - 1.0).abs() < 1e-12);
        let open = 0.45 + hertz_compression(c, preload) + 1e-6;
        assert_eq!(follower.kind.stiffness(&follower, open), 0.0);
        assert_eq!(follower.force(open, 0.0), 0.0);
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
