//! The FMI 2.0 co-simulation layer: exported C functions (`exports`), the
//! instance state machine (`instance`), modelDescription.xml
//! (`model_description`) and the logger (`logging`).
//!
//! It knows nothing of beams: it sees a `Model` with a variable table.

pub mod exports;
pub mod instance;
pub mod logging;
pub mod model_description;

use crate::model::{Dynamics, Model};
use crate::scene::Scene;

/// The physics behind the exported functions: the scene's (vehicles or
/// moving forces, `model::SceneDynamics`), or the stand-in of `model::fake`
/// when built with the `fake-physics` feature (to test the FMI machinery
/// alone).
#[cfg(not(feature = "fake-physics"))]
pub type Physics = crate::model::SceneDynamics;
#[cfg(feature = "fake-physics")]
pub type Physics = crate::model::fake::FakeDynamics;

/// What an FMU of `scene` declares: its modelDescription.xml, GUID and
/// variable table (built by the same code an instance uses, so the two
/// always agree).
pub struct Description {
    pub xml: String,
    pub guid: String,
    pub model_identifier: String,
    pub table: crate::model::VariableTable,
}

pub fn describe<D: Dynamics>(scene: &Scene) -> Result<Description, String> {
    let model = Model::<D>::new(scene.clone()).map_err(|e| e.0)?;
    let mut table = model.table().clone();
    table.set_initial_dependencies(&crate::model::initial_dependencies::<D>(model.scene())?);
    let (xml, guid) = model_description::generate(model.scene(), &table);
    Ok(Description {
        xml,
        guid,
        model_identifier: model_description::model_identifier(&scene.name),
        table,
    })
}

#[cfg(test)]
mod tests;
