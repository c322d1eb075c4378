//! Linear algebra the physics solves with: the band LDLᵀ factor of a beam's
//! matrices, the two-level solve on fine meshes and the small mixed linear
//! complementarity problem of the contact impulses.

pub mod band;
pub mod band_inverse;
pub mod complementarity;
pub mod dense_modes;
pub mod two_level;
pub mod wide_band;
