//! The beam's parameters as a scene gives them (`[beam]`: length, mass,
//! stiffness, elements, supports, joints, damping, foundation, and the
//! fields each structure kind owns), with their serde form; the scene
//! format (`scene::Scene`) composes them.

use serde::{Deserialize, Serialize};

/// `BeamSpec`: the common fields written here, in the file's order, then
/// each structure kind's fields of `[beam]` (`$field: $ty`, declared in its
/// line of the list in `structure/mod.rs`), each optional (left out:
/// `None`). Called once, through `with_kind_fields!`.
macro_rules! beam_spec {
    ($($(#[$attr:meta])* $field:ident: $ty:ty,)*) => {
        /// The beam of a scene (`[beam]`).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct BeamSpec {
            /// Length L of the beam (m).
            pub length: f64,
            /// Mass per unit length (kg/m).
            pub mass_per_length: f64,
            /// Bending stiffness EI (N m^2); left out when `frequency` gives it.
            #[serde(default = "stiffness_not_given")]
            pub bending_stiffness: f64,
            /// First natural frequency f1 (Hz), instead of `bending_stiffness`:
            /// reading the scene sets EI so that the model's first mode has f1,
            /// then clears this field.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub frequency: Option<f64>,
            /// Distance h from the neutral axis to the top surface (m).
            pub surface_offset: f64,
            /// Number of Hermite cubic elements.
            pub elements: usize,
            #[serde(default)]
            pub supports: SupportsSpec,
            /// Rayleigh structural damping C = α M + β K; none when absent.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub damping: Option<DampingSpec>,
            /// Joints splitting the structure into several beams in a row, by
            /// increasing abscissa; none: one beam.
            #[serde(default, skip_serializing_if = "Vec::is_empty")]
            pub joints: Vec<JointSpec>,
            /// A Winkler foundation under the whole beam (a rail on its track bed);
            /// none when absent.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub foundation: Option<FoundationSpec>,
            $(
                $(#[$attr])*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $field: Option<$ty>,
            )*
        }

        /// Every optional field left out (pinned ends, no damping, joint,
        /// foundation or kind field); the required numbers not given (NaN,
        /// no elements), so that a literal names them (`..BeamSpec::default()`
        /// for the rest) and validation refuses a spec that does not.
        impl Default for BeamSpec {
            fn default() -> BeamSpec {
                BeamSpec {
                    length: f64::NAN,
                    mass_per_length: f64::NAN,
                    bending_stiffness: stiffness_not_given(),
                    frequency: None,
                    surface_offset: f64::NAN,
                    elements: 0,
                    supports: SupportsSpec::default(),
                    damping: None,
                    joints: Vec::new(),
                    foundation: None,
                    $($field: None,)*
                }
            }
        }
    };
}

with_kind_fields!(beam_spec);

/// The serde default of `beam.bending_stiffness`: not a number, so that a
/// scene that gives neither EI nor f1 fails the rule on EI.
fn stiffness_not_given() -> f64 {
    f64::NAN
}

/// A continuous (Winkler) elastic foundation: a distributed spring and
/// damper to the ground under every point of the beam, per metre of beam.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoundationSpec {
    /// Typical values to start from (docs/structures.md gives their
    /// sources); `stiffness` and `damping` override them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<FoundationPreset>,
    /// Foundation modulus k (N/m per metre of beam, N/m²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Foundation damping c (N s/m per metre of beam, N s/m²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
}

/// Track beds with typical foundation values per rail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FoundationPreset {
    /// Rail on pads, sleepers and ballast.
    Ballasted,
    /// Rail on elastic fastenings on a concrete slab.
    Slab,
}

impl FoundationPreset {
    /// (stiffness N/m², damping N s/m²) per rail: docs/structures.md
    /// derives them from their sources.
    pub fn values(self) -> (f64, f64) {
        match self {
            FoundationPreset::Ballasted => (3.3e7, 4.5e4),
            FoundationPreset::Slab => (9.2e7, 7.3e4),
        }
    }
}

