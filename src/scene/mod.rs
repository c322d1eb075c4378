//! Scene description: beam, moving body, sensors and solver settings.
//!
//! Read from TOML with serde. Every length is in metres, mass in kilograms,
//! force in newtons, time in seconds.

mod advice;
mod annotate;
mod builtin;
mod error;
pub mod fields;
mod frequency;
mod irregularity;
mod limits;
mod on_deck;
mod validate;

pub use crate::contact::law::{ContactLawSpec, ResolvedLaw};
pub use crate::structure::profile::IrregularitySpec;
pub use crate::structure::track_sleepers::{SleeperPreset, SleepersSpec};
pub use crate::vehicle::presets::{BodyKind, BodySpec, BogieSpec, MaglevSpec, SuspensionSpec};
pub use crate::vehicle::speed::SpeedSpec;
pub use advice::advisories;
pub use builtin::{builtin, builtins, fmu_builtins, template_file, templates, DEFAULT_SCENE};
pub use error::{Problem, SceneError};
pub use fields::field_notes_markdown;
pub use irregularity::{
    parse_table, read_table, track_extent, MAX_IRREGULARITIES, MAX_TABLE_POINTS,
    TABLE_PATHS_VARIABLE,
};
pub use limits::{contact_rows, MAX_CONTACT_ROWS};
pub(crate) use validate::{fmt_f64, quoted, Checks};
pub use validate::{
    is_identifier, is_xml_char, MAX_DESCRIPTION_CHARS, MAX_ELEMENTS, MAX_INTERMEDIATE_SUPPORTS,
    MAX_ITERATIONS, MAX_MAGNITUDE, MAX_NAME_CHARS, MAX_SCENE_BYTES, MAX_SENSORS, MIN_MAGNITUDE,
};

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A complete, self-contained description of one simulation, as the rest
/// of the program sees it: the file's `[body]` is vehicle 0 of
/// `vehicles`, each `[[vehicles]]` entry the next one (`SceneFile` is the
/// file's own shape).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "SceneFile", into = "SceneFile")]
pub struct Scene {
    /// Short identifier, used as the FMU's model name.
    pub name: String,
    /// One line saying what the scene is.
    pub description: String,
    /// Acceleration of gravity (m/s², downward on every body).
    pub gravity: f64,
    pub beam: BeamSpec,
    /// Rigid ground before and after the beam.
    pub track: TrackSpec,
    /// Every vehicle on the track, in the file's order: `[body]`, then each
    /// of `[[vehicles]]` (`vehicle_path` names their fields). Validation
    /// refuses an empty list.
    pub vehicles: Vec<BodySpec>,
    pub sensors: Vec<SensorSpec>,
    /// Sections where the bending moment and the shear are reported.
    pub sections: Vec<SectionSpec>,
    /// Report every support's reaction (and a clamp's moment).
    pub reactions: bool,
    /// FMU outputs with the running error estimate in time.
    pub error_estimate: bool,
    pub solver: SolverSpec,
    /// Bodies (by name) that are coupling points of the FMU.
    pub couplings: Vec<String>,
}

/// The path a scene file names vehicle `k`'s fields by: `body` for the
/// file's `[body]` (vehicle 0), `vehicles[k-1]` for the others.
pub fn vehicle_path(k: usize) -> String {
    match k {
        0 => "body".to_string(),
        k => format!("vehicles[{}]", k - 1),
    }
}

