//! guideway: bodies moving on flexible structures.
//!
//! Folders are the layers (`docs/architecture.md` has the map). The physics
//! (`structure`, `vehicle`, `contact`, `solver`, `linalg`, assembled into a
//! `system::System` by `build` and run by `simulation`) knows nothing of
//! FMI. `outputs` is the catalogue of what a run reports. The `model`
//! module turns a scene into a table of named, typed variables; the `fmi2`
//! and `fmi3` fronts export that table through the FMI 2.0 and 3.0
//! co-simulation C ABIs over one shared layer (`fmi_common`) and know
//! nothing of beams; `report`, `study`, `design` and `moving_load`
//! sit above the physics.

pub mod build;
pub mod check;
pub mod contact;
pub mod design;
pub mod energy;
pub mod fmi2;
pub mod fmi3;
pub mod fmi_common;
pub mod fmu;
pub mod input_file;
pub mod linalg;
pub mod model;
pub mod moving_load;
pub mod numbers;
pub mod outputs;
pub mod report;
pub mod scene;
pub mod signal;
pub mod simulation;
pub mod solver;
pub mod state;
pub mod structure;
pub mod study;
pub mod system;
pub mod vehicle;

// The modules' paths before the layout of issue 23, kept so that code
// written against them (other branches, tests, examples) still compiles.
pub use build as assemble;
pub use contact::law as contact_law;
pub use linalg::{band, complementarity, dense_modes, wide_band};
pub use outputs::mask as output_mask;
pub use report::output_file;
pub use solver::{deadline, impact, integrate, iteration, static_start};
pub use structure::beam::{bending, mesh, two_level};
pub use structure::{beam, modal, profile};
pub use vehicle::{body, force_element};

pub use scene::Scene;
pub use simulation::{Advance, OutputInfo, OutputKind, SimState, Simulation, SolverError};
