//! Studies over many runs: error against run time (work-precision).

pub mod work_precision;
