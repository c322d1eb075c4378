//! The scene's field table: every field of a scene file once, with its unit,
//! default, rule, note and (for the numbers an FMU may set) how to read and
//! write it.
//!
//! One table drives the validation's rules for plain numbers, the notes of
//! the annotated scene (`guideway scenes --show`), the generated reference
//! page `docs/scene-fields.md` and the FMU's parameters (by path, for every
//! vehicle). A new field is one row here (plus its serde field in
//! `scene/mod.rs` and any rule that ties it to other fields in
//! `validate.rs`); a preset's own fields are rows in the preset's file
//! (`vehicle/presets/`), placed into this table by the `presets!` list,
//! and a structure kind's fields of `[beam]` rows in the kind's file
//! (`structure/`), placed by the `structure_kinds!` list.

use super::{
    BeamSpec, BodyKind, BodySpec, Scene, SensorSpec, SpeedSpec, MAX_ELEMENTS, MAX_MAGNITUDE,
    MIN_MAGNITUDE,
};
use std::sync::LazyLock;

/// One field of a scene file.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// Dotted path in the file; `body.*` fields are those of every vehicle
    /// (`[body]` and each `[[vehicles]]`), `sensors.*` of each sensor.
    pub path: &'static str,
    /// SI unit as FMI writes it (`N.m2`), empty for none.
    pub unit: &'static str,
    /// The value a scene that leaves the field out gets.
    pub default: Default,
    /// The rule the value must satisfy on its own (rules tying fields to
    /// each other are `validate.rs`'s).
    pub rule: Rule,
    /// Unit, meaning, rule in a few words: the comment beside the field in
    /// an annotated scene.
    pub note: &'static str,
    /// What the field means, as an FMU parameter's description (empty:
    /// not an FMU parameter).
    pub doc: &'static str,
    /// How an FMU reads and writes it; `Access::None`: not a parameter.
    pub access: Access,
}

/// The value of a field a scene leaves out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Default {
    /// The scene must give it (where its table or kind is present).
    Required,
    /// Left out: absent (off, or derived from other fields).
    Absent,
    /// Left out: this value.
    Value(&'static str),
}

/// The rule of one value on its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// A finite number within ±`MAX_MAGNITUDE`.
    Finite,
    /// Finite and > 0 (and >= `MIN_MAGNITUDE`).
    Positive,
    /// Finite and >= 0.
    NonNegative,
    /// Finite, in [0, 1].
    UnitInterval,
    /// An integer in 1..=`MAX_ELEMENTS`.
    Elements,
    /// Finite and >= -track.approach (a start on the approach or the
    /// beam; `validate.rs` adds the beam's end and the rail gaps).
    OnTrack,
    /// Not a plain number: the note states the rule, `validate.rs` checks
    /// it.
    Words,
}

/// How the table reads and writes a numeric field (`None` from the getter:
/// absent in this scene): validation checks the rule of every value it
/// reads, and a row with a `doc` is an FMU parameter.
#[derive(Debug, Clone, Copy)]
pub enum Access {
    None,
    /// A field of the scene itself.
    Scene(fn(&Scene) -> Option<f64>, fn(&mut Scene, f64)),
    /// A field of `[beam]` a structure kind owns (`structure::KindField`).
    Beam(fn(&BeamSpec) -> Option<f64>, fn(&mut BeamSpec, f64)),
    /// A field of each vehicle.
    Vehicle(fn(&BodySpec) -> Option<f64>, fn(&mut BodySpec, f64)),
    /// A field of each sensor.
    Sensor(fn(&SensorSpec) -> Option<f64>, fn(&mut SensorSpec, f64)),
}

/// A vehicle row's access to `field` of its optional preset block
/// (`block_field!(bogie.primary_stiffness)`): None where the vehicle has
/// no such block, and a set there leaves it without one.
macro_rules! block_field {
    ($block:ident . $field:ident) => {
        $crate::scene::fields::Access::Vehicle(
            |b| b.$block.as_ref().map(|g| g.$field),
            |b, x| {
                if let Some(g) = b.$block.as_mut() {
                    g.$field = x
                }
            },
        )
    };
}
pub(crate) use block_field;

