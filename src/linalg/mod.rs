//! Linear algebra the physics solves with: the band LDLᵀ factor of a beam's
//! matrices and the small mixed linear complementarity problem of the
//! contact impulses (the two-level solve on fine meshes is the beam's:
//! `structure::beam::two_level`).

pub mod band;
pub mod band_inverse;
pub mod bits;
pub mod complementarity;
pub mod dense_modes;
pub mod wide_band;
