//! The stepper: advances a system's state in time on the fixed grid, one
//! internal step at a time (force guess, active set, contact iteration over
//! the integrator, events located inside the step, accepted state).
//! `Stepper` holds only workspace and the records of the run; the system,
//! its loading (`RunSetup`), the state and the solver parameters are
//! arguments of each call (`Stepper::advance_to`), so the same workspace
//! never owns what it steps.

use nalgebra::{DVector, Vector2, Vector3};

use crate::contact::ContactForce;
use crate::integrate::{force_shape, DynamicState, ForceShape, Integrator};
use crate::iteration::{ContactIteration, StepSolution};
use crate::solver::integrate::ForceProfile;
use crate::solver::parameters::SolverParameters;
use crate::state::SimState;
use crate::system::constant_forces;
use crate::system::{System, TrackPart};
use crate::vehicle::speed::SpeedSpec;

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

/// How the run drives the system beside its state, fixed at the build.
#[derive(Debug, Clone)]
pub struct RunSetup {
    /// The first body of each vehicle: where its applied force (the
    /// state's `vehicle_forces`, in the same order) acts.
    pub vehicle_first_bodies: Vec<usize>,
    /// The bodies driven at a prescribed speed, and their speeds.
    pub drives: Vec<(usize, SpeedSpec)>,
    /// Per contact: its vehicle's coefficient of restitution.
    pub restitution: Vec<f64>,
    /// Without an end time the run ends when the last contact leaves the
    /// beam (the paper's exit); with one it goes on to it.
    pub stop_at_beam_exit: bool,
    /// The contact force's shape within a step.
    pub force_profile: ForceProfile,
}

/// The stepper's workspace (buffers reused from step to step, so that a
/// step allocates little) and the records of the run that are not part of
/// its state (a roll-back does not undo them).
pub struct Stepper {
    pub(crate) iteration: ContactIteration,
    /// The state at the end of the step being solved (after `accept`, the
    /// start of the step just taken).
    pub(crate) scratch: DynamicState,
    /// Per-step buffers: the force shapes, the force guesses and the
    /// constant body forces.
    pub(crate) shapes: Vec<ForceShape>,
    pub(crate) guess: Vec<ContactForce>,
    pub(crate) applied: Vec<Vector3<f64>>,
    /// The step's active set: which contacts are open in it, and which of
    /// them opened in it.
    pub(crate) open: Vec<bool>,
    pub(crate) opened: Vec<bool>,
    /// Where the integrator carries accelerations from step to step
    /// (HHT-α), it restarts where a contact switches surfaces; the weight
    /// (1 + α) γ of a step's end acceleration in its mean.
    pub(crate) restart_weight: Option<f64>,
    /// The grid step and how many contacts reopened in it (RK4; bounded
    /// by `max_reopenings`; a record of the run, not of its state).
    pub(crate) reopenings: (u64, usize),
    /// Impacts at rail gaps (not part of the state: a record of the run).
    pub(crate) joint_impacts: Vec<JointImpact>,
    /// A step was solved without the energy bookkeeping (no sink read it):
    /// the energy totals no longer hold, and are reported as NaN.
    pub(crate) unbooked: bool,
    /// The forces of a restart's last trial step, its restarted contacts'
    /// at the restart's p: the guess of the step after it, which is the
    /// same step from almost the same start (`Step::restart_passes`),
    /// for a step as long; taken by the next step solved.
    pub(crate) restart_guess: Option<(f64, Vec<ContactForce>)>,
    /// Whether a restart's trial steps hand their ends on as the next
    /// one's prediction (`TimeIntegrator::seed_prediction`); off only
    /// where a test compares the two ways.
    pub(crate) seeds_restarts: bool,
}

