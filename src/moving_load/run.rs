//! A time history of moving forces (`guideway run`): the crossing
//! (`Crossing`, the sweep's stepping) driven step by step to the exit or to
//! `solver.end_time`, its outputs those of the structure in any run
//! (sensors, sections, supports, the beam's energy) and the number of
//! forces on the beam; each vehicle's first and last axle's entry and exit
//! in closed form (the speeds are constant).

use super::{vehicle_axles, Axle, Crossing};
use crate::beam::Beam;
use crate::design::BeamDynamics;
use crate::outputs::Quantity;
use crate::outputs::{structure_catalogue, structure_value, BeamNow, OutputInfo, OutputKind};
use crate::scene::Scene;
use crate::simulation::{Advance, SolverError, Steppable};
use serde::{Deserialize, Serialize};

/// The output counting the forces on the beam.
pub const FORCES_ON_BEAM: &str = "forces.on_beam";

/// One vehicle of moving forces: its name and axles (the leading first).
#[derive(Debug, Clone, PartialEq)]
pub struct ForceVehicle {
    pub name: String,
    pub axles: Vec<Axle>,
}

/// When one axle crosses an end of the beam.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleEvent {
    /// `<vehicle>.axle<k>`, k from 1 at the leading axle.
    pub axle: String,
    /// `entry` (onto the beam) or `exit` (off it).
    pub kind: &'static str,
    /// Time (s).
    pub time: f64,
}

/// A saved state of a run: the steps taken, the crossing's time (a sum of
/// steps, kept as summed so that a restored run continues bit-identically)
/// and the beam's free DOFs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ForceState {
    pub steps: u64,
    pub time: f64,
    pub displacement: Vec<f64>,
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
}

/// The run: the crossing, its outputs and when it stops.
pub struct ForceRun {
    crossing: Crossing<'static>,
    /// The beam's state after the last step, as the design outputs read it.
    now: BeamDynamics<'static>,
    outputs: Vec<OutputInfo>,
    quantities: Vec<Quantity>,
    sensors: Vec<f64>,
    sections: Vec<f64>,
    vehicles: Vec<ForceVehicle>,
    /// Steps taken, and the steps after which the last force has left
    /// (the sweep's count, `Crossing::steps_to`).
    steps: u64,
    exit_steps: f64,
    /// Without `solver.end_time` the run ends at the last exit.
    stop_at_exit: bool,
}

impl ForceRun {
    /// The run of a valid moving-force scene, at rest at t = 0.
    pub fn new(scene: &Scene) -> Result<ForceRun, String> {
        if !super::is_moving_force_scene(scene) {
            return Err("a run of moving forces needs body.kind = \"moving_force\"".into());
        }
        let beam = Beam::new(&scene.beam)?;
        let vehicles: Vec<ForceVehicle> = scene
            .vehicles
            .iter()
            .map(|spec| ForceVehicle {
                name: spec.name.clone(),
                axles: vehicle_axles(spec, scene.gravity),
            })
            .collect();
        let axles: Vec<Axle> = vehicles.iter().flat_map(|v| v.axles.clone()).collect();
        let names = |list: &[crate::scene::SensorSpec]| -> Vec<String> {
            list.iter().map(|s| s.name.clone()).collect()
        };
        let sections: Vec<String> = scene.sections.iter().map(|s| s.name.clone()).collect();
        let (mut outputs, quantities): (Vec<OutputInfo>, Vec<Quantity>) =
            structure_catalogue(&beam, &names(&scene.sensors), &sections, scene.reactions)
                .into_iter()
                .unzip();
        outputs.push(OutputInfo {
            name: FORCES_ON_BEAM.into(),
            unit: "",
            description: "moving forces (axles) on the beam".into(),
            kind: OutputKind::Integer,
        });
        let crossing = Crossing::owning(beam, axles, scene.solver.step)?;
        let exit_steps = (crossing.exit_time() / scene.solver.step).ceil();
        Ok(ForceRun {
            now: crossing.dynamics(),
            crossing,
            outputs,
            quantities,
            sensors: scene.sensors.iter().map(|s| s.position).collect(),
            sections: scene.sections.iter().map(|s| s.position).collect(),
            vehicles,
            steps: 0,
            exit_steps,
            stop_at_exit: scene.solver.end_time.is_none(),
        })
    }

    /// `new`, running on past the last exit to any time asked for (the
    /// beam vibrating freely): a co-simulation's end is its stop time.
    pub fn open_ended(scene: &Scene) -> Result<ForceRun, String> {
        let mut run = ForceRun::new(scene)?;
        run.stop_at_exit = false;
        Ok(run)
    }

    pub fn beam(&self) -> &Beam {
        self.crossing.beam()
    }

    /// The fixed step (s) and the steps taken.
    pub fn steps(&self) -> (f64, u64) {
        (self.crossing.step_size(), self.steps)
    }

    /// Everything needed to continue the run bit-identically.
    pub fn state(&self) -> ForceState {
        let (u, v, a) = self.crossing.state();
        ForceState {
            steps: self.steps,
            time: self.crossing.time(),
            displacement: u.as_slice().to_vec(),
            velocity: v.as_slice().to_vec(),
            acceleration: a.as_slice().to_vec(),
        }
    }

