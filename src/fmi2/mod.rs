//! The FMI 2.0 co-simulation front: the exported C functions (`exports`),
//! the version's modes and call rules (`instance`), its modelDescription.xml
//! dialect (`model_description`) and its logger callback (`logging`).
//!
//! The life cycle, the value access and the FMU states are the shared layer
//! `crate::fmi_common`, which both FMI fronts drive; like it, this front
//! sees the model only through `model::FmuModel` (a variable table, a
//! `ModelInfo`, a life cycle).

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;

pub use crate::fmi_common::Description;
use crate::model::FmuModel;

/// What an FMI 2.0 FMU of the model of `config` declares.
pub fn describe<M: FmuModel>(config: M::Config) -> Result<Description, String> {
    crate::fmi_common::describe::<M, instance::Fmi2>(config)
}

#[cfg(test)]
mod tests;