/// One call's view of everything a step reads and writes: the stepper's
/// workspace, the system (written only by `set_drives`: a driven body's
/// acceleration over the step is a field of its `RigidBody`, which the
/// iteration reads), the run's setup, the state and the parameters. The
/// events (`solver::events`) are methods on it.
pub(crate) struct Step<'a> {
    pub work: &'a mut Stepper,
    pub system: &'a mut System,
    pub setup: &'a RunSetup,
    pub state: &'a mut SimState,
    pub params: &'a SolverParameters,
}

impl Stepper {
    /// The workspace of `system` stepped by `integrator` on the grid of
    /// `step`, its contacts open as `open` says, from a state whose dynamic
    /// part is `start`.
    pub fn new(
        integrator: Integrator,
        system: &System,
        step: f64,
        open: &[bool],
        start: &DynamicState,
    ) -> Stepper {
        let restart_weight = integrator
            .carries_step_end()
            .then(|| integrator.body_weights(1.0).0);
        Stepper {
            iteration: ContactIteration::new(integrator, system, step),
            scratch: start.clone(),
            shapes: Vec::new(),
            guess: Vec::new(),
            applied: Vec::new(),
            open: open.to_vec(),
            opened: vec![false; open.len()],
            restart_weight,
            reopenings: (0, 0),
            joint_impacts: Vec::new(),
            unbooked: false,
            restart_guess: None,
            seeds_restarts: true,
        }
    }

    /// Advance `state` to `target` with internal steps on the grid
    /// k·`params.step`, the last one shortened to land on `target`; steps
    /// are also shortened to land on events. Stops early when the run is
    /// over. On error the state is that at the start of the failing step.
    pub fn advance_to(
        &mut self,
        system: &mut System,
        setup: &RunSetup,
        state: &mut SimState,
        params: &SolverParameters,
        target: f64,
    ) -> Result<Advance, SolverError> {
        // What a restart hands on is for the step after it, in the same
        // call (a rest step follows its restart at once): none is left
        // from a call that ended on an exit or an error, nor crosses a
        // state set between calls.
        self.forget_restart();
        let mut step = Step {
            work: self,
            system,
            setup,
            state,
            params,
        };
        step.advance_to(target)
    }

    /// Forget what the last restart handed on to the step after it.
    pub(crate) fn forget_restart(&mut self) {
        self.restart_guess = None;
        self.iteration.integrator_mut().seed_prediction(None);
    }

    /// The contact iteration (its integrator, frame memo and counters).
    pub fn iteration(&self) -> &ContactIteration {
        &self.iteration
    }

    pub fn iteration_mut(&mut self) -> &mut ContactIteration {
        &mut self.iteration
    }

    /// Whether every step so far booked the energy the steps remove.
    pub fn booked(&self) -> bool {
        !self.unbooked
    }

    /// The impacts of contacts crossing rail gaps so far in this run.
    pub fn joint_impacts(&self) -> &[JointImpact] {
        &self.joint_impacts
    }
}

/// The constant generalized force on each body now: each vehicle's force
/// on its first body, the bodies' own, and the coupling loads.
pub fn constant_forces_now<'a>(
    system: &'a System,
    setup: &'a RunSetup,
    state: &'a SimState,
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    let couplings = &system.couplings;
    let loads = &state.coupling_loads;
    constant_forces(system, &setup.vehicle_first_bodies, &state.vehicle_forces)
        .enumerate()
        .map(move |(b, force)| {
            couplings
                .iter()
                .zip(loads)
                .filter(|(&c, _)| c == b)
                .fold(force, |f, (_, l)| f + Vector3::new(l[0], l[1], l[2]))
        })
}

/// Largest sum of |weights| an extrapolation of the force history may
/// have: it bounds how much the history's differences are magnified. With
/// equal steps the quadratic one has 7; after a step much shorter than the
/// next (an event located just after a grid point) it grows as dt² over
/// the short step's length, and a guess of 1e11 N threw the bodies off
/// the track before the first correction.
const MAX_EXTRAPOLATION_GAIN: f64 = SolverParameters::DEFAULT.max_extrapolation_gain;

