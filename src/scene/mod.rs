//! Scene description: beam, moving body, sensors and solver settings.
//!
//! Read from TOML with serde. Every length is in metres, mass in kilograms,
//! force in newtons, time in seconds.

mod advice;
mod annotate;
mod builtin;
mod contact_law;
mod error;
pub mod fields;
mod frequency;
mod irregularity;
mod limits;
mod on_deck;
mod validate;

pub use crate::structure::track_sleepers::{SleeperPreset, SleepersSpec};
pub use advice::advisories;
pub use builtin::{builtin, builtins, fmu_builtins, template_file, templates, DEFAULT_SCENE};
pub use contact_law::{ContactLawSpec, ResolvedLaw};
pub use error::{Problem, SceneError};
pub use fields::field_notes_markdown;
pub use irregularity::{
    parse_table, read_table, track_extent, IrregularitySpec, MAX_IRREGULARITIES, MAX_TABLE_POINTS,
    TABLE_PATHS_VARIABLE,
};
pub use limits::{contact_rows, MAX_CONTACT_ROWS};
pub use validate::{
    is_identifier, is_xml_char, MAX_DESCRIPTION_CHARS, MAX_ELEMENTS, MAX_INTERMEDIATE_SUPPORTS,
    MAX_ITERATIONS, MAX_MAGNITUDE, MAX_NAME_CHARS, MAX_SCENE_BYTES, MAX_SENSORS, MIN_MAGNITUDE,
};

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A complete, self-contained description of one simulation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short identifier, used as the FMU's model name.
    pub name: String,
    /// One line saying what the scene is.
    #[serde(default)]
    pub description: String,
    /// Acceleration of gravity (m/s², acting downward on every body); the
    /// paper's scenes set 0 and load the body with `force_y` instead.
    #[serde(default = "default_gravity")]
    pub gravity: f64,
    pub beam: BeamSpec,
    /// Rigid ground before and after the beam.
    #[serde(default, skip_serializing_if = "TrackSpec::is_default")]
    pub track: TrackSpec,
    pub body: BodySpec,
    /// More vehicles on the track, each like `[body]`; their applied forces
    /// are constant (the FMU's force inputs act on `[body]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vehicles: Vec<BodySpec>,
    #[serde(default)]
    pub sensors: Vec<SensorSpec>,
    /// Sections where the bending moment and the shear are reported.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<SectionSpec>,
    /// Report every support's reaction (and a clamp's moment).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub reactions: bool,
    /// FMU outputs with the running error estimate in time of each
    /// sensor's deflection and acceleration (docs/error-estimates.md).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub error_estimate: bool,
    #[serde(default)]
    pub solver: SolverSpec,
    /// Bodies (by name: `wheel`, `car_unsprung`, `train_bogie1`, ...) that
    /// are coupling points of the FMU: each gets inputs for an additional
    /// force and moment and outputs of its motion (see
    /// docs/coupling.md).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub couplings: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    /// Length L of the beam (m).
    pub length: f64,
    /// Mass per unit length (kg/m).
    pub mass_per_length: f64,
    /// Bending stiffness EI (N m^2); left out when `frequency` gives it.
    #[serde(default = "frequency::stiffness_not_given")]
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

