//! Simulation: the state of beam and bodies, the fixed-step advance, the
//! events (contacts entering and leaving the beam, leaving the track) and
//! the output values.

use nalgebra::{DVector, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::assemble::{assemble, constant_forces};
use crate::contact::ContactForce;
use crate::integrate::{
    choose_integrator, contact_frames, contact_frames_at_bodies, loads, DynamicState,
};
use crate::iteration::{ContactIteration, IterationSettings, StepSolution};
use crate::outputs::{catalogue, Quantity};
use crate::scene::{Scene, StartKind};
use crate::static_start::static_start;
use crate::system::{System, TrackPart};

pub use crate::integrate::{rk4_step_limit, AUTO_MIN_DAMPING};
pub use crate::outputs::{OutputInfo, OutputKind};

/// Result of `advance_to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    /// The requested time was reached.
    Reached,
    /// The run is over at `time` (the last contact left the beam in a run
    /// without an end time, or a contact left the track); the state is the
    /// state at that instant.
    Exited { time: f64 },
}

/// A failure inside a step. The simulation is left at the start of the
/// failing internal step.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverError {
    pub time: f64,
    pub message: String,
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "at t = {} s: {}", self.time, self.message)
    }
}
impl std::error::Error for SolverError {}

/// What a driver needs of a simulation: `Simulation` itself, or anything that
/// steps like it (a test double). The CLI's run loop needs only this; the FMI
/// model layer extends it (`model::Dynamics`).
pub trait Steppable {
    fn time(&self) -> f64;
    /// The outputs, in a fixed order.
    fn outputs(&self) -> &[OutputInfo];
    /// Current output values, in the order of `outputs()`.
    fn output_values(&self, values: &mut [f64]);
    /// Advance to `t`; on error the state is that at the start of the
    /// failing internal step.
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError>;
}

impl Steppable for Simulation {
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn outputs(&self) -> &[OutputInfo] {
        Simulation::outputs(self)
    }
    fn output_values(&self, values: &mut [f64]) {
        Simulation::output_values(self, values)
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        Simulation::advance_to(self, t)
    }
}

/// What happened to a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// The contact point rolled onto the beam.
    Entry,
    /// The contact point left the beam (onto rigid ground, or off the track).
    Exit,
    /// The contact point left the track: the run ends.
    LeftTrack,
}

/// An event located inside a step (the step is shortened to its instant).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactEvent {
    pub contact: usize,
    pub time: f64,
    pub kind: EventKind,
}

/// Events kept per run; later ones are counted, not kept.
pub const MAX_EVENTS: usize = 10_000;

/// Everything needed to continue a run bit-identically.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimState {
    pub time: f64,
    /// Index of the last grid point k·Δt reached (the grid of `solver.step`).
    pub grid_step: u64,
    pub dynamic: DynamicState,
    /// Per contact: the converged force of the last steps, newest first.
    /// With `step_history` (the lengths of the steps between them) the
    /// history the next step's initial guess is extrapolated from.
    pub force_history: Vec<[ContactForce; 3]>,
    pub step_history: [f64; 2],
    /// The applied force on the driven body (the FMU's inputs).
    pub body_force: [f64; 2],
    pub external_work: f64,
    pub gravity_work: f64,
    pub initial_energy: f64,
    pub last_iterations: u32,
    pub last_position_iterations: u32,
    pub last_velocity_error: f64,
    pub last_gap_error: f64,
    pub steps: u64,
    pub total_iterations: u64,
    /// Where each contact is along the track.
    pub parts: Vec<TrackPart>,
    pub events: Vec<ContactEvent>,
    pub events_dropped: u64,
    /// When the run ended (see `Advance::Exited`).
    pub exit_time: Option<f64>,
    /// The additional load (fx, fy, moment) on each coupling point
    /// (`System::couplings`), held until changed (the FMU's inputs).
    #[serde(default)]
    pub coupling_loads: Vec<[f64; 3]>,
    /// The constant generalized force on each body over the last step
    /// taken (empty before the first): the accelerations reported at its
    /// end are those of the loads that acted, whatever was set since.
    #[serde(default)]
    pub last_applied: Vec<Vector3<f64>>,
}

