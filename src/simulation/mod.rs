//! Simulation: the façade of a run. It owns the system, the run's setup,
//! the state, the solver parameters and the stepper's workspace, and offers
//! new, advance_to, state/restore, the inputs (applied force, coupling
//! loads) and the output values; the stepping is `solver::Stepper`'s, the
//! events `solver::events`', the start `start.rs`.

use nalgebra::Vector3;

use crate::outputs::{derived, evaluate, Needs, Probes, Quantity};
use crate::scene::{ForceProfile, Scene};
use crate::solver::parameters::SolverParameters;
use crate::solver::stepper::{constant_forces_now, RunSetup, Stepper};
use crate::system::System;

#[cfg(test)]
mod coaches_tests;
#[cfg(test)]
mod prediction_tests;
#[cfg(test)]
mod restart_seed_tests;
pub mod run_end;
#[cfg(test)]
mod secant_tests;
mod start;

pub use crate::integrate::{rk4_step_limit, AUTO_MIN_DAMPING};
pub use crate::outputs::{OutputInfo, OutputKind};
pub use crate::solver::stepper::{Advance, JointImpact, SolverError};
use crate::state::check_shape;
pub use crate::state::{ContactEvent, ContactStatus, EventKind, SimState, MAX_EVENTS};

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
/// contacts (`Step::count_reopening`), past which the run stops.
pub const RESTING_SPEED: f64 = SolverParameters::DEFAULT.resting_speed;

pub struct Simulation {
    system: System,
    /// How the run drives the system (vehicle forces, prescribed speeds,
    /// restitutions, end rule, force profile).
    setup: RunSetup,
    /// Every tolerance, cap and ratio of the run (`solver::parameters`).
    params: SolverParameters,
    state: SimState,
    /// The stepper's workspace and the run's records (`solver::stepper`).
    stepper: Stepper,
    /// The static envelope's loads, taken before the static start moves
    /// the bodies (`design::static_shares`).
    envelope_loads: Vec<(f64, f64)>,
    /// Which integrator runs, and why (for `auto`).
    integrator_choice: String,
    sensors: Vec<f64>,
    /// Abscissae of the sections whose moment and shear are outputs.
    sections: Vec<f64>,
    outputs: Vec<OutputInfo>,
    quantities: Vec<Quantity>,
    /// What the quantities need (`Needs::of`), found once per run.
    needs: Needs,
    /// The rows of the coordinates the design outputs' accelerations read,
    /// where they are cheaper than a solve a row (`AccelerationRows`).
    acceleration_rows: Option<crate::structure::acceleration_rows::AccelerationRows>,
    /// The outputs computed when a sink reads only some (`read_only`).
    read: Option<crate::output_mask::OutputMask>,
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

    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The integrator that runs, in words (`auto` says what it picked and why).
    /// The contact force's shape within a step.
    pub fn force_profile(&self) -> ForceProfile {
        self.setup.force_profile
    }

    pub fn integrator_choice(&self) -> &str {
        &self.integrator_choice
    }

    /// The integrator's order of accuracy in time with the run's force
    /// profile.
    pub fn integrator_order(&self) -> f64 {
        let integrator = self.stepper.iteration().integrator();
        integrator.order(self.setup.force_profile)
    }