/// The steps an `advance_to` took since it began or passed a grid point,
/// and (over the last half of `max_steps_in_grid_step`) the contacts whose
/// track part or status each step changed: what a stalled grid step's
/// error names.
#[derive(Default)]
struct Chatter {
    steps: usize,
    last: Vec<(TrackPart, bool)>,
    switching: Vec<usize>,
}

impl Chatter {
    fn watching(&self) -> bool {
        !self.last.is_empty()
    }

    fn before(&mut self, params: &SolverParameters, state: &SimState) {
        self.steps += 1;
        self.last.clear();
        if self.steps > params.max_steps_in_grid_step / 2 {
            let now = state.parts.iter().zip(&state.contacts);
            self.last.extend(now.map(|(&p, c)| (p, c.open)));
        }
    }

    fn after(&mut self, state: &SimState) {
        if !self.watching() {
            return;
        }
        let now = state.parts.iter().zip(&state.contacts);
        for (c, ((&part, status), &(was, open))) in now.zip(&self.last).enumerate() {
            if (part != was || status.open != open) && !self.switching.contains(&c) {
                self.switching.push(c);
            }
        }
    }
}

impl Step<'_> {
    /// The constant generalized force on each body now.
    pub(crate) fn constant_forces_iter(&self) -> impl Iterator<Item = Vector3<f64>> + '_ {
        constant_forces_now(self.system, self.setup, self.state)
    }

    /// `constant_forces_iter`, collected.
    pub(crate) fn constant_forces(&self) -> Vec<Vector3<f64>> {
        self.constant_forces_iter().collect()
    }

    /// Advance to `target` with internal steps on the grid k·`solver.step`,
    /// the last one shortened to land on `target`; steps are also shortened
    /// to land on events. Stops early when the run is over.
    pub(crate) fn advance_to(&mut self, target: f64) -> Result<Advance, SolverError> {
        let tolerance = self.params.same_instant();
        let mut chatter = Chatter::default();
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
            chatter.before(self.params, self.state);
            let reached = self.step_to(to)?;
            chatter.after(self.state);
            // An event within round-off of `to` counts as reaching it: the
            // step left over would be empty.
            if !reached && to - self.state.time <= tolerance {
                self.state.time = to;
            }
            if to == next_grid && self.state.time == to {
                self.state.grid_step += 1;
                self.restart_pending()?;
                chatter = Chatter::default();
            } else if chatter.steps > self.params.max_steps_in_grid_step {
                return Err(self.stalled(&chatter, next_grid));
            }
        }
    }

    /// The error of a grid step that `max_steps_in_grid_step` steps did not
    /// end, naming the contacts whose events kept shortening them.
    fn stalled(&self, chatter: &Chatter, next_grid: f64) -> SolverError {
        let names: Vec<&str> = (chatter.switching.iter())
            .take(4)
            .map(|&c| self.system.contacts[c].name.as_str())
            .collect();
        let who = match names.len() {
            0 => String::from("events kept shortening them"),
            1 => format!(
                "contact {} switches track part, or lifts off and lands, at every step",
                names[0]
            ),
            _ => format!(
                "contacts {} switch track part, or lift off and land, at every step",
                names.join(", ")
            ),
        };
        let deflection =
            heaviest_and_deflection(self.system, &self.state.dynamic.beam_displacement);
        SolverError {
            time: self.state.time,
            message: format!(
                "no progress: {} steps did not reach the grid point at {} s: {who}, a chatter \
                 no step resolves; {deflection}; with rigid contacts under massive bodies, a \
                 compliant contact law (docs/contact-laws.md)",
                chatter.steps,
                (next_grid * 1e9).round() / 1e9,
            ),
        }
    }

    /// Where the next step of a run's first grid step ends, with a shaped
    /// force profile under RK4: the first two steps have no converged means
    /// to fit (held, then linear: second-order steps, whose error at the
    /// full step outweighs the rest of the run's), so they are an eighth of
    /// the grid step each, and the rest of the grid step is taken in
    /// doubling steps (a fit then spans steps at most twice apart). Adds
    /// three steps to a run.
    pub(crate) fn start_up_target(&self, to: f64) -> f64 {
        let s = &*self.state;
        let fits = self.work.iteration.integrator().fits_force_shape();
        if self.setup.force_profile == ForceProfile::Held || !fits || s.grid_step != 0 {
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
    /// it (a track boundary crossed, an open contact landing), or as far as
    /// its active set settles (`solve_active_set`). Returns whether it
    /// reached `to`.
    pub(crate) fn step_to(&mut self, to: f64) -> Result<bool, SolverError> {
        self.land_at_start()?;
        let full = to - self.state.time;
        let (solution, dt, lifting) = self.solve_extrapolated(full)?;
        let track = self.first_event();
        let landing = self
            .first_landing()
            .filter(|&(f, _)| track.is_none_or(|(g, ..)| f < g));
        // A follower leaving a corner of the track ends the step there
        // (`events/follower.rs`).
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
            self.take_landing((fraction, contact), &solution.forces, dt)?;
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
        } else if dt < full {
            // The active set settled on a shorter step only
            // (`solve_active_set`).
            Ok(false)
        } else {
            self.state.time = to;
            Ok(true)
        }
    }

    /// The step of `dt` solved from the force history extrapolated to its
    /// end (procedure step 1; right after a restart's trials of this same
    /// step, from the last trial's forces: `Stepper::restart_guess`), with
    /// its active set settled (`solve_active_set`).
    fn solve_extrapolated(
        &mut self,
        dt: f64,
    ) -> Result<(StepSolution, f64, Option<usize>), SolverError> {
        let s = &*self.state;
        let mut guess = std::mem::take(&mut self.work.guess);
        guess.clear();
        match self.work.restart_guess.take() {
            Some((step, forces)) if step == dt && forces.len() == s.force_history.len() => {
                guess.extend_from_slice(&forces)
            }
            _ => guess.extend(
                s.force_history
                    .iter()
                    .map(|h| extrapolate(h, &s.step_history, dt)),
            ),
        }
        let solution = self.solve_active_set(&guess, dt);
        self.work.guess = guess;
        solution
    }

    /// The step of `dt` (solved with `forces`) ends where `contact`, the
    /// first to land in it at about `fraction` of it, lands, and it lands.
    fn take_landing(
        &mut self,
        (fraction, contact): (f64, usize),
        forces: &[ContactForce],
        dt: f64,
    ) -> Result<(), SolverError> {
        if fraction == 0.0 {
            // Back on the track within the step it bounced in: the
            // bounce is dropped (a plastic landing now) and the step
            // taken again with the contact closed.
            return self.land(contact, true);
        }
        let Some((solution, dt, contact)) = self.locate_landing(contact, forces, dt)? else {
            return self.land(contact, true);
        };
        self.record_lift_offs();
        self.accept(solution, dt);
        self.record_events(None);
        self.land(contact, false)
    }

    /// Take the step solved into `scratch`.
    pub(crate) fn accept(&mut self, solution: StepSolution, dt: f64) {
        let s = &mut *self.state;
        for (&b, force) in self
            .setup
            .vehicle_first_bodies
            .iter()
            .zip(&s.vehicle_forces)
        {
            let moved = self.work.scratch.bodies[b].position - s.dynamic.bodies[b].position;
            s.external_work += Vector2::new(force[0], force[1]).dot(&moved);
        }
        for (b, (old, new)) in s
            .dynamic
            .bodies
            .iter()
            .zip(&self.work.scratch.bodies)
            .enumerate()
        {
            let moved = new.position - old.position;
            let weight = -self.system.bodies[b].mass * self.system.gravity;
            s.gravity_work += weight * moved.y;
        }
        for (&b, load) in self.system.couplings.iter().zip(&s.coupling_loads) {
            let (old, new) = (&s.dynamic.bodies[b], &self.work.scratch.bodies[b]);
            let moved = new.position - old.position;
            s.external_work +=
                load[0] * moved.x + load[1] * moved.y + load[2] * (new.angle - old.angle);
        }
        s.last_applied.clone_from(&self.work.applied);
        std::mem::swap(&mut s.dynamic, &mut self.work.scratch);
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
        let gaps = self.work.iteration.contact_gaps();
        for ((status, &open), &gap) in s.contacts.iter_mut().zip(&self.work.open).zip(gaps) {
            status.open = open;
            status.gap = gap;
        }
        self.follower_transitions(dt);
    }

    pub(crate) fn solve(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
    ) -> Result<StepSolution, SolverError> {
        self.solve_shaped(guess, dt, self.setup.force_profile)
    }

    /// `solve` with the contact forces shaped by `profile` over the step.
    pub(crate) fn solve_shaped(
        &mut self,
        guess: &[ContactForce],
        dt: f64,
        profile: ForceProfile,
    ) -> Result<StepSolution, SolverError> {
        self.set_force_shapes(dt, profile);
        self.set_drives(dt);
        let mut applied = std::mem::take(&mut self.work.applied);
        applied.clear();
        applied.extend(self.constant_forces_iter());
        let solution = self.solve_with(guess, &applied, dt);
        self.work.applied = applied;
        solution
    }

    /// Each contact's force shape over a step of `dt`, fitted to the means
    /// of the steps before that it was closed in (none at the start, after
    /// a landing: held there).
    pub(crate) fn set_force_shapes(&mut self, dt: f64, profile: ForceProfile) {
        let s = &*self.state;
        // A step whose gap was corrected carries a position-correcting
        // impulse in its mean, not a sample of the smooth force: fitted
        // to, it would be carried on into the next steps' shapes.
        let steps_taken = if s.last_position_iterations > 0 {
            0
        } else {
            s.steps.min(2) as usize
        };
        self.work.shapes.clear();
        self.work
            .shapes
            .extend(s.force_history.iter().map(|history| {
                let closed = history.iter().take_while(|f| f.normal != 0.0).count();
                force_shape(
                    profile,
                    history,
                    &s.step_history,
                    closed.min(steps_taken),
                    dt,
                )
            }));
        self.work.iteration.set_force_shapes(&self.work.shapes);
    }

    /// Each driven body's ẍ over a step of `dt`: the one that brings its
    /// speed to the prescribed one at the step's end.
    pub(crate) fn set_drives(&mut self, dt: f64) {
        let end = self.state.time + dt;
        for (b, speed) in &self.setup.drives {
            let now = self.state.dynamic.bodies[*b].velocity.x;
            self.system.bodies[*b].drive = Some((speed.speed_at(end) - now) / dt);
        }
    }

    pub(crate) fn solve_with(
        &mut self,
        guess: &[ContactForce],
        applied: &[Vector3<f64>],
        dt: f64,
    ) -> Result<StepSolution, SolverError> {
        self.work.unbooked |= !self.work.iteration.integrator_mut().keeps_energy_books();
        let s = &*self.state;
        let solution = self
            .work
            .iteration
            .solve(
                self.system,
                &s.dynamic,
                &s.parts,
                guess,
                applied,
                dt,
                &self.params.iteration,
                &mut self.work.scratch,
            )
            .map_err(|e| step_failure(self.system, s, e))?;
        if !all_finite(self.work.scratch.beam_displacement.as_slice()) {
            return Err(SolverError {
                time: s.time,
                message: "the beam state became non-finite".into(),
            });
        }
        Ok(solution)
    }
}

