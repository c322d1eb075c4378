//! The vehicle presets, one file per kind: each owns its spec, its fields
//! of `[body]` (their rows of the field table, their rules, their refusal
//! on another kind), its build into bodies, force elements and contacts,
//! its reach and its FMU description. `BodyKind` names them; the
//! `presets!` list below is the one place that maps a kind to its file and
//! its fields (static dispatch, one match per question, `BodySpec` and the
//! checks, all generated from that list).

#[macro_use]
mod body_spec;
mod bogie_vehicle;
mod glider;
mod maglev_vehicle;
mod moving_force;
mod parts;
mod sprung_mass;
mod wheel;

pub use bogie_vehicle::{BogieSpec, BOGIE_HEIGHTS};
pub use maglev_vehicle::{MaglevSpec, MAGLEV_HEIGHT, MAX_MAGNETS};
pub use moving_force::{is_moving_force_scene, MOVING_FORCE_REFUSAL};
pub use parts::{Vehicle, GUIDE_STIFFNESS_RATIO};
pub use sprung_mass::{SuspensionSpec, SPRUNG_HEIGHT};

use crate::beam::Beam;
use crate::scene::fields::Field;
use crate::scene::Checks;
use crate::scene::ContactLawSpec;
use crate::vehicle::speed::SpeedSpec;
use serde::{Deserialize, Serialize};

/// How far a vehicle's contacts lie ahead of and behind its
/// `initial_position` (m, both ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reach {
    pub ahead: f64,
    pub behind: f64,
}

impl Reach {
    /// Contacts spread evenly ± `half` about the position.
    pub fn symmetric(half: f64) -> Reach {
        Reach {
            ahead: half,
            behind: half,
        }
    }
}

