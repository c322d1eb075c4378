//! The bridge description a dynamic check reads (`guideway check
//! BRIDGE.toml`): span and supports, mass per length with its bounds, f1
//! or EI, bridge type, track and maximum line speed, and the National
//! Annex settings with the recommended values as defaults; validated as
//! untrusted input.

use serde::{Deserialize, Serialize};

use super::rules::{BridgeType, BALLASTED_ACCELERATION_LIMIT, DIRECT_FASTENED_ACCELERATION_LIMIT};

/// The built-in example: the 20 m bridge of issue 28 (12 t/m, f1 = 5.5 Hz,
/// reinforced concrete, ballasted, 350 km/h).
pub const EXAMPLE_NAME: &str = "bridge20";
pub const EXAMPLE: &str = include_str!("../../bridges/bridge20.toml");

/// The track on the deck (EN 1990 A2.4.4.2.1(4)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackKind {
    Ballasted,
    DirectFastened,
}

/// One bridge to check.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeSpec {
    pub name: String,
    /// Span L (m) of a simply supported bridge (0 when `spans` gives a
    /// continuous beam's).
    #[serde(default)]
    pub span: f64,
    /// `simply_supported` (one span, `span`) or `continuous` (a beam over
    /// intermediate supports, `spans`).
    #[serde(default = "simply_supported")]
    pub supports: String,
    /// The spans (m) of a continuous beam, left to right, two or more.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spans: Vec<f64>,
    /// Mass per length (kg/m): the nominal value f1 belongs to.
    pub mass_per_length: f64,
    /// Lower and upper bounds of the mass per length (kg/m), EN 1991-2
    /// §6.4.6.3.2; the nominal value when absent.
    #[serde(default)]
    pub mass_lower: Option<f64>,
    #[serde(default)]
    pub mass_upper: Option<f64>,
    /// First natural frequency (Hz) at the nominal mass, or EI.
    #[serde(default)]
    pub first_frequency: Option<f64>,
    #[serde(default)]
    pub bending_stiffness: Option<f64>,
    pub bridge_type: BridgeType,
    pub track: TrackKind,
    /// Maximum line speed at the site (km/h).
    pub line_speed: f64,
    #[serde(default)]
    pub settings: Settings,
}

fn simply_supported() -> String {
    "simply_supported".into()
}

/// National Annex choices (recommended values by default) and the
/// numerical settings of the runs.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// EN 1990 A2.4.4.2.1(4)P γ_bt, γ_df (m/s²).
    pub acceleration_limit_ballasted: f64,
    pub acceleration_limit_direct_fastened: f64,
    /// EN 1991-2 §6.3.2(3) classification factor α of LM71.
    pub classification_factor: f64,
    /// EN 1991-2 §6.4.5.2(3): carefully maintained track (Φ2, φ″/2) or
    /// standard maintenance (Φ3, φ″).
    pub carefully_maintained: bool,
    /// Speed steps (km/h) away from and near resonance, and the band
    /// (fraction of the resonant speed) of the fine steps.
    pub speed_step: f64,
    pub fine_speed_step: f64,
    pub resonance_band: f64,
    /// Finite elements of the span and time step (s).
    pub elements: usize,
    pub step: f64,
    /// HSLM-B (EN 1991-2 Annex E, Figure E.8) for spans under 7 m: the
    /// number N of 170 kN forces and their spacing d (m) read off the
    /// figure for this span.
    pub hslm_b: Option<HslmB>,
    /// Run the shipped real trains (src/moving_load/trains/) beside HSLM.
    pub real_trains: bool,
    /// EN 1990 A2.4.4.3.2: the L/δ read off Figure A2.3 for this span and
    /// the maximum line speed (the figure gives curves, so the check does
    /// not guess it); the comfort check is skipped without it.
    pub comfort_span_to_deflection: Option<f64>,
    /// EN 1990 A2.4.4.3.1(2) b_v (m/s²): 1.0 "very good" (recommended,
    /// National Annex), 1.3 "good", 2.0 "acceptable".
    pub comfort_acceleration: f64,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HslmB {
    pub forces: usize,
    pub spacing: f64,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            acceleration_limit_ballasted: BALLASTED_ACCELERATION_LIMIT,
            acceleration_limit_direct_fastened: DIRECT_FASTENED_ACCELERATION_LIMIT,
            classification_factor: 1.0,
            carefully_maintained: true,
            speed_step: 5.0,
            fine_speed_step: 1.0,
            resonance_band: 0.03,
            elements: 20,
            step: 0.001,
            hslm_b: None,
            real_trains: true,
            comfort_span_to_deflection: None,
            comfort_acceleration: 1.0,
        }
    }
}