impl Rule {
    /// What is wrong with `x` under this rule, in the words of a scene
    /// error; `approach` is `track.approach` (for `OnTrack`).
    pub fn problem(self, x: f64, approach: f64) -> Option<String> {
        if !x.is_finite() {
            return Some("must be a finite number".into());
        }
        if x.abs() > MAX_MAGNITUDE {
            return Some(format!(
                "must lie within ±{MAX_MAGNITUDE:e} (the magnitude limit)"
            ));
        }
        match self {
            Rule::Positive if x <= 0.0 => Some("must be > 0".into()),
            Rule::Positive if x < MIN_MAGNITUDE => Some(format!(
                "must be >= {MIN_MAGNITUDE:e} (the magnitude limit)"
            )),
            Rule::NonNegative if x < 0.0 => Some("must be >= 0".into()),
            Rule::UnitInterval if !(0.0..=1.0).contains(&x) => Some("must lie in [0, 1]".into()),
            Rule::Elements if x < 1.0 => Some("must be >= 1".into()),
            Rule::Elements if x > MAX_ELEMENTS as f64 => Some(format!("must be <= {MAX_ELEMENTS}")),
            Rule::Elements if x.fract() != 0.0 => Some("must be an integer".into()),
            Rule::OnTrack if x < -approach => Some(format!(
                "must be >= {} (-track.approach: the start of the track)",
                -approach
            )),
            _ => None,
        }
    }

    /// The inclusive range of values this rule accepts, as declared bounds
    /// (every value within them passes `problem`).
    pub fn bounds(self, approach: f64) -> (f64, f64) {
        match self {
            Rule::Positive => (MIN_MAGNITUDE, MAX_MAGNITUDE),
            Rule::NonNegative => (0.0, MAX_MAGNITUDE),
            Rule::UnitInterval => (0.0, 1.0),
            Rule::Elements => (1.0, MAX_ELEMENTS as f64),
            Rule::OnTrack => ((-approach).max(-MAX_MAGNITUDE), MAX_MAGNITUDE),
            Rule::Finite | Rule::Words => (-MAX_MAGNITUDE, MAX_MAGNITUDE),
        }
    }
}

impl Field {
    /// How many holders of this field `scene` has: the scene itself (one),
    /// each sensor or each vehicle; none for a row no getter reads.
    pub fn holders(&self, scene: &Scene) -> usize {
        match self.access {
            Access::None => 0,
            Access::Scene(..) | Access::Beam(..) => 1,
            Access::Sensor(..) => scene.sensors.len(),
            Access::Vehicle(..) => scene.vehicles.len(),
        }
    }

    /// The value of holder `k` (the scene; sensor `k`; vehicle `k`, see
    /// `vehicle`), `None` where the holder or its field is absent.
    pub fn value(&self, scene: &Scene, k: usize) -> Option<f64> {
        match self.access {
            Access::None => None,
            Access::Scene(get, _) => get(scene),
            Access::Beam(get, _) => get(&scene.beam),
            Access::Sensor(get, _) => scene.sensors.get(k).and_then(get),
            Access::Vehicle(get, _) => vehicle(scene, k).and_then(get),
        }
    }

    /// Write `x` into holder `k`; false (nothing written) where the holder
    /// or its field is absent.
    pub fn set(&self, scene: &mut Scene, k: usize, x: f64) -> bool {
        if self.value(scene, k).is_none() {
            return false;
        }
        match self.access {
            Access::None => return false,
            Access::Scene(_, set) => set(scene, x),
            Access::Beam(_, set) => set(&mut scene.beam, x),
            Access::Sensor(_, set) => set(&mut scene.sensors[k], x),
            Access::Vehicle(_, set) => set(vehicle_mut(scene, k).expect("present"), x),
        }
        true
    }

    /// The FMU's name of holder `k`'s value: the path for the scene's own
    /// fields, `sensor.<name>.<field>` and `<vehicle name>.<field>` for the
    /// others (what `fmu_name_pattern` writes on the reference page).
    pub fn fmu_name(&self, scene: &Scene, k: usize) -> String {
        let rest = |prefix: &str| self.path.strip_prefix(prefix).unwrap_or(self.path);
        match self.access {
            Access::Sensor(..) => format!("sensor.{}.{}", scene.sensors[k].name, rest("sensors.")),
            Access::Vehicle(..) => {
                let name = vehicle(scene, k).map_or("", |v| v.name.as_str());
                format!("{name}.{}", rest("body."))
            }
            Access::None | Access::Scene(..) | Access::Beam(..) => self.path.to_string(),
        }
    }
}

