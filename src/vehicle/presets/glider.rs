//! The glider preset: a point body at the surface (r = 0, J = 0) on one
//! contact, the maglev model of the paper.

use super::{parts, Preset, Vehicle};
use crate::beam::Beam;
use crate::contact::ContactKind;
use crate::scene::BodySpec;

pub struct Glider;

impl Preset for Glider {
    const DESCRIPTION: &'static str = "maglev glider (J = 0, r = 0)";

    fn build(spec: &BodySpec, beam: &Beam, _gravity: f64) -> Result<Vehicle, String> {
        let glider = parts::contact_body(spec, beam, 0.0, ContactKind::Glider);
        Ok(Vehicle::single(glider))
    }

    fn contact_rows(_spec: &BodySpec) -> usize {
        1
    }
}
