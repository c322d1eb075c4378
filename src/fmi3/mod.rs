//! The FMI 3.0 co-simulation front, beside the FMI 2.0 one (`crate::fmi2`):
//! the exported C functions (`exports`, `unsupported`), the version's modes
//! and call rules (`instance`), its modelDescription.xml dialect
//! (`model_description`) and its logger callback (`logging`).
//!
//! Both fronts drive the same shared layer (`crate::fmi_common`) over the
//! same `model::FmuModel` with the same variable table, so one model gives
//! two FMUs whose variables, value references and results are the same.
//! Like the FMI 2.0 front it sees nothing of the model but that trait.

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;
mod unsupported;

pub use crate::fmi_common::Description;
use crate::model::FmuModel;

/// What an FMI 3.0 FMU of the model of `config` declares
/// (`Description::guid` holds the instantiation token).
pub fn describe<M: FmuModel>(config: M::Config) -> Result<Description, String> {
    crate::fmi_common::describe::<M, instance::Fmi3>(config)
}

#[cfg(test)]
mod tests;
