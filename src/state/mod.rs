//! The state of a run: everything needed to continue it bit-identically
//! (beam and bodies, contact forces and statuses, the event log, the energy
//! books), the checks a state from outside (a forged or corrupted FMU
//! state) must pass, and its copy for roll-back (`copy`).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::contact::ContactForce;
use crate::system::{System, TrackPart};

mod consistency;
mod copy;
mod dynamic;

pub use dynamic::DynamicState;

/// Events kept per run; later ones are counted, not kept (the solver's
/// `SolverParameters::max_events` is this bound).
pub const MAX_EVENTS: usize = 10_000;

/// What happened to a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// The contact point rolled onto the beam.
    Entry,
    /// The contact point left the beam (onto rigid ground, or off the track).
    Exit,
    /// The contact point left the track: the run ends.
    LeftTrack,
    /// The contact opened: its normal force would have turned tensile in
    /// the step from this instant.
    LiftOff,
    /// An open contact's gap closed: an impact (which may bounce); a
    /// massless follower's law turned compressive again: no impact.
    Landing,
}

/// Whether a contact is closed (the paper's rows) or open (in flight), its
/// gap, and its last impact.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ContactStatus {
    pub open: bool,
    /// Gap g to the track at the current time (m): zero to the gap
    /// tolerance while closed.
    pub gap: f64,
    /// The impulse of the last impact on the body (N s): tangential, normal.
    pub impulse: [f64; 2],
    /// The grid step in which it last opened: a contact opens at most once
    /// per grid step (see `solver::events::active_set`).
    pub opened_in: Option<u64>,
    /// The grid step in which it last landed: a second landing in the same
    /// grid step is plastic (see `solver::events::landing`).
    #[serde(default)]
    pub landed_in: Option<u64>,
}

/// An event located inside a step (the step is shortened to its instant).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactEvent {
    pub contact: usize,
    pub time: f64,
    pub kind: EventKind,
}

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
    /// The applied force (fx, fy) on each vehicle's first body, held
    /// until changed (the FMU's inputs).
    pub vehicle_forces: Vec<[f64; 2]>,
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
    /// Per contact: closed or open, gap, last impact.
    pub contacts: Vec<ContactStatus>,
    /// Kinetic energy removed by impacts since t = 0 (J).
    pub impact_loss: f64,
    /// The additional load (fx, fy, moment) on each coupling point
    /// (`System::couplings`), held until changed (the FMU's inputs).
    #[serde(default)]
    pub coupling_loads: Vec<[f64; 3]>,
    /// The constant generalized force on each body over the last step
    /// taken (empty before the first): the accelerations reported at its
    /// end are those of the loads that acted, whatever was set since.
    #[serde(default)]
    pub last_applied: Vec<Vector3<f64>>,
    /// Contacts whose HHT-α restart fitted a step shorter than the grid
    /// step (after an event inside it): restarted again at the next grid
    /// point, for the full steps that follow.
    #[serde(default)]
    pub pending_restart: Vec<usize>,
}

impl SimState {
    /// Every number finite, the beam's vectors alike in length, and the
    /// time on the state's own grid of `step`: what a state from outside (a
    /// serialized FMU state) must satisfy before anything is sized by it.
    pub fn check_values(&self, step: f64) -> Result<(), String> {
        self.check_lengths()?;
        self.check_finite()?;
        self.check_time(step)
    }

    /// Every number finite. One branch-free sum over every number first
    /// (this runs after every FMU step); the number is looked for only when
    /// there is one.
    fn check_finite(&self) -> Result<(), String> {
        if self.not_finite_sum() != 0.0 {
            if let Some(x) = self.first_not_finite() {
                return Err(format!("the state holds a non-finite number ({x})"));
            }
        }
        Ok(())
    }

    /// The state's scalars that `check_values` checks.
    fn scalars(&self) -> [f64; 12] {
        let d = &self.dynamic;
        [
            self.time,
            self.external_work,
            self.gravity_work,
            self.initial_energy,
            self.last_velocity_error,
            self.last_gap_error,
            self.exit_time.unwrap_or(0.0),
            d.dissipated,
            d.beam_dissipated,
            d.tractive_work,
            d.numerical_dissipation,
            self.impact_loss,
        ]
    }

    /// The beam's vectors.
    fn beam_vectors(&self) -> [&nalgebra::DVector<f64>; 4] {
        let d = &self.dynamic;
        let (u, v) = (&d.beam_displacement, &d.beam_velocity);
        [u, v, &d.beam_acceleration, &d.beam_load]
    }

