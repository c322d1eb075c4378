//! The vehicle presets, one file per kind: each owns its spec, its rules,
//! its build into bodies, force elements and contacts, its reach and its
//! FMU description. `BodyKind` names them; the `presets!` list below is
//! the one place that maps a kind to its file (static dispatch, one match
//! per question, all generated from that list).

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
use crate::scene::{fmt_f64, quoted, BodySpec, Checks};
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
    /// The optional block of `[body]` the preset owns (other kinds must
    /// leave it out), if any.
    const BLOCK: Option<Block> = None;
    /// Its own rules on `body` (fields named under `prefix`), checked where
    /// its block's rules stand.
    fn check(_checks: &mut Checks, _prefix: &str, _body: &BodySpec) {}
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

/// The optional blocks of `[body]` that belong to one kind, in the order
/// their rules are checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    /// `inertia` and `radius`.
    InertiaRadius,
    Suspension,
    Train,
    Bogie,
    Maglev,
}

macro_rules! presets {
    ($($(#[$attr:meta])* $kind:ident => $preset:ty;)*) => {
        /// The kind of a vehicle: which preset builds it.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(rename_all = "lowercase")]
        pub enum BodyKind {
            $($(#[$attr])* $kind,)*
        }

        impl BodyKind {
            /// See `Preset::DESCRIPTION`.
            pub fn description(self) -> &'static str {
                match self { $(BodyKind::$kind => <$preset>::DESCRIPTION,)* }
            }
            fn block(self) -> Option<Block> {
                match self { $(BodyKind::$kind => <$preset>::BLOCK,)* }
            }
            fn check_own(self, checks: &mut Checks, prefix: &str, body: &BodySpec) {
                match self { $(BodyKind::$kind => <$preset>::check(checks, prefix, body),)* }
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
    Wheel => wheel::Wheel;
    /// Point body gliding at the surface (r = 0, J = 0): the maglev model.
    Glider => glider::Glider;
    /// Moving oscillator: the body (J = 0) on a vertical spring–damper over
    /// an unsprung glider (`suspension`).
    #[serde(rename = "sprung_mass")]
    SprungMass => sprung_mass::SprungMass;
    /// Car body over two bogies over four wheelsets (`bogie`); the body's
    /// `initial_position` is the car body's centre.
    #[serde(rename = "bogie_vehicle")]
    BogieVehicle => bogie_vehicle::BogieVehicle;
    /// Car body over N magnets (gliders) on spring–dampers along its
    /// length (`maglev`); `initial_position` is the car body's centre.
    #[serde(rename = "maglev_vehicle")]
    MaglevVehicle => maglev_vehicle::MaglevVehicle;
    /// A point force at constant speed with no body (no inertia, no
    /// contact): its weight `mass` × `gravity` plus `force_y`, or each axle
    /// of its `train`. Run by `guideway sweep`, not `guideway run`.
    #[serde(rename = "moving_force")]
    MovingForce => moving_force::MovingForce;
}

/// Every rule on the preset blocks of `body`: each block in its order,
/// checked by the preset that owns it when `body` is of that kind, else
/// refused when present.
pub(crate) fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
    let blocks = [
        Block::InertiaRadius,
        Block::Suspension,
        Block::Train,
        Block::Bogie,
        Block::Maglev,
    ];
    for block in blocks {
        if body.kind.block() == Some(block) {
            body.kind.check_own(checks, prefix, body);
        } else {
            refuse_stray(checks, prefix, body, block);
        }
    }
}

/// A block present on a vehicle of another kind than its owner's.
fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec, block: Block) {
    let path = |field: &str| format!("{prefix}.{field}");
    let unless = |kind: &str| format!("must be left out unless {prefix}.kind = \"{kind}\"");
    match block {
        Block::InertiaRadius => {
            for (path, value) in [
                (path("inertia"), body.inertia),
                (path("radius"), body.radius),
            ] {
                if let Some(v) = value {
                    checks.fail(
                        path,
                        fmt_f64(v),
                        "must be left out for a glider or a sprung mass (J = 0, r = 0)",
                    );
                }
            }
        }
        Block::Suspension if body.suspension.is_some() => {
            checks.fail(path("suspension"), "present", unless("sprung_mass"))
        }
        Block::Train => {
            if let Some(name) = &body.train {
                checks.fail(path("train"), quoted(name), unless("moving_force"));
            }
        }
        Block::Bogie if body.bogie.is_some() => {
            checks.fail(path("bogie"), "present", unless("bogie_vehicle"))
        }
        Block::Maglev if body.maglev.is_some() => {
            checks.fail(path("maglev"), "present", unless("maglev_vehicle"))
        }
        Block::Suspension | Block::Bogie | Block::Maglev => {}
    }
}
