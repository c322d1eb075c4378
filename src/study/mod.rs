//! Studies over many runs: error against run time (work-precision), speed
//! sweeps of moving forces.

pub mod local_error;
pub mod sweep;
pub mod work_precision;
