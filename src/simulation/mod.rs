//! Simulation: the state of beam and bodies, the fixed-step advance, the
//! events (contacts entering and leaving the beam, leaving the track) and
//! the output values.

use nalgebra::{DVector, Vector2, Vector3};

use crate::assemble::{assemble, constant_forces};
use crate::contact::ContactForce;
use crate::integrate::{
    choose_integrator, contact_frames, contact_frames_at_bodies, force_shape, loads, DynamicState,
    ForceShape,
};
use crate::iteration::{ContactIteration, StepSolution};
use crate::outputs::{catalogue, derived, evaluate, Probes, Quantity};
use crate::scene::{ForceProfile, Scene, SpeedSpec, StartKind};
use crate::solver::parameters::SolverParameters;
use crate::static_start::{place_on_profile, static_start};
use crate::system::{System, TrackPart};

mod follower;
mod lift_off;
pub mod run_end;
mod switch;

pub use crate::integrate::{rk4_step_limit, AUTO_MIN_DAMPING};
pub use crate::outputs::{OutputInfo, OutputKind};
use crate::state::{check_shape, push_event};
pub use crate::state::{ContactEvent, ContactStatus, EventKind, SimState, MAX_EVENTS};

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

/// Impacts slower than this (m/s) are plastic whatever the restitution: a
/// bouncing contact comes to rest after finitely many bounces (e^k v₀ <
/// `RESTING_SPEED`) instead of an endless sequence of ever shorter flights.
/// A contact bounces at most once per grid step (a second landing in it is
/// plastic). Under HHT-α it also opens at most once per grid step (it then
/// stays closed to the grid point), so it has at most three events per
/// grid step and a run takes at most (1 + 3 × contacts) steps per grid
/// step plus its track events (and three start-up steps with a shaped
/// force profile, `START_UP_DIVISIONS`). Under RK4 a contact that would
/// pull opens again, at most `max_reopenings` times per grid step over all
/// contacts (`Simulation::count_reopening`), past which the run stops.
pub const RESTING_SPEED: f64 = SolverParameters::DEFAULT.resting_speed;

/// A contact's impact on the far corner of a rail gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointImpact {
    /// When it ended (s).
    pub time: f64,
    pub contact: usize,
    /// Tangential and normal impulse on the body in the new corner's
    /// frame (N s).
    pub impulse: Vector2<f64>,
}

/// Largest sum of |weights| an extrapolation of the force history may
/// have: it bounds how much the history's differences are magnified. With
/// equal steps the quadratic one has 7; after a step much shorter than the
/// next (an event located just after a grid point) it grows as dt² over
/// the short step's length, and a guess of 1e11 N threw the bodies off
/// the track before the first correction.
const MAX_EXTRAPOLATION_GAIN: f64 = SolverParameters::DEFAULT.max_extrapolation_gain;

/// Initial guess of the next step's contact force (procedure step 1):
/// quadratic extrapolation of the last three converged forces, at times
/// 0, −h₀, −h₀−h₁, to time `dt`; linear, or the last force, where the
/// higher order would magnify the history by more than
/// `MAX_EXTRAPOLATION_GAIN`.
fn extrapolate(history: &[ContactForce; 3], steps: &[f64; 2], dt: f64) -> ContactForce {
    let nodes = [0.0, -steps[0], -steps[0] - steps[1]];
    for order in [2, 1] {
        let mut weights = [0.0; 3];
        for (i, weight) in weights.iter_mut().enumerate().take(order + 1) {
            *weight = 1.0;
            for (j, node) in nodes.iter().enumerate().take(order + 1) {
                if i != j {
                    *weight *= (dt - node) / (nodes[i] - node);
                }
            }
        }
        let gain: f64 = weights.iter().map(|w| w.abs()).sum();
        if gain <= MAX_EXTRAPOLATION_GAIN {
            let mut guess = Vector2::zeros();
            for (weight, force) in weights.iter().zip(history).take(order + 1) {
                guess += *weight * force.as_vector();
            }
            return ContactForce::from_vector(guess);
        }
    }
    history[0]
}

pub struct Simulation {
    system: System,
    /// The static envelope's loads, taken before the static start moves
    /// the bodies (`design::static_shares`).
    envelope_loads: Vec<(f64, f64)>,
    /// Which integrator runs, and why (for `auto`).
    integrator_choice: String,
    sensors: Vec<f64>,
    /// Abscissae of the sections whose moment and shear are outputs.
    sections: Vec<f64>,
    /// Without an end time the run ends when the last contact leaves the
    /// beam (the paper's exit); with one it goes on to it.
    stop_at_beam_exit: bool,
    /// The first body of each vehicle and the constant force on it; the
    /// first is the driven body, whose force is `SimState::body_force`.
    vehicle_forces: Vec<(usize, [f64; 2])>,
    /// The bodies driven at a prescribed speed, and their speeds.
    drives: Vec<(usize, SpeedSpec)>,
    /// Every tolerance, cap and ratio of the run (`solver::parameters`).
    params: SolverParameters,
    /// The contact force's shape within a step, and its per-step buffer.
    force_profile: ForceProfile,
    shapes: Vec<ForceShape>,
    iteration: ContactIteration,
    state: SimState,
    scratch: DynamicState,
    outputs: Vec<OutputInfo>,
    quantities: Vec<Quantity>,
    /// The outputs computed when a sink reads only some (`read_only`).
    read: Option<crate::output_mask::OutputMask>,
    /// A step was solved without the energy bookkeeping (no sink read it):
    /// the energy totals no longer hold, and are reported as NaN.
    unbooked: bool,
    /// Per-step buffers: the force guesses and the constant body forces.
    guess: Vec<ContactForce>,
    applied: Vec<Vector3<f64>>,
    /// Per contact: its vehicle's coefficient of restitution.
    restitution: Vec<f64>,
    /// The step's active set: which contacts are open in it, and which of
    /// them opened in it.
    open: Vec<bool>,
    opened: Vec<bool>,
    /// The grid step and how many contacts reopened in it (RK4; bounded
    /// by `max_reopenings`; a record of the run, not of its state).
    reopenings: (u64, usize),
    /// Impacts at rail gaps (not part of the state: a record of the run).
    joint_impacts: Vec<JointImpact>,
    /// Where the integrator carries accelerations from step to step
    /// (HHT-α), it restarts where a contact switches surfaces; the weight
    /// (1 + α) γ of a step's end acceleration in its mean.
    restart_weight: Option<f64>,
}