impl SimState {
    /// Every number finite, the beam's vectors alike in length, and the
    /// time on the state's own grid of `step`: what a state from outside (a
    /// serialized FMU state) must satisfy before anything is sized by it.
    pub fn check_values(&self, step: f64) -> Result<(), String> {
        let d = &self.dynamic;
        let n = d.beam_displacement.len();
        let lengths = [
            d.beam_velocity.len(),
            d.beam_acceleration.len(),
            d.beam_load.len(),
        ];
        if lengths.iter().any(|&m| m != n) {
            return Err(format!(
                "the state's beam vectors differ in length ({n}, {lengths:?})"
            ));
        }
        let scalars = [
            self.time,
            self.external_work,
            self.gravity_work,
            self.initial_energy,
            self.last_velocity_error,
            self.last_gap_error,
            self.exit_time.unwrap_or(0.0),
            d.dissipated,
            d.beam_dissipated,
        ];
        let bodies = d.bodies.iter().flat_map(|b| {
            [
                b.position.x,
                b.position.y,
                b.velocity.x,
                b.velocity.y,
                b.angle,
                b.angular_velocity,
            ]
        });
        let forces = self
            .force_history
            .iter()
            .flatten()
            .flat_map(|f| [f.tangential, f.normal]);
        let generalized = d.body_accelerations.iter().chain(&d.body_loads).flatten();
        let beam = [
            &d.beam_displacement,
            &d.beam_velocity,
            &d.beam_acceleration,
            &d.beam_load,
        ];
        let mut all = scalars
            .into_iter()
            .chain(self.step_history)
            .chain(self.body_force)
            .chain(d.contact_x.iter().copied())
            .chain(self.events.iter().map(|e| e.time))
            .chain(bodies)
            .chain(forces)
            .chain(generalized.copied())
            .chain(beam.into_iter().flatten().copied());
        if let Some(x) = all.find(|x| !x.is_finite()) {
            return Err(format!("the state holds a non-finite number ({x})"));
        }
        let grid = self.grid_step as f64 * step;
        let slack = 1e-6 * step;
        if !(self.time >= 0.0 && grid - slack <= self.time && self.time <= grid + step + slack) {
            return Err(format!(
                "the state's time {} s is not in its step {} of solver.step = {step} s",
                self.time, self.grid_step
            ));
        }
        Ok(())
    }
}

/// Initial guess of the next step's contact force (procedure step 1):
/// quadratic extrapolation of the last three converged forces, at times
/// 0, −h₀, −h₀−h₁, to time `dt`.
fn extrapolate(history: &[ContactForce; 3], steps: &[f64; 2], dt: f64) -> ContactForce {
    let nodes = [0.0, -steps[0], -steps[0] - steps[1]];
    let mut guess = Vector2::zeros();
    for (i, force) in history.iter().enumerate() {
        let mut weight = 1.0;
        for (j, node) in nodes.iter().enumerate() {
            if i != j {
                weight *= (dt - node) / (nodes[i] - node);
            }
        }
        guess += weight * force.as_vector();
    }
    ContactForce::from_vector(guess)
}

pub struct Simulation {
    system: System,
    /// Which integrator runs, and why (for `auto`).
    integrator_choice: String,
    sensors: Vec<f64>,
    step: f64,
    /// Without an end time the run ends when the last contact leaves the
    /// beam (the paper's exit); with one it goes on to it.
    stop_at_beam_exit: bool,
    /// The first body of each vehicle and the constant force on it; the
    /// first is the driven body, whose force is `SimState::body_force`.
    vehicle_forces: Vec<(usize, [f64; 2])>,
    settings: IterationSettings,
    iteration: ContactIteration,
    state: SimState,
    scratch: DynamicState,
    outputs: Vec<OutputInfo>,
    quantities: Vec<Quantity>,
    /// Per-step buffers: the force guesses and the constant body forces.
    guess: Vec<ContactForce>,
    applied: Vec<Vector3<f64>>,
}

impl Simulation {
    /// Build the model a scene asks for. The scene must be valid.
    pub fn new(scene: &Scene) -> Result<Simulation, String> {
        Simulation::build(scene, false)
    }

    /// The model of `scene` for a co-simulation: the end of the structure
    /// is an event, not the end of the run. A contact that leaves the track
    /// (past the run-off, or past the beam's end where there is none) goes
    /// on over level ground beyond it, which the structure no longer feels,
    /// and the run goes on to any time asked for.
    pub fn new_open_ended(scene: &Scene) -> Result<Simulation, String> {
        Simulation::build(scene, true)
    }

