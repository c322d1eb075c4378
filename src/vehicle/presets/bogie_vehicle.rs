//! The bogie-vehicle preset, the 10-DOF half vehicle: a car body (bounce,
//! pitch) on secondary spring–dampers over two bogies (bounce, pitch), each
//! on primary spring–dampers over two wheelsets (gliders or rolling wheels,
//! or massless followers when `wheelset_mass = 0`).

use serde::{Deserialize, Serialize};

use super::{parts, refuse_unless, Preset, Reach, Vehicle};
use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactKind};
use crate::scene::fields::{block_field, Access, Default as FieldDefault, Field, Rule};
use crate::scene::{fmt_f64, BodySpec, Checks};

/// The bogies, wheelsets and suspensions of a `bogie_vehicle`; both
/// suspensions are preloaded with the weight they carry.
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

/// Heights of a bogie's centre above its wheelsets and of the car body's
/// centre above its bogies at rest (m): only differences of heights enter.
pub const BOGIE_HEIGHTS: [f64; 2] = [0.5, 1.5];

pub struct BogieVehicle;

impl Preset for BogieVehicle {
    const DESCRIPTION: &'static str = "car body on two bogies over four wheelsets (10 DOF)";
    const ROWS: &'static [Field] = BOGIE_ROWS;
    const BLOCK_NOTE: &'static str = "bogie_vehicle: car body on two bogies on four wheelsets";
    const NAMES_ITS_CONTACTS: bool = true;

    fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        if body.bogie.is_some() {
            refuse_unless(checks, prefix, "bogie", "present", "bogie_vehicle");
        }
    }

    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        match &body.bogie {
            Some(b) => check_bogie(checks, prefix, b),
            None => checks.fail(
                format!("{prefix}.bogie"),
                "missing",
                format!(
                    "a bogie_vehicle needs [{prefix}.bogie] with its masses, distances and \
                     suspensions"
                ),
            ),
        }
    }

    /// Body 0 the car body, bodies 1–2 the front and rear bogies, bodies
    /// 3–6 the wheelsets (front to rear).
    fn build(spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String> {
        let b: BogieSpec = spec.bogie.expect("a validated bogie_vehicle has its bogie");
        let (mut parts, contacts) = bodies(spec, &b, beam);
        let (bodies, states): (Vec<RigidBody>, Vec<BodyState>) = parts.drain(..).unzip();
        let force_elements = suspensions(spec, &b, gravity, &states);
        Ok(Vehicle {
            bodies,
            contacts,
            force_elements,
            states,
        })
    }

    /// The wheelsets lie ± (bogie_half_distance + axle_half_distance) about
    /// the car body's centre.
    fn reach(spec: &BodySpec) -> Option<Reach> {
        let b = spec.bogie?;
        Some(Reach::symmetric(
            b.bogie_half_distance + b.axle_half_distance,
        ))
    }
    const STARTS_ON_TRACK: bool = true;

    fn body_names(spec: &BodySpec) -> Vec<String> {
        let n = &spec.name;
        let mut names = vec![n.clone()];
        names.extend((1..=2).map(|i| format!("{n}_bogie{i}")));
        // Massless followers are contacts, not bodies.
        if !Self::massless_contacts(spec) {
            names.extend((1..=4).map(|i| format!("{n}_wheelset{i}")));
        }
        names
    }

    fn massless_contacts(spec: &BodySpec) -> bool {
        spec.bogie.is_some_and(|b| b.wheelset_mass == 0.0)
    }

    /// Four wheelsets, each rolling (two rows) when it has a radius.
    fn contact_rows(_spec: &BodySpec) -> usize {
        8
    }
}

/// The car body, the bogies and the wheelsets where they start, and the
/// wheelsets' contacts.
fn bodies(
    spec: &BodySpec,
    b: &BogieSpec,
    beam: &Beam,
) -> (Vec<(RigidBody, BodyState)>, Vec<Contact>) {
    let (lc, lt) = (b.bogie_half_distance, b.axle_half_distance);
    // Wheel wheelsets lift everything above them by their radius.
    let lift = b.wheel_radius.unwrap_or(0.0);
    let at = |dx: f64, dy: f64, mass: f64, inertia: f64, name: String| {
        let (_, _, mut state) = parts::glider_at(spec, beam, dx);
        state.position.y += dy + lift;
        let body = RigidBody {
            name,
            mass,
            inertia,
            drive: None,
        };
        (body, state)
    };
    let [bogie_height, car_height] = BOGIE_HEIGHTS;
    let mut parts = vec![at(
        0.0,
        car_height,
        spec.mass,
        b.car_inertia,
        spec.name.clone(),
    )];
    for (i, side) in [1.0, -1.0].into_iter().enumerate() {
        let name = format!("{}_bogie{}", spec.name, i + 1);
        parts.push(at(
            side * lc,
            bogie_height,
            b.bogie_mass,
            b.bogie_inertia,
            name,
        ));
    }
    let mut contacts = Vec::new();
    for (i, (bogie, axle)) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let name = format!("{}_wheelset{}", spec.name, i + 1);
        let (part, contact) = wheelset(spec, b, bogie * lc + axle * lt, name, beam);
        parts.push(part);
        contacts.push(Contact {
            body: 3 + i,
            ..contact
        });
    }
    (parts, contacts)
}

