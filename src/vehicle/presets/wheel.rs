//! The wheel preset: a rigid disc (mass, inertia, radius) rolling without
//! slip on one contact.

use super::{parts, Block, Preset, Vehicle};
use crate::beam::Beam;
use crate::contact::ContactKind;
use crate::scene::{BodySpec, Checks};

pub struct Wheel;

impl Preset for Wheel {
    const DESCRIPTION: &'static str = "wheel (rolls, no slip)";
    const BLOCK: Option<Block> = Some(Block::InertiaRadius);

    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        // Present values' rule (> 0) is the field table's row.
        checks.required(&format!("{prefix}.inertia"), body.inertia, "a wheel needs");
        checks.required(&format!("{prefix}.radius"), body.radius, "a wheel needs");
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
