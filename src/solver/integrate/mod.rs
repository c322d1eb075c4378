//! Time integration of beam and bodies over one step with the contact forces
//! held: the paper's explicit RK4, or HHT-α (implicit, unconditionally
//! stable for the beam) for stiff meshes. Each implements `TimeIntegrator`
//! (its step and its answers to the capability queries) and serves the
//! contact-force iteration through `Integrator`, generated from the one
//! list below.

#[macro_use]
mod dispatch; // first: `integrators!`, used below
mod choice;
mod hht_energy;
mod hht_scheme;
mod load_footprint;
mod memo;
mod profile;
mod step_end;

// The integrators, one line each: its variant (whose lowercase is its
// scene name) and its module and type, which implements `TimeIntegrator`.
integrators! {
    /// Classical fourth-order Runge-Kutta, the paper's scheme (explicit).
    #[default]
    Rk4 => rk4::Rk4,
    /// HHT-α for the beam (implicit, unconditionally stable), damping
    /// `numerical_damping`.
    Hht => hht::Hht,
}

use nalgebra::{DVector, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::body::{BodyState, ContactRotations};
use crate::contact::{ContactForce, ContactFrame};
use crate::force_element::add_element_forces;
use crate::system::{System, TrackPart};

pub use choice::{auto_pick, choose_integrator, rk4_step_limit, AUTO_MIN_DAMPING};
use choice::{build_within_limit, Built};
pub use load_footprint::LoadFootprint;
pub use memo::FrameMemo;
pub use profile::{force_shape, ForceProfile, ForceShape};
pub use step_end::EndForces;
// The state a step advances is the state's (state/), named here too for
// the integrators and the iteration.
pub use crate::state::DynamicState;

/// What one step starts from: the state, its contact frames (the same for
/// every iteration of the step), the constant forces on each body (applied
/// forces and weight, held over the step) and the step length.
#[derive(Debug, Clone, Copy)]
pub struct StepStart<'a> {
    pub state: &'a DynamicState,
    pub frames: &'a [ContactFrame],
    /// Where each contact is along the track (fixed over the step).
    pub parts: &'a [TrackPart],
    pub applied: &'a [Vector3<f64>],
    pub dt: f64,
    /// Each contact's force shape over the step (RK4; HHT-α's unknown is
    /// the end-of-step force and ignores it).
    pub shapes: &'a [ForceShape],
}

/// What the contact iteration measured at an integration's end, handed to
/// the next integration whose prediction that end is
/// (`TimeIntegrator::know_prediction`).
pub struct KnownAtPrediction<'a> {
    pub frames: &'a [ContactFrame],
    /// The force laws there.
    pub laws: KnownLaws<'a>,
}

/// The force laws at a configuration (`KnownAtPrediction`).
pub struct KnownLaws<'a> {
    /// The force elements' loads on each body (each the sum over the
    /// elements from zero, as `add_element_forces` makes it) and the
    /// dampers' power.
    pub element_loads: &'a [Vector3<f64>],
    pub element_power: f64,
    /// Per contact: a follower's gap and gap rate (`follower_gap`; any
    /// value for the other contacts).
    pub follower_gaps: &'a [(f64, f64)],
}

/// Failure of one integration.
#[derive(Debug, Clone, PartialEq)]
pub enum IntegrationError {
    /// No foot point: a body is far from the beam or the beam is wildly
    /// deformed. `centre`: the contact's point (x, y) the search started
    /// from, the last abscissa `x`.
    LostContact {
        contact: usize,
        x: f64,
        centre: [f64; 2],
    },
    /// The implicit scheme's effective matrix for a step of `step` seconds
    /// has no factor (a non-positive pivot met by rounding on a very fine
    /// mesh).
    Factorization { step: f64, reason: String },
}