    fn build(scene: &Scene, open_ends: bool) -> Result<Simulation, String> {
        let mut assembly = assemble(scene)?;
        assembly.system.track.open_ends = open_ends;
        let step = scene.solver.step;
        let body_force = [scene.body.force_x, scene.body.force_y];
        let mut vehicle_forces = assembly.vehicle_forces;
        vehicle_forces[0].1 = body_force;
        let applied: Vec<Vector3<f64>> =
            constant_forces(&assembly.system, &vehicle_forces).collect();
        let u = match scene.solver.start {
            StartKind::Rest => DVector::zeros(assembly.system.beam.free_dofs()),
            StartKind::Static => static_start(
                &mut assembly.system,
                &mut assembly.bodies,
                &mut assembly.forces,
                &applied,
            )?,
        };
        let system = assembly.system;
        let (integrator, integrator_choice) = choose_integrator(&system, &scene.solver)?;
        let dynamic = initial_state(&system, u, &assembly.bodies, &assembly.forces, &applied)?;
        let sensor_names: Vec<String> = scene.sensors.iter().map(|s| s.name.clone()).collect();
        let (outputs, quantities) = catalogue(&system, &sensor_names).into_iter().unzip();
        let parts = dynamic
            .contact_x
            .iter()
            .map(|&x| system.track_part(x))
            .collect();
        let mut simulation = Simulation {
            sensors: scene.sensors.iter().map(|s| s.position).collect(),
            step,
            stop_at_beam_exit: scene.solver.end_time.is_none(),
            vehicle_forces,
            settings: IterationSettings {
                velocity_tolerance: scene.solver.velocity_tolerance,
                gap_tolerance: scene.solver.gap_tolerance,
                max_iterations: scene.solver.max_iterations,
            },
            iteration: ContactIteration::new(integrator, &system, step),
            integrator_choice,
            scratch: dynamic.clone(),
            state: SimState {
                time: 0.0,
                grid_step: 0,
                dynamic,
                force_history: assembly.forces.iter().map(|&f| [f; 3]).collect(),
                step_history: [step; 2],
                body_force,
                external_work: 0.0,
                gravity_work: 0.0,
                initial_energy: 0.0,
                last_iterations: 0,
                last_position_iterations: 0,
                last_velocity_error: 0.0,
                last_gap_error: 0.0,
                steps: 0,
                total_iterations: 0,
                parts,
                events: Vec::new(),
                events_dropped: 0,
                exit_time: None,
                coupling_loads: vec![[0.0; 3]; system.couplings.len()],
                last_applied: Vec::new(),
            },
            system,
            outputs,
            quantities,
            guess: Vec::new(),
            applied: Vec::new(),
        };
        simulation.state.initial_energy = simulation.energy_balance();
        Ok(simulation)
    }

    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The integrator that runs, in words (`auto` says what it picked and why).
    pub fn integrator_choice(&self) -> &str {
        &self.integrator_choice
    }