    /// Whether `state` (which may be forged) fits this run: vectors of the
    /// beam's free DOFs, finite numbers, its time in its step.
    pub fn check_state(&self, state: &ForceState) -> Result<(), String> {
        let dofs = self.crossing.beam().free_dofs();
        let vectors = [
            ("displacement", &state.displacement),
            ("velocity", &state.velocity),
            ("acceleration", &state.acceleration),
        ];
        for (name, values) in vectors {
            if values.len() != dofs {
                return Err(format!(
                    "the state's {name} has {} values, the beam {dofs} free DOFs",
                    values.len()
                ));
            }
            if let Some(x) = values.iter().find(|x| !x.is_finite()) {
                return Err(format!(
                    "the state's {name} holds a non-finite number ({x})"
                ));
            }
        }
        // The crossing's time is a sum of steps: within half a step of
        // its count of them (rounding adds far less).
        let step = self.crossing.step_size();
        let grid = state.steps as f64 * step;
        if !(state.time >= 0.0 && (state.time - grid).abs() < 0.5 * step) {
            return Err(format!(
                "the state's time {} s is not that of its step {} of solver.step = {step} s",
                state.time, state.steps
            ));
        }
        Ok(())
    }

    /// Continue from `state`, refused (naming why) unless it fits.
    pub fn restore(&mut self, state: &ForceState) -> Result<(), String> {
        self.check_state(state)?;
        let vectors = (
            state.displacement.as_slice(),
            state.velocity.as_slice(),
            state.acceleration.as_slice(),
        );
        self.crossing.set_state(state.time, vectors);
        self.steps = state.steps;
        self.now = self.crossing.dynamics();
        Ok(())
    }

    /// The vehicles and their axles.
    pub fn vehicles(&self) -> &[ForceVehicle] {
        &self.vehicles
    }

    /// When the last force leaves the beam (s; infinite if one never does).
    pub fn exit_time(&self) -> f64 {
        self.crossing.exit_time()
    }

    /// The beam's state now, as the design outputs read it.
    pub fn beam_dynamics(&self) -> &BeamDynamics<'static> {
        &self.now
    }

    /// Each vehicle's first and last axle's entry and exit up to now, in
    /// time order (an axle on the beam at t = 0 has no entry).
    pub fn events(&self) -> Vec<AxleEvent> {
        let (length, now) = (self.beam().length, self.crossing.time());
        let mut events: Vec<AxleEvent> = self
            .vehicles
            .iter()
            .flat_map(|v| {
                let last = v.axles.len().saturating_sub(1);
                let ends = if last == 0 { vec![0] } else { vec![0, last] };
                ends.into_iter()
                    .map(move |k| (format!("{}.axle{}", v.name, k + 1), v.axles[k]))
            })
            .flat_map(|(name, axle)| {
                let (entry, exit) = crossing_times(axle, length);
                [("entry", entry), ("exit", exit)]
                    .into_iter()
                    .filter_map(move |(kind, time)| {
                        let axle = name.clone();
                        time.map(|time| AxleEvent { axle, kind, time })
                    })
            })
            .filter(|e| e.time <= now)
            .collect();
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
        events
    }
}

/// When `axle` enters a beam of `length` (None if it starts on it or never
/// reaches it) and leaves it (None if it never does).
pub fn crossing_times(axle: Axle, length: f64) -> (Option<f64>, Option<f64>) {
    let (near, far) = if axle.speed > 0.0 {
        (0.0, length)
    } else {
        (length, 0.0)
    };
    let at = |edge: f64| {
        let t = (edge - axle.position) / axle.speed;
        (t.is_finite() && t > 0.0).then_some(t)
    };
    let entry = at(near).filter(|_| !(0.0..=length).contains(&axle.position));
    (entry, at(far))
}

impl Steppable for ForceRun {
    fn time(&self) -> f64 {
        self.crossing.time()
    }

    fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }

    fn output_values(&self, values: &mut [f64]) {
        let (u, v, _) = self.crossing.state();
        let now = BeamNow {
            displacement: u,
            velocity: v,
            dynamics: Some(&self.now),
        };
        let probes = (self.sensors.as_slice(), self.sections.as_slice());
        let beam = self.crossing.beam();
        for (value, &q) in values.iter_mut().zip(&self.quantities) {
            *value = structure_value(beam, &now, probes, q).unwrap_or(f64::NAN);
        }
        if let Some(count) = values.get_mut(self.quantities.len()) {
            *count = self.crossing.point_loads().len() as f64;
        }
    }

    /// Whole steps of the crossing's fixed step until `t` (the last one may
    /// pass it, as the sweep's last step passes the exit); without an end
    /// time the run is over after the step in which the last force left.
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        let step = self.crossing.step_size();
        let target = (t / step - 1e-9).ceil();
        while (self.steps as f64) < target {
            if self.stop_at_exit && self.steps as f64 >= self.exit_steps {
                break;
            }
            self.crossing.step();
            self.steps += 1;
            let (u, v, a) = self.crossing.state();
            self.now
                .update((u, v, a), self.crossing.point_loads().iter().copied());
        }
        if self.stop_at_exit && self.steps as f64 >= self.exit_steps {
            return Ok(Advance::Exited {
                time: self.exit_time(),
            });
        }
        Ok(Advance::Reached)
    }
}
