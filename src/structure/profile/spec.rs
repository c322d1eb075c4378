//! One irregularity of the running surface as a scene gives it
//! (`[[track.irregularities]]`), with its serde form; `Profile` sums them
//! and the scene format (`scene::Scene`) composes them and checks them.

use serde::{Deserialize, Serialize};

/// One irregularity of the running surface, r(x) in metres (up positive),
/// added on the beam and on the rigid approach and run-off alike.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum IrregularitySpec {
    /// A rise by `height` centred at `position`, smoothed over `smoothing`
    /// metres (half a sine period): a bilateral contact cannot follow a
    /// sharp step without an impulse.
    Step {
        position: f64,
        height: f64,
        smoothing: f64,
    },
    /// A linear rise by `height` from `start` over `length`, its two
    /// corners rounded over `smoothing` metres each.
    Ramp {
        start: f64,
        length: f64,
        height: f64,
        smoothing: f64,
    },
    /// A dip −depth (1 + cos 2π(x − position)/wavelength)/2 one wavelength
    /// long, centred at `position`.
    CosineDip {
        position: f64,
        wavelength: f64,
        depth: f64,
    },
    /// amplitude · sin(2π x / wavelength + phase) along the whole track.
    Sine {
        amplitude: f64,
        wavelength: f64,
        #[serde(default)]
        phase: f64,
    },
    /// A table of (x, r) points, inline or read from a CSV `file` (path
    /// relative to the scene file; read when the scene is loaded and kept
    /// inline from then on), interpolated by a cubic spline.
    Table {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        file: Option<String>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        points: Vec<[f64; 2]>,
    },
    /// A random profile from a spectrum (`iso8608` class A–H, `fra` class
    /// 1–6, `german_low`, `german_high`) within a wavelength band, from a
    /// seed; `spacing` of its samples defaults to shortest_wavelength / 10.
    Random {
        spectrum: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        class: Option<String>,
        seed: u32,
        shortest_wavelength: f64,
        longest_wavelength: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spacing: Option<f64>,
    },
}

impl IrregularitySpec {
    /// The sample spacing of a random profile.
    pub fn random_spacing(shortest_wavelength: f64, spacing: Option<f64>) -> f64 {
        spacing.unwrap_or(shortest_wavelength / 10.0)
    }
}