/// Contact frames of every contact at the start of a run: each searched
/// from its body's abscissa, on the part of the track that abscissa lies on.
pub fn contact_frames_at_bodies(
    system: &System,
    u: &DVector<f64>,
    bodies: &[BodyState],
    frames: &mut Vec<ContactFrame>,
) -> Result<(), IntegrationError> {
    let guesses: Vec<f64> = system
        .contacts
        .iter()
        .map(|c| c.point(&bodies[c.body]).position.x)
        .collect();
    let parts: Vec<TrackPart> = guesses.iter().map(|&x| system.track_part(x)).collect();
    contact_frames(system, u, bodies, (&guesses, &parts), frames)
}

/// Contact frames of every contact for the given configuration, on the
/// parts of the track in `parts` (where each contact was at the start of
/// the step), searched from the foot points in `guesses`.
#[inline]
pub fn contact_frames(
    system: &System,
    u: &DVector<f64>,
    bodies: &[BodyState],
    (guesses, parts): (&[f64], &[TrackPart]),
    frames: &mut Vec<ContactFrame>,
) -> Result<(), IntegrationError> {
    // Each frame written in its slot: a frame returned and pushed was
    // copied twice, a sixth of the frames' cost on a train's ground.
    let n = system.contacts.len();
    if frames.len() != n {
        frames.clear();
        frames.resize(n, ContactFrame::on_ground(&Vector2::zeros()));
    }
    let mut rotations = ContactRotations::default();
    for (c, contact) in system.contacts.iter().enumerate() {
        let centre = &(contact.point_turned(&bodies[contact.body], &mut rotations)).position;
        if system.on_flat_ground(centre, parts[c]) {
            frames[c] = ContactFrame::on_ground(centre);
            continue;
        }
        match system.contact_frame(u, centre, guesses[c], parts[c]) {
            Ok(frame) => frames[c] = frame,
            Err(e) => {
                frames.truncate(c);
                return Err(IntegrationError::LostContact {
                    contact: c,
                    x: e.last_x,
                    centre: [centre.x, centre.y],
                });
            }
        }
    }
    Ok(())
}

/// All loads for contact `forces` at `frames`: the beam's load vector into
/// `beam_load` (overwritten) and each body's generalized force (F_x, F_y,
/// torque) into `body_loads`: `applied`, the contact forces and the force
/// elements. A follower's force comes from its suspension law at this
/// configuration (`beam_velocity` gives its gap rate), not from `forces`.
/// Returns the power the dampers dissipate.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn loads(
    system: &System,
    frames: &[ContactFrame],
    forces: &[ContactForce],
    applied: &[Vector3<f64>],
    bodies: &[BodyState],
    beam_velocity: &DVector<f64>,
    beam_load: &mut DVector<f64>,
    body_loads: &mut [Vector3<f64>],
) -> f64 {
    let loads = (beam_load, &mut *body_loads);
    let at = (bodies, beam_velocity);
    let followers = HeldFollowers::<()>::default();
    loads_but_laws(system, frames, (forces, followers), applied, at, loads)
        + add_element_forces(&system.force_elements, bodies, body_loads)
}

/// Which followers' forces a step holds as given (`held`, per contact;
/// empty: none, each from its law), and where to record every follower's
/// force the loads used (`used`; empty: not recorded).
#[derive(Default)]
pub struct HeldFollowers<'a, K: KnownGaps = ()> {
    pub held: &'a [bool],
    pub used: &'a mut [ContactForce],
    /// Per contact: a follower's gap and gap rate at this configuration,
    /// where already known (`()`: none, each measured here, with the code
    /// of before they could be known).
    pub gaps: K,
}

/// A follower's gap and rate at the configuration of the loads, where
/// known (`HeldFollowers::gaps`).
pub trait KnownGaps {
    fn known(&self, contact: usize) -> Option<(f64, f64)>;
}

impl KnownGaps for () {
    #[inline(always)]
    fn known(&self, _contact: usize) -> Option<(f64, f64)> {
        None
    }
}

impl KnownGaps for &[(f64, f64)] {
    #[inline(always)]
    fn known(&self, contact: usize) -> Option<(f64, f64)> {
        self.get(contact).copied()
    }
}

