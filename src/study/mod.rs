//! Studies over many runs: error against run time (work-precision), speed
//! sweeps of moving forces and of vehicles, the deck acceleration as EN 1991-2 counts it,
//! error estimates of any scene's figures, and the plots of sweeps and
//! convergence ladders.

pub mod converge;
pub mod converge_plot;
pub mod convergence;
pub mod local_error;
pub mod refine;
pub mod sweep;
pub mod sweep_plot;
pub mod vehicle_sweep;
pub mod work_precision;

// The filter's old path (scripts and tests name it).
pub use crate::signal as deck_filter;