/// The primary suspensions (bogie–wheelset) and the secondary ones
/// (car–bogie), preloaded with the weight each carries.
fn suspensions(
    spec: &BodySpec,
    b: &BogieSpec,
    gravity: f64,
    states: &[BodyState],
) -> Vec<crate::force_element::ForceElement> {
    let (lc, lt) = (b.bogie_half_distance, b.axle_half_distance);
    let secondary_load = 0.5 * spec.mass * gravity;
    let primary_load = 0.5 * (secondary_load + b.bogie_mass * gravity);
    let mut force_elements = Vec::new();
    // Leaves first: the static start balances horizontal forces from the
    // wheelsets up to the car body in this order.
    for (w, bogie) in [1, 1, 2, 2].into_iter().enumerate() {
        let side = if w % 2 == 0 { lt } else { -lt };
        let name = format!("{}.primary{}", spec.name, w + 1);
        let (k, c) = (b.primary_stiffness, b.primary_damping);
        let at = (bogie, side);
        parts::suspension(
            &name,
            at,
            3 + w,
            k,
            c,
            primary_load,
            states,
            &mut force_elements,
        );
    }
    for (i, side) in [lc, -lc].into_iter().enumerate() {
        let name = format!("{}.secondary{}", spec.name, i + 1);
        let (k, c) = (b.secondary_stiffness, b.secondary_damping);
        let at = (0, side);
        parts::suspension(
            &name,
            at,
            1 + i,
            k,
            c,
            secondary_load,
            states,
            &mut force_elements,
        );
    }
    force_elements
}

/// A wheelset `dx` from the car body's centre: a glider, or a rolling
/// wheel when the bogie spec gives `wheel_radius`.
fn wheelset(
    spec: &BodySpec,
    b: &BogieSpec,
    dx: f64,
    name: String,
    beam: &Beam,
) -> ((RigidBody, BodyState), Contact) {
    let mut s = spec.clone();
    s.initial_position += dx;
    s.mass = b.wheelset_mass;
    let (inertia, kind) = match (b.wheel_radius, b.wheelset_inertia) {
        (Some(radius), Some(inertia)) => (inertia, ContactKind::Wheel { radius }),
        _ => (0.0, ContactKind::Glider),
    };
    let (mut body, mut contact, state) = parts::contact_body(&s, beam, inertia, kind);
    body.name = name.clone();
    contact.name = name;
    ((body, state), contact)
}

/// The bogie's own values: positive masses, inertias, distances and
/// stiffnesses, non-negative dampings, wheelsets that are wheels or
/// gliders, and axles that do not overlap.
fn check_bogie(checks: &mut Checks, prefix: &str, b: &BogieSpec) {
    let path = |field: &str| format!("{prefix}.bogie.{field}");
    // The numbers' own rules are the field table's rows; a wheelset mass
    // is 0 (massless followers under the axles) or positive, which the
    // row's >= 0 leaves to here.
    if b.wheelset_mass > 0.0 && b.wheelset_mass.is_finite() {
        checks.positive(&path("wheelset_mass"), b.wheelset_mass);
    }
    check_wheel_wheelsets(checks, &path, b);
    // The two bogies' axles must not overlap: lc > lt.
    if b.bogie_half_distance.is_finite()
        && b.axle_half_distance.is_finite()
        && b.bogie_half_distance <= b.axle_half_distance
    {
        checks.fail(
            path("bogie_half_distance"),
            fmt_f64(b.bogie_half_distance),
            format!(
                "must exceed bogie.axle_half_distance = {} (the bogies' axles would overlap)",
                fmt_f64(b.axle_half_distance)
            ),
        );
    }
}

