//! The flexible structure the vehicles cross: the list of its kinds (each
//! a file implementing `ops::StructureOps` and `kinds::ChosenKind`: the
//! Hermite beam, its modal reduction, the rail over the deck), the seam
//! over them (`Structure`, `seam.rs`), and the track's pieces and
//! irregularity profile.
//!
//! A new kind is its file and its line below: the line declares its
//! module, its variant of `Structure` and the fields of `[beam]` it owns
//! (`kinds.rs` has the syntax); its file implements the two traits.

pub mod acceleration_rows;
#[macro_use]
mod kinds;
pub mod modal;
mod ops;
pub mod profile;
pub mod rail_on_deck;
pub mod section_forces;
mod sleeper_layout;
pub mod track_on_deck;
pub mod track_sleepers;
pub mod track_spec;

structure_kinds! {
    /// Every free DOF of the Hermite mesh is a state entry.
    Hermite => beam::HermiteBeam;
    /// The state is the kept modes' coordinates.
    Modal => reduced::ModalBeam;
    /// A rail over the deck: the contacts run on the rail (the mesh), the
    /// state is the rail's and the deck's DOFs interleaved.
    Track => track_seam::TrackBeam in Box;
}

pub mod seam;

pub use kinds::{KindField, KindRule};