/// What one preset knows of itself; `BodyKind` delegates each question to
/// the preset of its kind.
pub(crate) trait Preset {
    /// The body's kind in words, for the FMU's documentation.
    const DESCRIPTION: &'static str;
    /// The field table's rows of the fields of `[body]` the preset owns
    /// (its block, declared in its line of `presets!`), and the row of the
    /// scene's own table they stand before (`scene::fields::FIELDS`).
    const ROWS: &'static [Field] = &[];
    const ROWS_BEFORE: &'static str = TABLE_BLOCKS_BEFORE;
    /// The comment above its block's table (`[body.<block>]`, and each
    /// `[vehicles.<block>]`) in an annotated scene and in the docs' list
    /// of tables; empty for a block that is not a table (a train's name).
    const BLOCK_NOTE: &'static str = "";
    /// Its own rules on `body` (fields named under `prefix`), checked in
    /// the list's order among the other presets' refusals of their blocks.
    fn check(_checks: &mut Checks, _prefix: &str, _body: &BodySpec) {}
    /// Its block present on a vehicle of another kind: refused.
    fn refuse_stray(_checks: &mut Checks, _prefix: &str, _body: &BodySpec) {}
    /// Its bodies, contacts and force elements, where they start.
    fn build(spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String>;
    /// How far its contacts lie about `initial_position`; None where its
    /// spec lacks what places them (which validation refuses).
    fn reach(_spec: &BodySpec) -> Option<Reach> {
        Some(Reach::default())
    }
    /// Whether its contacts spread about `initial_position` and must all
    /// start on the track (a train's axles may start off it: they enter).
    const STARTS_ON_TRACK: bool = false;
    /// The names of its bodies, as the assembled system names them.
    fn body_names(spec: &BodySpec) -> Vec<String> {
        vec![spec.name.clone()]
    }
    /// Whether it runs on massless followers in place of contact bodies
    /// that its build makes (folded by `build::followers`).
    fn massless_contacts(_spec: &BodySpec) -> bool {
        false
    }
    /// Whether its contacts are massless followers whatever their law.
    fn on_followers(spec: &BodySpec) -> bool {
        Self::massless_contacts(spec)
    }
    /// Rows of the contact iteration it brings: an upper bound from its
    /// spec alone, saturating.
    fn contact_rows(spec: &BodySpec) -> usize;
    /// Whether its build names its contacts (else a vehicle after the
    /// first names them `<name>_contact`).
    const NAMES_ITS_CONTACTS: bool = false;
}

/// Where a preset's table block (`[body.<block>]`) stands in the field
/// table: after the track's rows, before the contact law's.
pub const TABLE_BLOCKS_BEFORE: &str = "body.contact_law.law";

/// The list of presets, each line a kind, its preset and the fields of
/// `[body]` it owns: `fields { .. }` flat after `mass` (the wheel's),
/// `block { .. }` after `force_y` (a table such as `[body.suspension]`, or
/// a train's name). From it come `BodyKind`, `BodySpec` (`body_spec!`),
/// one match per question, the checks, the field table's rows and the
/// notes of the blocks (`block_notes`).
macro_rules! presets {
    ($(
        $(#[$attr:meta])* $kind:ident => $preset:ty
        $(, fields { $($(#[$hattr:meta])* $hfield:ident: $hty:ty),* $(,)? })?
        $(, block { $(#[$tattr:meta])* $tfield:ident: $tty:ty $(,)? })?
    ;)*) => {
        /// The kind of a vehicle: which preset builds it.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(rename_all = "lowercase")]
        pub enum BodyKind {
            $($(#[$attr])* $kind,)*
        }

        body_spec! {
            head { $($($($(#[$hattr])* $hfield: $hty,)*)?)* }
            tail { $($($(#[$tattr])* $tfield: $tty,)?)* }
        }

        /// Every rule of the presets on `body`, preset by preset in the
        /// list's order: its own preset's rules, the others' refusals of
        /// their blocks.
        pub(crate) fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
            $(if body.kind == BodyKind::$kind {
                <$preset>::check(checks, prefix, body);
            } else {
                <$preset>::refuse_stray(checks, prefix, body);
            })*
        }

        /// Each preset's block (`[body.<block>]`) that is a table, with its
        /// note (`Preset::BLOCK_NOTE`), in the list's order.
        pub fn block_notes() -> Vec<(&'static str, &'static str)> {
            let notes = [$($((stringify!($tfield), <$preset>::BLOCK_NOTE),)?)*];
            notes.into_iter().filter(|(_, note)| !note.is_empty()).collect()
        }

        /// Each preset's rows of the field table with the row they stand
        /// before, in the list's order.
        pub fn rows() -> [(&'static str, &'static [Field]); [$(stringify!($kind)),*].len()] {
            [$((<$preset>::ROWS_BEFORE, <$preset>::ROWS)),*]
        }

        impl BodyKind {
            /// Every kind, in the list's order.
            pub const ALL: [BodyKind; [$(stringify!($kind)),*].len()] = [$(BodyKind::$kind),*];

            /// See `Preset::DESCRIPTION`.
            pub fn description(self) -> &'static str {
                match self { $(BodyKind::$kind => <$preset>::DESCRIPTION,)* }
            }
            /// See `Preset::build`.
            pub fn build(self, spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String> {
                match self { $(BodyKind::$kind => <$preset>::build(spec, beam, gravity),)* }
            }
            /// See `Preset::reach`.
            pub fn reach(self, spec: &BodySpec) -> Option<Reach> {
                match self { $(BodyKind::$kind => <$preset>::reach(spec),)* }
            }
            /// See `Preset::STARTS_ON_TRACK`.
            pub fn starts_on_track(self) -> bool {
                match self { $(BodyKind::$kind => <$preset>::STARTS_ON_TRACK,)* }
            }
            /// See `Preset::body_names`.
            pub fn body_names(self, spec: &BodySpec) -> Vec<String> {
                match self { $(BodyKind::$kind => <$preset>::body_names(spec),)* }
            }
            /// See `Preset::massless_contacts`.
            pub fn massless_contacts(self, spec: &BodySpec) -> bool {
                match self { $(BodyKind::$kind => <$preset>::massless_contacts(spec),)* }
            }
            /// See `Preset::on_followers`.
            pub fn on_followers(self, spec: &BodySpec) -> bool {
                match self { $(BodyKind::$kind => <$preset>::on_followers(spec),)* }
            }
            /// See `Preset::contact_rows`.
            pub fn contact_rows(self, spec: &BodySpec) -> usize {
                match self { $(BodyKind::$kind => <$preset>::contact_rows(spec),)* }
            }
            /// See `Preset::NAMES_ITS_CONTACTS`.
            pub fn names_its_contacts(self) -> bool {
                match self { $(BodyKind::$kind => <$preset>::NAMES_ITS_CONTACTS,)* }
            }
        }
    };
}

presets! {
    /// Rigid disc rolling without slip (mass, inertia, radius).
    Wheel => wheel::Wheel, fields {
        /// Centroidal moment of inertia J (kg m^2); wheels only.
        inertia: f64,
        /// Radius r (m); wheels only.
        radius: f64,
    };
    /// Point body gliding at the surface (r = 0, J = 0): the maglev model.
    Glider => glider::Glider;
    /// Moving oscillator: the body (J = 0) on a vertical spring–damper over
    /// an unsprung glider (`suspension`).
    #[serde(rename = "sprung_mass")]
    SprungMass => sprung_mass::SprungMass, block {
        /// The suspension of a `sprung_mass`; left out for other kinds.
        suspension: SuspensionSpec
    };
    /// Car body over two bogies over four wheelsets (`bogie`); the body's
    /// `initial_position` is the car body's centre.
    #[serde(rename = "bogie_vehicle")]
    BogieVehicle => bogie_vehicle::BogieVehicle, block {
        /// The bogies, wheelsets and suspensions of a `bogie_vehicle` (whose
        /// `mass` is the car body's); left out for other kinds.
        bogie: BogieSpec
    };
    /// Car body over N magnets (gliders) on spring–dampers along its
    /// length (`maglev`); `initial_position` is the car body's centre.
    #[serde(rename = "maglev_vehicle")]
    MaglevVehicle => maglev_vehicle::MaglevVehicle, block {
        /// The magnets and suspensions of a `maglev_vehicle` (whose `mass`
        /// is the car body's); left out for other kinds.
        maglev: MaglevSpec
    };
    /// A point force at constant speed with no body (no inertia, no
    /// contact): its weight `mass` × `gravity` plus `force_y`, or each axle
    /// of its `train`. Run by `guideway sweep`, not `guideway run`.
    #[serde(rename = "moving_force")]
    MovingForce => moving_force::MovingForce, block {
        /// A `moving_force` that stands for a whole standard train
        /// (`HSLM-A1` … `HSLM-A10`): its first axle at `initial_position`,
        /// the others behind.
        train: String
    };
}

/// A preset's block `prefix.field` (shown as `shown`) on a vehicle that is
/// not its `owner` kind: refused.
pub(crate) fn refuse_unless(
    checks: &mut Checks,
    prefix: &str,
    field: &str,
    shown: impl Into<String>,
    owner: &str,
) {
    checks.fail(
        format!("{prefix}.{field}"),
        shown,
        format!("must be left out unless {prefix}.kind = \"{owner}\""),
    );
}

impl BodyKind {
    /// Every kind's name in a scene file (`kind = ".."`), in the list's order.
    pub fn names() -> Vec<String> {
        let name = |kind: BodyKind| match serde_json::to_value(kind) {
            Ok(serde_json::Value::String(name)) => name,
            other => unreachable!("a kind serialises to its name, not {other:?}"),
        };
        BodyKind::ALL.into_iter().map(name).collect()
    }
}