fn default_gravity() -> f64 {
    9.81
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

/// The vehicle (or moving force): its kind, mass, start and loads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Prefix of the body's variables (`wheel.x`, `glider.x`, ...).
    pub name: String,
    pub kind: BodyKind,
    /// Mass m (kg).
    pub mass: f64,
    /// Centroidal moment of inertia J (kg m^2); wheels only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// Radius r (m); wheels only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Abscissa of the contact point at t = 0 (m).
    #[serde(default)]
    pub initial_position: f64,
    /// Initial travel speed (m/s), positive to the right.
    pub initial_speed: f64,
    /// Hold the body's horizontal speed (m/s): a number, or a table of
    /// (time s, speed m/s) rows, linear between rows and held beyond them;
    /// tractive forces computed each step hold it on every body of the
    /// vehicle (any kind but a moving force).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prescribed_speed: Option<SpeedSpec>,
    /// Constant force on the body's centre, x component (N).
    #[serde(default)]
    pub force_x: f64,
    /// Constant force on the body's centre, y component (N); the paper's
    /// scenes use -600 kN.
    #[serde(default)]
    pub force_y: f64,
    /// The suspension of a `sprung_mass`; left out for other kinds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub suspension: Option<SuspensionSpec>,
    /// A `moving_force` that stands for a whole standard train (`HSLM-A1` …
    /// `HSLM-A10`): its first axle at `initial_position`, the others behind.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub train: Option<String>,
    /// The bogies, wheelsets and suspensions of a `bogie_vehicle` (whose
    /// `mass` is the car body's); left out for other kinds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bogie: Option<BogieSpec>,
    /// The magnets and suspensions of a `maglev_vehicle` (whose `mass` is
    /// the car body's); left out for other kinds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub maglev: Option<MaglevSpec>,
    /// Newton's coefficient of restitution e ∈ [0, 1] of the vehicle's
    /// contacts at a landing (0: plastic, 1: elastic).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub restitution: f64,
    /// Height (m) of the whole vehicle above its place on the track at
    /// t = 0: its contacts start open and it falls (needs `start = "rest"`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub initial_height: f64,
    /// How the vehicle's contact bodies meet the track: Lee's rigid
    /// contact when left out, or a compliant law (`contact_law`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_law: Option<ContactLawSpec>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// A maglev car body (bounce, pitch) over `magnets` gliders evenly spaced
/// along it, each on a vertical spring–damper preloaded with its share of
/// the car body's weight.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaglevSpec {
    /// Pitch inertia of the car body (kg m^2).
    pub car_inertia: f64,
    /// Number of magnets, front to rear, centred on the car body.
    pub magnets: usize,
    /// Distance between neighbouring magnets (m).
    pub magnet_spacing: f64,
    /// Mass of one magnet (kg).
    pub magnet_mass: f64,
    /// Suspension of one magnet: stiffness (N/m) and damping (N s/m).
    pub stiffness: f64,
    #[serde(default)]
    pub damping: f64,
}

impl MaglevSpec {
    /// Offset of magnet `i` (0 = front) from the car body's centre (m).
    pub fn offset(&self, i: usize) -> f64 {
        (0.5 * (self.magnets as f64 - 1.0) - i as f64) * self.magnet_spacing
    }
}

/// A prescribed horizontal speed: constant, or a table of (time, speed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a speed in m/s, or a table [[t0, v0], [t1, v1], ...] of times (s) and speeds (m/s)"
)]
pub enum SpeedSpec {
    Constant(f64),
    Table(Vec<[f64; 2]>),
}

impl SpeedSpec {
    /// The speed at time `t` (m/s): linear between the table's rows, held
    /// before the first and after the last.
    pub fn speed_at(&self, t: f64) -> f64 {
        match self {
            SpeedSpec::Constant(v) => *v,
            SpeedSpec::Table(rows) => {
                let after = rows.partition_point(|row| row[0] <= t);
                match (after.checked_sub(1).map(|i| rows[i]), rows.get(after)) {
                    (Some(a), Some(b)) => a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0]),
                    (Some(a), None) => a[1],
                    (None, Some(b)) => b[1],
                    (None, None) => 0.0,
                }
            }
        }
    }
}

/// The 10-DOF half vehicle: a car body (bounce, pitch) on secondary
/// spring–dampers over two bogies (bounce, pitch), each on primary
/// spring–dampers over two wheelsets (gliders, bounce). Both suspensions are
/// preloaded with the weight they carry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BogieSpec {
    /// Pitch inertia of the car body (kg m^2).
    pub car_inertia: f64,
    /// Mass of one bogie (kg).
    pub bogie_mass: f64,
    /// Pitch inertia of one bogie (kg m^2).
    pub bogie_inertia: f64,
    /// Mass of one wheelset (kg).
    pub wheelset_mass: f64,
    /// Half the distance between the bogie centres (m).
    pub bogie_half_distance: f64,
    /// Half the distance between the two axles of a bogie (m).
    pub axle_half_distance: f64,
    /// Primary suspension, per axle: stiffness (N/m) and damping (N s/m).
    pub primary_stiffness: f64,
    #[serde(default)]
    pub primary_damping: f64,
    /// Secondary suspension, per bogie: stiffness (N/m) and damping (N s/m).
    pub secondary_stiffness: f64,
    #[serde(default)]
    pub secondary_damping: f64,
    /// Radius of the wheelsets (m): with it they are rolling wheels (no
    /// slip, pitch inertia `wheelset_inertia`), without it gliders.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel_radius: Option<f64>,
    /// Polar moment of inertia of one wheelset (kg m^2); with `wheel_radius`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheelset_inertia: Option<f64>,
}

