//! The loads the contacts put on the structure, as point loads on its axis
//! (what the structure's internal forces, `structure::section_forces`, are
//! read under).

use crate::beam::Beam;
use crate::contact::{ContactForce, ContactFrame};
use crate::structure::section_forces::PointLoad;

/// The loads the contacts put on the beam: a contact force (F_t, F_n) on
/// the body acts on the beam's surface as −(F_t t + F_n n), which on the
/// axis is a vertical force and, through the surface offset h, the couple
/// of the tangential part (the load vector of `integrate::loads`).
pub fn contact_loads(
    beam: &Beam,
    frames: &[ContactFrame],
    forces: &[ContactForce],
) -> Vec<PointLoad> {
    frames
        .iter()
        .zip(forces)
        .filter(|(frame, _)| frame.on_beam)
        .map(|(frame, force)| PointLoad {
            x: frame.x,
            element: frame.shape.element,
            force: -(force.tangential * frame.sin + force.normal * frame.cos),
            couple: force.tangential * beam.surface_offset * frame.cos,
        })
        .collect()
}