    /// The outputs this scene has, in a fixed order.
    pub fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }

    /// What each output reports, in the order of `outputs`.
    pub fn quantities(&self) -> &[Quantity] {
        &self.quantities
    }

    /// The static envelope's loads: (abscissa at the start, downward
    /// force) of each contact's static share, taken before the static start
    /// moved the bodies (`design::envelope_of_run` reads them).
    pub fn envelope_loads(&self) -> &[(f64, f64)] {
        &self.envelope_loads
    }

    /// The assembled system (bodies, force elements, contacts, beam).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Current output values, in the order of `outputs()`.
    pub fn output_values(&self, values: &mut [f64]) {
        let probes = self.probes();
        match &self.read {
            None => {
                let all = (self.quantities.as_slice(), self.needs);
                evaluate(&self.system, &self.state, &probes, all, values)
            }
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
        self.stepper
            .iteration_mut()
            .integrator_mut()
            .keep_energy_books(books);
    }

    /// `total`, one of the energy totals the steps book, or NaN where a
    /// step was solved without the bookkeeping (see `read_only`).
    pub fn booked(&self, total: f64) -> f64 {
        if !self.stepper.booked() {
            f64::NAN
        } else {
            total
        }
    }

    /// Potential energy of the force elements and of the followers'
    /// suspensions (at their gaps at the end of the last step) (J).
    pub fn spring_energy(&self) -> f64 {
        let end = self.stepper.iteration().integrator().end_forces();
        crate::energy::spring_with(&self.system, &self.state, end)
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
        let end = self.stepper.iteration().integrator().end_forces();
        let energies = (spring_energy, end);
        self.booked(crate::energy::balance_with(
            &self.system,
            &self.state,
            energies,
        ))
    }

    pub fn body_kinetic_energy(&self) -> f64 {
        crate::energy::body_kinetic(&self.system, &self.state)
    }

    /// Total energy at t = 0 (J), the reference of relative energy drift.
    pub fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }

    /// Set the applied force (N) on the centre of vehicle `vehicle`'s
    /// first body, held until changed; a vehicle the model lacks is
    /// ignored.
    pub fn set_vehicle_force(&mut self, vehicle: usize, force: [f64; 2]) {
        if let Some(held) = self.state.vehicle_forces.get_mut(vehicle) {
            *held = force;
        }
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
        self.stepper.iteration().response_cache_peak()
    }

    /// What the contact operators cost so far: whole-beam solves for
    /// responses, and the condensed builds' work (issue 29).
    pub fn delassus_work(&self) -> (u64, crate::iteration::CondensedWork) {
        self.stepper.iteration().delassus_work()
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
        Ok(())
    }

    /// Whether `restore` accepts `state` (which may be forged): its shape
    /// this model's and the bodies where its contacts say they are.
    pub fn check_restorable(&self, state: &SimState) -> Result<(), String> {
        check_shape(&self.system, state)?;
        let vehicles = self.setup.vehicle_first_bodies.len();
        if state.vehicle_forces.len() != vehicles {
            return Err(format!(
                "the state has {} vehicle forces but this model has {vehicles} vehicles",
                state.vehicle_forces.len()
            ));
        }
        state.check_consistent(&self.system, self.params.iteration.gap_tolerance)
    }

    /// The constant generalized force on each body now.
    fn constant_forces(&self) -> Vec<Vector3<f64>> {
        constant_forces_now(&self.system, &self.setup, &self.state).collect()
    }

    /// What the outputs read beside the system and the state.
    fn probes(&self) -> Probes<'_> {
        Probes {
            sensors: &self.sensors,
            sections: &self.sections,
            frames: self.stepper.iteration().frame_memo(),
            end_forces: self.stepper.iteration().integrator().end_forces(),
            acceleration_rows: self.acceleration_rows.as_ref(),
            booked: self.stepper.booked(),
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
    pub fn beam_dynamics(&self) -> Option<crate::structure::section_forces::BeamDynamics<'_>> {
        let iteration = self.stepper.iteration();
        let route = derived::AccelerationRoute {
            end_forces: iteration.integrator().end_forces(),
            rows: self.acceleration_rows.as_ref(),
            whole: true,
        };
        derived::beam_dynamics(&self.system, &self.state, iteration.frame_memo(), route)
    }

    /// Advance to `target` with internal steps on the grid k·`solver.step`,
    /// the last one shortened to land on `target`; steps are also shortened
    /// to land on events. Stops early when the run is over.
    pub fn advance_to(&mut self, target: f64) -> Result<Advance, SolverError> {
        let (system, setup) = (&mut self.system, &self.setup);
        self.stepper
            .advance_to(system, setup, &mut self.state, &self.params, target)
    }

    /// The impacts of contacts crossing rail gaps so far in this run.
    pub fn joint_impacts(&self) -> &[JointImpact] {
        self.stepper.joint_impacts()
    }

    /// The contact frames of the current state (each contact on the part
    /// of the track it is on now); `None` when one cannot be located.
    pub fn contact_frames_now(&self) -> Option<Vec<crate::contact::ContactFrame>> {
        let memo = self.stepper.iteration().frame_memo();
        let frames = derived::frames_now(&self.system, &self.state, memo);
        frames.ok().map(std::borrow::Cow::into_owned)
    }
}
