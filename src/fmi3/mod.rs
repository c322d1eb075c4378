//! The FMI 3.0 co-simulation layer, beside the FMI 2.0 one (`crate::fmi2`):
//! exported C functions (`exports`, `unsupported`), the instance state
//! machine (`instance`), modelDescription.xml (`model_description`) and the
//! logger (`logging`).
//!
//! Like the FMI 2.0 layer it knows nothing of beams: it sees the same
//! `Model` with the same variable table, so one scene gives two FMUs whose
//! variables, value references and results are the same.

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;
mod unsupported;

use crate::fmi2::Description;
use crate::model::{Dynamics, Model};
use crate::scene::Scene;

pub use crate::fmi2::Physics;

/// What an FMI 3.0 FMU of `scene` declares (`Description::guid` holds the
/// instantiation token).
pub fn describe<D: Dynamics>(scene: &Scene) -> Result<Description, String> {
    let model = Model::<D>::new(scene.clone()).map_err(|e| e.0)?;
    let mut table = model.table().clone();
    table.set_initial_dependencies(&crate::model::initial_dependencies::<D>(model.scene())?);
    let (xml, token) = model_description::generate(model.scene(), &table);
    Ok(Description {
        xml,
        guid: token,
        model_identifier: crate::fmi2::model_description::model_identifier(&scene.name),
        table,
    })
}

#[cfg(test)]
mod tests;
