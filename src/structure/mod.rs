//! The flexible structure the vehicles cross: the Hermite beam (its mesh,
//! supports and bending operator), its modal reduction, and the track's
//! irregularity profile.

pub mod beam;
pub mod modal;
pub mod profile;