/// `loads` without the force elements; a follower whose force is held
/// (`HeldFollowers`) takes it from `forces` instead of its law.
#[inline]
pub fn loads_but_laws<K: KnownGaps>(
    system: &System,
    frames: &[ContactFrame],
    forces: (&[ContactForce], HeldFollowers<K>),
    applied: &[Vector3<f64>],
    at: (&[BodyState], &DVector<f64>),
    (beam_load, body_loads): (&mut DVector<f64>, &mut [Vector3<f64>]),
) -> f64 {
    beam_load.as_mut_slice().fill(0.0); // a memset: DVector::fill goes entry by entry
    add_loads_but_laws(system, frames, forces, applied, at, (beam_load, body_loads))
}

/// `loads_but_laws` added to `beam_load` as it is (zero but where the
/// caller's `LoadFootprint` says); `body_loads` overwritten.
#[inline]
pub fn add_loads_but_laws<K: KnownGaps>(
    system: &System,
    frames: &[ContactFrame],
    (forces, followers): (&[ContactForce], HeldFollowers<K>),
    applied: &[Vector3<f64>],
    (bodies, beam_velocity): (&[BodyState], &DVector<f64>),
    (beam_load, body_loads): (&mut DVector<f64>, &mut [Vector3<f64>]),
) -> f64 {
    body_loads.copy_from_slice(applied);
    let mut dissipation = 0.0;
    let mut rotations = ContactRotations::default();
    let contacts = system.contacts.iter().zip(frames).zip(forces);
    for (c, ((contact, frame), force)) in contacts.enumerate() {
        let follower_force;
        let force = match contact.follower {
            Some(follower) => {
                let (gap, rate) = match followers.gaps.known(c) {
                    Some(known) => known,
                    None => {
                        let at = (bodies, beam_velocity);
                        follower_gap_turned(system, contact, frame, at, &mut rotations)
                    }
                };
                dissipation += follower.dissipation(gap, rate);
                follower_force = match followers.held.get(c) {
                    Some(true) => *force,
                    _ => ContactForce {
                        tangential: 0.0,
                        normal: follower.force(gap, rate),
                    },
                };
                if let Some(used) = followers.used.get_mut(c) {
                    *used = follower_force;
                }
                &follower_force
            }
            None => force,
        };
        if frame.on_beam {
            let (t_row, n_row) = frame.beam_rows(system.beam.surface_offset);
            let (tangential, normal) = ((&t_row, -force.tangential), (&n_row, -force.normal));
            system
                .beam
                .scatter_rows(&frame.shape, tangential, normal, beam_load);
        }
        let on_body = frame.tangent() * force.tangential + frame.normal() * force.normal;
        let load = &mut body_loads[contact.body];
        load.x += on_body.x;
        load.y += on_body.y;
        let body = &bodies[contact.body];
        load.z += force.tangential * contact.radius()
            + contact.torque_turned(body, &on_body, &mut rotations);
    }
    dissipation
}

/// A follower's gap g (from its body's centre to the surface along the
/// normal) and gap rate ġ at `frame`.
pub fn follower_gap(
    system: &System,
    contact: &crate::contact::Contact,
    frame: &ContactFrame,
    bodies: &[BodyState],
    beam_velocity: &DVector<f64>,
) -> (f64, f64) {
    let state = &contact.point(&bodies[contact.body]);
    frame.gap_and_rate(&system.beam, state, beam_velocity)
}

/// `follower_gap` with the body's rotation from `rotations` (kept for
/// `bodies`): the same bits.
#[inline]
fn follower_gap_turned(
    system: &System,
    contact: &crate::contact::Contact,
    frame: &ContactFrame,
    (bodies, beam_velocity): (&[BodyState], &DVector<f64>),
    rotations: &mut ContactRotations,
) -> (f64, f64) {
    let state = &contact.point_turned(&bodies[contact.body], rotations);
    frame.gap_and_rate(&system.beam, state, beam_velocity)
}

/// The power every follower's damper dissipates at the given configuration.
pub fn follower_dissipation(
    system: &System,
    frames: &[ContactFrame],
    bodies: &[BodyState],
    beam_velocity: &DVector<f64>,
) -> f64 {
    let contacts = system.contacts.iter().zip(frames);
    let mut rotations = ContactRotations::default();
    contacts
        .filter_map(|(contact, frame)| {
            let follower = contact.follower?;
            let at = (bodies, beam_velocity);
            let (gap, rate) = follower_gap_turned(system, contact, frame, at, &mut rotations);
            Some(follower.dissipation(gap, rate))
        })
        .sum()
}