    /// The outputs this scene has, in a fixed order.
    pub fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }

    /// The assembled system (bodies, force elements, contacts, beam).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Current output values, in the order of `outputs()`.
    pub fn output_values(&self, values: &mut [f64]) {
        crate::outputs::values(self, &self.quantities, values);
    }

    /// Kinetic + strain + spring energy + energy dissipated (dampers and
    /// structural damping) − work of
    /// gravity and of the applied force (J).
    pub fn energy_balance(&self) -> f64 {
        let d = &self.state.dynamic;
        let s = &self.system;
        self.body_kinetic_energy()
            + s.beam.kinetic_energy(&d.beam_velocity)
            + s.beam.strain_energy(&d.beam_displacement)
            + s.spring_energy(&d.bodies)
            + d.dissipated
            + d.beam_dissipated
            - self.state.gravity_work
            - self.state.external_work
    }

    pub fn body_kinetic_energy(&self) -> f64 {
        let d = &self.state.dynamic;
        self.system
            .bodies
            .iter()
            .zip(&d.bodies)
            .map(|(body, state)| body.kinetic_energy(state))
            .sum()
    }

    /// Total energy at t = 0 (J), the reference of relative energy drift.
    pub fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }

    /// Set the applied force on the driven body's centre (N), held until changed.
    pub fn set_body_force(&mut self, fx: f64, fy: f64) {
        self.state.body_force = [fx, fy];
        self.vehicle_forces[0].1 = [fx, fy];
    }

    /// Set the additional loads (fx, fy in N, moment in N m) on the
    /// coupling points, one per `System::couplings` entry (extra entries are
    /// ignored, missing ones left as they were), held until changed.
    pub fn set_coupling_loads(&mut self, loads: &[[f64; 3]]) {
        for (held, load) in self.state.coupling_loads.iter_mut().zip(loads) {
            *held = *load;
        }
    }

    /// The fixed internal step (s).
    pub fn step_size(&self) -> f64 {
        self.step
    }

    /// Steps taken and contact iterations spent so far.
    pub fn counters(&self) -> (u64, u64) {
        (self.state.steps, self.state.total_iterations)
    }

    /// When the run ended (see `Advance::Exited`).
    pub fn exit_time(&self) -> Option<f64> {
        self.state.exit_time
    }

    /// The contacts' entries onto and exits from the beam so far.
    pub fn events(&self) -> &[ContactEvent] {
        &self.state.events
    }

    pub fn state(&self) -> SimState {
        self.state.clone()
    }

    /// The current state (for the output catalogue).
    pub(crate) fn current(&self) -> &SimState {
        &self.state
    }

    pub(crate) fn sensor_positions(&self) -> &[f64] {
        &self.sensors
    }

    /// Restore a state from `state()`; refused unless it has this model's
    /// shape (beam DOFs, bodies, contacts).
    pub fn restore(&mut self, state: &SimState) -> Result<(), String> {
        check_shape(&self.system, state)?;
        self.state = state.clone();
        self.vehicle_forces[0].1 = state.body_force;
        Ok(())
    }

    /// The constant generalized force on each body now.
    fn constant_forces(&self) -> Vec<Vector3<f64>> {
        self.constant_forces_iter().collect()
    }

    fn constant_forces_iter(&self) -> impl Iterator<Item = Vector3<f64>> + '_ {
        let couplings = &self.system.couplings;
        let loads = &self.state.coupling_loads;
        constant_forces(&self.system, &self.vehicle_forces)
            .enumerate()
            .map(move |(b, force)| {
                couplings
                    .iter()
                    .zip(loads)
                    .filter(|(&c, _)| c == b)
                    .fold(force, |f, (_, l)| f + Vector3::new(l[0], l[1], l[2]))
            })
    }

    /// Each body's (ẍ, ÿ, θ̈) in the current state under the last forces.
    pub fn body_accelerations(&self) -> Vec<Vector3<f64>> {
        let d = &self.state.dynamic;
        let mut frames = Vec::new();
        let mut beam_load = DVector::zeros(d.beam_displacement.len());
        let mut body_loads = vec![Vector3::zeros(); self.system.bodies.len()];
        let forces: Vec<ContactForce> = self.state.force_history.iter().map(|h| h[0]).collect();
        let applied = match self.state.last_applied.len() {
            0 => self.constant_forces(),
            _ => self.state.last_applied.clone(),
        };
        let ok = contact_frames(
            &self.system,
            &d.beam_displacement,
            &d.bodies,
            (&d.contact_x, &self.state.parts),
            &mut frames,
        );
        if ok.is_err() {
            return vec![Vector3::repeat(f64::NAN); self.system.bodies.len()];
        }
        let (s, bodies) = (&self.system, &d.bodies);
        loads(
            s,
            &frames,
            &forces,
            &applied,
            bodies,
            &mut beam_load,
            &mut body_loads,
        );
        s.bodies
            .iter()
            .zip(&body_loads)
            .map(|(body, load)| body.acceleration(load))
            .collect()
    }

    /// Advance to `target` with internal steps on the grid k·`solver.step`,
    /// the last one shortened to land on `target`; steps are also shortened
    /// to land on events. Stops early when the run is over.
    pub fn advance_to(&mut self, target: f64) -> Result<Advance, SolverError> {
        let tolerance = 1e-9 * self.step;
        loop {
            if let Some(time) = self.state.exit_time {
                return Ok(Advance::Exited { time });
            }
            if self.state.time >= target - tolerance {
                return Ok(Advance::Reached);
            }
            let next_grid = (self.state.grid_step + 1) as f64 * self.step;
            let to = if next_grid <= target + tolerance {
                next_grid
            } else {
                target
            };
            let reached = self.step_to(to)?;
            // An event within round-off of `to` counts as reaching it: the
            // step left over would be empty.
            if !reached && to - self.state.time <= tolerance {
                self.state.time = to;
            }
            if to == next_grid && self.state.time == to {
                self.state.grid_step += 1;
            }
        }
    }

    /// One step from the current time to `to`, or to the first event inside
    /// it. Returns whether it reached `to`.
    fn step_to(&mut self, to: f64) -> Result<bool, SolverError> {
        let dt = to - self.state.time;
        let s = &self.state;
        let mut guess = std::mem::take(&mut self.guess);
        guess.clear();
        guess.extend(
            s.force_history
                .iter()
                .map(|h| extrapolate(h, &s.step_history, dt)),
        );
        let solution = self.solve(&guess, dt);
        self.guess = guess;
        let solution = solution?;
        self.refuse_lift_off(&solution)?;
        let (solution, dt, event) = match self.first_event() {
            None => (solution, dt, None),
            Some((contact, edge, part)) => {
                let (solution, dt) = self.locate_event(contact, edge, &solution.forces, dt)?;
                (solution, dt, Some((contact, part)))
            }
        };
        self.accept(solution, dt);
        if let Some((contact, part)) = event {
            self.record_events(contact, part);
            Ok(false)
        } else {
            self.state.time = to;
            Ok(true)
        }
    }

    fn refuse_lift_off(&self, solution: &StepSolution) -> Result<(), SolverError> {
        for (c, force) in solution.forces.iter().enumerate() {
            // Beyond the end of an open-ended track the body has left the
            // model: the level ground there only keeps its motion defined
            // and holds it both ways.
            let left_model =
                self.system.track.open_ends && self.state.parts[c] == TrackPart::Beyond;
            if force.normal < 0.0 && !left_model {
                // The contact is bilateral: a tensile normal force means the
                // body would leave the surface, which this model does not follow.
                let which = if solution.forces.len() > 1 {
                    format!(" of {}", self.system.contacts[c].name)
                } else {
                    String::new()
                };
                return Err(SolverError {
                    time: self.state.time,
                    message: format!(
                        "lift-off: the normal contact force{which} would become tensile \
                         ({:.6e} N) in the step from t = {} s at x = {:.6} m; the contact is \
                         bilateral, so the run stops at the last step with compression",
                        force.normal, self.state.time, self.scratch.contact_x[c]
                    ),
                });
            }
        }
        Ok(())
    }

    /// The contact whose crossing of a track boundary comes first in the
    /// step just solved (into `scratch`), the boundary's abscissa and the
    /// part beyond it.
    fn first_event(&self) -> Option<(usize, f64, TrackPart)> {
        let (start, end) = (&self.state.dynamic.contact_x, &self.scratch.contact_x);
        let mut first: Option<(f64, usize, f64, TrackPart)> = None;
        for c in 0..start.len() {
            let from = self.state.parts[c];
            let Some(right) = self.system.leaves(from, start[c], end[c]) else {
                continue;
            };
            let (edge, part) = self.system.next_part(from, right);
            // Linear estimate of when in the step the edge is crossed.
            let fraction = ((edge - start[c]) / (end[c] - start[c])).clamp(0.0, 1.0);
            if first.is_none_or(|(f, ..)| fraction < f) {
                first = Some((fraction, c, edge, part));
            }
        }
        first.map(|(_, c, edge, part)| (c, edge, part))
    }

    /// Take the step solved into `scratch`.
    fn accept(&mut self, solution: StepSolution, dt: f64) {
        let s = &mut self.state;
        for &(b, force) in &self.vehicle_forces {
            let moved = self.scratch.bodies[b].position - s.dynamic.bodies[b].position;
            s.external_work += Vector2::new(force[0], force[1]).dot(&moved);
        }
        for (b, (old, new)) in s
            .dynamic
            .bodies
            .iter()
            .zip(&self.scratch.bodies)
            .enumerate()
        {
            let moved = new.position - old.position;
            let weight = -self.system.bodies[b].mass * self.system.gravity;
            s.gravity_work += weight * moved.y;
        }
        for (&b, load) in self.system.couplings.iter().zip(&s.coupling_loads) {
            let (old, new) = (&s.dynamic.bodies[b], &self.scratch.bodies[b]);
            let moved = new.position - old.position;
            s.external_work +=
                load[0] * moved.x + load[1] * moved.y + load[2] * (new.angle - old.angle);
        }
        s.last_applied.clone_from(&self.applied);
        std::mem::swap(&mut s.dynamic, &mut self.scratch);
        for (history, force) in s.force_history.iter_mut().zip(&solution.forces) {
            *history = [*force, history[0], history[1]];
        }
        s.step_history = [dt, s.step_history[0]];
        s.time += dt;
        s.last_iterations = solution.iterations;
        s.last_position_iterations = solution.position_iterations;
        s.last_velocity_error = solution.velocity_error;
        s.last_gap_error = solution.gap_error;
        s.steps += 1;
        s.total_iterations += solution.iterations as u64;
    }

    /// Record the events of the step just taken, which ends where contact
    /// `located` reaches `part`, and end the run if it is over.
    fn record_events(&mut self, located: usize, part: TrackPart) {
        let s = &mut self.state;
        // `accept` swapped the step's start state into `scratch`.
        let starts = &self.scratch.contact_x;
        for (c, &x) in s.dynamic.contact_x.iter().enumerate() {
            let from = s.parts[c];
            // The located contact sits on its edge to round-off: take the
            // side it was moving to.
            let to = if c == located {
                part
            } else {
                match self.system.leaves(from, starts[c], x) {
                    Some(right) => self.system.next_part(from, right).1,
                    None => continue,
                }
            };
            s.parts[c] = to;
            let kind = match (from, to) {
                (_, TrackPart::Beyond) => EventKind::LeftTrack,
                (_, TrackPart::Beam) => EventKind::Entry,
                _ => EventKind::Exit,
            };
            let mut push = |kind| {
                if s.events.len() < MAX_EVENTS {
                    s.events.push(ContactEvent {
                        contact: c,
                        time: s.time,
                        kind,
                    });
                } else {
                    s.events_dropped += 1;
                }
            };
            if from == TrackPart::Beam && kind == EventKind::LeftTrack {
                push(EventKind::Exit);
            }
            push(kind);
        }
        let left_track = s.parts.contains(&TrackPart::Beyond);
        let all_left_beam = !s.parts.contains(&TrackPart::Beam)
            && (0..s.parts.len()).all(|c| {
                s.events
                    .iter()
                    .any(|e| e.contact == c && e.kind == EventKind::Exit)
            });
        let run_over = left_track || (self.stop_at_beam_exit && all_left_beam);
        if run_over && !self.system.track.open_ends {
            s.exit_time = Some(s.time);
        }
    }

    fn solve(&mut self, guess: &[ContactForce], dt: f64) -> Result<StepSolution, SolverError> {
        let mut applied = std::mem::take(&mut self.applied);
        applied.clear();
        applied.extend(self.constant_forces_iter());
        let solution = self.solve_with(guess, &applied, dt);
        self.applied = applied;
        solution
    }

    fn solve_with(
        &mut self,
        guess: &[ContactForce],
        applied: &[Vector3<f64>],
        dt: f64,
    ) -> Result<StepSolution, SolverError> {
        let s = &self.state;
        let solution = self
            .iteration
            .solve(
                &self.system,
                &s.dynamic,
                &s.parts,
                guess,
                applied,
                dt,
                &self.settings,
                &mut self.scratch,
            )
            .map_err(|e| SolverError {
                time: s.time,
                message: e.to_string(),
            })?;
        if !self.scratch.beam_displacement.iter().all(|x| x.is_finite()) {
            return Err(SolverError {
                time: s.time,
                message: "the beam state became non-finite".into(),
            });
        }
        Ok(solution)
    }

    /// Shorten the step so that contact `contact` lands on `edge` (regula
    /// falsi on the step length, Illinois variant). Leaves the state at
    /// that instant in `scratch`.
    fn locate_event(
        &mut self,
        contact: usize,
        edge: f64,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64), SolverError> {
        let start_x = self.state.dynamic.contact_x[contact];
        let (mut lo, mut f_lo) = (0.0, start_x - edge);
        let (mut hi, mut f_hi) = (dt, self.scratch.contact_x[contact] - edge);
        let mut side = 0;
        let scale = self.system.beam.length;
        for _ in 0..60 {
            let tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let solution = self.solve(forces, tau)?;
            let f = self.scratch.contact_x[contact] - edge;
            if f.abs() <= 1e-12 * scale || (hi - lo) <= 1e-15 * dt {
                return Ok((solution, tau));
            }
            if (f > 0.0) == (f_hi > 0.0) {
                hi = tau;
                f_hi = f;
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            } else {
                lo = tau;
                f_lo = f;
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            }
        }
        Err(SolverError {
            time: self.state.time,
            message: format!(
                "the instant {} reaches x = {edge} m could not be located",
                self.system.contacts[contact].name
            ),
        })
    }
}