    /// 0 when every number of the state is finite, NaN otherwise.
    fn not_finite_sum(&self) -> f64 {
        let d = &self.dynamic;
        let mut nan = not_finite(&self.scalars())
            + not_finite(&self.step_history)
            + not_finite(self.vehicle_forces.as_flattened())
            + not_finite(&d.contact_x);
        for e in &self.events {
            nan += not_finite(&[e.time]);
        }
        for c in &self.contacts {
            nan += not_finite(&[c.gap, c.impulse[0], c.impulse[1]]);
        }
        for b in &d.bodies {
            nan += not_finite(&b.numbers());
        }
        for f in self.force_history.iter().flatten() {
            nan += not_finite(&[f.tangential, f.normal]);
        }
        for v in d.body_accelerations.iter().chain(&d.body_loads) {
            nan += not_finite(v.as_slice());
        }
        for v in self.beam_vectors() {
            nan += not_finite(v.as_slice());
        }
        nan
    }

    /// The first number of the state that is not finite.
    fn first_not_finite(&self) -> Option<f64> {
        let d = &self.dynamic;
        let forces = (self.force_history.iter().flatten()).flat_map(|f| [f.tangential, f.normal]);
        let generalized = d.body_accelerations.iter().chain(&d.body_loads).flatten();
        let statuses = (self.contacts.iter()).flat_map(|c| [c.gap, c.impulse[0], c.impulse[1]]);
        let mut all = (self.scalars().into_iter())
            .chain(self.step_history)
            .chain(self.vehicle_forces.iter().flatten().copied())
            .chain(d.contact_x.iter().copied())
            .chain(self.events.iter().map(|e| e.time))
            .chain(statuses)
            .chain(d.bodies.iter().flat_map(crate::body::BodyState::numbers))
            .chain(forces)
            .chain(generalized.copied())
            .chain(self.beam_vectors().into_iter().flatten().copied());
        all.find(|x| !x.is_finite())
    }

    /// `check_values` but the numbers' finiteness (`copy_checked_from`
    /// sums them as it copies).
    fn check_lengths_and_time(&self, step: f64) -> Result<(), String> {
        self.check_lengths()?;
        self.check_time(step)
    }

    /// The beam's vectors alike in length.
    fn check_lengths(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// The time on the state's own grid of `step`.
    fn check_time(&self, step: f64) -> Result<(), String> {
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

/// 0 when every number of `xs` is finite, NaN otherwise: x − x is 0 for a
/// finite x and NaN for an infinite or NaN one, so the sum needs no branch
/// per number.
#[allow(clippy::eq_op)] // x − x is the point: 0 or NaN
fn not_finite(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0, |sum, &x| sum + (x - x))
}

/// Record an event of contact `c` at the state's time (counted, not kept,
/// beyond `MAX_EVENTS`).
pub(crate) fn push_event(s: &mut SimState, c: usize, kind: EventKind) {
    let time = s.time;
    push_event_at(s, c, kind, time);
}

/// Record an event of contact `c` at `time` (counted, not kept, beyond
/// `MAX_EVENTS`).
pub(crate) fn push_event_at(s: &mut SimState, c: usize, kind: EventKind, time: f64) {
    if s.events.len() < MAX_EVENTS {
        s.events.push(ContactEvent {
            contact: c,
            time,
            kind,
        });
    } else {
        s.events_dropped += 1;
    }
}

/// Refuse a state whose vectors do not fit `system` (a state is untrusted
/// input: it may come from another model or be corrupted).
pub fn check_shape(system: &System, state: &SimState) -> Result<(), String> {
    let d = &state.dynamic;
    let n = system.beam.coordinates();
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
        ("contact states", state.contacts.len(), contacts),
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
    let loads =
        (state.coupling_loads.iter().flatten()).chain(state.vehicle_forces.iter().flatten());
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
    if !state.parts.iter().all(|&p| system.has_part(p)) {
        return Err(
            "the state names a piece or joint of the track this model does not have".into(),
        );
    }
    if state.pending_restart.iter().any(|&c| c >= contacts) {
        return Err("the state's pending restarts name a contact this model does not have".into());
    }
    if state.events.len() > MAX_EVENTS || state.events.iter().any(|e| e.contact >= contacts) {
        return Err("the state's event list does not fit this model".into());
    }
    Ok(())
}