impl FoundationSpec {
    /// The foundation modulus k (N/m²): the given one, else the preset's,
    /// else 0 (refused by validation).
    pub fn stiffness(&self) -> f64 {
        self.stiffness
            .or(self.preset.map(|p| p.values().0))
            .unwrap_or(0.0)
    }

    /// The foundation damping c (N s/m²): the given one, else the
    /// preset's, else 0.
    pub fn damping(&self) -> f64 {
        self.damping
            .or(self.preset.map(|p| p.values().1))
            .unwrap_or(0.0)
    }
}

/// Where one beam of the track meets the next.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Abscissa of the joint (m); for a separate joint, where the beam
    /// before it ends.
    pub at: f64,
    pub kind: JointKind,
    /// Separate joints only: width of the rail gap (m); the next beam
    /// starts at `at + gap`.
    #[serde(default)]
    pub gap: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointKind {
    /// The beam runs on over a pinned support at `at` (as an intermediate
    /// support).
    Continuous,
    /// Internal hinge: deflection shared, rotations independent; no support
    /// of its own (add an intermediate support or a spring at `at`).
    Hinge,
    /// Two simply supported beams: the one before ends pinned at `at`, the
    /// next starts pinned at `at + gap`.
    Separate,
}

/// An elastic support at a node: vertical and rotational springs and
/// dampers to the ground (all default 0).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Abscissa (m), 0 <= at <= L; a node is placed there.
    pub at: f64,
    /// Vertical stiffness (N/m).
    #[serde(default)]
    pub vertical: f64,
    /// Rotational stiffness (N m/rad).
    #[serde(default)]
    pub rotational: f64,
    /// Vertical damping (N s/m).
    #[serde(default)]
    pub vertical_damping: f64,
    /// Rotational damping (N m s/rad).
    #[serde(default)]
    pub rotational_damping: f64,
}

/// Rayleigh damping of the beam, C = α M + β K, given either way:
/// `{ alpha = 0.1, beta = 1e-4 }` (coefficients, 1/s and s), or
/// `{ ratio = 0.02, modes = [1, 3] }` (the same damping ratio ζ at the two
/// natural bending modes numbered from 1), or
/// `{ ratios = [0.02, 0.03], frequencies = [4.0, 30.0] }` (ζ at two
/// frequencies in Hz); or modal damping, `{ ratio = 0.015 }` alone: the
/// same ratio ζ in every mode (EN 1991-2's one ratio; C = Σ 2 ζ ωᵢ
/// (M φᵢ)(M φᵢ)ᵀ, exact on the modal structure).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    deny_unknown_fields,
    expecting = "one of { alpha, beta } (Rayleigh coefficients), { ratio, modes = [i, j] }, \
                 { ratios = [z1, z2], frequencies = [f1, f2] } (Hz), or { ratio } alone (the \
                 same ratio in every mode), with no other fields"
)]
pub enum DampingSpec {
    Coefficients {
        alpha: f64,
        beta: f64,
    },
    Modes {
        ratio: f64,
        modes: [usize; 2],
    },
    Frequencies {
        ratios: [f64; 2],
        frequencies: [f64; 2],
    },
    /// After `Modes`, so that `{ ratio, modes }` stays Rayleigh.
    Modal {
        ratio: f64,
    },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportsSpec {
    #[serde(default = "pinned")]
    pub left: EndSupport,
    #[serde(default = "pinned")]
    pub right: EndSupport,
    /// Abscissae (m) of intermediate pinned supports for multi-span beams.
    #[serde(default)]
    pub intermediate: Vec<f64>,
    /// Elastic supports (springs and dampers to the ground) at nodes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<SpringSpec>,
}

fn pinned() -> EndSupport {
    EndSupport::Pinned
}

impl Default for SupportsSpec {
    fn default() -> Self {
        SupportsSpec {
            left: EndSupport::Pinned,
            right: EndSupport::Pinned,
            intermediate: Vec::new(),
            springs: Vec::new(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EndSupport {
    /// Deflection held, rotation free.
    Pinned,
    /// Deflection and rotation held.
    Clamped,
    /// Nothing held.
    Free,
}