/// Every follower's force at the given configuration into `forces` (the
/// other contacts' are left as they are).
pub fn follower_forces(
    system: &System,
    frames: &[ContactFrame],
    bodies: &[BodyState],
    beam_velocity: &DVector<f64>,
    forces: &mut [ContactForce],
) {
    let mut rotations = ContactRotations::default();
    for ((contact, frame), force) in system.contacts.iter().zip(frames).zip(forces) {
        if let Some(follower) = contact.follower {
            let at = (bodies, beam_velocity);
            let (gap, rate) = follower_gap_turned(system, contact, frame, at, &mut rotations);
            *force = ContactForce {
                tangential: 0.0,
                normal: follower.force(gap, rate),
            };
        }
    }
}

/// What an integrator is to the rest of guideway: how it is built and
/// described, its step, and the capability queries the stepper, the
/// iteration, the chooser and validation ask instead of its name. A new
/// integrator is one file implementing this and one line in the list of
/// integrators (`integrators!`, above).
pub trait TimeIntegrator: Sized {
    /// Its name in a scene (`solver.integrator`), which also starts its
    /// description.
    const NAME: &'static str;
    /// How a refusal of its step names it ("explicit RK4").
    const TITLE: &'static str;
    /// Whether it carries each step's end accelerations and contact forces
    /// into the next step, so that it must restart where a contact switches
    /// surfaces or meets an impact.
    const CARRIES_STEP_END: bool;
    /// Whether its stages sample the contact force's shape within a step,
    /// so that a shaped `force_profile` means something (and needs
    /// start-up steps); otherwise only the held profile is accepted.
    const FITS_FORCE_SHAPE: bool;
    /// Whether the force elements are evaluated at a predicted end
    /// configuration that the iteration must refine, rather than in the
    /// scheme's own stages.
    const LAGS_FORCE_LAWS: bool;
    /// Whether it steps the rail layer over the deck (whose effective
    /// matrix is built for it).
    const STEPS_TRACK_ON_DECK: bool;
    /// Whether the held contact forces act in the frames of the predicted
    /// end (the last integration's), not the step's start, and the end's
    /// displacements answer the end forces `body_weights`' ratio times the
    /// velocities (a Newmark-family scheme): the contact iteration's
    /// operator is then the step's exact Jacobian (`iteration::turn_rates`).
    const HOLDS_FORCES_AT_END: bool;

    /// The integrator for `system` on steps of `step` with numerical
    /// damping `damping` (where it has any), and its description.
    fn build(system: &System, step: f64, damping: f64) -> Result<(Self, String), String>;
    /// The largest stable step for `system` (s); None: stable at any step.
    fn stable_step(system: &System) -> Option<f64>;
    /// Its order of accuracy in time with the force profile `profile`.
    fn order(profile: ForceProfile) -> f64;