/// Wheel wheelsets need both their radius and their inertia; gliders
/// neither.
fn check_wheel_wheelsets(checks: &mut Checks, path: &dyn Fn(&str) -> String, b: &BogieSpec) {
    match (b.wheel_radius, b.wheelset_inertia) {
        // r and j's own rules (> 0) are the field table's rows.
        (Some(_), Some(_)) => {
            if b.wheelset_mass == 0.0 {
                checks.fail(
                    path("wheelset_mass"),
                    "0",
                    "a massless follower does not roll: wheel wheelsets (with wheel_radius) \
                     need a mass > 0; leave out wheel_radius and wheelset_inertia for followers",
                );
            }
        }
        (Some(_), None) => checks.fail(
            path("wheelset_inertia"),
            "missing",
            "wheel wheelsets (with wheel_radius) need a value > 0",
        ),
        (None, Some(_)) => checks.fail(
            path("wheel_radius"),
            "missing",
            "wheel wheelsets (with wheelset_inertia) need a value > 0; leave both out for \
             glider wheelsets",
        ),
        (None, None) => {}
    }
}

/// The field table's rows of the fields this preset owns.
const BOGIE_ROWS: &[Field] = &[
    Field {
        path: "body.bogie.car_inertia",
        unit: "kg.m2",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "kg m^2, > 0, car body pitch inertia",
        doc: "car body pitch inertia",
        access: block_field!(bogie.car_inertia),
    },
    Field {
        path: "body.bogie.bogie_mass",
        unit: "kg",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "kg, > 0, one bogie",
        doc: "mass of one bogie",
        access: block_field!(bogie.bogie_mass),
    },
    Field {
        path: "body.bogie.bogie_inertia",
        unit: "kg.m2",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "kg m^2, > 0, one bogie",
        doc: "pitch inertia of one bogie",
        access: block_field!(bogie.bogie_inertia),
    },
    Field {
        path: "body.bogie.wheelset_mass",
        unit: "kg",
        default: FieldDefault::Required,
        rule: Rule::NonNegative,
        note: "kg, > 0, or 0: massless followers under the axles",
        doc: "mass of one wheelset (0: massless followers)",
        access: block_field!(bogie.wheelset_mass),
    },
    Field {
        path: "body.bogie.bogie_half_distance",
        unit: "m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "m, l_c > l_t: half the distance of the bogie centres",
        doc: "half the distance of the bogie centres",
        access: block_field!(bogie.bogie_half_distance),
    },
    Field {
        path: "body.bogie.axle_half_distance",
        unit: "m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "m, l_t > 0: half a bogie's axle distance",
        doc: "half a bogie's axle distance",
        access: block_field!(bogie.axle_half_distance),
    },
    Field {
        path: "body.bogie.primary_stiffness",
        unit: "N/m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "N/m, k1 > 0, per axle",
        doc: "primary suspension stiffness per axle",
        access: block_field!(bogie.primary_stiffness),
    },
    Field {
        path: "body.bogie.primary_damping",
        unit: "N.s/m",
        default: FieldDefault::Value("0"),
        rule: Rule::NonNegative,
        note: "N s/m, c1 >= 0, per axle",
        doc: "primary suspension damping per axle",
        access: block_field!(bogie.primary_damping),
    },
    Field {
        path: "body.bogie.secondary_stiffness",
        unit: "N/m",
        default: FieldDefault::Required,
        rule: Rule::Positive,
        note: "N/m, k2 > 0, per bogie",
        doc: "secondary suspension stiffness per bogie",
        access: block_field!(bogie.secondary_stiffness),
    },
    Field {
        path: "body.bogie.secondary_damping",
        unit: "N.s/m",
        default: FieldDefault::Value("0"),
        rule: Rule::NonNegative,
        note: "N s/m, c2 >= 0, per bogie",
        doc: "secondary suspension damping per bogie",
        access: block_field!(bogie.secondary_damping),
    },
    Field {
        path: "body.bogie.wheel_radius",
        unit: "m",
        default: FieldDefault::Absent,
        rule: Rule::Positive,
        note: "m, > 0, with wheelset_inertia: rolling wheelsets",
        doc: "rolling radius of the wheelsets",
        access: Access::Vehicle(
            |b| b.bogie.as_ref().and_then(|g| g.wheel_radius),
            |b, x| {
                if let Some(g) = b.bogie.as_mut() {
                    g.wheel_radius = Some(x)
                }
            },
        ),
    },
    Field {
        path: "body.bogie.wheelset_inertia",
        unit: "kg.m2",
        default: FieldDefault::Absent,
        rule: Rule::Positive,
        note: "kg m^2, > 0, with wheel_radius",
        doc: "rolling inertia of one wheelset",
        access: Access::Vehicle(
            |b| b.bogie.as_ref().and_then(|g| g.wheelset_inertia),
            |b, x| {
                if let Some(g) = b.bogie.as_mut() {
                    g.wheelset_inertia = Some(x)
                }
            },
        ),
    },
];
