//! The flexible structure the vehicles cross: the seam (`Structure`) with
//! its implementations (the Hermite beam, its modal reduction), and the
//! track's irregularity profile.

pub mod beam;
pub mod dof_access;
pub mod modal;
pub mod profile;
pub mod rail_on_deck;
pub mod reduced;
pub mod seam;
pub mod track_on_deck;
pub mod track_seam;
pub mod track_sleepers;

pub use seam::Structure;