/// Check that `value` (named `field`) is finite and within `low ..= high`.
fn within(field: &str, value: f64, low: f64, high: f64, unit: &str) -> Result<(), String> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(format!(
            "{field} = {value}: must be a number from {low} to {high} {unit}"
        ))
    }
}

impl BridgeSpec {
    /// The spans as the report states them.
    pub fn span_description(&self) -> String {
        if self.is_continuous() {
            let list: Vec<String> = self.spans.iter().map(|l| format!("{l}")).collect();
            format!(
                "{} m, continuous over {} spans",
                list.join(" + "),
                self.spans.len()
            )
        } else {
            format!("{} m, simply supported", self.span)
        }
    }

    /// A continuous beam over intermediate supports.
    pub fn is_continuous(&self) -> bool {
        self.supports == "continuous"
    }

    /// The span lengths (m): `span` alone, or the continuous beam's.
    pub fn span_lengths(&self) -> Vec<f64> {
        if self.is_continuous() {
            self.spans.clone()
        } else {
            vec![self.span]
        }
    }

    /// The length of the beam (m): the sum of the spans.
    pub fn length(&self) -> f64 {
        self.span_lengths().iter().sum()
    }

    /// The longest span (m): the L of Table 6.6, eq. (6.13) and L/600
    /// (the conservative choice on a continuous beam: the least damping).
    pub fn longest_span(&self) -> f64 {
        self.span_lengths().iter().fold(0.0, |a: f64, &b| a.max(b))
    }

    /// The abscissae (m) of the intermediate supports.
    pub fn intermediate_supports(&self) -> Vec<f64> {
        let spans = self.span_lengths();
        let mut x = 0.0;
        let mut out = Vec::new();
        for l in &spans[..spans.len() - 1] {
            x += l;
            out.push(x);
        }
        out
    }

    /// Parse and validate a bridge description.
    pub fn from_toml_str(text: &str) -> Result<BridgeSpec, String> {
        if text.len() > 1 << 20 {
            return Err("the bridge file is over 1 MiB".into());
        }
        let spec: BridgeSpec = toml::from_str(text).map_err(|e| e.to_string())?;
        spec.validate()?;
        Ok(spec)
    }

    /// Every field within its bounds; one of f1 and EI.
    pub fn validate(&self) -> Result<(), String> {
        self.validate_spans()?;
        within("mass_per_length", self.mass_per_length, 100.0, 1e6, "kg/m")?;
        let lower = self.mass_lower.unwrap_or(self.mass_per_length);
        let upper = self.mass_upper.unwrap_or(self.mass_per_length);
        within(
            "mass_lower",
            lower,
            100.0,
            self.mass_per_length,
            "kg/m (not above mass_per_length)",
        )?;
        within(
            "mass_upper",
            upper,
            self.mass_per_length,
            1e6,
            "kg/m (not below mass_per_length)",
        )?;
        match (self.first_frequency, self.bending_stiffness) {
            (Some(f), None) => within("first_frequency", f, 0.1, 100.0, "Hz")?,
            (None, Some(ei)) => within("bending_stiffness", ei, 1e3, 1e15, "N m²")?,
            _ => {
                return Err("give one of first_frequency (Hz) and bending_stiffness (N m²)".into())
            }
        }
        within("line_speed", self.line_speed, 10.0, 600.0, "km/h")?;
        // HSLM-B is for simply supported spans (EN 1991-2 Annex E, E.1(2)).
        let hslm_b_span = if self.is_continuous() {
            f64::INFINITY
        } else {
            self.span
        };
        self.settings.validate(hslm_b_span)
    }

