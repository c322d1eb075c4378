//! The sprung-mass preset (the moving oscillator): a body (J = 0) on a
//! vertical spring–damper over an unsprung glider, or over a massless
//! follower when `unsprung_mass = 0`.

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use super::{parts, refuse_unless, Preset, Vehicle, GUIDE_STIFFNESS_RATIO};
use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactKind, Follower};
use crate::force_element::{Direction, ForceElement};
use crate::scene::fields::{block_field, Default as FieldDefault, Field, Rule};
use crate::scene::{BodySpec, Checks};

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

/// Height of a sprung mass's centre above its unsprung mass at rest (m):
/// only differences of heights enter the model.
pub const SPRUNG_HEIGHT: f64 = 1.0;

pub struct SprungMass;

impl Preset for SprungMass {
    const DESCRIPTION: &'static str = "sprung mass on a spring-damper over a glider";
    const ROWS: &'static [Field] = SUSPENSION_ROWS;
    const BLOCK_NOTE: &'static str = "sprung_mass: vertical spring-damper over an unsprung glider";

    fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        if body.suspension.is_some() {
            refuse_unless(checks, prefix, "suspension", "present", "sprung_mass");
        }
    }

    /// A sprung mass needs its suspension.
    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        let path = |field: &str| format!("{prefix}.{field}");
        match &body.suspension {
            // Its numbers' own rules are the field table's rows.
            Some(_) => {}
            None => checks.fail(
                path("suspension"),
                "missing",
                format!(
                    "a sprung_mass needs [{prefix}.suspension] with stiffness and unsprung_mass"
                ),
            ),
        }
    }

    /// Body 0 the sprung mass (J = 0), body 1 the unsprung glider, a
    /// vertical spring–damper preloaded with the sprung weight and a stiff
    /// longitudinal guide between them.
    fn build(spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String> {
        let suspension = spec.suspension.unwrap_or(SuspensionSpec {
            stiffness: 0.0,
            damping: 0.0,
            unsprung_mass: 0.0,
        });
        if suspension.unsprung_mass == 0.0 {
            return Ok(on_follower(spec, &suspension, beam, gravity));
        }
        let (unsprung, mut contact, contact_state) =
            parts::contact_body(spec, beam, 0.0, ContactKind::Glider);
        let unsprung = RigidBody {
            name: format!("{}_unsprung", spec.name),
            mass: suspension.unsprung_mass,
            ..unsprung
        };
        contact.body = 1;
        let sprung_state = BodyState {
            position: contact_state.position + Vector2::new(0.0, SPRUNG_HEIGHT),
            ..contact_state
        };
        Ok(Vehicle {
            bodies: vec![sprung_body(spec), unsprung],
            contacts: vec![contact],
            force_elements: elements(spec, &suspension, gravity),
            states: vec![sprung_state, contact_state],
        })
    }

    fn body_names(spec: &BodySpec) -> Vec<String> {
        let mut names = vec![spec.name.clone()];
        // A massless follower (unsprung_mass = 0) is a contact, not a body.
        if !Self::on_followers(spec) {
            names.push(format!("{}_unsprung", spec.name));
        }
        names
    }

    fn on_followers(spec: &BodySpec) -> bool {
        spec.suspension.is_some_and(|s| s.unsprung_mass == 0.0)
    }

    fn contact_rows(_spec: &BodySpec) -> usize {
        1
    }
}

/// The suspension and the guide between the sprung mass (0) and the
/// unsprung glider (1).
fn elements(spec: &BodySpec, suspension: &SuspensionSpec, gravity: f64) -> Vec<ForceElement> {
    let element = |name: &str, direction, stiffness, damping, preload, rest| ForceElement {
        name: format!("{}.{name}", spec.name),
        body_a: 0,
        point_a: Vector2::zeros(),
        body_b: 1,
        point_b: Vector2::zeros(),
        direction,
        stiffness,
        damping,
        preload,
        rest,
    };
    vec![
        element(
            "suspension",
            Direction::Vertical,
            suspension.stiffness,
            suspension.damping,
            spec.mass * gravity,
            SPRUNG_HEIGHT,
        ),
        element(
            "guide",
            Direction::Longitudinal,
            GUIDE_STIFFNESS_RATIO * suspension.stiffness,
            0.0,
            0.0,
            0.0,
        ),
    ]
}

/// The sprung mass of a `sprung_mass` vehicle: bounce only (no pitch).
fn sprung_body(spec: &BodySpec) -> RigidBody {
    RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia: 0.0,
        drive: None,
    }
}

/// The moving oscillator over a massless follower (`unsprung_mass = 0`):
/// one body, the sprung mass, whose contact is the follower at
/// `SPRUNG_HEIGHT` below it; the suspension is the follower's force law.
fn on_follower(spec: &BodySpec, suspension: &SuspensionSpec, beam: &Beam, gravity: f64) -> Vehicle {
    let (_, contact, contact_state) = parts::contact_body(spec, beam, 0.0, ContactKind::Glider);
    let contact = Contact {
        follower: Some(Follower {
            stiffness: suspension.stiffness,
            damping: suspension.damping,
            preload: spec.mass * gravity,
            rest: SPRUNG_HEIGHT,
            attachment: Vector2::zeros(),
            kind: Default::default(),
        }),
        ..contact
    };
    Vehicle {
        bodies: vec![sprung_body(spec)],
        contacts: vec![contact],
        force_elements: Vec::new(),
        states: vec![BodyState {
            position: contact_state.position + Vector2::new(0.0, SPRUNG_HEIGHT),
            ..contact_state
        }],
    }
}

/// The field table's rows of the fields this preset owns.
const SUSPENSION_ROWS: &[Field] = &[
    Field {
        path: "body.suspension.stiffness",
        unit: "N/m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "N/m, vertical spring, > 0",
        doc: "vertical spring of the suspension",
        access: block_field!(suspension.stiffness),
    },
    Field {
        path: "body.suspension.damping",
        unit: "N.s/m",
        default: FieldDefault::Value("0"),
        rule: Rule::NonNegative,
        note: "N s/m, vertical damper, >= 0",
        doc: "vertical damper of the suspension",
        access: block_field!(suspension.damping),
    },
    Field {
        path: "body.suspension.unsprung_mass",
        unit: "kg",
        default: FieldDefault::Required,
        rule: Rule::NonNegative,
        note: "kg, the glider under the spring, >= 0 (0: the massless follower)",
        doc: "mass of the glider under the spring",
        access: block_field!(suspension.unsprung_mass),
    },
];