/// Whether every entry of `x` is finite, in one pass that vectorises:
/// x − x is NaN exactly where x is not finite, and a NaN stays in a sum
/// (nalgebra's element iterator with an exit per entry cost some 15
/// instructions an entry, a twentieth of a 2,500-element beam's step).
#[allow(clippy::eq_op)] // x − x: the test, not a mistake
fn all_finite(x: &[f64]) -> bool {
    let chunks = x.chunks_exact(4);
    let rest = chunks.remainder();
    let mut sums = [0.0f64; 4];
    for chunk in chunks {
        for (sum, x) in sums.iter_mut().zip(chunk) {
            *sum += x - x;
        }
    }
    sums.iter().chain(rest).all(|s| s.is_finite())
}

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

/// A failed step's error, naming what most often causes its kind.
fn step_failure(system: &System, s: &SimState, e: crate::iteration::StepError) -> SolverError {
    use crate::iteration::{StepError, FORCE_LAW_STAGE};
    SolverError {
        time: s.time,
        message: match e {
            StepError::LostContact { contact, x, centre } => {
                lost_contact(system, s, (contact, x, centre))
            }
            StepError::NotConverged { stage, .. } | StepError::Diverged { stage, .. }
                if stage == FORCE_LAW_STAGE =>
            {
                format!("{e}; {}", heaviest_on_laws(system))
            }
            e => e.to_string(),
        },
    }
}

