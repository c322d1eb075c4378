//! The FMI 3.0 co-simulation front, beside the FMI 2.0 one (`crate::fmi2`):
//! the exported C functions (`exports`, `unsupported`), the version's modes
//! and call rules (`instance`), its modelDescription.xml dialect
//! (`model_description`) and its logger callback (`logging`).
//!
//! Both fronts drive the same shared layer (`crate::fmi_common`) over the
//! same `Model` with the same variable table, so one scene gives two FMUs
//! whose variables, value references and results are the same. Like the
//! FMI 2.0 front it knows nothing of beams.

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;
mod unsupported;

pub use crate::fmi_common::{Description, Physics};
use crate::model::Dynamics;
use crate::scene::Scene;

/// What an FMI 3.0 FMU of `scene` declares (`Description::guid` holds the
/// instantiation token).
pub fn describe<D: Dynamics>(scene: &Scene) -> Result<Description, String> {
    crate::fmi_common::describe::<D, instance::Fmi3>(scene)
}

#[cfg(test)]
mod tests;