/// The dynamic state at t = 0: at rest on the beam deflected by `u` (zero
/// or the static deflection), with loads and accelerations consistent with
/// the initial contact forces (the implicit scheme starts from them).
fn initial_state(
    system: &System,
    u: DVector<f64>,
    bodies: &[crate::body::BodyState],
    forces: &[ContactForce],
    applied: &[Vector3<f64>],
) -> Result<DynamicState, String> {
    let n = system.beam.free_dofs();
    let mut frames = Vec::new();
    contact_frames_at_bodies(system, &u, bodies, &mut frames).map_err(|e| match e {
        crate::integrate::IntegrationError::LostContact { x, .. } => {
            format!("no contact point at the start (x = {x})")
        }
    })?;
    let mut beam_load = DVector::zeros(n);
    let mut body_loads = vec![Vector3::zeros(); bodies.len()];
    loads(
        system,
        &frames,
        forces,
        applied,
        bodies,
        &mut beam_load,
        &mut body_loads,
    );
    let mut beam_acceleration = DVector::zeros(n);
    // The start is at rest: the beam's velocity is zero.
    let at_rest = DVector::zeros(n);
    system
        .beam
        .accelerations((&u, &at_rest), &beam_load, &mut beam_acceleration);
    let body_accelerations = system
        .bodies
        .iter()
        .zip(&body_loads)
        .map(|(body, load)| body.acceleration(load))
        .collect();
    Ok(DynamicState {
        beam_displacement: u,
        beam_velocity: DVector::zeros(n),
        beam_acceleration,
        body_accelerations,
        beam_load,
        body_loads,
        bodies: bodies.to_vec(),
        contact_x: frames.iter().map(|f| f.x).collect(),
        dissipated: 0.0,
        beam_dissipated: 0.0,
    })
}

