//! The track's spec (`[track]`, `[track.on_deck]`): the rigid approach
//! and run-off, the irregularities of the running surface and the rail
//! over the deck. Its structure owner reads it (`Structure::of_scene`,
//! `TrackBeam::new`); `scene::` re-exports it, serde unchanged.

use serde::{Deserialize, Serialize};

use crate::structure::beam::FoundationPreset;
use crate::structure::profile::IrregularitySpec;
use crate::structure::track_sleepers::SleepersSpec;

/// The rigid approach (x < 0) and run-off (x > L) of the track (m).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    #[serde(default)]
    pub approach: f64,
    #[serde(default)]
    pub run_off: f64,
    /// Irregularities of the running surface, summed (none when empty).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub irregularities: Vec<IrregularitySpec>,
    /// A rail over the deck on the track's layer, on the ground along the
    /// approach and the run-off; the contacts run on the rail. None: the
    /// contacts run on the beam and the approach and run-off are rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on_deck: Option<OnDeckSpec>,
}

/// `[track.on_deck]`: the rail (an Euler–Bernoulli beam continuous from
/// the approach to the run-off) and the layer between it and the deck
/// (and the ground), per metre of rail. Values for the line the contacts
/// load: for wheelsets, both rails.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OnDeckSpec {
    /// Typical values of the layer (`ballasted` or `slab`, per rail:
    /// docs/structures.md); `stiffness` and `damping` override them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<FoundationPreset>,
    /// Rail to deck stiffness per metre (N/m²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Rail to deck damping per metre (N s/m²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Rail to ground on the approach and the run-off (N/m², N s/m²);
    /// the deck's layer when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground_stiffness: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground_damping: Option<f64>,
    /// The rail's bending stiffness EI (N m²) and mass per metre (kg/m).
    pub rail_bending_stiffness: f64,
    pub rail_mass_per_length: f64,
    /// Discrete supports (pads, sleepers, ballast) in place of the layer
    /// and the ground's layer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sleepers: Option<SleepersSpec>,
}

impl OnDeckSpec {
    /// The layer's stiffness: the given one, else the preset's, else 0
    /// (refused by validation).
    pub fn stiffness(&self) -> f64 {
        self.stiffness
            .or(self.preset.map(|p| p.values().0))
            .unwrap_or(0.0)
    }

    /// The layer's damping: the given one, else the preset's, else 0.
    pub fn damping(&self) -> f64 {
        self.damping
            .or(self.preset.map(|p| p.values().1))
            .unwrap_or(0.0)
    }

    /// The ground's stiffness: the given one, else the layer's.
    pub fn ground_stiffness(&self) -> f64 {
        self.ground_stiffness.unwrap_or(self.stiffness())
    }

    /// The ground's damping: the given one, else the layer's.
    pub fn ground_damping(&self) -> f64 {
        self.ground_damping.unwrap_or(self.damping())
    }
}

impl TrackSpec {
    pub fn is_default(&self) -> bool {
        *self == TrackSpec::default()
    }
}