/// A sprung mass's suspension: a vertical spring–damper over an unsprung
/// contact mass (a glider), preloaded with the sprung weight so that the
/// vehicle starts in static equilibrium.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuspensionSpec {
    /// Vertical stiffness k (N/m).
    pub stiffness: f64,
    /// Vertical damping c (N s/m).
    #[serde(default)]
    pub damping: f64,
    /// Mass of the contact body under the spring (kg); 0 makes it the
    /// massless follower (its force is the suspension's).
    pub unsprung_mass: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// Rigid disc rolling without slip (mass, inertia, radius).
    Wheel,
    /// Point body gliding at the surface (r = 0, J = 0): the maglev model.
    Glider,
    /// Moving oscillator: the body (J = 0) on a vertical spring–damper over
    /// an unsprung glider (`suspension`).
    #[serde(rename = "sprung_mass")]
    SprungMass,
    /// Car body over two bogies over four wheelsets (`bogie`); the body's
    /// `initial_position` is the car body's centre.
    #[serde(rename = "bogie_vehicle")]
    BogieVehicle,
    /// Car body over N magnets (gliders) on spring–dampers along its
    /// length (`maglev`); `initial_position` is the car body's centre.
    #[serde(rename = "maglev_vehicle")]
    MaglevVehicle,
    /// A point force at constant speed with no body (no inertia, no
    /// contact): its weight `mass` × `gravity` plus `force_y`, or each axle
    /// of its `train`. Run by `guideway sweep`, not `guideway run`.
    #[serde(rename = "moving_force")]
    MovingForce,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Sensor name; its output is `sensor.<name>.deflection`.
    pub name: String,
    /// Abscissa along the beam (m).
    pub position: f64,
}

/// A cross-section of the beam: its outputs are `section.<name>.moment`
/// and `section.<name>.shear`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    pub name: String,
    /// Abscissa along the beam (m).
    pub position: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Fixed internal time step (s).
    #[serde(default = "default_step")]
    pub step: f64,
    /// Tolerance on the velocity error |e| (m/s); paper: 1e-7.
    #[serde(default = "default_velocity_tolerance")]
    pub velocity_tolerance: f64,
    /// Tolerance on the gap error |g| (m); paper: 1e-5.
    #[serde(default = "default_gap_tolerance")]
    pub gap_tolerance: f64,
    /// Cap on contact-force iterations per stage and step.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: u32,
    /// Time integrator of the bodies.
    #[serde(default)]
    pub integrator: IntegratorKind,
    /// Numerical damping of the implicit scheme, −α of HHT-α, in [0, 1/3]
    /// (0: Newmark's average acceleration, energy-conserving).
    #[serde(default)]
    pub numerical_damping: f64,
    /// How the contact force varies within a step under RK4 (HHT-α's
    /// unknown force is its end-of-step value whatever this says).
    #[serde(default, skip_serializing_if = "ForceProfile::is_default")]
    pub force_profile: ForceProfile,
    /// Stop time (s) if the body has not left the beam before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_time: Option<f64>,
    /// The state at t = 0: `rest` on the undeformed beam, or `static`: the
    /// beam deflected under the vehicles' weight and every suspension at
    /// its preload (the vehicles start in equilibrium).
    #[serde(default, skip_serializing_if = "StartKind::is_rest")]
    pub start: StartKind,
    /// How the beam is represented: its finite elements (`full`), or its
    /// lowest natural modes (`modal`, with `modes` or `max_frequency`).
    #[serde(default, skip_serializing_if = "StructureKind::is_full")]
    pub structure: StructureKind,
    /// With `structure = "modal"`: how many of the lowest modes to keep.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<usize>,
    /// With `structure = "modal"`: keep the modes up to this frequency (Hz).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_frequency: Option<f64>,
    /// Relative error the summary figures must meet: `guideway run` then
    /// chooses the step (as with `--rtol`; docs/error-estimates.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StructureKind {
    /// Every finite-element DOF of the beam (the paper's model).
    #[default]
    Full,
    /// The beam's lowest natural modes of the finite-element model.
    Modal,
}

