//! The wheel preset: a rigid disc (mass, inertia, radius) rolling without
//! slip on one contact.

use super::{parts, Preset, Vehicle};
use crate::beam::Beam;
use crate::contact::ContactKind;
use crate::scene::fields::{Access, Default as FieldDefault, Field, Rule};
use crate::scene::{fmt_f64, BodySpec, Checks};

pub struct Wheel;

impl Preset for Wheel {
    const DESCRIPTION: &'static str = "wheel (rolls, no slip)";
    const ROWS: &'static [Field] = WHEEL_ROWS;
    const ROWS_BEFORE: &'static str = "body.initial_position";

    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        // Present values' rule (> 0) is the field table's row.
        checks.required(&format!("{prefix}.inertia"), body.inertia, "a wheel needs");
        checks.required(&format!("{prefix}.radius"), body.radius, "a wheel needs");
    }

    /// J and r on another kind: refused (its bodies have neither).
    fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        for (field, value) in [("inertia", body.inertia), ("radius", body.radius)] {
            if let Some(v) = value {
                checks.fail(
                    format!("{prefix}.{field}"),
                    fmt_f64(v),
                    "must be left out for a glider or a sprung mass (J = 0, r = 0)",
                );
            }
        }
    }

    fn build(spec: &BodySpec, beam: &Beam, _gravity: f64) -> Result<Vehicle, String> {
        let kind = ContactKind::Wheel {
            radius: spec.radius.unwrap_or(0.0),
        };
        let inertia = spec.inertia.unwrap_or(0.0);
        Ok(Vehicle::single(parts::contact_body(
            spec, beam, inertia, kind,
        )))
    }

    /// No slip and normal.
    fn contact_rows(_spec: &BodySpec) -> usize {
        2
    }
}

/// The field table's rows of the fields this preset owns.
const WHEEL_ROWS: &[Field] = &[
    Field {
        path: "body.inertia",
        unit: "kg.m2",
        default: FieldDefault::Absent,
        rule: Rule::Positive,
        note: "kg m^2, centroidal J; wheel only",
        doc: "centroidal moment of inertia of the wheel",
        access: Access::Vehicle(|b| b.inertia, |b, x| b.inertia = Some(x)),
    },
    Field {
        path: "body.radius",
        unit: "m",
        default: FieldDefault::Absent,
        rule: Rule::Positive,
        note: "m, r; wheel only",
        doc: "radius of the wheel",
        access: Access::Vehicle(|b| b.radius, |b, x| b.radius = Some(x)),
    },
];