/// Vehicle `k` of `scene` (`vehicle_path(k)` in its file).
pub fn vehicle(scene: &Scene, k: usize) -> Option<&BodySpec> {
    scene.vehicles.get(k)
}

fn vehicle_mut(scene: &mut Scene, k: usize) -> Option<&mut BodySpec> {
    scene.vehicles.get_mut(k)
}

/// The row of `path` (`vehicles.*` read as `body.*`).
pub fn field(path: &str) -> Option<&'static Field> {
    let body_path;
    let path = match path.strip_prefix("vehicles.") {
        Some(rest) => {
            body_path = format!("body.{rest}");
            body_path.as_str()
        }
        None => path,
    };
    FIELDS.iter().find(|f| f.path == path)
}

/// A vehicle's initial speed; a constant prescribed speed follows it (the
/// scene's rule: the prescribed speed starts at the initial speed).
/// The setter of `body.initial_speed` (for a train's speed, which sets it
/// on every vehicle).
pub fn initial_speed_setter() -> fn(&mut BodySpec, f64) {
    set_initial_speed
}

fn set_initial_speed(body: &mut BodySpec, x: f64) {
    body.initial_speed = x;
    if let Some(SpeedSpec::Constant(v)) = body.prescribed_speed.as_mut() {
        *v = x;
    }
}

/// Every field of a scene file, in the order of the reference page: the
/// scene's own rows, the contact laws' (`contact::law::LAW_ROWS`, from
/// their list) before the beam's, each preset's rows
/// (`vehicle::presets::rows`, the fields of `[body]` a preset owns) and
/// each structure kind's (`structure::kind_fields`, the fields of `[beam]`
/// a kind owns) before the row the preset or kind names.
pub static FIELDS: LazyLock<Vec<Field>> = LazyLock::new(|| {
    let mut rows = SCENE_ROWS.to_vec();
    let laws = crate::contact::law::LAW_ROWS
        .iter()
        .map(|&row| law_row(row));
    splice_before(&mut rows, "beam.length", laws);
    for (before, own) in crate::vehicle::presets::rows() {
        splice_before(&mut rows, before, own.iter().copied());
    }
    for (before, own) in crate::structure::kind_fields() {
        splice_before(&mut rows, before, own.iter().map(kind_row));
    }
    if let Some(kind) = rows.iter_mut().find(|f| f.path == "body.kind") {
        kind.note = LazyLock::force(&KIND_NOTE).as_str();
    }
    rows
});

/// The note of `body.kind`: every preset's name (`wheel | glider | ...`).
static KIND_NOTE: LazyLock<String> = LazyLock::new(|| BodyKind::names().join(" | "));

/// Put `own` into `rows` just before the row of `path`.
fn splice_before(rows: &mut Vec<Field>, path: &str, own: impl Iterator<Item = Field>) {
    let at = rows.iter().position(|f| f.path == path);
    let at = at.unwrap_or_else(|| panic!("rows placed before {path}: no such row"));
    rows.splice(at..at, own);
}

/// The row of a field of `[body.contact_law]` (`contact::law`'s list):
/// absent unless given, its rules the law's own (`Rule::Words`), not an
/// FMU parameter.
fn law_row((path, unit, note): crate::contact::law_spec::LawRow) -> Field {
    Field {
        path,
        unit,
        default: Default::Absent,
        rule: Rule::Words,
        note,
        doc: "",
        access: Access::None,
    }
}

/// The row of a field of `[beam]` a structure kind owns: absent unless
/// given, read and written in the scene's beam.
fn kind_row(field: &crate::structure::KindField) -> Field {
    use crate::structure::KindRule;
    Field {
        path: field.path,
        unit: field.unit,
        default: Default::Absent,
        rule: match field.rule {
            KindRule::Positive => Rule::Positive,
            KindRule::NonNegative => Rule::NonNegative,
        },
        note: field.note,
        doc: field.doc,
        access: Access::Beam(field.value, field.set),
    }
}

