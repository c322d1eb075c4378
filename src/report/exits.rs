//! Each vehicle's exit from the structure: when its first and its last
//! contact left the beam, and the vehicle's speed then, recorded while the
//! run goes (the run may go on into the free vibration to `end_time`).

use crate::outputs::{output_name, QuantityKind};
use crate::simulation::{Advance, EventKind, OutputInfo, Simulation, SolverError, Steppable};
use serde::{Deserialize, Serialize};

/// One vehicle's exit figures in the run summary. `None` (JSON `null`):
/// that contact did not leave the beam during the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VehicleExit {
    /// The vehicle's name (`body.name`, `vehicles[k].name`).
    pub vehicle: String,
    /// Its contacts with the track (wheels, wheelsets, magnets).
    pub contacts: usize,
    /// Time (s) when its first contact left the beam.
    pub first_exit_time: Option<f64>,
    /// Its speed (m/s) then: the nominal speed V (eq. 24) where the
    /// vehicle has one (wheel, glider), else its first body's forward
    /// speed; read at the end of the step in which the contact left.
    pub first_exit_speed: Option<f64>,
    /// Time (s) when its last contact left the beam.
    pub last_exit_time: Option<f64>,
    /// Its speed (m/s) then, as `first_exit_speed`.
    pub last_exit_speed: Option<f64>,
}

/// Which vehicle each contact belongs to and where each vehicle's speed is
/// among the outputs.
struct ExitPlan {
    /// Per vehicle: name and the output column of its speed.
    vehicles: Vec<(String, Option<usize>)>,
    /// Per contact: its vehicle, if any owns it.
    owner: Vec<Option<usize>>,
}

impl ExitPlan {
    fn of(simulation: &Simulation, vehicles: &[String]) -> ExitPlan {
        let names: Vec<&str> = simulation
            .outputs()
            .iter()
            .map(|o| o.name.as_str())
            .collect();
        let column = |name: &str| {
            [
                output_name(QuantityKind::NominalSpeed, name),
                output_name(QuantityKind::Vx, name),
            ]
            .iter()
            .find_map(|wanted| names.iter().position(|n| n == wanted))
        };
        let system = simulation.system();
        let owner = system
            .contacts
            .iter()
            .map(|c| owner_of(&system.bodies[c.body].name, vehicles))
            .collect();
        ExitPlan {
            vehicles: vehicles.iter().map(|v| (v.clone(), column(v))).collect(),
            owner,
        }
    }

    /// The output columns the plan reads.
    fn columns(&self) -> impl Iterator<Item = usize> + '_ {
        self.vehicles.iter().filter_map(|(_, column)| *column)
    }
}

/// The names of `scene`'s vehicles: `[body]`, then each of `[[vehicles]]`.
pub fn vehicle_names(scene: &crate::scene::Scene) -> Vec<String> {
    scene.vehicles.iter().map(|v| v.name.clone()).collect()
}

/// The output columns an `ExitWatch` of `simulation` reads (to be computed
/// when a run computes only the outputs it reads).
pub fn exit_columns(simulation: &Simulation, vehicles: &[String]) -> Vec<usize> {
    ExitPlan::of(simulation, vehicles).columns().collect()
}

/// The vehicle whose bodies include `body`: a vehicle named `coach1` owns
/// `coach1` and `coach1_...`; of several such names the longest.
fn owner_of(body: &str, vehicles: &[String]) -> Option<usize> {
    vehicles
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            body == v.as_str()
                || body
                    .strip_prefix(v.as_str())
                    .is_some_and(|rest| rest.starts_with('_'))
        })
        .max_by_key(|(_, v)| v.len())
        .map(|(k, _)| k)
}

/// A simulation whose steps are watched for contacts leaving the beam; it
/// steps as the simulation it wraps.
pub trait Watched: Steppable {
    fn simulation(&self) -> &Simulation;
}

impl Watched for Simulation {
    fn simulation(&self) -> &Simulation {
        self
    }
}

/// Records, as the run goes, each contact's exit time and its vehicle's
/// speed at the end of that step (the speed is not kept for every step).
pub struct ExitWatch<'s, S: Watched> {
    inner: &'s mut S,
    plan: ExitPlan,
    /// Events already looked at.
    seen: usize,
    /// Per contact: its first exit (time, vehicle speed).
    exits: Vec<Option<(f64, Option<f64>)>>,
    values: Vec<f64>,
}

impl<'s, S: Watched> ExitWatch<'s, S> {
    /// Watch `inner`, whose vehicles are named `vehicles` (the scene's
    /// `[body]` first, then its `[[vehicles]]`).
    pub fn new(inner: &'s mut S, vehicles: &[String]) -> ExitWatch<'s, S> {
        let simulation = inner.simulation();
        let plan = ExitPlan::of(simulation, vehicles);
        let contacts = simulation.system().contacts.len();
        let values = vec![0.0; simulation.outputs().len()];
        ExitWatch {
            seen: simulation.events().len(),
            inner,
            plan,
            exits: vec![None; contacts],
            values,
        }
    }

    fn note_new_events(&mut self) {
        let simulation = self.inner.simulation();
        let events = simulation.events();
        let new = &events[self.seen.min(events.len())..];
        if new.iter().any(|e| e.kind == EventKind::Exit) {
            simulation.output_values(&mut self.values);
        }
        for event in new.iter().filter(|e| e.kind == EventKind::Exit) {
            let Some(exit) = self.exits.get_mut(event.contact) else {
                continue;
            };
            let vehicle = self.plan.owner[event.contact];
            let column = vehicle.and_then(|v| self.plan.vehicles[v].1);
            let speed = column.map(|k| self.values[k]);
            exit.get_or_insert((event.time, speed));
        }
        self.seen = events.len();
    }

    /// Each vehicle's figures, in the order of the names given to `new`.
    pub fn finish(self) -> Vec<VehicleExit> {
        let ExitWatch { plan, exits, .. } = self;
        plan.vehicles
            .iter()
            .enumerate()
            .map(|(v, (name, _))| {
                let own: Vec<_> = (0..exits.len())
                    .filter(|&c| plan.owner[c] == Some(v))
                    .map(|c| exits[c])
                    .collect();
                vehicle_exit(name, &own)
            })
            .collect()
    }
}

/// The figures of one vehicle from its contacts' exits.
fn vehicle_exit(name: &str, exits: &[Option<(f64, Option<f64>)>]) -> VehicleExit {
    let left: Vec<(f64, Option<f64>)> = exits.iter().flatten().copied().collect();
    let first = left.iter().copied().min_by(|a, b| a.0.total_cmp(&b.0));
    // The last contact has left only when every one of them has.
    let all_left = !exits.is_empty() && left.len() == exits.len();
    let last = all_left
        .then(|| left.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0)))
        .flatten();
    VehicleExit {
        vehicle: name.to_string(),
        contacts: exits.len(),
        first_exit_time: first.map(|e| e.0),
        first_exit_speed: first.and_then(|e| e.1),
        last_exit_time: last.map(|e| e.0),
        last_exit_speed: last.and_then(|e| e.1),
    }
}

impl<S: Watched> Steppable for ExitWatch<'_, S> {
    fn time(&self) -> f64 {
        self.inner.time()
    }
    fn outputs(&self) -> &[OutputInfo] {
        self.inner.outputs()
    }
    fn output_values(&self, values: &mut [f64]) {
        self.inner.output_values(values)
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        let advance = self.inner.advance_to(t)?;
        self.note_new_events();
        Ok(advance)
    }
}