    /// `span` for a simply supported bridge, `spans` (2 … 20) for a
    /// continuous one, each from 1 m to 200 m.
    fn validate_spans(&self) -> Result<(), String> {
        match self.supports.as_str() {
            "simply_supported" => {
                if !self.spans.is_empty() {
                    return Err("spans: only with supports = \"continuous\" (a simply \
                                supported bridge gives span)"
                        .into());
                }
                within("span", self.span, 1.0, 200.0, "m")
            }
            "continuous" => {
                if self.span != 0.0 {
                    return Err(format!(
                        "span = {}: a continuous beam gives its spans in spans = [...]",
                        self.span
                    ));
                }
                within("spans (count)", self.spans.len() as f64, 2.0, 20.0, "spans")?;
                for (i, &l) in self.spans.iter().enumerate() {
                    within(&format!("spans[{i}]"), l, 1.0, 200.0, "m")?;
                }
                Ok(())
            }
            other => Err(format!(
                "supports = {other:?}: must be \"simply_supported\" (span) or \"continuous\" \
                 (spans)"
            )),
        }
    }
}

impl Settings {
    /// Each plain setting with its accepted range and unit words:
    /// (name, value, min, max, unit).
    fn ranges(&self) -> Vec<(&'static str, f64, f64, f64, &'static str)> {
        let mut rows = vec![
            (
                "acceleration_limit_ballasted",
                self.acceleration_limit_ballasted,
                0.1,
                50.0,
                "m/s²",
            ),
            (
                "acceleration_limit_direct_fastened",
                self.acceleration_limit_direct_fastened,
                0.1,
                50.0,
                "m/s²",
            ),
            (
                "classification_factor",
                self.classification_factor,
                0.5,
                2.0,
                "",
            ),
            ("speed_step", self.speed_step, 0.5, 100.0, "km/h"),
            (
                "fine_speed_step",
                self.fine_speed_step,
                0.1,
                self.speed_step,
                "km/h (not above speed_step)",
            ),
            ("resonance_band", self.resonance_band, 0.0, 0.5, ""),
            ("elements", self.elements as f64, 4.0, 400.0, ""),
            ("step", self.step, 1e-5, 0.01, "s"),
            (
                "comfort_acceleration",
                self.comfort_acceleration,
                0.1,
                10.0,
                "m/s²",
            ),
        ];
        if let Some(ratio) = self.comfort_span_to_deflection {
            rows.push((
                "comfort_span_to_deflection",
                ratio,
                100.0,
                10_000.0,
                "(L/δ of EN 1990 Figure A2.3)",
            ));
        }
        if let Some(b) = self.hslm_b {
            rows.push(("hslm_b.forces", b.forces as f64, 1.0, 100.0, ""));
            rows.push(("hslm_b.spacing", b.spacing, 1.0, 10.0, "m"));
        }
        rows
    }

    fn validate(&self, span: f64) -> Result<(), String> {
        for (name, value, lo, hi, unit) in self.ranges() {
            within(&format!("settings.{name}"), value, lo, hi, unit)?;
        }
        if self.hslm_b.is_none() && span < 7.0 {
            return Err(format!(
                "span = {span} m < 7 m: EN 1991-2 Annex E asks for HSLM-B; give \
                 settings.hslm_b = {{ forces = N, spacing = d }} read off Figure E.8 \
                 for this span"
            ));
        }
        Ok(())
    }
}
