//! `[body.contact_law]`: the law a vehicle's contact bodies meet the track
//! with, Lee's rigid contact unless the scene chooses a compliant one
//! (`crate::contact_law`), by a preset, by its data, or both (the data
//! override the preset's).

use serde::{Deserialize, Serialize};

pub use crate::contact_law::ResolvedLaw;
use crate::contact_law::{hertz_coefficient, STEEL};

/// The scene's choice of contact law for one vehicle's contact bodies.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactLawSpec {
    /// `rigid` (Lee's constraint, the default), `hertz` or `ems`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<String>,
    /// `wheel-rail` (Hertz, a 0.46 m wheel on a 0.3 m rail head, steel) or
    /// `ems` (a 10 mm air gap, K_p/i₀ = 160 1/m, K_d/i₀ = 0.9 s/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Hertz: C_H (N/m^1.5), or from the radii below.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coefficient: Option<f64>,
    /// Hertz: the wheel's rolling radius and the rail head's transverse
    /// radius (m), and their material (Pa; steel if left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel_radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rail_radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elastic_modulus: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// EMS: the nominal air gap s₀ (m), the controller's gains over the
    /// operating current K_p/i₀ (1/m) and K_d/i₀ (s/m), and the force the
    /// magnet saturates at (N; twice its static load if left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nominal_gap: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proportional_gain: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub derivative_gain: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_force: Option<f64>,
}

/// A broken rule: the field (under `contact_law`), its value, the rule.
pub type LawProblem = (&'static str, String, String);

/// The presets' names.
pub const PRESETS: [&str; 2] = ["wheel-rail", "ems"];

impl ContactLawSpec {
    /// The law with the preset's values under the scene's own.
    fn with_preset(&self) -> Result<ContactLawSpec, LawProblem> {
        let mut out = match self.preset.as_deref() {
            None => ContactLawSpec::default(),
            Some("wheel-rail") => ContactLawSpec {
                law: Some("hertz".into()),
                wheel_radius: Some(0.46),
                rail_radius: Some(0.3),
                ..Default::default()
            },
            Some("ems") => ContactLawSpec {
                law: Some("ems".into()),
                nominal_gap: Some(0.01),
                proportional_gain: Some(160.0),
                derivative_gain: Some(0.9),
                ..Default::default()
            },
            Some(other) => {
                let rule = format!("must be one of {}", PRESETS.join(", "));
                return Err(("preset", format!("{other:?}"), rule));
            }
        };
        let or = |mine: Option<f64>, preset: Option<f64>| mine.or(preset);
        out.law = self.law.clone().or(out.law);
        out.coefficient = or(self.coefficient, out.coefficient);
        out.wheel_radius = or(self.wheel_radius, out.wheel_radius);
        out.rail_radius = or(self.rail_radius, out.rail_radius);
        out.elastic_modulus = or(self.elastic_modulus, out.elastic_modulus);
        out.poisson_ratio = or(self.poisson_ratio, out.poisson_ratio);
        out.nominal_gap = or(self.nominal_gap, out.nominal_gap);
        out.proportional_gain = or(self.proportional_gain, out.proportional_gain);
        out.derivative_gain = or(self.derivative_gain, out.derivative_gain);
        out.max_force = or(self.max_force, out.max_force);
        Ok(out)
    }

    /// The law the scene asks for, or the first rule it breaks.
    pub fn resolve(&self) -> Result<ResolvedLaw, LawProblem> {
        let spec = self.with_preset()?;
        match spec.law.as_deref().unwrap_or("rigid") {
            "rigid" => Ok(ResolvedLaw::Rigid),
            "hertz" => spec.resolve_hertz(),
            "ems" => spec.resolve_ems(),
            other => Err((
                "law",
                format!("{other:?}"),
                "must be rigid, hertz or ems".into(),
            )),
        }
    }

    fn resolve_hertz(&self) -> Result<ResolvedLaw, LawProblem> {
        let coefficient = match (self.coefficient, self.wheel_radius, self.rail_radius) {
            (Some(c), _, _) => positive("coefficient", c)?,
            (None, Some(rw), Some(rr)) => {
                let (e, nu) = STEEL;
                let e = positive("elastic_modulus", self.elastic_modulus.unwrap_or(e))?;
                let nu = self.poisson_ratio.unwrap_or(nu);
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

    fn resolve_ems(&self) -> Result<ResolvedLaw, LawProblem> {
        let need = |field: &'static str, value: Option<f64>| {
            let rule = "an ems law needs nominal_gap, proportional_gain and derivative_gain";
            value.ok_or((field, "missing".to_string(), rule.to_string()))
        };
        let nominal_gap = positive("nominal_gap", need("nominal_gap", self.nominal_gap)?)?;
        let proportional_gain = need("proportional_gain", self.proportional_gain)?;
        if !(proportional_gain.is_finite() && proportional_gain > 1.0 / nominal_gap) {
            let rule = format!(
                "must exceed 1 / nominal_gap = {} 1/m: the controller must overcome the \
                 magnet's negative stiffness",
                1.0 / nominal_gap
            );
            return Err(("proportional_gain", proportional_gain.to_string(), rule));
        }
        let derivative_gain = need("derivative_gain", self.derivative_gain)?;
        if !(derivative_gain.is_finite() && derivative_gain >= 0.0) {
            let rule = "must be finite and >= 0".to_string();
            return Err(("derivative_gain", derivative_gain.to_string(), rule));
        }
        let max_force = self
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
}

/// `value` if it is a finite positive real within the scene's magnitudes.
fn positive(field: &'static str, value: f64) -> Result<f64, LawProblem> {
    let (low, high) = (
        super::validate::MIN_MAGNITUDE,
        super::validate::MAX_MAGNITUDE,
    );
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err((
            field,
            value.to_string(),
            format!("must be a real in [{low:e}, {high:e}]"),
        ))
    }
}