/// A contact lost inside a step, named, with where the iteration's trial
/// put it and the two causes seen: a body far heavier than the beam (a
/// coach of 1e15 kg, thrown 476 km at its first step on the beam), and a
/// rigid contact of a massive body chattering at a kink of the track (a
/// 1,400 kg wheelset entering a 20 m span at 0.75 ms, thrown 24 m up with
/// the beam's displacements at 4.8 mm; `tests/vehicles/no_tension.rs`).
fn lost_contact(system: &System, s: &SimState, (c, x, centre): (usize, f64, [f64; 2])) -> String {
    let name = system.contacts.get(c).map_or("?", |c| c.name.as_str());
    let deflection = largest_displacement(&s.dynamic.beam_displacement);
    format!(
        "no foot point of {name} on the beam could be found (last abscissa {} m): a trial of \
         the contact iteration put it {} m {} the beam's axis at x = {} m, with the beam's \
         displacements at {} m at the step's start: the contact forces it tried diverged. \
         Either a body is too heavy for the beam (the heaviest is {}; lighter bodies or a \
         stiffer beam keep the contacts on the track), or a rigid contact chatters at a kink \
         of the track, a beam's end or a joint (a compliant contact law is well posed there: \
         docs/contact-laws.md)",
        short(x),
        short(centre[1].abs()),
        if centre[1] < 0.0 { "below" } else { "above" },
        short(centre[0]),
        short(deflection),
        heaviest_body(system)
    )
}

/// `x` to four significant digits, in words' width.
fn short(x: f64) -> String {
    crate::numbers::fmt_number(format!("{x:.3e}").parse().unwrap_or(x))
}

/// The largest |u| of the beam's coordinates.
fn largest_displacement(u: &DVector<f64>) -> f64 {
    u.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// What most often loses a contact: the beam's largest displacement and
/// the heaviest body, in words.
pub(crate) fn heaviest_and_deflection(system: &System, u: &DVector<f64>) -> String {
    use crate::numbers::fmt_number;
    let deflection = largest_displacement(u);
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
        crate::numbers::fmt_number(mass)
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
    fn all_finite_finds_a_non_finite_entry_wherever_it_is() {
        for n in [0usize, 1, 3, 4, 5, 9, 4900] {
            let x: Vec<f64> = (0..n).map(|i| 1e300 * libm::sin(i as f64)).collect();
            assert!(all_finite(&x), "{n}");
            for at in [0, n / 2, n.saturating_sub(1)]
                .into_iter()
                .filter(|_| n > 0)
            {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut y = x.clone();
                    y[at] = bad;
                    assert!(!all_finite(&y), "{n} entries, {bad} at {at}");
                }
            }
        }
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
