//! The flexible structure the vehicles cross: the seam (`Structure`, an
//! enum over the kinds that implement `ops::StructureOps`: the Hermite
//! beam, its modal reduction, the rail over the deck), and the track's
//! irregularity profile.

pub mod acceleration_rows;
pub mod beam;
pub mod modal;
mod ops;
pub mod profile;
pub mod rail_on_deck;
pub mod reduced;
pub mod seam;
pub mod section_forces;
mod sleeper_layout;
pub mod track_on_deck;
pub mod track_seam;
pub mod track_sleepers;
pub mod track_spec;

pub use seam::Structure;