/// A scene file's shape: `[body]` and the `[[vehicles]]` after it, read
/// into `Scene::vehicles` as one list (users' files keep their `[body]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    name: String,
    #[serde(default)]
    description: String,
    /// The paper's scenes set 0 and load the body with `force_y` instead.
    #[serde(default = "default_gravity")]
    gravity: f64,
    beam: BeamSpec,
    #[serde(default, skip_serializing_if = "TrackSpec::is_default")]
    track: TrackSpec,
    /// Required in a file (the missing-field error names it); `None` only
    /// when written from a scene without vehicles.
    #[serde(
        deserialize_with = "required_body",
        skip_serializing_if = "Option::is_none"
    )]
    body: Option<BodySpec>,
    /// More vehicles on the track, each like `[body]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    vehicles: Vec<BodySpec>,
    #[serde(default)]
    sensors: Vec<SensorSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    sections: Vec<SectionSpec>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    reactions: bool,
    /// (docs/error-estimates.md)
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    error_estimate: bool,
    #[serde(default)]
    solver: SolverSpec,
    /// Each gets inputs for an additional force and moment and outputs of
    /// its motion (docs/coupling.md).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    couplings: Vec<String>,
}

fn required_body<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<BodySpec>, D::Error> {
    BodySpec::deserialize(d).map(Some)
}

impl From<SceneFile> for Scene {
    fn from(file: SceneFile) -> Scene {
        let SceneFile {
            name,
            description,
            gravity,
            beam,
            track,
            body,
            vehicles,
            sensors,
            sections,
            reactions,
            error_estimate,
            solver,
            couplings,
        } = file;
        Scene {
            name,
            description,
            gravity,
            beam,
            track,
            vehicles: body.into_iter().chain(vehicles).collect(),
            sensors,
            sections,
            reactions,
            error_estimate,
            solver,
            couplings,
        }
    }
}

impl From<Scene> for SceneFile {
    fn from(scene: Scene) -> SceneFile {
        let Scene {
            name,
            description,
            gravity,
            beam,
            track,
            vehicles,
            sensors,
            sections,
            reactions,
            error_estimate,
            solver,
            couplings,
        } = scene;
        let mut vehicles = vehicles.into_iter();
        SceneFile {
            name,
            description,
            gravity,
            beam,
            track,
            body: vehicles.next(),
            vehicles: vehicles.collect(),
            sensors,
            sections,
            reactions,
            error_estimate,
            solver,
            couplings,
        }
    }
}

// The beam's parameters are the structure's (structure/beam/spec.rs).
pub use crate::structure::beam::{
    BeamSpec, DampingSpec, FoundationPreset, FoundationSpec, JointKind, JointSpec, SpringSpec,
};

// The track's spec is the structure's (structure/track_spec.rs).
pub use crate::structure::track_spec::{OnDeckSpec, TrackSpec};

fn default_gravity() -> f64 {
    9.81
}

pub use crate::structure::beam::{EndSupport, SupportsSpec};

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

// The solver's parameters are the solver's (solver/spec.rs, solver/integrate).
pub use crate::solver::integrate::{ForceProfile, IntegratorKind};
pub use crate::solver::spec::{SolverSpec, StartKind};
pub use crate::structure::modal::StructureKind;

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
        let (name, inertia, radius) = if kind == BodyKind::Wheel {
            ("wheel", Some(135.0), Some(0.3))
        } else {
            ("glider", None, None)
        };
        Scene {
            name: format!("lee1994-{name}-{initial_speed}"),
            description: String::new(),
            gravity: 0.0,
            beam: BeamSpec {
                length: 24.0,
                mass_per_length: 1250.0,
                bending_stiffness: 1e9,
                surface_offset: 0.6,
                elements: 2,
                ..BeamSpec::default()
            },
            vehicles: vec![BodySpec {
                inertia,
                radius,
                initial_speed,
                force_y: -600e3,
                ..BodySpec::bare(name, kind, 3000.0)
            }],
            track: TrackSpec::default(),
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

    /// The names of every body of the scene, vehicle by vehicle (what a
    /// coupling may name).
    pub fn body_names(&self) -> Vec<String> {
        self.vehicles
            .iter()
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
        self.kind.body_names(self)
    }

    /// Whether a bogie or maglev vehicle runs on massless followers
    /// (`bogie.wheelset_mass = 0`, `maglev.magnet_mass = 0`) in place of
    /// its wheelsets or magnets.
    pub fn massless_contacts(&self) -> bool {
        self.kind.massless_contacts(self)
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
