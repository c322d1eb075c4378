//! Physics against independent references: moving forces and sprung masses
//! against series and modal solutions, beams, damping, the integrators'
//! order, energy books and error estimates. One test binary of many modules,
//! so that the integration tests link the library a few times, not seventy.

// The helpers every group shares, one folder up.
#[path = "../common/mod.rs"]
mod common;

mod beam_frequency;
mod damping;
mod deck_acceleration_filtered;
mod delassus_one_pass;
mod design_outputs;
mod design_static;
mod energy_books;
mod error_estimates;
mod error_sprung_mass;
mod force_profile;
mod free_vibration;
mod fryba;
mod hht_events;
mod hslm;
mod large_meshes;
mod local_error;
mod modal;
mod modal_damping;
mod moving_force_run;
mod numerical_dissipation;
mod paper_figures;
mod response_cache;
mod sprung_mass;
mod stability;
mod work_precision;