    /// Called once before the iterations of each step of `dt`.
    fn begin_step(&mut self, system: &System, dt: f64) -> Result<(), IntegrationError>;
    /// Advance from `from` over its step with `forces` held, into `end`.
    fn step(
        &mut self,
        system: &System,
        from: &StepStart,
        forces: &[ContactForce],
        end: &mut DynamicState,
    ) -> Result<(), IntegrationError>;
    /// Called once after the iterations of a step that converged, with its
    /// last integration in `end`: what only the accepted step needs.
    fn finish_step(&mut self, _system: &System, _from: &StepStart, _end: &mut DynamicState) {}
    /// Book the energy the steps remove, or not (a scheme that books it
    /// in its stages always does).
    fn keep_energy_books(&mut self, _on: bool) {}
    /// Whether the steps' energy is booked (see `keep_energy_books`).
    fn keeps_energy_books(&self) -> bool {
        true
    }
    /// From the next integration on, the compliant followers' forces
    /// (`held`, per contact) are the ones the iteration gives, not their
    /// laws' at the predicted end (a scheme that lags its force laws).
    fn hold_followers(&mut self, _held: &[bool]) {}
    /// Whether a step's first integration predicts its end with the
    /// start's accelerations (u0 + Δt v0 + ½Δt² a0, v0 + Δt a0) rather
    /// than at constant velocity (a scheme that lags its force laws).
    fn predict_with_accelerations(&mut self, _on: bool) {}
    /// The next step, if it is `dt` long, predicts its first integration
    /// at `end` instead of from its start (a scheme that lags its force
    /// laws): where a step is solved again from almost the same start (a
    /// restart's trial steps and the step after them), the force elements
    /// are then taken near where they end. None forgets it; the step after
    /// the next never sees it.
    fn seed_prediction(&mut self, _end: Option<(&DynamicState, f64)>) {}
    /// The bodies of the end the step being solved took as its first
    /// prediction (`seed_prediction`), from `begin_step` to the next.
    fn seeded_bodies(&self) -> Option<&[BodyState]> {
        None
    }
    /// Every follower's force in the last integration (empty where the
    /// scheme evaluates them in its stages).
    fn held_follower_forces(&self) -> &[ContactForce] {
        &[]
    }
    /// K u + C v at the last accepted step's end, where the scheme keeps
    /// them (see `EndForces`); None where it does not.
    fn end_forces(&self) -> Option<&EndForces> {
        None
    }
    /// Lagged force laws: the force elements' loads on each body in the
    /// last integration and the bodies the next evaluates them at; None
    /// where the scheme evaluates them in its stages.
    fn body_predictions(&mut self) -> Option<(&[Vector3<f64>], &mut [BodyState])> {
        None
    }
    /// Lagged force laws: what the caller measured at the last
    /// integration's end, which is the next one's prediction while nobody
    /// moves it: every contact's frame there (found on the step's parts of
    /// the track) and the force elements' loads on each
    /// body and their dampers' power (`KnownAtPrediction`). The next
    /// integration takes them instead of searching and evaluating them
    /// again at the same configuration.
    fn know_prediction(&mut self, _known: KnownAtPrediction) {}
    /// How a body's end-of-step velocity and position respond to the
    /// force at the end of the step, per unit of acceleration it causes.
    fn body_weights(&self, dt: f64) -> (f64, f64);
    /// The band factor and weights the beam's responses on the nominal
    /// step are made of, where they are a plain band solve; else None.
    fn nominal_band_response(&self) -> Option<(&crate::band::BandLdlt, f64, f64)> {
        None
    }
    /// The structure's compliance at a contact over a nominal step: the
    /// displacement and velocity along `row` on `shape` that `beam_response`
    /// gives to a unit load along the same row, read from the effective
    /// matrix's inverse within its band. None off the nominal step, where
    /// that inverse is not kept (a modal or two-level factor) or where the
    /// scheme has no effective matrix.
    fn point_compliance(
        &mut self,
        _system: &System,
        _shape: &crate::beam::Shape,
        _row: &[f64; 4],
        _dt: f64,
    ) -> Option<(f64, f64)> {
        None
    }
    /// Displacement and velocity of the beam alone after `dt` under a
    /// constant `load`, from rest: the step's response to a unit contact
    /// load, from which the iteration builds its Delassus operator.
    fn beam_response(
        &mut self,
        system: &System,
        load: &DVector<f64>,
        dt: f64,
        displacement: &mut DVector<f64>,
        velocity: &mut DVector<f64>,
    );
}

#[cfg(test)]
pub(crate) mod fixtures {
    use crate::scene::{BodyKind, Scene};

    /// Two paper wheels on a four-element beam, in different elements
    /// (at 3 m and 15.5 m).
    pub fn two_paper_wheels() -> Scene {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        scene.beam.elements = 4;
        scene.vehicles[0].initial_position = 3.0;
        let mut second = scene.vehicles[0].clone();
        second.name = "second".into();
        second.initial_position = 15.5;
        scene.vehicles.push(second);
        scene
    }
}