/// Refuse a state whose vectors do not fit `system` (a state is untrusted
/// input: it may come from another model or be corrupted).
fn check_shape(system: &System, state: &SimState) -> Result<(), String> {
    let d = &state.dynamic;
    let n = system.beam.free_dofs();
    let (bodies, contacts) = (system.bodies.len(), system.contacts.len());
    let checks = [
        ("beam DOFs (displacement)", d.beam_displacement.len(), n),
        ("beam DOFs (velocity)", d.beam_velocity.len(), n),
        ("beam DOFs (acceleration)", d.beam_acceleration.len(), n),
        ("beam DOFs (load)", d.beam_load.len(), n),
        ("bodies", d.bodies.len(), bodies),
        ("body accelerations", d.body_accelerations.len(), bodies),
        ("body loads", d.body_loads.len(), bodies),
        ("contact positions", d.contact_x.len(), contacts),
        (
            "contact force histories",
            state.force_history.len(),
            contacts,
        ),
        ("contact track parts", state.parts.len(), contacts),
        (
            "coupling loads",
            state.coupling_loads.len(),
            system.couplings.len(),
        ),
    ];
    if !(state.last_applied.is_empty() || state.last_applied.len() == bodies) {
        return Err(format!(
            "the state has {} last applied forces but this model has {bodies} bodies",
            state.last_applied.len()
        ));
    }
    let loads = state.coupling_loads.iter().flatten();
    let applied = state.last_applied.iter().flat_map(|v| v.iter());
    if !loads.chain(applied).all(|x| x.is_finite()) {
        return Err("the state has a load that is not finite".into());
    }
    for (what, found, expected) in checks {
        if found != expected {
            return Err(format!(
                "the state has {found} {what} but this model has {expected}"
            ));
        }
    }
    if state.events.len() > MAX_EVENTS || state.events.iter().any(|e| e.contact >= contacts) {
        return Err("the state's event list does not fit this model".into());
    }
    Ok(())
}
