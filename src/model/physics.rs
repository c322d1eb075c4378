//! The dynamics an exported scene runs, chosen from the scene when it is
//! built: its vehicles (`Simulation`, Lee's contact iteration) or moving
//! forces (`ForceDynamics`). The FMI layers see one type and stay blind to
//! which.

use super::forces::ForceDynamics;
use super::{snapshot, Dynamics, Snapshot};
use crate::moving_load::{is_moving_force_scene, ForceState};
use crate::scene::Scene;
use crate::simulation::{Advance, OutputInfo, SimState, Simulation, SolverError, Steppable};
use serde::{Deserialize, Serialize};

/// A scene's dynamics.
#[allow(clippy::large_enum_variant)] // one per FMU instance, never moved in a loop
pub enum SceneDynamics {
    Vehicles(Simulation),
    Forces(ForceDynamics),
}

/// A state of either. Untagged, so that a vehicle scene's serialized
/// state keeps its bytes (and states saved before moving forces load).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
#[allow(clippy::large_enum_variant)] // a few per instance (roll-back copies kept in place)
pub enum SceneState {
    Vehicles(SimState),
    Forces(ForceState),
}

/// Said when a state of one kind is handed to the other's dynamics.
const WRONG_KIND: &str = "the state is not one of this model (a vehicle state for moving \
                          forces, or the reverse)";

/// `$body` on the dynamics inside `$self`, whichever they are.
macro_rules! either {
    ($self:expr, $d:ident => $body:expr) => {
        match $self {
            SceneDynamics::Vehicles($d) => $body,
            SceneDynamics::Forces($d) => $body,
        }
    };
}

impl Steppable for SceneDynamics {
    fn time(&self) -> f64 {
        either!(self, d => Steppable::time(d))
    }
    fn outputs(&self) -> &[OutputInfo] {
        either!(self, d => Steppable::outputs(d))
    }
    fn output_values(&self, values: &mut [f64]) {
        either!(self, d => Steppable::output_values(d, values))
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        either!(self, d => Steppable::advance_to(d, t))
    }
}

impl Dynamics for SceneDynamics {
    type State = SceneState;

    fn build(scene: &Scene) -> Result<Self, String> {
        if is_moving_force_scene(scene) {
            ForceDynamics::build(scene).map(SceneDynamics::Forces)
        } else {
            <Simulation as Dynamics>::build(scene).map(SceneDynamics::Vehicles)
        }
    }
    fn set_vehicle_force(&mut self, vehicle: usize, force: [f64; 2]) {
        either!(self, d => Dynamics::set_vehicle_force(d, vehicle, force))
    }
    fn set_coupling_loads(&mut self, loads: &[[f64; 3]]) {
        either!(self, d => Dynamics::set_coupling_loads(d, loads))
    }
    fn exit_time(&self) -> Option<f64> {
        either!(self, d => Dynamics::exit_time(d))
    }
    fn check_target(&self, t: f64) -> Result<(), String> {
        either!(self, d => Dynamics::check_target(d, t))
    }
    fn events_since(&self, from: usize) -> Vec<String> {
        either!(self, d => Dynamics::events_since(d, from))
    }
    fn event_count(&self) -> usize {
        either!(self, d => Dynamics::event_count(d))
    }
    /// The untagged state says only that no kind matched: say why each
    /// did not (a forged vehicle state's wrong length, say).
    fn explain_undecodable(guid: &str, bytes: &[u8]) -> Option<String> {
        let as_vehicles = snapshot::decode::<Snapshot<SimState>>(guid, bytes).err()?;
        let as_forces = snapshot::decode::<Snapshot<ForceState>>(guid, bytes).err()?;
        Some(format!(
            "{as_vehicles} (read as a vehicle state); {as_forces} (read as a moving-force state)"
        ))
    }

    fn state(&self) -> SceneState {
        match self {
            SceneDynamics::Vehicles(d) => SceneState::Vehicles(Dynamics::state(d)),
            SceneDynamics::Forces(d) => SceneState::Forces(Dynamics::state(d)),
        }
    }
    fn save_into(&self, into: &mut SceneState) {
        match (self, into) {
            (SceneDynamics::Vehicles(d), SceneState::Vehicles(s)) => d.save_into(s),
            (SceneDynamics::Forces(d), SceneState::Forces(s)) => d.save_into(s),
            (_, into) => *into = self.state(),
        }
    }
    fn restore(&mut self, state: &SceneState) -> Result<(), String> {
        match (self, state) {
            (SceneDynamics::Vehicles(d), SceneState::Vehicles(s)) => Dynamics::restore(d, s),
            (SceneDynamics::Forces(d), SceneState::Forces(s)) => Dynamics::restore(d, s),
            _ => Err(WRONG_KIND.into()),
        }
    }
    fn check_state(&self, state: &SceneState) -> Result<(), String> {
        match (self, state) {
            (SceneDynamics::Vehicles(d), SceneState::Vehicles(s)) => d.check_state(s),
            (SceneDynamics::Forces(d), SceneState::Forces(s)) => d.check_state(s),
            _ => Err(WRONG_KIND.into()),
        }
    }
    fn check_restorable(&self, state: &SceneState) -> Result<(), String> {
        match (self, state) {
            (SceneDynamics::Vehicles(d), SceneState::Vehicles(s)) => d.check_restorable(s),
            (SceneDynamics::Forces(d), SceneState::Forces(s)) => d.check_restorable(s),
            _ => Err(WRONG_KIND.into()),
        }
    }
    fn check_current(&self) -> Result<(), String> {
        either!(self, d => Dynamics::check_current(d))
    }
    fn save_checked_into(&self, into: &mut SceneState) -> Result<(), String> {
        match (self, into) {
            (SceneDynamics::Vehicles(d), SceneState::Vehicles(s)) => d.save_checked_into(s),
            (SceneDynamics::Forces(d), SceneState::Forces(s)) => d.save_checked_into(s),
            (_, into) => {
                self.check_current()?;
                *into = self.state();
                Ok(())
            }
        }
    }
    fn regridded(state: &SceneState, ratio: f64) -> Option<SceneState> {
        match state {
            SceneState::Vehicles(s) => Simulation::regridded(s, ratio).map(SceneState::Vehicles),
            SceneState::Forces(_) => None,
        }
    }
    fn same_scheme(&self, companion: &Self) -> bool {
        match (self, companion) {
            (SceneDynamics::Vehicles(a), SceneDynamics::Vehicles(b)) => a.same_scheme(b),
            _ => false,
        }
    }
    fn order_in_time(&self) -> f64 {
        either!(self, d => Dynamics::order_in_time(d))
    }
}