impl StructureKind {
    pub fn is_full(&self) -> bool {
        *self == StructureKind::Full
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartKind {
    #[default]
    Rest,
    Static,
}

impl StartKind {
    pub fn is_rest(&self) -> bool {
        *self == StartKind::Rest
    }
}

// The solver's defaults are `SolverParameters::DEFAULT`'s (one source).
const SOLVER_DEFAULTS: crate::solver::parameters::SolverParameters =
    crate::solver::parameters::SolverParameters::DEFAULT;

fn default_step() -> f64 {
    SOLVER_DEFAULTS.step
}
fn default_velocity_tolerance() -> f64 {
    SOLVER_DEFAULTS.iteration.velocity_tolerance
}
fn default_gap_tolerance() -> f64 {
    SOLVER_DEFAULTS.iteration.gap_tolerance
}
fn default_max_iterations() -> u32 {
    SOLVER_DEFAULTS.iteration.max_iterations
}

impl Default for SolverSpec {
    fn default() -> Self {
        SolverSpec {
            step: default_step(),
            velocity_tolerance: default_velocity_tolerance(),
            gap_tolerance: default_gap_tolerance(),
            max_iterations: default_max_iterations(),
            integrator: IntegratorKind::default(),
            numerical_damping: 0.0,
            force_profile: ForceProfile::default(),
            end_time: None,
            start: StartKind::Rest,
            structure: StructureKind::Full,
            modes: None,
            max_frequency: None,
            tolerance: None,
        }
    }
}

/// The contact force within a step. The iteration's unknown is always the
/// force's mean over the step; the profile sets its shape from the means of
/// the steps before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ForceProfile {
    /// Constant over the step: the paper's scheme (second order).
    #[default]
    Held,
    /// Linear: its mean over this step and the previous one as found.
    Linear,
    /// Quadratic: its means over this step and the two before as found.
    Quadratic,
}

impl ForceProfile {
    pub fn is_default(&self) -> bool {
        *self == ForceProfile::default()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum IntegratorKind {
    /// Classical fourth-order Runge-Kutta, the paper's scheme (explicit).
    #[default]
    Rk4,
    /// HHT-α for the beam (implicit, unconditionally stable), damping
    /// `numerical_damping`.
    Hht,
    /// RK4 where `step` is within its stability limit for the mesh, HHT-α
    /// otherwise.
    Auto,
}

impl Scene {
    /// Parse a scene from TOML text and validate it.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, None).map(|(scene, _)| scene)
    }

    /// Parse, read profile tables relative to `base` (the scene file's
    /// folder) when given, and validate.
    /// Also returns the table files read.
    fn parse(text: &str, base: Option<&Path>) -> Result<(Scene, Vec<PathBuf>), SceneError> {
        if text.len() as u64 > MAX_SCENE_BYTES {
            return Err(SceneError::TooLarge {
                bytes: text.len() as u64,
            });
        }
        let mut scene: Scene = serde_path_to_error::deserialize(toml::Deserializer::new(text))
            .map_err(|e| error::from_toml_error(e, text))?;
        frequency::resolve(&mut scene, text)?;
        let tables = match base {
            Some(base) => irregularity::read_tables(&mut scene, base)?,
            None => Vec::new(),
        };
        scene.validate()?;
        Ok((scene, tables))
    }

    /// Check every rule; the error lists every broken one with the field's
    /// path, its value and the rule.
    pub fn validate(&self) -> Result<(), SceneError> {
        validate::validate(self)
    }

    /// Load a scene from a TOML file, or a built-in scene by name. An
    /// existing file wins over a built-in of the same name; anything ending
    /// in `.toml` or containing a path separator is taken as a file.
    pub fn load(file_or_builtin: &str) -> Result<Scene, SceneError> {
        Scene::load_with_inputs(file_or_builtin).map(|(scene, _)| scene)
    }

    /// `load`, and the files it read: the scene file (none for a built-in)
    /// and its table files, which no output of the run may overwrite.
    pub fn load_with_inputs(file_or_builtin: &str) -> Result<(Scene, Vec<PathBuf>), SceneError> {
        let path = Path::new(file_or_builtin);
        let looks_like_file = file_or_builtin.ends_with(".toml")
            || file_or_builtin.contains(std::path::MAIN_SEPARATOR)
            || file_or_builtin.contains('/');
        if path.is_file() || looks_like_file {
            let base = path.parent().unwrap_or(Path::new(""));
            let (scene, mut inputs) =
                Scene::parse(&read_limited(path, file_or_builtin)?, Some(base))?;
            inputs.insert(0, path.to_path_buf());
            return Ok((scene, inputs));
        }
        let scene = builtin(file_or_builtin).ok_or_else(|| SceneError::NotFound {
            name: file_or_builtin.to_string(),
        })?;
        Ok((scene, Vec::new()))
    }

    /// The scene as TOML that `from_toml_str` reads back to the same scene.
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).expect("a scene always serialises to TOML")
    }

