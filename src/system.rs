//! The assembled mechanical system: the beam and the body on it.

use crate::beam::Beam;
use crate::body::RigidBody;

pub struct System {
    pub beam: Beam,
    pub body: RigidBody,
}
