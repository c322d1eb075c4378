//! The physics as the model layer sees it: build from a scene, step, read
//! outputs, save and restore state.
//!
//! `Simulation` (vehicles) and `model::forces::ForceDynamics` (moving
//! forces) implement it, chosen per scene by `model::SceneDynamics`; a small
//! fake (`model::fake`) tests the model and FMI layers apart from the
//! physics.

use crate::scene::Scene;
use crate::simulation::{SimState, Simulation, Steppable};
use serde::{de::DeserializeOwned, Serialize};

/// `Steppable` (time, outputs, output values, advance) plus what the FMU
/// needs besides: building, inputs, exit, state.
pub trait Dynamics: Steppable + Sized {
    /// Everything needed to continue a run bit-identically.
    type State: Clone + Serialize + DeserializeOwned;

    /// Build the model a (valid) scene asks for.
    fn build(scene: &Scene) -> Result<Self, String>;
    /// The applied force (fx, fy) on vehicle `vehicle`'s first body.
    fn set_vehicle_force(&mut self, vehicle: usize, force: [f64; 2]);
    /// The coupling ports' additional loads (fx, fy, moment), one per port.
    fn set_coupling_loads(&mut self, _loads: &[[f64; 3]]) {}
    fn exit_time(&self) -> Option<f64>;
    /// Whether the dynamics can advance to `t` (their time): Err naming
    /// the rule where they cannot, checked before a communication step
    /// runs (so that a refused step has changed nothing).
    fn check_target(&self, _t: f64) -> Result<(), String> {
        Ok(())
    }
    /// The simulation events (entries, exits, ...) after the first `from`,
    /// in words, each with its time; the list only grows as the run goes on.
    fn events_since(&self, _from: usize) -> Vec<String> {
        Vec::new()
    }
    /// How many events there are so far.
    fn event_count(&self) -> usize {
        0
    }
    /// Why `bytes` (a serialized snapshot of model `guid`) do not decode,
    /// in better words than the decoder's own where the dynamics can say
    /// (a state of several kinds tried in turn); `None` keeps the decoder's.
    fn explain_undecodable(_guid: &str, _bytes: &[u8]) -> Option<String> {
        None
    }
    fn state(&self) -> Self::State;
    /// `*into = self.state()`, in `into`'s storage where the dynamics can
    /// (the roll-back copy taken before every communication step).
    fn save_into(&self, into: &mut Self::State) {
        *into = self.state();
    }
    /// Continue from `state`, which may come from a forged FMU state:
    /// refused (Err naming why) unless it fits these dynamics.
    fn restore(&mut self, state: &Self::State) -> Result<(), String>;
    /// Whether `state` is one `restore` accepts (every state a step reaches
    /// must be: the importer may save and restore it).
    fn check_state(&self, _state: &Self::State) -> Result<(), String> {
        Ok(())
    }
    /// Whether `restore` would accept `state`, without restoring it (a
    /// deserialized state is checked as a whole before it is kept).
    fn check_restorable(&self, state: &Self::State) -> Result<(), String> {
        self.check_state(state)
    }
    /// `check_state` of the current state (without copying it where the
    /// dynamics can lend it: this runs after every communication step).
    fn check_current(&self) -> Result<(), String> {
        self.check_state(&self.state())
    }
    /// `check_current` and `save_into(into)` in one (where the dynamics can,
    /// in one pass): each state a step reaches is checked and kept as the
    /// next step's roll-back copy. On Err `into` is no copy of anything.
    fn save_checked_into(&self, into: &mut Self::State) -> Result<(), String> {
        self.check_current()?;
        self.save_into(into);
        Ok(())
    }
    /// `state` (taken on these dynamics' grid of `step`) as a state of a
    /// companion run of the same scene at `step · ratio` (the error
    /// estimate's step doubling), or `None` where it is not on that grid or
    /// the dynamics have no companions.
    fn regridded(_state: &Self::State, _ratio: f64) -> Option<Self::State> {
        None
    }
    /// Whether `companion` (built from this scene at another step) runs the
    /// same integration scheme.
    fn same_scheme(&self, _companion: &Self) -> bool {
        false
    }
    /// The order in time of the integration scheme (2 unless known higher).
    fn order_in_time(&self) -> f64 {
        2.0
    }
}

