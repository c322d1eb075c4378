//! The FMI 2.0 co-simulation front: the exported C functions (`exports`),
//! the version's modes and call rules (`instance`), its modelDescription.xml
//! dialect (`model_description`) and its logger callback (`logging`).
//!
//! The life cycle, the value access and the FMU states are the shared layer
//! `crate::fmi_common`, which both FMI fronts drive; like it, this front
//! knows nothing of beams: it sees a `Model` with a variable table.

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;

pub use crate::fmi_common::{Description, Physics};
use crate::model::Dynamics;
use crate::scene::Scene;

/// What an FMI 2.0 FMU of `scene` declares.
pub fn describe<D: Dynamics>(scene: &Scene) -> Result<Description, String> {
    crate::fmi_common::describe::<D, instance::Fmi2>(scene)
}

#[cfg(test)]
mod tests;
