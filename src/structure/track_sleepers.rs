//! The rail's discrete supports (`[track.on_deck.sleepers]`, issue 24):
//! sleepers at a spacing, each a mass on the rail pad (rail to sleeper)
//! over the ballast (sleeper to deck, or to the ground off the deck), in
//! place of the continuous layer; the scene's spec, its preset with its
//! source, the resolved values the assembly uses and their rules.

use serde::{Deserialize, Serialize};

/// Typical discrete supports, per rail seat (one rail on half a sleeper).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SleeperPreset {
    /// Concrete sleepers on pads and ballast.
    Ballasted,
}

impl SleeperPreset {
    /// The preset's values per rail seat: "Study on Transmission
    /// Characteristics of Vertical Rail Vibrations in Ballast Track",
    /// Mathematical Problems in Engineering 2017, article 5872419, Table 1
    /// (pad 225 kN/mm with loss factor 0.25, half sleeper 170 kg at 0.55 m,
    /// ballast 20 kN/mm per half sleeper with loss factor 1), each loss
    /// factor η taken as a viscous damper η k / ω₀ at ω₀ = 742 rad/s, the
    /// continuous `ballasted` layer's reference (docs/structures.md).
    pub fn values(self) -> Sleepers {
        const REFERENCE: f64 = 742.0;
        match self {
            SleeperPreset::Ballasted => Sleepers {
                spacing: 0.55,
                pad_stiffness: 2.25e8,
                pad_damping: 0.25 * 2.25e8 / REFERENCE,
                sleeper_mass: 170.0,
                ballast_stiffness: 2.0e7,
                ballast_damping: 1.0 * 2.0e7 / REFERENCE,
                rail_elements_per_bay: None,
            },
        }
    }
}

/// `[track.on_deck.sleepers]`: each value for one support of the line the
/// contacts load (for wheelsets, both rail seats of a sleeper: twice the
/// per-rail preset), a given value overriding the preset's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SleepersSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<SleeperPreset>,
    /// Distance between sleepers (m), the first sleeper at the approach's
    /// start: a whole number of the deck's elements unless
    /// `rail_elements_per_bay` meshes the rail at the sleepers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// The rail meshed on its own: a node at every sleeper and this many
    /// equal elements between two, the deck on its own mesh under it.
    /// None: the rail's nodes are the deck's, and the sleepers sit there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rail_elements_per_bay: Option<usize>,
    /// Rail pad, rail to sleeper (N/m, N s/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_stiffness: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_damping: Option<f64>,
    /// The sleeper's mass under the line (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sleeper_mass: Option<f64>,
    /// Ballast, sleeper to deck or ground (N/m, N s/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ballast_stiffness: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ballast_damping: Option<f64>,
}

/// The resolved discrete supports (every value given).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sleepers {
    pub spacing: f64,
    pub pad_stiffness: f64,
    pub pad_damping: f64,
    pub sleeper_mass: f64,
    pub ballast_stiffness: f64,
    pub ballast_damping: f64,
    /// Rail elements between two sleepers, the rail meshed at the
    /// sleepers (None: at the deck's nodes).
    pub rail_elements_per_bay: Option<usize>,
}

impl SleepersSpec {
    /// Each value: the given one, else the preset's, else NaN (refused by
    /// `problems`); dampers default to 0 without a preset.
    pub fn resolve(&self) -> Sleepers {
        let preset = self.preset.map(SleeperPreset::values);
        let pick = |given: Option<f64>, of: fn(&Sleepers) -> f64, default: f64| {
            given.or(preset.as_ref().map(of)).unwrap_or(default)
        };
        Sleepers {
            spacing: pick(self.spacing, |s| s.spacing, f64::NAN),
            pad_stiffness: pick(self.pad_stiffness, |s| s.pad_stiffness, f64::NAN),
            pad_damping: pick(self.pad_damping, |s| s.pad_damping, 0.0),
            sleeper_mass: pick(self.sleeper_mass, |s| s.sleeper_mass, f64::NAN),
            ballast_stiffness: pick(self.ballast_stiffness, |s| s.ballast_stiffness, f64::NAN),
            ballast_damping: pick(self.ballast_damping, |s| s.ballast_damping, 0.0),
            rail_elements_per_bay: self.rail_elements_per_bay,
        }
    }
}

impl Sleepers {
    /// The pad and the ballast in series (N/m): the static stiffness of
    /// one support.
    pub fn series_stiffness(&self) -> f64 {
        self.pad_stiffness * self.ballast_stiffness / (self.pad_stiffness + self.ballast_stiffness)
    }

    /// Each broken rule as (field, value, rule): stiffnesses, mass and
    /// spacing finite and > 0, dampers finite and >= 0 (the rail elements
    /// a bay are the field table's and `rail_at_sleepers`'s).
    pub fn problems(&self) -> Vec<(&'static str, f64, &'static str)> {
        let positive = [
            ("spacing", self.spacing),
            ("pad_stiffness", self.pad_stiffness),
            ("sleeper_mass", self.sleeper_mass),
            ("ballast_stiffness", self.ballast_stiffness),
        ];
        let non_negative = [
            ("pad_damping", self.pad_damping),
            ("ballast_damping", self.ballast_damping),
        ];
        let mut out = Vec::new();
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                out.push((name, value, "must be finite and > 0 (or give a preset)"));
            }
        }
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                out.push((name, value, "must be finite and >= 0"));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The preset's pad and ballast in series, per metre of rail, are the
    /// continuous `ballasted` layer's 3.3e7 N/m² (both from one source).
    #[test]
    fn the_ballasted_preset_in_series_is_the_continuous_ballasted_layer() {
        let s = SleeperPreset::Ballasted.values();
        let per_metre = s.series_stiffness() / s.spacing;
        assert!((per_metre / 3.3e7 - 1.0).abs() < 0.02, "{per_metre:e}");
    }

    #[test]
    fn a_missing_value_without_a_preset_is_named() {
        let spec = SleepersSpec {
            preset: None,
            spacing: Some(0.6),
            pad_stiffness: Some(-1.0),
            pad_damping: None,
            sleeper_mass: Some(150.0),
            ballast_stiffness: None,
            ballast_damping: None,
            rail_elements_per_bay: None,
        };
        let names: Vec<_> = spec.resolve().problems().iter().map(|p| p.0).collect();
        assert_eq!(names, ["pad_stiffness", "ballast_stiffness"]);
    }
}