impl Dynamics for Simulation {
    type State = SimState;

    /// A co-simulation runs to its stop time: the end of the structure is
    /// an event.
    fn build(scene: &Scene) -> Result<Self, String> {
        Simulation::new_open_ended(scene)
    }
    fn set_vehicle_force(&mut self, vehicle: usize, force: [f64; 2]) {
        Simulation::set_vehicle_force(self, vehicle, force)
    }
    fn set_coupling_loads(&mut self, loads: &[[f64; 3]]) {
        Simulation::set_coupling_loads(self, loads)
    }
    fn event_count(&self) -> usize {
        Simulation::events(self).len()
    }
    fn events_since(&self, from: usize) -> Vec<String> {
        let contacts = &self.system().contacts;
        let events = Simulation::events(self);
        events
            .get(from..)
            .unwrap_or_default()
            .iter()
            .map(|e| {
                let name = contacts.get(e.contact).map_or("?", |c| c.name.as_str());
                format!("t = {} s: {:?} of {name}", e.time, e.kind)
            })
            .collect()
    }
    fn exit_time(&self) -> Option<f64> {
        Simulation::exit_time(self)
    }
    fn state(&self) -> SimState {
        Simulation::state(self)
    }
    fn save_into(&self, into: &mut SimState) {
        into.copy_from(self.current());
    }
    fn restore(&mut self, state: &SimState) -> Result<(), String> {
        check_sim_state(state, self.step_size())?;
        Simulation::restore(self, state)
    }
    fn check_state(&self, state: &SimState) -> Result<(), String> {
        check_sim_state(state, self.step_size())
    }
    fn check_restorable(&self, state: &SimState) -> Result<(), String> {
        check_sim_state(state, self.step_size())?;
        Simulation::check_restorable(self, state)
    }
    fn check_current(&self) -> Result<(), String> {
        check_sim_state(self.current(), self.step_size())
    }
    fn save_checked_into(&self, into: &mut SimState) -> Result<(), String> {
        // (The same rules as `check_sim_state`.)
        into.copy_checked_from(self.current(), self.step_size())
    }
    fn regridded(state: &SimState, ratio: f64) -> Option<SimState> {
        let grid = |k: u64| -> Option<u64> {
            let scaled = k as f64 / ratio;
            (scaled.fract() == 0.0 && scaled <= u64::MAX as f64 / 4.0).then_some(scaled as u64)
        };
        let mut regridded = state.clone();
        regridded.grid_step = grid(state.grid_step)?;
        regridded.steps = grid(state.steps).unwrap_or(regridded.grid_step);
        for contact in &mut regridded.contacts {
            // (the companion's grid step that holds the opening)
            contact.opened_in = contact.opened_in.map(|k| (k as f64 / ratio).floor() as u64);
        }
        Some(regridded)
    }
    fn same_scheme(&self, companion: &Self) -> bool {
        let scheme = |s: &Simulation| s.integrator_choice().split(';').next().map(str::to_owned);
        scheme(self) == scheme(companion)
    }
    /// The integrator's order with the run's force profile (RK4 with the
    /// quadratic profile is fourth order; the held and linear profiles and
    /// HHT-α second: docs/error-estimates.md).
    fn order_in_time(&self) -> f64 {
        self.integrator_order()
    }
}

/// A state may come from a forged serialized FMU state: its numbers and
/// time are checked here (`SimState::check_values`), its vector lengths
/// against the model by `Simulation::restore`.
fn check_sim_state(s: &SimState, step: f64) -> Result<(), String> {
    s.check_values(step)
}