    /// The paper's model 1 (Vu-Quoc & Olsson's beam) with the given body.
    pub fn lee1994(kind: BodyKind, initial_speed: f64, step: f64) -> Scene {
        let (name, inertia, radius) = match kind {
            BodyKind::Wheel => ("wheel", Some(135.0), Some(0.3)),
            BodyKind::Glider
            | BodyKind::SprungMass
            | BodyKind::BogieVehicle
            | BodyKind::MaglevVehicle
            | BodyKind::MovingForce => ("glider", None, None),
        };
        Scene {
            name: format!("lee1994-{name}-{initial_speed}"),
            description: String::new(),
            gravity: 0.0,
            beam: BeamSpec {
                length: 24.0,
                mass_per_length: 1250.0,
                bending_stiffness: 1e9,
                frequency: None,
                surface_offset: 0.6,
                elements: 2,
                supports: SupportsSpec::default(),
                damping: None,
                joints: Vec::new(),
                foundation: None,
            },
            body: BodySpec {
                name: name.to_string(),
                kind,
                mass: 3000.0,
                inertia,
                radius,
                initial_position: 0.0,
                initial_speed,
                prescribed_speed: None,
                force_x: 0.0,
                force_y: -600e3,
                suspension: None,
                train: None,
                bogie: None,
                maglev: None,
                restitution: 0.0,
                initial_height: 0.0,
                contact_law: None,
            },
            track: TrackSpec::default(),
            vehicles: Vec::new(),
            sensors: vec![SensorSpec {
                name: "midspan".into(),
                position: 12.0,
            }],
            sections: Vec::new(),
            reactions: false,
            error_estimate: false,
            solver: SolverSpec {
                step,
                ..SolverSpec::default()
            },
            couplings: Vec::new(),
        }
    }

    /// Every vehicle: `[body]`, then each of `[[vehicles]]`.
    pub fn every_vehicle(&self) -> impl Iterator<Item = &BodySpec> + Clone {
        std::iter::once(&self.body).chain(&self.vehicles)
    }

    /// The names of every body of the scene, vehicle by vehicle (what a
    /// coupling may name).
    pub fn body_names(&self) -> Vec<String> {
        self.every_vehicle()
            .flat_map(BodySpec::body_names)
            .collect()
    }
}

impl BodySpec {
    /// The names of this vehicle's bodies, as the assembled system names
    /// them: `<name>`, and `<name>_unsprung` (sprung mass) or
    /// `<name>_bogie1..2`, `<name>_wheelset1..4` (bogie vehicle),
    /// `<name>_magnet1..N` (maglev vehicle); none for a moving force.
    pub fn body_names(&self) -> Vec<String> {
        let n = &self.name;
        let mut names = vec![n.clone()];
        match self.kind {
            BodyKind::Wheel | BodyKind::Glider => {}
            // A massless follower (unsprung_mass = 0) is a contact, not a body.
            BodyKind::SprungMass if self.suspension.is_some_and(|s| s.unsprung_mass == 0.0) => {}
            BodyKind::SprungMass => names.push(format!("{n}_unsprung")),
            BodyKind::BogieVehicle => {
                names.extend((1..=2).map(|i| format!("{n}_bogie{i}")));
                // Massless followers are contacts, not bodies.
                if !self.massless_contacts() {
                    names.extend((1..=4).map(|i| format!("{n}_wheelset{i}")));
                }
            }
            // Massless followers are contacts, not bodies.
            BodyKind::MaglevVehicle if self.massless_contacts() => {}
            BodyKind::MaglevVehicle => {
                let magnets = self.maglev.map_or(0, |m| m.magnets);
                names.extend((1..=magnets).map(|i| format!("{n}_magnet{i}")));
            }
            // A moving force is a load, not a body.
            BodyKind::MovingForce => names.clear(),
        }
        names
    }

    /// Whether a bogie or maglev vehicle runs on massless followers
    /// (`bogie.wheelset_mass = 0`, `maglev.magnet_mass = 0`) in place of
    /// its wheelsets or magnets.
    pub fn massless_contacts(&self) -> bool {
        match self.kind {
            BodyKind::BogieVehicle => self.bogie.is_some_and(|b| b.wheelset_mass == 0.0),
            BodyKind::MaglevVehicle => self.maglev.is_some_and(|m| m.magnet_mass == 0.0),
            _ => false,
        }
    }
}

/// The text of a scene file, refused unread beyond `MAX_SCENE_BYTES` (a
/// device or a growing file is read only up to one byte past the limit).
fn read_limited(path: &Path, shown: &str) -> Result<String, SceneError> {
    use std::io::Read;
    let read_error = |e: std::io::Error| SceneError::Read {
        path: shown.to_string(),
        message: e.to_string(),
    };
    crate::input_file::check_regular(path).map_err(|message| SceneError::Read {
        path: shown.to_string(),
        message,
    })?;
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        let size = std::fs::metadata(path).map_or(bytes.len() as u64, |m| m.len());
        return Err(SceneError::TooLarge { bytes: size });
    }
    String::from_utf8(bytes).map_err(|e| SceneError::Read {
        path: shown.to_string(),
        message: format!("not UTF-8 text: {e}"),
    })
}

#[cfg(test)]
mod tests;
