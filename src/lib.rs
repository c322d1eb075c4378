//! guideway: bodies moving on flexible structures.
//!
//! The physics (beam, bodies, contact, integrators, the contact-force
//! iteration of Lee 1994) lives in the modules below `simulation`; it knows
//! nothing of FMI. The `model` module turns a scene into a table of named,
//! typed variables; the `fmi2` layer exports that table through the FMI 2.0
//! co-simulation C ABI and knows nothing of beams.

pub mod assemble;
pub mod band;
pub mod beam;
pub mod bending;
pub mod body;
pub mod check;
pub mod complementarity;
pub mod contact;
pub mod design;
pub mod fmi2;
pub mod fmu;
pub mod force_element;
pub mod impact;
pub mod integrate;
pub mod iteration;
pub mod mesh;
pub mod modal;
pub mod model;
pub mod moving_load;
pub mod output_file;
pub mod output_mask;
pub mod outputs;
pub mod profile;
pub mod report;
pub mod scene;
pub mod simulation;
pub mod static_start;
pub mod study;
pub mod system;
pub mod two_level;

pub use scene::Scene;
pub use simulation::{Advance, OutputInfo, OutputKind, SimState, Simulation, SolverError};