/// Every body of each vehicle at a prescribed speed, and its speed: a
/// vehicle's bodies run from its first body (`vehicle_forces`) to the next
/// vehicle's.
fn driven_bodies(
    scene: &Scene,
    vehicle_forces: &[(usize, [f64; 2])],
    bodies: usize,
) -> Vec<(usize, SpeedSpec)> {
    let firsts: Vec<usize> = vehicle_forces.iter().map(|&(b, _)| b).collect();
    let ends = firsts.iter().skip(1).copied().chain([bodies]);
    scene
        .every_vehicle()
        .zip(firsts.iter().zip(ends))
        .filter_map(|(spec, (&first, end))| Some((spec.prescribed_speed.clone()?, first..end)))
        .flat_map(|(speed, range)| range.map(move |b| (b, speed.clone())))
        .collect()
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
        let envelope_loads = crate::design::static_shares(&assembly);
        assembly.system.track.open_ends = open_ends;
        let step = scene.solver.step;
        let body_force = [scene.body.force_x, scene.body.force_y];
        let mut vehicle_forces = assembly.vehicle_forces;
        let drives = driven_bodies(scene, &vehicle_forces, assembly.system.bodies.len());
        vehicle_forces[0].1 = body_force;
        let applied: Vec<Vector3<f64>> =
            constant_forces(&assembly.system, &vehicle_forces).collect();
        let u = match scene.solver.start {
            StartKind::Rest if assembly.system.profile.is_some() => {
                let u = DVector::zeros(assembly.system.beam.coordinates());
                place_on_profile(&mut assembly.system, &mut assembly.bodies, &u)?;
                u
            }
            StartKind::Rest => DVector::zeros(assembly.system.beam.coordinates()),
            StartKind::Static => static_start(
                &mut assembly.system,
                &mut assembly.bodies,
                &mut assembly.forces,
                &applied,
            )?,
        };
        let system = assembly.system;
        let (integrator, integrator_choice) = choose_integrator(&system, &scene.solver)?;
        let restart_weight = integrator
            .carries_step_end()
            .then(|| integrator.body_weights(1.0).0);
        let dynamic = initial_state(&system, u, &assembly.bodies, &assembly.forces, &applied)?;
        let sensor_names: Vec<String> = scene.sensors.iter().map(|s| s.name.clone()).collect();
        let section_names: Vec<String> = scene.sections.iter().map(|s| s.name.clone()).collect();
        let (outputs, quantities) =
            catalogue(&system, &sensor_names, &section_names, scene.reactions)
                .into_iter()
                .unzip();
        let parts: Vec<TrackPart> = dynamic
            .contact_x
            .iter()
            .map(|&x| system.track_part(x))
            .collect();
        let contacts = initial_contacts(&system, &dynamic, &parts, &assembly.open)?;
        let mut simulation = Simulation {
            sensors: scene.sensors.iter().map(|s| s.position).collect(),
            envelope_loads,
            sections: scene.sections.iter().map(|s| s.position).collect(),
            stop_at_beam_exit: scene.solver.end_time.is_none(),
            vehicle_forces,
            drives,
            params: crate::build::solver_parameters(&scene.solver),
            iteration: ContactIteration::new(integrator, &system, step),
            force_profile: scene.solver.force_profile,
            shapes: Vec::new(),
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
                contacts,
                impact_loss: 0.0,
                coupling_loads: vec![[0.0; 3]; system.couplings.len()],
                last_applied: Vec::new(),
                pending_restart: Vec::new(),
            },
            system,
            outputs,
            quantities,
            read: None,
            unbooked: false,
            guess: Vec::new(),
            applied: Vec::new(),
            open: assembly.open.clone(),
            opened: vec![false; assembly.open.len()],
            reopenings: (0, 0),
            restitution: assembly.restitution,
            joint_impacts: Vec::new(),
            restart_weight,
        };
        simulation.state.initial_energy = simulation.energy_balance();
        Ok(simulation)
    }

    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The integrator that runs, in words (`auto` says what it picked and why).
    /// The contact force's shape within a step.
    pub fn force_profile(&self) -> ForceProfile {
        self.force_profile
    }

    pub fn integrator_choice(&self) -> &str {
        &self.integrator_choice
    }

    /// The outputs this scene has, in a fixed order.
    pub fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }

    /// The assembled system (bodies, force elements, contacts, beam).
    /// The static envelope of `scene` (the summary's amplification
    /// reference) on this simulation's beam: assembling the scene again
    /// would solve a modal beam's eigenproblem a second time.
    pub fn static_envelope(&self, scene: &Scene) -> Result<crate::design::StaticEnvelope, String> {
        if crate::moving_load::is_moving_force_scene(scene) {
            return crate::design::static_envelope(scene);
        }
        crate::design::envelope_of_loads(scene, &self.system.beam, &self.envelope_loads)
    }

    pub fn system(&self) -> &System {
        &self.system
    }

    /// Current output values, in the order of `outputs()`.
    pub fn output_values(&self, values: &mut [f64]) {
        let probes = self.probes();
        match &self.read {
            None => evaluate(&self.system, &self.state, &probes, &self.quantities, values),
            Some(mask) => mask.values(&self.system, &self.state, &probes, values),
        }
    }

    /// Compute only the outputs whose flag in `read` is set (those a sink
    /// reads); the others are reported as 0. `None`: all of them.
    /// Where no read output needs the energy the steps remove (the
    /// dissipated energies and the balance), it is not booked.
    pub fn read_only(&mut self, read: Option<&[bool]>) {
        self.read = read.map(|r| crate::output_mask::OutputMask::new(&self.quantities, r));
        let books = self.read.as_ref().is_none_or(|m| m.reads_energy_books());
        self.iteration.integrator_mut().keep_energy_books(books);
    }

    /// `total`, one of the energy totals the steps book, or NaN where a
    /// step was solved without the bookkeeping (see `read_only`).
    pub fn booked(&self, total: f64) -> f64 {
        if self.unbooked {
            f64::NAN
        } else {
            total
        }
    }

    /// Potential energy of the force elements and of the followers'
    /// suspensions (at their gaps at the end of the last step) (J).
    pub fn spring_energy(&self) -> f64 {
        crate::energy::spring(&self.system, &self.state)
    }

    /// Kinetic + strain + spring energy + energy dissipated (dampers,
    /// structural damping, impacts and HHT-α's numerical damping) − work of
    /// gravity and of the applied force (J).
    pub fn energy_balance(&self) -> f64 {
        self.energy_balance_with(self.spring_energy())
    }

    /// `energy_balance` with `spring_energy` already known (the outputs
    /// report both: one sweep over the force elements, not two).
    pub fn energy_balance_with(&self, spring_energy: f64) -> f64 {
        self.booked(crate::energy::balance_with(
            &self.system,
            &self.state,
            spring_energy,
        ))
    }

    pub fn body_kinetic_energy(&self) -> f64 {
        crate::energy::body_kinetic(&self.system, &self.state)
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
    ///
    /// Before the first step the rigid contacts of each coupled body carry
    /// its load, as they carry `body.force_y` (`build::assemble`), so that
    /// the start balances its inputs whenever a master sets them (before,
    /// in or after initialization: masters differ). Without it a coupled
    /// body at rest read its load over its own mass as its acceleration at
    /// t = 0 (−10 g for a car on a glider of a tenth of its mass).
    pub fn set_coupling_loads(&mut self, loads: &[[f64; 3]]) {
        let at_start = self.state.steps == 0;
        for (k, load) in loads
            .iter()
            .enumerate()
            .take(self.state.coupling_loads.len())
        {
            let change = load[1] - self.state.coupling_loads[k][1];
            self.state.coupling_loads[k] = *load;
            if at_start && change != 0.0 {
                self.carry_at_start(self.system.couplings[k], change);
            }
        }
    }

    /// Shift the start's normal forces of `body`'s closed rigid contacts by
    /// their share of a vertical load change `change_y` (positive up).
    fn carry_at_start(&mut self, body: usize, change_y: f64) {
        let carrying: Vec<usize> = (self.system.contacts.iter().enumerate())
            .filter(|(c, contact)| {
                contact.body == body && contact.follower.is_none() && !self.state.contacts[*c].open
            })
            .map(|(c, _)| c)
            .collect();
        let share = change_y / carrying.len().max(1) as f64;
        for c in carrying {
            let mut force = self.state.force_history[c][0];
            force.normal = (force.normal - share).max(0.0);
            self.state.force_history[c] = [force; 3];
        }
    }

    /// The fixed internal step (s).
    pub fn step_size(&self) -> f64 {
        self.params.step
    }

    /// The most the contact iteration's unit-load response cache held at
    /// once (issue 29: linear in the elements).
    pub fn response_cache_peak(&self) -> crate::iteration::Footprint {
        self.iteration.response_cache_peak()
    }

    /// What the contact operators cost so far: whole-beam solves for
    /// responses, and the condensed builds' work (issue 29).
    pub fn delassus_work(&self) -> (u64, crate::iteration::CondensedWork) {
        self.iteration.delassus_work()
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

    /// Each contact's status: closed or open, gap, last impact.
    pub fn contact_statuses(&self) -> &[ContactStatus] {
        &self.state.contacts
    }

    /// Kinetic energy lost in impacts so far (J).
    pub fn impact_loss(&self) -> f64 {
        self.state.impact_loss
    }

    pub fn state(&self) -> SimState {
        self.state.clone()
    }

    /// The current state, borrowed.
    pub(crate) fn current(&self) -> &SimState {
        &self.state
    }

    /// Restore a state from `state()`; refused unless it has this model's
    /// shape (beam DOFs, bodies, contacts).
    pub fn restore(&mut self, state: &SimState) -> Result<(), String> {
        self.check_restorable(state)?;
        self.state = state.clone();
        self.vehicle_forces[0].1 = state.body_force;
        Ok(())
    }

    /// Whether `restore` accepts `state` (which may be forged): its shape
    /// this model's and the bodies where its contacts say they are.
    pub fn check_restorable(&self, state: &SimState) -> Result<(), String> {
        check_shape(&self.system, state)?;
        state.check_consistent(&self.system, self.params.iteration.gap_tolerance)
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

    /// What the outputs read beside the system and the state.
    fn probes(&self) -> Probes<'_> {
        Probes {
            sensors: &self.sensors,
            sections: &self.sections,
            frames: self.iteration.frame_memo(),
            booked: !self.unbooked,
            start_applied: match self.state.last_applied.len() {
                0 => self.constant_forces(),
                _ => Vec::new(),
            },
        }
    }

    /// Each body's (ẍ, ÿ, θ̈) in the current state under the last forces.
    pub fn body_accelerations(&self) -> Vec<Vector3<f64>> {
        derived::body_accelerations(&self.system, &self.state, &self.probes())
    }

    /// The beam now under the contact forces of the last step, with the
    /// acceleration they give (design outputs); `None` when a contact
    /// point cannot be located.
    pub fn beam_dynamics(&self) -> Option<crate::design::BeamDynamics> {
        derived::beam_dynamics(&self.system, &self.state, self.iteration.frame_memo())
    }

    /// Advance to `target` with internal steps on the grid k·`solver.step`,
    /// the last one shortened to land on `target`; steps are also shortened
    /// to land on events. Stops early when the run is over.
    pub fn advance_to(&mut self, target: f64) -> Result<Advance, SolverError> {
        let tolerance = self.params.same_instant();
        loop {
            if let Some(time) = self.state.exit_time {
                return Ok(Advance::Exited { time });
            }
            if self.state.time >= target - tolerance {
                return Ok(Advance::Reached);
            }
            let next_grid = (self.state.grid_step + 1) as f64 * self.params.step;
            let to = if next_grid <= target + tolerance {
                next_grid
            } else {
                target
            };
            let to = self.start_up_target(to);
            let reached = self.step_to(to)?;
            // An event within round-off of `to` counts as reaching it: the
            // step left over would be empty.
            if !reached && to - self.state.time <= tolerance {
                self.state.time = to;
            }
            if to == next_grid && self.state.time == to {
                self.state.grid_step += 1;
                self.restart_pending()?;
            }
        }
    }

    /// Where the next step of a run's first grid step ends, with a shaped
    /// force profile under RK4: the first two steps have no converged means
    /// to fit (held, then linear: second-order steps, whose error at the
    /// full step outweighs the rest of the run's), so they are an eighth of
    /// the grid step each, and the rest of the grid step is taken in
    /// doubling steps (a fit then spans steps at most twice apart). Adds
    /// three steps to a run.
    fn start_up_target(&self, to: f64) -> f64 {
        let s = &self.state;
        let fits = self.iteration.integrator().fits_force_shape();
        if self.force_profile == ForceProfile::Held || !fits || s.grid_step != 0 {
            return to;
        }
        let next = if s.steps < 2 {
            self.params.step / self.params.start_up_divisions
        } else {
            2.0 * s.step_history[0]
        };
        if s.time + next < to - self.params.same_instant() {
            s.time + next
        } else {
            to
        }
    }

    /// One step from the current time to `to`, or to the first event inside
    /// it (a track boundary crossed, an open contact landing). Returns
    /// whether it reached `to`.
    fn step_to(&mut self, to: f64) -> Result<bool, SolverError> {
        self.land_at_start()?;
        let dt = to - self.state.time;
        let s = &self.state;
        let mut guess = std::mem::take(&mut self.guess);
        guess.clear();
        guess.extend(
            s.force_history
                .iter()
                .map(|h| extrapolate(h, &s.step_history, dt)),
        );
        let solution = self.solve_active_set(&guess, dt);
        self.guess = guess;
        let (solution, dt, lifting) = solution?;
        let track = self.first_event();
        let landing = self
            .first_landing()
            .filter(|&(f, _)| track.is_none_or(|(g, ..)| f < g));
        // A follower leaving a corner of the track ends the step there
        // (`follower.rs`).
        let first = landing.map(|l| l.0).or(track.map(|t| t.0));
        if let Some((_, c)) = self
            .first_corner_departure()
            .filter(|&(f, _)| first.is_none_or(|g| f < g))
        {
            let (solution, dt) = self.locate_corner_departure(c, &solution.forces, dt)?;
            self.record_lift_offs();
            self.accept(solution, dt);
            return Ok(false);
        }
        if let Some((fraction, contact)) = landing {
            if fraction == 0.0 {
                // Back on the track within the step it bounced in: the
                // bounce is dropped (a plastic landing now) and the step
                // taken again with the contact closed.
                self.land(contact, true)?;
                return Ok(false);
            }
            let Some((solution, dt, contact)) =
                self.locate_landing(contact, &solution.forces, dt)?
            else {
                self.land(contact, true)?;
                return Ok(false);
            };
            self.record_lift_offs();
            self.accept(solution, dt);
            self.record_events(None);
            self.land(contact, false)?;
            return Ok(false);
        }
        let (solution, dt, event) = match track {
            None => (solution, dt, None),
            Some((_, contact, edge, part)) => {
                let (solution, dt) = self.locate_event(contact, edge, &solution.forces, dt)?;
                (solution, dt, Some((contact, part)))
            }
        };
        self.record_lift_offs();
        self.accept(solution, dt);
        if let Some((contact, _)) = event {
            let before = self.state.parts.clone();
            self.record_events(event);
            self.after_switch(contact, &before)?;
            Ok(false)
        } else if let Some(contact) = lifting {
            self.record_events(None);
            self.lift_off_now(contact)?;
            Ok(false)
        } else {
            self.state.time = to;
            Ok(true)
        }
    }

    /// Solve the step with the contacts open at its start open, then make
    /// its active set complementary: open every closed contact whose normal
    /// force came out tensile and solve it again; where none pulls, close
    /// again the first contact opened in this step whose gap ends below the
    /// track (it would have pushed: opening it was another contact's doing),
    /// and solve again. The step ends with every closed contact's force
    /// ≥ 0 and every contact it opened off the track (the complementarity
    /// problem of the step's contacts, solved by the switches of
    /// `linalg::complementarity` on the whole step). A closed contact is
    /// not kept closed under tension where it opened and landed in this
    /// grid step already, under RK4 (bounded by `count_reopening`); under
    /// HHT-α it still is (see `open_the_pulling`). At most
    /// `active_set_passes` solves: a step whose set still switches is an
    /// error saying so.
    ///
    /// Under HHT-α a contact that carries a compressive force into the step
    /// does not open at its start (which would drop that force's share of
    /// the step's impulse): the step is shortened to the instant its end
    /// force reaches zero (`locate_lift_off`), and the contact opens there.
    /// Where it pulls from the start, it lifts off there with HHT-α's
    /// restart where the step then leaves it off the track
    /// (`lift_off_at_start`), else it opens at the start in the step's set.
    /// Returns the solution, the step's length and that contact.
    fn solve_active_set(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64, Option<usize>), SolverError> {
        for (open, status) in self.open.iter_mut().zip(&self.state.contacts) {
            *open = status.open;
        }
        self.opened.fill(false);
        let mut tried = vec![false; self.open.len()];
        for _ in 0..active_set_passes(self.open.len()) {
            self.iteration.set_open(&self.open);
            let solution = self.solve(guess, dt)?;
            if let Some(c) = self.lift_off_inside(&solution.forces) {
                if let Some((solution, tau)) = self.locate_lift_off(c, &solution.forces, dt) {
                    // Another closed contact that pulls at the located
                    // instant opens at the step's start and the step is
                    // solved again: taken as it is, a contact holding a
                    // separating velocity jump over a sliver of a step
                    // pulled 1e11 N, carried into the next step.
                    if self.open_the_pulling_but(&solution.forces, Some(c))? {
                        continue;
                    }
                    if self.state.contacts[c].opened_in == Some(self.state.grid_step) {
                        self.count_reopening()?;
                    }
                    return Ok((solution, tau, Some(c)));
                }
                let first_try = !std::mem::replace(&mut tried[c], true);
                if first_try && self.lift_off_at_start(c, guess, dt)? {
                    continue;
                }
                // Else it opens at the step's start (below).
            }
            if !self.open_the_pulling(&solution.forces)? && !self.close_a_penetrating() {
                return Ok((solution, dt, None));
            }
        }
        Err(SolverError {
            time: self.state.time,
            message: format!(
                "the contacts' active set of a step of {dt:e} s did not settle in {} solves \
                 (a contact opened pulls, closed sinks below the track): the rigid contact \
                 chatters here; a compliant contact law is well posed (docs/contact-laws.md)",
                active_set_passes(self.open.len())
            ),
        })
    }

    /// Open every closed contact whose normal force in `forces` pulls;
    /// whether one did.
    fn open_the_pulling(&mut self, forces: &[ContactForce]) -> Result<bool, SolverError> {
        self.open_the_pulling_but(forces, None)
    }

    /// `open_the_pulling`, leaving `kept` (a lift-off located at the
    /// step's end, whose force is zero to its tolerance) as it is.
    fn open_the_pulling_but(
        &mut self,
        forces: &[ContactForce],
        kept: Option<usize>,
    ) -> Result<bool, SolverError> {
        let mut opened_any = false;
        let grid = self.state.grid_step;
        for (c, force) in forces.iter().enumerate() {
            if self.open[c] || force.normal >= 0.0 || kept == Some(c) {
                continue;
            }
            if self.state.contacts[c].opened_in == Some(grid) {
                self.count_reopening()?;
            }
            self.open[c] = true;
            self.opened[c] = true;
            opened_any = true;
        }
        Ok(opened_any)
    }

    /// Count a contact's reopening in the grid step it opened in already:
    /// at most `max_reopenings` in a grid step, past which the contacts
    /// chatter without end and the run stops, saying so.
    fn count_reopening(&mut self) -> Result<(), SolverError> {
        let grid = self.state.grid_step;
        if self.reopenings.0 != grid {
            self.reopenings = (grid, 0);
        }
        self.reopenings.1 += 1;
        let bound = max_reopenings(self.open.len());
        if self.reopenings.1 <= bound {
            return Ok(());
        }
        Err(SolverError {
            time: self.state.time,
            message: format!(
                "the contacts reopened more than {bound} times in one grid step of {} s: \
                 the rigid contact chatters without end here; a compliant contact law is \
                 well posed (docs/contact-laws.md)",
                self.params.step
            ),
        })
    }

    /// Close again the first contact opened in this step whose gap ends
    /// below the track by more than the iteration's gap tolerance (the
    /// band a closed contact's gap is held in: a contact closed at a gap
    /// of −1e-7 m that opens and rises still ends below zero); whether one
    /// was.
    fn close_a_penetrating(&mut self) -> bool {
        let gaps = self.iteration.contact_gaps();
        let tolerance = self.params.iteration.gap_tolerance;
        let sinking = (0..self.opened.len()).find(|&c| self.opened[c] && gaps[c] < -tolerance);
        if let Some(c) = sinking {
            self.open[c] = false;
            self.opened[c] = false;
        }
        sinking.is_some()
    }

    /// The contacts opened in the step just solved lift off at its start.
    fn record_lift_offs(&mut self) {
        let grid = self.state.grid_step;
        for c in 0..self.opened.len() {
            if self.opened[c] {
                self.state.contacts[c].opened_in = Some(grid);
                push_event(&mut self.state, c, EventKind::LiftOff);
            }
        }
    }

    /// The open contact (open at the step's start) whose gap closes first
    /// in the step just solved, with a linear estimate of the fraction of
    /// the step at which it does: 0 for a contact that starts the step on
    /// the track (it has just bounced) and ends it below.
    fn first_landing(&self) -> Option<(f64, usize)> {
        let end = self.iteration.contact_gaps();
        let mut first: Option<(f64, usize)> = None;
        for c in self.landing_candidates() {
            let (g0, g1) = (self.state.contacts[c].gap, end[c]);
            let fraction = if g0 > 0.0 { g0 / (g0 - g1) } else { 0.0 };
            if first.is_none_or(|(f, _)| fraction < f) {
                first = Some((fraction, c));
            }
        }
        first
    }

    /// An open contact that starts the step on or below the track and
    /// approaching it (left there by an event located just before its
    /// landing) lands now.
    fn land_at_start(&mut self) -> Result<(), SolverError> {
        for c in 0..self.state.contacts.len() {
            let status = self.state.contacts[c];
            let follower = self.system.contacts[c].follower.is_some();
            if status.open && !follower && status.gap <= 0.0 && self.normal_velocity_error(c)? < 0.0
            {
                self.land(c, false)?;
            }
        }
        Ok(())
    }

    /// The impacts of contacts crossing rail gaps so far in this run.
    pub fn joint_impacts(&self) -> &[JointImpact] {
        &self.joint_impacts
    }

    /// The contact whose crossing of a track boundary comes first in the
    /// step just solved (into `scratch`): the fraction of the step at which
    /// it does (linear estimate), the contact, the boundary's abscissa and
    /// the part beyond it.
    fn first_event(&self) -> Option<(f64, usize, f64, TrackPart)> {
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
        first
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
        let gaps = self.iteration.contact_gaps();
        for ((status, &open), &gap) in s.contacts.iter_mut().zip(&self.open).zip(gaps) {
            status.open = open;
            status.gap = gap;
        }
        self.follower_transitions(dt);
    }

    /// Record the track events of the step just taken, which ends where
    /// contact `located.0` reaches part `located.1` (or at another event),
    /// and end the run if it is over.
    fn record_events(&mut self, located: Option<(usize, TrackPart)>) {
        let s = &mut self.state;
        // `accept` swapped the step's start state into `scratch`.
        let starts = &self.scratch.contact_x;
        for (c, &start) in starts.iter().enumerate() {
            let x = s.dynamic.contact_x[c];
            let from = s.parts[c];
            // The located contact sits on its edge to round-off: take the
            // side it was moving to.
            let to = if let Some((_, part)) = located.filter(|&(l, _)| l == c) {
                part
            } else {
                match self.system.leaves(from, start, x) {
                    Some(right) => self.system.next_part(from, right).1,
                    None => continue,
                }
            };
            let contact = &self.system.contacts[c];
            let centre_x = contact.point(&s.dynamic.bodies[contact.body]).position.x;
            let to = self.system.settle_part(to, centre_x);
            if matches!(to, TrackPart::JointBefore(_) | TrackPart::JointAfter(_)) {
                // Over a joint the contact's abscissa is its centre's.
                s.dynamic.contact_x[c] = centre_x;
            }
            s.parts[c] = to;
            let kind = match (from, to) {
                (_, TrackPart::Beyond) => EventKind::LeftTrack,
                // From piece to joint to piece: still on the structure.
                _ if from.on_structure() && to.on_structure() => continue,
                _ if to.on_structure() => EventKind::Entry,
                _ => EventKind::Exit,
            };
            if from.on_structure() && kind == EventKind::LeftTrack {
                push_event(s, c, EventKind::Exit);
            }
            push_event(s, c, kind);
        }
        let left_track = s.parts.contains(&TrackPart::Beyond);
        let all_left_beam = !s.parts.iter().any(|p| p.on_structure())
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

    /// Shorten the step so that open contact `contact`'s gap closes at its
    /// end, or, where another landing contact is then below the track (its
    /// gap crossed zero first, though a straight line through its gaps at
    /// the step's ends put `contact` first: a contact that has just bounced
    /// comes down again late in the step), so that the first of them
    /// closes. Leaves the state at that instant in `scratch`; returns the
    /// contact that lands.
    fn locate_landing(
        &mut self,
        contact: usize,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<Option<(StepSolution, f64, usize)>, SolverError> {
        let candidates: Vec<usize> = self.landing_candidates().collect();
        let end_gaps = self.iteration.contact_gaps().to_vec();
        let start = self.state.contacts[contact].gap;
        let gap = |sim: &Simulation, _: &StepSolution| sim.iteration.contact_gaps()[contact];
        let ends = (start, end_gaps[contact]);
        let Some(bracket) = self.landing_bracket(forces, dt, ends, gap)? else {
            return Ok(None);
        };
        let (low, (high, at_high)) = bracket;
        let located = self.locate(forces, high, (low, at_high), LANDING_GAP, gap)?;
        let below = |sim: &Simulation| {
            let gaps = sim.iteration.contact_gaps();
            candidates.iter().any(|&d| gaps[d] < -LANDING_GAP)
        };
        if let Some((solution, tau)) = located.filter(|_| !below(self)) {
            return Ok(Some((solution, tau, contact)));
        }
        let lowest = |gaps: &[f64]| {
            (candidates.iter().map(|&d| (gaps[d], d))).fold((f64::INFINITY, contact), |a, b| {
                if b.0 < a.0 {
                    b
                } else {
                    a
                }
            })
        };
        let start = candidates.iter().map(|&d| self.state.contacts[d].gap);
        let ends = (start.fold(f64::INFINITY, f64::min), lowest(&end_gaps).0);
        let miss = |sim: &Simulation, _: &StepSolution| lowest(sim.iteration.contact_gaps()).0;
        let Some(bracket) = self.landing_bracket(forces, dt, ends, miss)? else {
            return Ok(None);
        };
        let (low, (high, at_high)) = bracket;
        let (solution, tau) = self
            .locate(forces, high, (low, at_high), LANDING_GAP, miss)?
            .ok_or_else(|| SolverError {
                time: self.state.time,
                message: format!(
                    "the instant {} lands could not be located",
                    self.system.contacts[contact].name
                ),
            })?;
        let first = lowest(self.iteration.contact_gaps()).1;
        Ok(Some((solution, tau, first)))
    }

    /// The bracket ((lo, gap), (hi, gap)) of the step in which `gap`
    /// closes: the whole step where it starts above `LANDING_GAP`. One that
    /// starts on the track (a contact that has just bounced) first rises:
    /// the locator would take the start itself for the landing and leave a
    /// sliver of a step whose closed contacts' forces explode; its bracket
    /// starts at the largest dt/2^k at which it is above. None where it is
    /// above nowhere down to dt/2^`BOUNCE_HALVINGS`: the bounce is lost in
    /// the step, and the contact lands now.
    fn landing_bracket(
        &mut self,
        forces: &[ContactForce],
        dt: f64,
        (start, end): (f64, f64),
        gap: impl Fn(&Simulation, &StepSolution) -> f64,
    ) -> Result<Option<Bracket>, SolverError> {
        let mut hi = (dt, end);
        if start > LANDING_GAP {
            return Ok(Some(((0.0, start), hi)));
        }
        for k in 1..=BOUNCE_HALVINGS {
            let tau = dt * 0.5f64.powi(k);
            let solution = self.solve(forces, tau)?;
            let g = gap(self, &solution);
            if g > LANDING_GAP {
                return Ok(Some(((tau, g), hi)));
            }
            if g < 0.0 {
                hi = (tau, g);
            }
        }
        Ok(None)
    }

    /// The open contacts whose gap closes in the step just solved: not
    /// opened in it, and not slack followers (a follower's gap is its
    /// suspension's: it lands by its law).
    fn landing_candidates(&self) -> impl Iterator<Item = usize> + '_ {
        let end = self.iteration.contact_gaps();
        (self.state.contacts.iter().enumerate())
            .filter(move |&(c, status)| {
                let follower = self.system.contacts[c].follower.is_some();
                status.open && !self.opened[c] && !follower && end[c] < 0.0
            })
            .map(|(c, _)| c)
    }

    /// The contact frames of state `d`, each contact on the part of the
    /// track it is on now.
    fn frames_of(
        &self,
        d: &DynamicState,
    ) -> Result<Vec<crate::contact::ContactFrame>, crate::integrate::IntegrationError> {
        let memo = self.iteration.frame_memo();
        crate::outputs::derived::frames_of(&self.system, d, &self.state.parts, memo)
    }

    /// The contact frames of the current state (each contact on the part
    /// of the track it is on now); `None` when one cannot be located.
    pub fn contact_frames_now(&self) -> Option<Vec<crate::contact::ContactFrame>> {
        derived::frames_now(&self.system, &self.state, self.iteration.frame_memo()).ok()
    }

    /// The contact frames of the current state.
    fn frames_now(&self) -> Result<Vec<crate::contact::ContactFrame>, SolverError> {
        self.frames_of(&self.state.dynamic)
            .map_err(|e| SolverError {
                time: self.state.time,
                message: crate::iteration::StepError::from(e).to_string(),
            })
    }

    /// Contact `c`'s normal velocity error now (m/s): negative approaches.
    fn normal_velocity_error(&self, c: usize) -> Result<f64, SolverError> {
        let frames = self.frames_now()?;
        Ok(self.velocity_errors(&frames)[c].y)
    }

    /// Every contact's velocity error (tangential, normal) at `frames`.
    fn velocity_errors(&self, frames: &[crate::contact::ContactFrame]) -> Vec<Vector2<f64>> {
        let d = &self.state.dynamic;
        let beam = &self.system.beam;
        self.system
            .contacts
            .iter()
            .zip(frames)
            .map(|(contact, frame)| {
                let point = contact.point(&d.bodies[contact.body]);
                frame.velocity_error(beam, contact.radius(), &point, &d.beam_velocity)
            })
            .collect()
    }

    /// Open contact `c` lands now, with every other open contact on the
    /// track (gap within `LANDING_GAP`) and approaching it: one impact over
    /// them and all closed contacts (`crate::impact`), Newton's law on each
    /// landing contact with its restitution (plastic below
    /// `RESTING_SPEED`, for a second landing in the same grid step and, for
    /// `c`, if `plastic`), the closed ones kept (held bilateral if they
    /// opened in this grid step already, see `solve_active_set`). A landing
    /// contact closes unless it bounces; one whose impulse would pull
    /// leaves the track instead (a closed one: a lift-off at the impact),
    /// if at `RESTING_SPEED` at least and, for a landing one, at its first
    /// landing in the grid step (else it closes, with no impulse).
    fn land(&mut self, c: usize, plastic: bool) -> Result<(), SolverError> {
        let frames = self.frames_now()?;
        let parts = self.impact_parts(c, plastic, &frames);
        let impact = crate::impact::resolve(&self.system, &frames, &parts, &mut self.state.dynamic)
            .map_err(|message| SolverError {
                time: self.state.time,
                message,
            })?;
        let grid = self.state.grid_step;
        self.state.impact_loss += impact.loss;
        let mut relanded = Vec::new();
        for (d, &part) in parts.iter().enumerate() {
            let s = &mut self.state;
            let status = &mut s.contacts[d];
            if part != crate::impact::Part::Out {
                status.impulse = [impact.impulses[d].x, impact.impulses[d].y];
            }
            let leaves = impact.separation[d] >= self.params.resting_speed;
            match part {
                crate::impact::Part::Landing(e) => {
                    let first = status.landed_in != Some(grid);
                    status.open = e > 0.0 || (leaves && first);
                    status.landed_in = Some(grid);
                    if !first && !status.open {
                        relanded.push(d);
                    }
                    s.force_history[d] = [ContactForce::default(); 3];
                    push_event(s, d, EventKind::Landing);
                }
                crate::impact::Part::Closed => self.leave_at_impact(d, impact.separation[d]),
                _ => {}
            }
        }
        self.restart(&relanded, self.grid_remainder())
    }

    /// A closed contact that an impact sends away from the track at
    /// `separation` (m/s) opens, with a lift-off event, if that is at least
    /// `RESTING_SPEED`; slower, it stays closed.
    fn leave_at_impact(&mut self, d: usize, separation: f64) {
        if separation < self.params.resting_speed {
            return;
        }
        let s = &mut self.state;
        s.contacts[d].open = true;
        s.contacts[d].opened_in = Some(s.grid_step);
        s.force_history[d] = [ContactForce::default(); 3];
        push_event(s, d, EventKind::LiftOff);
    }

    /// How each contact takes part in the impact of `c`'s landing.
    fn impact_parts(
        &self,
        c: usize,
        plastic: bool,
        frames: &[crate::contact::ContactFrame],
    ) -> Vec<crate::impact::Part> {
        use crate::impact::Part;
        let errors = self.velocity_errors(frames);
        let grid = self.state.grid_step;
        let statuses = self.state.contacts.iter().enumerate();
        statuses
            .map(|(d, status)| {
                let approach = errors[d].y.min(0.0);
                if self.system.contacts[d].follower.is_some() {
                    // A force law with no mass: no impulse passes through it.
                    return Part::Out;
                }
                if !status.open {
                    return if status.opened_in == Some(grid) {
                        Part::Held
                    } else {
                        Part::Closed
                    };
                }
                if d != c && (status.gap > LANDING_GAP || approach == 0.0) {
                    return Part::Out;
                }
                let again = status.landed_in == Some(grid);
                if -approach < self.params.resting_speed || again || (plastic && d == c) {
                    Part::Landing(0.0)
                } else {
                    Part::Landing(self.restitution[d])
                }
            })
            .collect()
    }

    fn solve(&mut self, guess: &[ContactForce], dt: f64) -> Result<StepSolution, SolverError> {
        self.solve_shaped(guess, dt, self.force_profile)
    }

    /// `solve` with the contact forces shaped by `profile` over the step.
    fn solve_shaped(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
        profile: ForceProfile,
    ) -> Result<StepSolution, SolverError> {
        self.set_force_shapes(dt, profile);
        self.set_drives(dt);
        let mut applied = std::mem::take(&mut self.applied);
        applied.clear();
        applied.extend(self.constant_forces_iter());
        let solution = self.solve_with(guess, &applied, dt);
        self.applied = applied;
        solution
    }

    /// Each contact's force shape over a step of `dt`, fitted to the means
    /// of the steps before that it was closed in (none at the start, after
    /// a landing: held there).
    fn set_force_shapes(&mut self, dt: f64, profile: ForceProfile) {
        let s = &self.state;
        // A step whose gap was corrected carries a position-correcting
        // impulse in its mean, not a sample of the smooth force: fitted
        // to, it would be carried on into the next steps' shapes.
        let steps_taken = if s.last_position_iterations > 0 {
            0
        } else {
            s.steps.min(2) as usize
        };
        self.shapes.clear();
        self.shapes.extend(s.force_history.iter().map(|history| {
            let closed = history.iter().take_while(|f| f.normal != 0.0).count();
            force_shape(
                profile,
                history,
                &s.step_history,
                closed.min(steps_taken),
                dt,
            )
        }));
        self.iteration.set_force_shapes(&self.shapes);
    }

    /// Each driven body's ẍ over a step of `dt`: the one that brings its
    /// speed to the prescribed one at the step's end.
    fn set_drives(&mut self, dt: f64) {
        let end = self.state.time + dt;
        for (b, speed) in &self.drives {
            let now = self.state.dynamic.bodies[*b].velocity.x;
            self.system.bodies[*b].drive = Some((speed.speed_at(end) - now) / dt);
        }
    }

    fn solve_with(
        &mut self,
        guess: &[ContactForce],
        applied: &[Vector3<f64>],
        dt: f64,
    ) -> Result<StepSolution, SolverError> {
        self.unbooked |= !self.iteration.integrator_mut().keeps_energy_books();
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
                &self.params.iteration,
                &mut self.scratch,
            )
            .map_err(|e| SolverError {
                time: s.time,
                message: match e {
                    crate::iteration::StepError::LostContact { .. } => format!(
                        "{e}: {}",
                        heaviest_and_deflection(&self.system, &s.dynamic.beam_displacement)
                    ),
                    crate::iteration::StepError::NotConverged { stage, .. }
                    | crate::iteration::StepError::Diverged { stage, .. }
                        if stage == crate::iteration::FORCE_LAW_STAGE =>
                    {
                        format!("{e}; {}", heaviest_on_laws(&self.system))
                    }
                    e => e.to_string(),
                },
            })?;
        if !self.scratch.beam_displacement.iter().all(|x| x.is_finite()) {
            return Err(SolverError {
                time: s.time,
                message: "the beam state became non-finite".into(),
            });
        }
        Ok(solution)
    }

    /// Shorten the step so that contact `contact` lands on `edge`. Leaves
    /// the state at that instant in `scratch`.
    fn locate_event(
        &mut self,
        contact: usize,
        edge: f64,
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<(StepSolution, f64), SolverError> {
        let start = self.state.dynamic.contact_x[contact] - edge;
        let tolerance = 1e-12 * self.system.beam.length;
        let miss = |sim: &Simulation, _: &StepSolution| sim.scratch.contact_x[contact] - edge;
        let end = self.scratch.contact_x[contact] - edge;
        self.locate(forces, dt, ((0.0, start), end), tolerance, miss)?
            .ok_or_else(|| SolverError {
                time: self.state.time,
                message: format!(
                    "the instant {} reaches x = {edge} m could not be located",
                    self.system.contacts[contact].name
                ),
            })
    }

    /// Shorten the step until `miss`, a signed distance read from the
    /// solved state and solution (`start` at the step's start, or at the
    /// step length given with it, `end` at its end), is within
    /// `tolerance`: regula falsi on the step length,
    /// Illinois variant. `None` when 60 passes do not get there.
    pub(crate) fn locate(
        &mut self,
        forces: &[ContactForce],
        dt: f64,
        ((lo, start), end): ((f64, f64), f64),
        tolerance: f64,
        miss: impl Fn(&Simulation, &StepSolution) -> f64,
    ) -> Result<Option<(StepSolution, f64)>, SolverError> {
        let (mut lo, mut f_lo) = (lo, start);
        let (mut hi, mut f_hi) = (dt, end);
        let mut side = 0;
        for _ in 0..60 {
            let tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let solution = self.solve(forces, tau)?;
            let f = miss(self, &solution);
            if f.abs() <= tolerance || (hi - lo) <= 1e-15 * dt {
                return Ok(Some((solution, tau)));
            }
            if (f > 0.0) == (f_hi > 0.0) {
                (hi, f_hi) = (tau, f);
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            } else {
                (lo, f_lo) = (tau, f);
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            }
        }
        Ok(None)
    }
}

/// Gaps within which a landing counts as located (m).
const LANDING_GAP: f64 = 1e-12;

/// Two instants of a step with a signed distance at each: (τ, miss).
type Bracket = ((f64, f64), (f64, f64));

/// How far (dt/2^k) the landing locator looks for a just-bounced contact
/// above the track before it counts the bounce as lost in the step.
const BOUNCE_HALVINGS: i32 = 30;

/// Reopenings of contacts that opened in the grid step already that one
/// grid step may hold (`Simulation::count_reopening`): four per contact,
/// and four.
fn max_reopenings(contacts: usize) -> usize {
    4 * contacts + 4
}

/// Solves a step's active set may take (`solve_active_set`): every
/// contact opened once and closed again once, lifted off at the step's
/// start once (under HHT-α), and the first solve.
fn active_set_passes(contacts: usize) -> usize {
    3 * contacts + 2
}

/// Each contact's status at t = 0: open where its vehicle starts above the
/// track, with its gap.
fn initial_contacts(
    system: &System,
    d: &DynamicState,
    parts: &[TrackPart],
    open: &[bool],
) -> Result<Vec<ContactStatus>, String> {
    let mut frames = Vec::new();
    let located = (d.contact_x.as_slice(), parts);
    contact_frames(
        system,
        &d.beam_displacement,
        &d.bodies,
        located,
        &mut frames,
    )
    .map_err(|e| no_start_point(system, &d.beam_displacement, e))?;
    let statuses = system.contacts.iter().zip(&frames).zip(open);
    Ok(statuses
        .map(|((contact, frame), &open)| {
            let centre = &contact.point(&d.bodies[contact.body]).position;
            ContactStatus {
                open,
                gap: frame.gap(&system.beam, contact.radius(), centre),
                ..ContactStatus::default()
            }
        })
        .collect())
}

/// Why a contact has no point on the track at the start, naming what
/// likely put it there: the heaviest body and the beam's largest static
/// deflection (a coach of 1e15 kg deflects the beam past any foot point).
fn no_start_point(
    system: &System,
    u: &DVector<f64>,
    error: crate::integrate::IntegrationError,
) -> String {
    use crate::report::fmt_number;
    let crate::integrate::IntegrationError::LostContact { contact, x } = error else {
        return format!("{error:?}");
    };
    let name = system
        .contacts
        .get(contact)
        .map_or("?", |c| c.name.as_str());
    format!(
        "no contact point at the start for {name} (x = {}): {}",
        fmt_number(x),
        heaviest_and_deflection(system, u)
    )
}

/// What most often loses a contact: the beam's largest displacement and
/// the heaviest body, in words.
fn heaviest_and_deflection(system: &System, u: &DVector<f64>) -> String {
    use crate::report::fmt_number;
    let deflection = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    format!(
        "the beam's displacements reach {} m under the bodies' weight, the heaviest being \
         {}; lighter bodies or a stiffer beam keep the contacts on the track",
        fmt_number(deflection),
        heaviest_body(system)
    )
}

/// The heaviest body, in words: "coach1 with a mass of 1e15 kg".
fn heaviest_body(system: &System) -> String {
    let heaviest = system
        .bodies
        .iter()
        .max_by(|a, b| a.mass.total_cmp(&b.mass));
    let (body, mass) = heaviest.map_or(("?", 0.0), |b| (b.name.as_str(), b.mass));
    format!(
        "{body} with a mass of {} kg",
        crate::report::fmt_number(mass)
    )
}

/// What most often keeps a compliant law from settling: the weight it
/// carries, named by the heaviest body (a coach of 1e15 kg presses a Hertz
/// contact far past any force the step can follow).
fn heaviest_on_laws(system: &System) -> String {
    format!(
        "the compliant contacts carry the bodies' weight, the heaviest being {}",
        heaviest_body(system)
    )
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
    let n = system.beam.coordinates();
    let mut frames = Vec::new();
    contact_frames_at_bodies(system, &u, bodies, &mut frames)
        .map_err(|e| no_start_point(system, &u, e))?;
    let mut beam_load = DVector::zeros(n);
    let mut body_loads = vec![Vector3::zeros(); bodies.len()];
    loads(
        system,
        &frames,
        forces,
        applied,
        bodies,
        &DVector::zeros(n),
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
        tractive_work: 0.0,
        numerical_dissipation: 0.0,
    })
}

#[cfg(test)]
mod extrapolation_tests {
    use super::*;

    fn history(values: [f64; 3]) -> [ContactForce; 3] {
        values.map(|normal| ContactForce {
            tangential: -0.1 * normal,
            normal,
        })
    }

    #[test]
    fn equal_steps_extrapolate_a_quadratic_exactly() {
        // f(t) = 5 + 3 t − 2 t² sampled at 0, −h, −2h, guessed at h.
        let h = 1e-3;
        let f = |t: f64| 5e5 + 3e7 * t - 2e9 * t * t;
        let guess = extrapolate(&history([f(0.0), f(-h), f(-2.0 * h)]), &[h, h], h);
        assert!((guess.normal - f(h)).abs() < 1e-6 * f(h), "{guess:?}");
        assert!((guess.tangential + 0.1 * f(h)).abs() < 1e-7 * f(h));
    }

    #[test]
    fn a_step_far_shorter_than_the_next_does_not_magnify_the_history() {
        // An event located 8.5e-12 s after a grid point, then a full step:
        // quadratic extrapolation would multiply the differences of the
        // history by about 1e8 (forces of 1e11 N from a history of 1e5 N).
        let forces = history([1.21e5, 1.29e5, 1.15e5]);
        let guess = extrapolate(&forces, &[8.45e-12, 9.9e-4], 9.9e-4);
        let (low, high) = (1.15e5, 1.29e5);
        let spread = high - low;
        assert!(
            guess.normal > low - 2.0 * spread && guess.normal < high + 2.0 * spread,
            "{guess:?}"
        );
        // Both steps short: the last force, held.
        let held = extrapolate(&forces, &[1e-12, 1e-12], 1e-3);
        assert_eq!(held, forces[0]);
    }
}