/// The rows of the fields of a scene file that no preset or structure
/// kind owns.
const SCENE_ROWS: &[Field] = &[
    Field {
        path: "name",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        note: "letters, digits, - _ . ; the FMU's model name",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "description",
        unit: "",
        default: Default::Value("\"\""),
        rule: Rule::Words,
        note: "one line",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "gravity",
        unit: "m/s^2",
        default: Default::Value("9.81"),
        rule: Rule::NonNegative,
        note: "m/s^2, downward on every body; 0 in the paper's scenes",
        doc: "",
        access: Access::Scene(|s| Some(s.gravity), |s, x| s.gravity = x),
    },
    Field {
        path: "track.approach",
        unit: "m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "m, rigid ground before the beam (x < 0)",
        doc: "",
        access: Access::Scene(|s| Some(s.track.approach), |s, x| s.track.approach = x),
    },
    Field {
        path: "track.run_off",
        unit: "m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "m, rigid ground after the beam (x > L)",
        doc: "",
        access: Access::Scene(|s| Some(s.track.run_off), |s, x| s.track.run_off = x),
    },
    Field {
        path: "track.on_deck.preset",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "ballasted | slab: the layer's typical k and c per rail (docs/structures.md)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.stiffness",
        unit: "N/m2",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N/m², rail-to-deck layer per metre of rail, > 0 (else the preset's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.damping",
        unit: "N s/m2",
        default: Default::Absent,
        rule: Rule::NonNegative,
        note: "N s/m², rail-to-deck damping per metre, >= 0 (else the preset's, or 0)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.ground_stiffness",
        unit: "N/m2",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N/m², rail to ground on the approach and run-off, > 0 (else the layer's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.ground_damping",
        unit: "N s/m2",
        default: Default::Absent,
        rule: Rule::NonNegative,
        note: "N s/m², rail-to-ground damping per metre, >= 0 (else the layer's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.rail_bending_stiffness",
        unit: "N.m2",
        default: Default::Required,
        rule: Rule::Positive,
        note: "N m², the rail's EI (both rails for wheelsets), > 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.rail_mass_per_length",
        unit: "kg/m",
        default: Default::Required,
        rule: Rule::Positive,
        note: "kg/m, the rail's mass per metre (both rails for wheelsets), > 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.preset",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "ballasted: typical pad, sleeper and ballast per rail seat (docs/structures.md)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.spacing",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "m, between sleepers, > 0 (else the preset's); a whole number of the deck's \
               elements unless rail_elements_per_bay is given",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.rail_elements_per_bay",
        unit: "",
        default: Default::Absent,
        rule: Rule::Elements,
        note: "rail elements between two sleepers, the rail meshed at the sleepers and the deck \
               on its own mesh, >= 1 (absent: the rail's nodes are the deck's)",
        doc: "",
        access: Access::Scene(
            |s| {
                let sleepers = s.track.on_deck.as_ref()?.sleepers?;
                sleepers.rail_elements_per_bay.map(|n| n as f64)
            },
            |s, x| {
                let sleepers = s.track.on_deck.as_mut().and_then(|d| d.sleepers.as_mut());
                if let Some(sleepers) = sleepers {
                    sleepers.rail_elements_per_bay = Some(x as usize);
                }
            },
        ),
    },
    Field {
        path: "track.on_deck.sleepers.pad_stiffness",
        unit: "N/m",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N/m, rail pad (rail to sleeper) per support, > 0 (else the preset's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.pad_damping",
        unit: "N s/m",
        default: Default::Absent,
        rule: Rule::NonNegative,
        note: "N s/m, rail pad damping per support, >= 0 (else the preset's, or 0)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.sleeper_mass",
        unit: "kg",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "kg, the sleeper's mass under the line, > 0 (else the preset's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.ballast_stiffness",
        unit: "N/m",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N/m, ballast (sleeper to deck or ground) per support, > 0 (else the preset's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.on_deck.sleepers.ballast_damping",
        unit: "N s/m",
        default: Default::Absent,
        rule: Rule::NonNegative,
        note: "N s/m, ballast damping per support, >= 0 (else the preset's, or 0)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.type",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "step | ramp | cosine_dip | sine | table | random; only its fields",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.position",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, centre of a step or a cosine dip",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.height",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, rise of a step or a ramp",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.smoothing",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, > 0, rounding of a step or a ramp",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.start",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, where a ramp begins",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.length",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, > 0, length of a ramp",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.wavelength",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, > 0, of a cosine dip or a sine",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.depth",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, of a cosine dip",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.amplitude",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, of a sine",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.phase",
        unit: "rad",
        default: Default::Absent,
        rule: Rule::Words,
        note: "rad, of a sine",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.points",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "[[x, r], ...] in m, x increasing, 2 to 100 000",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.file",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "CSV of rows x, r (m), relative to the scene file",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.spectrum",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "iso8608 | fra | german_low | german_high",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.class",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "A ... H (iso8608), 1 ... 6 (fra)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.seed",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "0 to 4294967295",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.shortest_wavelength",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, > 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.longest_wavelength",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, > shortest_wavelength",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "track.irregularities.spacing",
        unit: "m",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m, <= shortest / 4; default shortest / 10",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.length",
        unit: "m",
        default: Default::Required,
        rule: Rule::Positive,
        note: "m, L",
        doc: "length of the beam",
        access: Access::Scene(|s| Some(s.beam.length), |s, x| s.beam.length = x),
    },
    Field {
        path: "beam.mass_per_length",
        unit: "kg/m",
        default: Default::Required,
        rule: Rule::Positive,
        note: "kg/m",
        doc: "mass per unit length",
        access: Access::Scene(
            |s| Some(s.beam.mass_per_length),
            |s, x| s.beam.mass_per_length = x,
        ),
    },
    Field {
        path: "beam.bending_stiffness",
        unit: "N.m2",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N m^2, EI > 0; this or frequency",
        doc: "bending stiffness EI",
        access: Access::Scene(
            |s| Some(s.beam.bending_stiffness),
            |s, x| s.beam.bending_stiffness = x,
        ),
    },
    Field {
        path: "beam.frequency",
        unit: "Hz",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "Hz, first natural frequency f1 > 0 instead of bending_stiffness: EI is set so the model's first mode has f1",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.surface_offset",
        unit: "m",
        default: Default::Required,
        rule: Rule::NonNegative,
        note: "m, h: neutral axis to top surface, >= 0",
        doc: "distance from the neutral axis to the top surface",
        access: Access::Scene(
            |s| Some(s.beam.surface_offset),
            |s, x| s.beam.surface_offset = x,
        ),
    },
    Field {
        path: "beam.elements",
        unit: "",
        default: Default::Required,
        rule: Rule::Elements,
        note: "Hermite cubic elements, >= 1",
        doc: "number of Hermite cubic beam elements",
        access: Access::Scene(
            |s| Some(s.beam.elements as f64),
            |s, x| s.beam.elements = x as usize,
        ),
    },
    Field {
        path: "beam.supports.left",
        unit: "",
        default: Default::Value("pinned"),
        rule: Rule::Words,
        note: "pinned | clamped | free",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.right",
        unit: "",
        default: Default::Value("pinned"),
        rule: Rule::Words,
        note: "pinned | clamped | free",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.intermediate",
        unit: "m",
        default: Default::Value("[]"),
        rule: Rule::Words,
        note: "m, pinned supports strictly inside, increasing",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.springs.at",
        unit: "m",
        default: Default::Required,
        rule: Rule::Words,
        note: "m, 0 <= at <= L: an elastic support",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.springs.vertical",
        unit: "N/m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "N/m, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.springs.rotational",
        unit: "N.m/rad",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "N m/rad, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.springs.vertical_damping",
        unit: "N.s/m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "N s/m, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.supports.springs.rotational_damping",
        unit: "N.m.s/rad",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "N m s/rad, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.joints.at",
        unit: "m",
        default: Default::Required,
        rule: Rule::Words,
        note: "m, 0 < at, at + gap < L, increasing",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.joints.kind",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        note: "continuous | hinge | separate",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.joints.gap",
        unit: "m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "m, rail gap >= 0, separate joints only",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.alpha",
        unit: "1/s",
        default: Default::Required,
        rule: Rule::NonNegative,
        note: "1/s, Rayleigh C = alpha M + beta K, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.beta",
        unit: "s",
        default: Default::Required,
        rule: Rule::NonNegative,
        note: "s, Rayleigh stiffness coefficient, >= 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.ratio",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "damping ratio at both `modes`, or alone in every mode (exact; the full mesh runs in all its modes, up to 600 DOFs), 0 <= ratio < 1",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.modes",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "two different bending modes, from 1",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.ratios",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "damping ratios at `frequencies`, [0, 1)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.damping.frequencies",
        unit: "Hz",
        default: Default::Absent,
        rule: Rule::Words,
        note: "Hz, two different, > 0",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.foundation.preset",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "ballasted | slab: typical k and c per rail (docs/structures.md)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.foundation.stiffness",
        unit: "N/m2",
        default: Default::Absent,
        rule: Rule::Positive,
        note: "N/m², Winkler modulus k per metre of beam, > 0 (else the preset's)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "beam.foundation.damping",
        unit: "N s/m2",
        default: Default::Absent,
        rule: Rule::NonNegative,
        note: "N s/m², foundation damping c per metre, >= 0 (else the preset's, or 0)",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "body.name",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        note: "identifier; outputs are <name>.x, ...",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "body.kind",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        // The presets' names, `KIND_NOTE`, put in by `FIELDS`.
        note: "",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "body.mass",
        unit: "kg",
        default: Default::Required,
        rule: Rule::Positive,
        note: "kg, > 0",
        doc: "mass of the body",
        access: Access::Vehicle(|b| Some(b.mass), |b, x| b.mass = x),
    },
    Field {
        path: "body.initial_position",
        unit: "m",
        default: Default::Value("0"),
        rule: Rule::OnTrack,
        note: "m, contact abscissa at t = 0, -approach <= x < L",
        doc: "abscissa of the contact point at t = 0",
        access: Access::Vehicle(|b| Some(b.initial_position), |b, x| b.initial_position = x),
    },
    Field {
        path: "body.initial_speed",
        unit: "m/s",
        default: Default::Required,
        rule: Rule::Finite,
        note: "m/s, positive to the right",
        doc: "initial travel speed, positive to the right (a constant prescribed_speed follows it)",
        access: Access::Vehicle(|b| Some(b.initial_speed), set_initial_speed),
    },
    Field {
        path: "body.prescribed_speed",
        unit: "m/s",
        default: Default::Absent,
        rule: Rule::Words,
        note: "m/s, or [[t, v], ...]: held by a tractive force",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "body.force_x",
        unit: "N",
        default: Default::Value("0"),
        rule: Rule::Finite,
        note: "N, constant force on the body's centre",
        // Read for the table's pass; no doc: an FMU input, not a parameter.
        doc: "",
        access: Access::Vehicle(|b| Some(b.force_x), |b, x| b.force_x = x),
    },
    Field {
        path: "body.force_y",
        unit: "N",
        default: Default::Value("0"),
        rule: Rule::Finite,
        note: "N, y up: the paper's load is -600 kN",
        // Read for the table's pass; no doc: an FMU input, not a parameter.
        doc: "",
        access: Access::Vehicle(|b| Some(b.force_y), |b, x| b.force_y = x),
    },
    Field {
        path: "body.restitution",
        unit: "",
        default: Default::Value("0"),
        rule: Rule::UnitInterval,
        note: "0 (plastic) to 1 (elastic), at a landing",
        doc: "coefficient of restitution at a landing",
        access: Access::Vehicle(|b| Some(b.restitution), |b, x| b.restitution = x),
    },
    Field {
        path: "body.initial_height",
        unit: "m",
        default: Default::Value("0"),
        rule: Rule::NonNegative,
        note: "m, >= 0, above its place on the track",
        doc: "height above its place on the track at t = 0",
        access: Access::Vehicle(|b| Some(b.initial_height), |b, x| b.initial_height = x),
    },
    Field {
        path: "error_estimate",
        unit: "",
        default: Default::Value("false"),
        rule: Rule::Words,
        note: "true: FMU outputs sensor.<name>.deflection_error, .acceleration_error",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "reactions",
        unit: "",
        default: Default::Value("false"),
        rule: Rule::Words,
        note: "true: support.<name>.reaction outputs",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "sensors.name",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        note: "identifier; output sensor.<name>.deflection",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "sensors.position",
        unit: "m",
        default: Default::Required,
        rule: Rule::NonNegative,
        note: "m, 0 <= x <= L",
        doc: "abscissa of the sensor along the beam",
        access: Access::Sensor(|e| Some(e.position), |e, x| e.position = x),
    },
    Field {
        path: "sections.name",
        unit: "",
        default: Default::Required,
        rule: Rule::Words,
        note: "identifier; outputs section.<name>.moment, .shear",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "sections.position",
        unit: "m",
        default: Default::Required,
        rule: Rule::NonNegative,
        note: "m, 0 <= x <= L",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "couplings",
        unit: "",
        default: Default::Value("[]"),
        rule: Rule::Words,
        note: "bodies that are the FMU's coupling points",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.step",
        unit: "s",
        default: Default::Value("2.5e-3"),
        rule: Rule::Positive,
        note: "s, fixed internal time step",
        doc: "fixed internal time step",
        access: Access::Scene(|s| Some(s.solver.step), |s, x| s.solver.step = x),
    },
    Field {
        path: "solver.velocity_tolerance",
        unit: "m/s",
        default: Default::Value("1e-7"),
        rule: Rule::Positive,
        note: "m/s, on the velocity error |e|",
        doc: "tolerance on the velocity error |e|",
        access: Access::Scene(
            |s| Some(s.solver.velocity_tolerance),
            |s, x| s.solver.velocity_tolerance = x,
        ),
    },
    Field {
        path: "solver.gap_tolerance",
        unit: "m",
        default: Default::Value("1e-5"),
        rule: Rule::Positive,
        note: "m, on the gap error |g|",
        doc: "tolerance on the gap error |g|",
        access: Access::Scene(
            |s| Some(s.solver.gap_tolerance),
            |s, x| s.solver.gap_tolerance = x,
        ),
    },
    Field {
        path: "solver.tolerance",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "relative error of the summary figures; chooses the step",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.max_iterations",
        unit: "",
        default: Default::Value("50"),
        rule: Rule::Words,
        note: "per stage and step",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.integrator",
        unit: "",
        default: Default::Value("rk4"),
        rule: Rule::Words,
        note: "rk4 (the paper's, explicit) | hht (implicit) | auto",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.numerical_damping",
        unit: "",
        default: Default::Value("0"),
        rule: Rule::Words,
        note: "HHT's -alpha in [0, 1/3]; 0 conserves energy",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.force_profile",
        unit: "",
        default: Default::Value("held"),
        rule: Rule::Words,
        note: "held (the paper's) | linear | quadratic: RK4's force in the step",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.end_time",
        unit: "s",
        default: Default::Absent,
        rule: Rule::Words,
        note: "s, run to here, past the exit, unless a contact leaves the track",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.start",
        unit: "",
        default: Default::Value("rest"),
        rule: Rule::Words,
        note: "rest | static: deflected under the vehicles' weight",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.structure",
        unit: "",
        default: Default::Value("full"),
        rule: Rule::Words,
        note: "full | modal: the beam's lowest modes",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.modes",
        unit: "",
        default: Default::Absent,
        rule: Rule::Words,
        note: "modal: how many of the lowest modes",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "solver.max_frequency",
        unit: "Hz",
        default: Default::Absent,
        rule: Rule::Words,
        note: "Hz, modal: every mode up to this",
        doc: "",
        access: Access::None,
    },
];

/// The reference page of every field, `docs/scene-fields.md` (the docs test
/// checks that the committed page is this).
pub fn field_notes_markdown() -> String {
    let mut page = String::from(
        "# Scene fields\n\n\
         Generated from the scene's field table (`src/scene/fields.rs`), which \
         also gives the notes `guideway scenes --show` writes beside each field, \
         the rules of plain numbers and the FMU's parameters; do not edit by hand: \
         `GUIDEWAY_UPDATE_DOCS=1 cargo test --release --test guards docs::` rewrites it. \
         The rules in full are in [Scenes, every field](scenes.md#every-field). \
         A train's `[[vehicles]]` take the fields of `[body]`; the FMU \
         parameter column names the parameter an FMU exports for the field \
         (for every vehicle and every sensor that has it; \
         [The FMU](fmu-reference.md)).\n\n\
         | table | what it holds |\n|---|---|\n",
    );
    for (path, note) in super::annotate::table_notes() {
        page += &format!("| `[{path}]` | {note} |\n");
    }
    page += "\n| field | unit | default | FMU parameter | unit, meaning, rule |\n\
             |---|---|---|---|---|\n";
    for f in FIELDS.iter() {
        let default = match f.default {
            Default::Required => "required".to_string(),
            Default::Absent => "absent".to_string(),
            Default::Value(v) => format!("`{v}`"),
        };
        page += &format!(
            "| `{}` | {} | {default} | {} | {} |\n",
            f.path,
            f.unit,
            fmu_name_pattern(f),
            f.note.replace('|', "\\|")
        );
    }
    page
}

/// How the FMU names the parameter of `f`, with `<vehicle>` and `<sensor>`
/// for the names the scene gives; empty for no parameter.
fn fmu_name_pattern(f: &Field) -> String {
    let rest = |prefix: &str| f.path.strip_prefix(prefix).unwrap_or(f.path);
    match f.access {
        _ if f.doc.is_empty() && !matches!(f.access, Access::Vehicle(..)) => String::new(),
        Access::None => String::new(),
        Access::Scene(..) | Access::Beam(..) => format!("`{}`", f.path),
        // every vehicle's, where it has the field (src/model/variables.rs)
        Access::Vehicle(..) if !f.doc.is_empty() => format!("`<vehicle>.{}`", rest("body.")),
        Access::Vehicle(..) => String::new(),
        Access::Sensor(..) => format!("`sensor.<sensor>.{}`", rest("sensors.")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene with every table present and every optional field left out.
    const MINIMAL: &str = r#"
        name = "m"
        [beam]
        length = 20.0
        mass_per_length = 1000.0
        bending_stiffness = 1e9
        surface_offset = 0.0
        elements = 4
        [body]
        name = "car"
        kind = "sprung_mass"
        mass = 1000.0
        initial_speed = 10.0
        [body.suspension]
        stiffness = 1e5
        unsprung_mass = 100.0
    "#;

    #[test]
    fn paths_are_unique() {
        for (i, f) in FIELDS.iter().enumerate() {
            assert!(FIELDS[..i].iter().all(|g| g.path != f.path), "{}", f.path);
        }
    }

    /// The table's numeric defaults are serde's (the independent source:
    /// the parser fills a field a scene leaves out).
    #[test]
    fn numeric_defaults_are_what_the_parser_fills_in() {
        let scene: Scene = toml::from_str(MINIMAL).unwrap();
        let mut checked = 0;
        for f in FIELDS.iter() {
            let Default::Value(text) = f.default else {
                continue;
            };
            let Ok(expected) = text.parse::<f64>() else {
                continue;
            };
            let got = match f.access {
                Access::Scene(get, _) => get(&scene),
                Access::Beam(get, _) => get(&scene.beam),
                Access::Vehicle(get, _) => get(&scene.vehicles[0]),
                _ => continue,
            };
            // None: the field's table (bogie, maglev) is not in MINIMAL.
            let Some(got) = got else { continue };
            assert_eq!(got, expected, "{}", f.path);
            checked += 1;
        }
        assert!(checked >= 6, "only {checked} defaults checked");
    }

    /// A setter writes what its getter reads, and only there.
    #[test]
    fn setters_and_getters_agree() {
        let scene: Scene = toml::from_str(MINIMAL).unwrap();
        for f in FIELDS.iter() {
            let mut changed = scene.clone();
            let (before, after) = match f.access {
                Access::Scene(get, set) => {
                    set(&mut changed, 7.0);
                    (get(&scene), get(&changed))
                }
                Access::Beam(get, set) => {
                    set(&mut changed.beam, 7.0);
                    (get(&scene.beam), get(&changed.beam))
                }
                Access::Vehicle(get, set) => {
                    set(&mut changed.vehicles[0], 7.0);
                    (get(&scene.vehicles[0]), get(&changed.vehicles[0]))
                }
                _ => continue,
            };
            if before.is_some() {
                assert_eq!(after, Some(7.0), "{}", f.path);
                assert_ne!(changed, scene, "{}", f.path);
            }
        }
    }

    #[test]
    fn every_field_is_on_the_reference_page() {
        let page = field_notes_markdown();
        for f in FIELDS.iter() {
            assert!(page.contains(&format!("| `{}` |", f.path)), "{}", f.path);
        }
    }

    /// Each rule's declared bounds are accepted, the next value beyond
    /// refused, with the rule in words.
    #[test]
    fn bounds_are_the_rule() {
        for rule in [
            Rule::Positive,
            Rule::NonNegative,
            Rule::UnitInterval,
            Rule::Elements,
            Rule::OnTrack,
            Rule::Finite,
        ] {
            let (lo, hi) = rule.bounds(5.0);
            assert_eq!(rule.problem(lo, 5.0), None, "{rule:?}");
            assert_eq!(rule.problem(hi, 5.0), None, "{rule:?}");
            assert!(rule.problem(lo.next_down(), 5.0).is_some(), "{rule:?}");
            assert!(rule.problem(hi.next_up(), 5.0).is_some(), "{rule:?}");
        }
        assert_eq!(
            Rule::Positive.problem(-1.0, 0.0).as_deref(),
            Some("must be > 0")
        );
    }
}
