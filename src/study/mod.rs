//! Studies over many runs: error against run time (work-precision), speed
//! sweeps of moving forces, the deck acceleration as EN 1991-2 counts it.

pub mod deck_filter;
pub mod local_error;
pub mod sweep;
pub mod work_precision;
