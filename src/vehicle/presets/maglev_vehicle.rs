//! The maglev-vehicle preset: a car body (bounce, pitch) over N magnets
//! (gliders, or massless followers when `magnet_mass = 0`) evenly spaced
//! along it, each on a vertical spring–damper preloaded with its share of
//! the car body's weight.

use serde::{Deserialize, Serialize};

use super::{parts, refuse_unless, Preset, Reach, Vehicle};
use crate::beam::Beam;
use crate::body::RigidBody;
use crate::contact::Contact;
use crate::scene::fields::{block_field, Access, Default as FieldDefault, Field, Rule};
use crate::scene::{BodySpec, Checks};

/// The magnets and suspensions of a `maglev_vehicle` (whose `mass` is the
/// car body's).
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

/// Most magnets on one maglev vehicle.
pub const MAX_MAGNETS: usize = 1000;

/// Height of a maglev car body's centre above its magnets at rest (m).
pub const MAGLEV_HEIGHT: f64 = 1.0;

pub struct MaglevVehicle;

impl Preset for MaglevVehicle {
    const DESCRIPTION: &'static str = "car body over magnets on spring-dampers";
    const ROWS: &'static [Field] = MAGLEV_ROWS;
    const BLOCK_NOTE: &'static str = "maglev_vehicle: car body over N magnets on spring-dampers";
    const NAMES_ITS_CONTACTS: bool = true;

    fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        if body.maglev.is_some() {
            refuse_unless(checks, prefix, "maglev", "present", "maglev_vehicle");
        }
    }

    /// A maglev vehicle needs its magnets.
    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        let path = |field: &str| format!("{prefix}.maglev.{field}");
        let Some(m) = &body.maglev else {
            return checks.fail(
                format!("{prefix}.maglev"),
                "missing",
                format!(
                    "a maglev_vehicle needs [{prefix}.maglev] with car_inertia, magnets, \
                     magnet_spacing, magnet_mass and stiffness"
                ),
            );
        };
        // The numbers' own rules are the field table's rows; a magnet
        // mass is 0 (massless followers at the magnets' stations) or
        // positive, which the row's >= 0 leaves to here.
        if m.magnet_mass > 0.0 && m.magnet_mass.is_finite() {
            checks.positive(&path("magnet_mass"), m.magnet_mass);
        }
        if !(1..=MAX_MAGNETS).contains(&m.magnets) {
            checks.fail(
                path("magnets"),
                m.magnets.to_string(),
                format!("must be 1 to {MAX_MAGNETS}"),
            );
        }
    }

    /// Body 0 the car body (M, J), bodies 1..=N the magnets (front to
    /// rear), each on a vertical spring–damper with a longitudinal guide,
    /// preloaded with M g / N.
    fn build(spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String> {
        let m: MaglevSpec = spec
            .maglev
            .expect("a validated maglev_vehicle has its magnets");
        let (_, _, mut car_state) = parts::glider_at(spec, beam, 0.0);
        car_state.position.y += MAGLEV_HEIGHT;
        let mut bodies = vec![RigidBody {
            name: spec.name.clone(),
            mass: spec.mass,
            inertia: m.car_inertia,
            drive: None,
        }];
        let mut states = vec![car_state];
        let mut contacts = Vec::with_capacity(m.magnets);
        for i in 0..m.magnets {
            let (_, contact, state) = parts::glider_at(spec, beam, m.offset(i));
            let name = format!("{}_magnet{}", spec.name, i + 1);
            bodies.push(RigidBody {
                name: name.clone(),
                mass: m.magnet_mass,
                inertia: 0.0,
                drive: None,
            });
            states.push(state);
            contacts.push(Contact {
                name,
                body: 1 + i,
                ..contact
            });
        }
        let load = spec.mass * gravity / m.magnets as f64;
        let mut force_elements = Vec::with_capacity(2 * m.magnets);
        for i in 0..m.magnets {
            let name = format!("{}.magnet{}", spec.name, i + 1);
            let (k, c) = (m.stiffness, m.damping);
            let at = (0, m.offset(i));
            parts::suspension(&name, at, 1 + i, k, c, load, &states, &mut force_elements);
        }
        Ok(Vehicle {
            bodies,
            contacts,
            force_elements,
            states,
        })
    }

    /// The magnets lie ± (magnets − 1) magnet_spacing / 2 about the car
    /// body's centre (none counted beyond `MAX_MAGNETS`, which validation
    /// refuses).
    fn reach(spec: &BodySpec) -> Option<Reach> {
        let m = spec.maglev.filter(|m| m.magnets <= MAX_MAGNETS)?;
        Some(Reach::symmetric(m.offset(0)))
    }
    const STARTS_ON_TRACK: bool = true;

    fn body_names(spec: &BodySpec) -> Vec<String> {
        let n = &spec.name;
        let mut names = vec![n.clone()];
        // Massless followers are contacts, not bodies.
        if !Self::massless_contacts(spec) {
            let magnets = spec.maglev.map_or(0, |m| m.magnets);
            names.extend((1..=magnets).map(|i| format!("{n}_magnet{i}")));
        }
        names
    }

    fn massless_contacts(spec: &BodySpec) -> bool {
        spec.maglev.is_some_and(|m| m.magnet_mass == 0.0)
    }

    fn contact_rows(spec: &BodySpec) -> usize {
        spec.maglev.map_or(0, |m| m.magnets)
    }
}

/// The field table's rows of the fields this preset owns.
const MAGLEV_ROWS: &[Field] = &[
    Field {
        path: "body.maglev.car_inertia",
        unit: "kg.m2",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "kg m^2, > 0, car body pitch inertia",
        doc: "car body pitch inertia",
        access: block_field!(maglev.car_inertia),
    },
    Field {
        path: "body.maglev.magnets",
        unit: "",
        default: FieldDefault::Required,
        rule: Rule::Words,
        note: "1 to 1000, centred on the car body",
        doc: "",
        access: Access::None,
    },
    Field {
        path: "body.maglev.magnet_spacing",
        unit: "m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "m, > 0",
        doc: "distance between neighbouring magnets",
        access: block_field!(maglev.magnet_spacing),
    },
    Field {
        path: "body.maglev.magnet_mass",
        unit: "kg",
        default: FieldDefault::Required,
        rule: Rule::NonNegative,
        note: "kg, > 0, or 0: massless followers under the magnets' stations",
        doc: "mass of one magnet (0: massless followers)",
        access: block_field!(maglev.magnet_mass),
    },
    Field {
        path: "body.maglev.stiffness",
        unit: "N/m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "N/m, k > 0, one magnet's suspension",
        doc: "stiffness of one magnet's suspension",
        access: block_field!(maglev.stiffness),
    },
    Field {
        path: "body.maglev.damping",
        unit: "N.s/m",
        default: FieldDefault::Value("0"),
        rule: Rule::NonNegative,
        note: "N s/m, c >= 0, one magnet's suspension",
        doc: "damping of one magnet's suspension",
        access: block_field!(maglev.damping),
    },
];
