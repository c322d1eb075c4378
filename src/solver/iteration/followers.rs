//! A secant (Newton) step for the compliant contact laws under HHT-α.
//!
//! HHT-α evaluates a follower's law (Hertz, an EMS magnet) at the end
//! configuration predicted by the previous integration of the step, so the
//! plain fixed point f ← F(end(f)) contracts by ρ ≈ k (w_body + w_track),
//! with k the law's stiffness linearised and w the step's compliances of
//! the body and of the track under it. A Hertz wheelset on a light rail
//! converges slowly (8.0 integrations a step on the rail over the deck,
//! 2.8 for massless followers on the bare deck). So once the plain fixed
//! point has taken two integrations of a step without settling it, each
//! compliant follower's force becomes the iteration's own unknown: held
//! over each integration and updated by a secant step on its residual
//! r = F(end) − f, with the slope of F(end) against f measured on the last
//! two integrations. The converged step is the same fixed point, f =
//! F(end), to the tolerance (`laws_settled`); only the way there changes.
//! Suspension followers keep the plain fixed point (their bodies are
//! heavy: it converges in two or three integrations). Where every contact
//! is compliant, the secant step starts at the first integration and a
//! step is settled on its residuals (`settled_on_residuals`), one
//! integration sooner than by measuring the bodies' last change. There
//! the first slope takes the structure's compliance under the contact
//! from the effective matrix's inverse within its band
//! (`TimeIntegrator::point_compliance`), and each next integration's
//! bodies are predicted where the new forces will move them, so that the
//! force elements do not lag an integration behind (`anticipate_bodies`):
//! on the rail a step then settles in two integrations, not three.

use nalgebra::Vector3;

use super::laws::response;
use super::ContactIteration;
use crate::contact::ContactForce;
use crate::contact_law::LawKind;
use crate::force_element::add_element_forces;
use crate::integrate::{follower_forces, follower_gap, DynamicState, KnownLaws};
use crate::system::System;

/// The slope s of F(end) against f a secant step uses, bounded: a
/// measured s ≥ 1 would step away from the fixed point, and one far below
/// −1 comes from a law crossing a kink (lift-off, saturation) between the
/// two integrations.
const SLOPE_RANGE: (f64, f64) = (-20.0, 0.5);

/// Where every contact is compliant, a step is settled once the change its
/// residuals would make is within this share of the velocity tolerance
/// (or within the tolerance where the bodies' last change also was): the
/// integration accepted is then the one measured, not the one after it.
/// At 0.03 every kind of output of `train-8-coaches-3x25-300` ends nearer
/// the converged step than the old test left it; at 0.1 half of them ended
/// 1.7 times farther (docs/performance-log.md, "The contact iteration's cost").
const RESIDUAL_SHARE: f64 = 0.03;

/// Per compliant follower: the force held over the last integration and
/// the law's force at its end, for the last two integrations.
#[derive(Default)]
pub(super) struct Secant {
    /// Whether the contact's force is the iteration's (compliant law).
    pub compliant: Vec<bool>,
    /// Whether this step's forces are held (from its first secant step).
    holding: bool,
    /// The integration (its count in the step) whose laws' forces
    /// `first_used` holds, while the plain fixed point runs.
    first: Option<u32>,
    first_used: Vec<f64>,
    /// (held, law at the end) of the last and the one before.
    last: Vec<Option<(f64, f64)>>,
    before: Vec<Option<(f64, f64)>>,
    /// The laws' forces at the end of the last integration.
    at_end: Vec<ContactForce>,
    /// Whether every contact is a compliant follower: then a step is
    /// settled on its residuals (`settled_on_residuals`).
    every: bool,
    /// Per body: the generalized force the residuals would change.
    change: Vec<Vector3<f64>>,
    /// Per body: the force elements' generalized force at the end, and
    /// their dampers' power there, while the end is the last one measured;
    /// per contact, a follower's gap and rate there.
    elements: Vec<Vector3<f64>>,
    elements_power: Option<f64>,
    gaps: Vec<(f64, f64)>,
    /// Per contact: the structure's compliance under it over the step
    /// (displacement, velocity per unit force), for a first secant step.
    structure: Vec<(f64, f64)>,
    /// Whether the first slope leaves out the structure's compliance and
    /// the next integration's bodies are not anticipated: only where a
    /// test measures what they save (`aid_secant`).
    plain: bool,
}

impl Secant {
    /// `lags`: the integrator evaluates the laws at a predicted end (HHT-α);
    /// RK4 evaluates them in its stages, and nothing is held.
    pub fn new(system: &System, lags: bool) -> Secant {
        let compliant: Vec<bool> = (system.contacts.iter())
            .map(|c| {
                lags && c
                    .follower
                    .is_some_and(|f| !matches!(f.kind, LawKind::Suspension))
            })
            .collect();
        let n = compliant.len();
        Secant {
            every: n > 0 && compliant.iter().all(|&c| c),
            change: Vec::new(),
            elements: Vec::new(),
            elements_power: None,
            gaps: vec![(0.0, 0.0); n],
            structure: Vec::new(),
            plain: false,
            compliant,
            holding: false,
            first: None,
            first_used: vec![0.0; n],
            last: vec![None; n],
            before: vec![None; n],
            at_end: vec![ContactForce::default(); n],
        }
    }

    /// Whether any contact's force is the iteration's.
    pub fn any(&self) -> bool {
        self.compliant.contains(&true)
    }

    /// Whether every contact's force is the iteration's.
    pub fn every(&self) -> bool {
        self.every
    }

    /// The force elements' loads on each body at the last integration's
    /// end, their dampers' power and the followers' gaps, where
    /// `residual_change` evaluated them there.
    pub fn laws_at_end(&self) -> Option<KnownLaws<'_>> {
        self.elements_power.map(|power| KnownLaws {
            element_loads: &self.elements,
            element_power: power,
            follower_gaps: &self.gaps,
        })
    }

    /// Every contact's law force at the last integration's end, where
    /// `laws_at_end` is known.
    pub fn forces_at_end(&self) -> &[ContactForce] {
        &self.at_end
    }

    /// The next integration moves the end: its laws are not known.
    pub fn forget_laws_at_end(&mut self) {
        self.elements_power = None;
    }

    /// Forget the step before: a new step starts.
    pub fn reset(&mut self) {
        self.last.fill(None);
        self.before.fill(None);
        self.holding = false;
        self.first = None;
    }
}

/// The next force from (held, law at end) pairs: the secant step where
/// two are known and their held forces differ, the plain fixed point else.
fn secant_step(last: (f64, f64), before: Option<(f64, f64)>) -> f64 {
    step_with(last, measured_slope(last, before).unwrap_or(0.0))
}

/// The slope of F(end) against f between two (held, law at end) pairs,
/// bounded (`SLOPE_RANGE`); None where it cannot be measured.
fn measured_slope(last: (f64, f64), before: Option<(f64, f64)>) -> Option<f64> {
    let (held, law) = last;
    before
        .filter(|&(f, _)| f != held)
        .map(|(f, g)| (law - g) / (held - f))
        .filter(|s| s.is_finite())
        .map(|s| s.clamp(SLOPE_RANGE.0, SLOPE_RANGE.1))
}

/// The slope of F(end) against f for a step's first secant step (where
/// none is measured yet): a force f moves the body by w_u f / m and
/// w_v f / m along the normal (`weights`, the end-of-step force's
/// weights) and the structure under the contact the other way by g_u f
/// and g_v f (`structure`, its compliance over the step: 0 where it is not
/// known), against the law's stiffness k and damping c at the end (at its
/// gap there, `gap`, which `residual_change` kept):
/// −k (w_u / m + g_u) − c (w_v / m + g_v). The coupling to the other
/// contacts is left out; the next steps measure it.
fn first_slope(
    system: &System,
    contact: &crate::contact::Contact,
    gap: f64,
    (velocity_weight, position_weight): (f64, f64),
    (structure_u, structure_v): (f64, f64),
) -> f64 {
    let Some(follower) = contact.follower else {
        return 0.0;
    };
    let mass = system.bodies[contact.body].mass;
    let stiffness = follower.kind.stiffness(&follower, gap);
    let slope = -stiffness * (position_weight / mass + structure_u)
        - follower.damping * (velocity_weight / mass + structure_v);
    slope.clamp(SLOPE_RANGE.0, SLOPE_RANGE.1)
}

/// The force a secant step of slope `slope` takes from (held, law at end).
fn step_with((held, law): (f64, f64), slope: f64) -> f64 {
    (held + (law - held) / (1.0 - slope)).max(0.0)
}

impl ContactIteration {
    /// Whether the step is at its fixed point after its `iteration`-th
    /// integration, into `end` (`settled`: whether its bodies settled);
    /// where not, the next integration's compliant forces are set. While the
    /// bodies settle within two integrations the plain fixed point runs
    /// (each integration takes the laws where the last ended, as a secant
    /// step without a slope would, and the laws are evaluated once per
    /// integration); after two that did not, the forces are held and
    /// stepped (`step_laws`), seeded with the laws' forces of those two,
    /// and the step is settled when the bodies are and the laws' residuals
    /// are within `tolerance`.
    pub(super) fn laws_settled(
        &mut self,
        system: &System,
        (dt, tolerance): (f64, f64),
        end: &DynamicState,
        (settled, iteration): (bool, u32),
    ) -> bool {
        if !self.secant.any() {
            return settled;
        }
        if self.secant.every {
            return self.settled_on_residuals(system, (dt, tolerance), end, settled);
        }
        if !self.secant.holding {
            if settled {
                return true;
            }
            let used = self.integrator.held_follower_forces();
            let secant = &mut self.secant;
            if secant.first.is_none_or(|k| k + 1 != iteration) {
                secant.first = Some(iteration);
                secant.first_used.clear();
                secant.first_used.extend(used.iter().map(|f| f.normal));
                return false;
            }
            // The laws' forces at the end of the integration before are
            // those this one took (its prediction was that end).
            for c in (0..used.len()).filter(|&c| secant.compliant[c]) {
                secant.last[c] = Some((secant.first_used[c], used[c].normal));
            }
            secant.holding = true;
        }
        let largest = self.step_laws(system, dt, end);
        settled && largest <= tolerance
    }

    /// After an integration of the step into `end`: the laws' forces at
    /// its end, and each compliant follower's next force by the secant
    /// step into `self.forces`, which the next integration holds. Returns
    /// the largest body velocity change the residuals F(end) − f would
    /// make over the step (m/s): within the velocity tolerance, the step
    /// is at its fixed point as far as the laws go.
    pub(super) fn step_laws(&mut self, system: &System, dt: f64, end: &DynamicState) -> f64 {
        let secant = &mut self.secant;
        let frames = &self.end_frames;
        follower_forces(
            system,
            frames,
            &end.bodies,
            &end.beam_velocity,
            &mut secant.at_end,
        );
        let held = self.integrator.held_follower_forces();
        let velocity_weight = self.integrator.body_weights(dt).0;
        let mut largest: f64 = 0.0;
        for (c, contact) in system.contacts.iter().enumerate() {
            if !secant.compliant[c] {
                continue;
            }
            let pair = (held[c].normal, secant.at_end[c].normal);
            let mass = system.bodies[contact.body].mass;
            largest = largest.max(velocity_weight * (pair.1 - pair.0).abs() / mass);
            secant.before[c] = secant.last[c].replace(pair);
            self.forces[c] = ContactForce {
                tangential: 0.0,
                normal: secant_step(pair, secant.before[c]),
            };
        }
        self.integrator.hold_followers(&self.secant.compliant);
        largest
    }
}

impl ContactIteration {
    /// Where every contact is a compliant follower: whether the step that
    /// ended in `end` is at its fixed point, judged by its residuals, the
    /// laws' forces at the end less those the integration held (or took at
    /// its prediction) and the force elements' loads at the end less those
    /// it took at its prediction. The next integration would change each
    /// body's velocities by its rigid response to those changes
    /// (`residual_change`); within `RESIDUAL_SHARE` of `tolerance` (or
    /// within it where the bodies' velocities also `settled` within it
    /// since the integration before), the step is settled here, without
    /// integrating again to measure that change. Otherwise each follower's
    /// next force is a secant step: at the step's first integration with
    /// the slope its body and the structure under it give (`first_slope`),
    /// then with the slope of the step's last two integrations; then the
    /// next integration's bodies are anticipated (`anticipate_bodies`).
    fn settled_on_residuals(
        &mut self,
        system: &System,
        (dt, tolerance): (f64, f64),
        end: &DynamicState,
        settled: bool,
    ) -> bool {
        let largest = self.residual_change(system, dt, end);
        self.settle_change = largest;
        if largest <= RESIDUAL_SHARE * tolerance || (settled && largest <= tolerance) {
            return true;
        }
        let weights = self.integrator.body_weights(dt);
        self.structure_compliances(system, dt);
        let held = self.integrator.held_follower_forces();
        let secant = &mut self.secant;
        for (c, contact) in system.contacts.iter().enumerate() {
            let pair = (held[c].normal, secant.at_end[c].normal);
            secant.before[c] = secant.last[c].replace(pair);
            let slope = match (measured_slope(pair, secant.before[c]), secant.before[c]) {
                (Some(slope), _) => slope,
                (None, None) => {
                    let structure = secant.structure[c];
                    first_slope(system, contact, secant.gaps[c].0, weights, structure)
                }
                (None, Some(_)) => 0.0,
            };
            self.forces[c] = ContactForce {
                tangential: 0.0,
                normal: step_with(pair, slope),
            };
        }
        self.integrator.hold_followers(&self.secant.compliant);
        if !self.secant.plain {
            self.anticipate_bodies(system, dt, end);
        }
        false
    }

    /// Where every contact is compliant, after the next forces are set:
    /// the next integration's bodies predicted at this end moved by their
    /// rigid response to the change it will apply (the followers' next
    /// forces less those held, and the force elements at this end less
    /// those used), and the force elements and the followers' gaps
    /// evaluated there, handed over with this end's frames. The force
    /// elements no longer lag a whole integration behind the contact
    /// forces (`iteration::laws` does the same for rigid contacts): on
    /// `rail.toml` a step settled after its third integration, its second
    /// left a residual of 0.13 tolerances (median), the primary dampers'
    /// lag ρ ≈ 0.2 % of the first residual's 81. The frames change with
    /// the bodies' move, which vanishes as the step settles; searching
    /// them again cost more than the step's other law evaluations.
    fn anticipate_bodies(&mut self, system: &System, dt: f64, end: &DynamicState) {
        let weights = self.integrator.body_weights(dt);
        let secant = &mut self.secant;
        // `residual_change` left the change the laws at this end would
        // apply; the next forces differ from those by the secant steps.
        let change = &mut secant.change;
        for (c, contact) in system.contacts.iter().enumerate() {
            let step = self.forces[c].normal - secant.at_end[c].normal;
            let on_body = self.end_frames[c].normal() * step;
            let torque = contact.torque(&end.bodies[contact.body], &on_body);
            change[contact.body] += Vector3::new(on_body.x, on_body.y, torque);
        }
        let Some((_, next)) = self.integrator.body_predictions() else {
            self.end_is_prediction = false;
            return;
        };
        Self::moved(system, weights, &end.bodies, |b| change[b], next);
        secant.elements.fill(Vector3::zeros());
        let power = add_element_forces(&system.force_elements, next, &mut secant.elements);
        secant.elements_power = Some(power);
        let contacts = system.contacts.iter().zip(&self.end_frames);
        for ((contact, frame), gaps) in contacts.zip(&mut secant.gaps) {
            if contact.follower.is_some() {
                *gaps = follower_gap(system, contact, frame, next, &end.beam_velocity);
            }
        }
    }

    /// Whether the secant path takes the structure's compliance into its
    /// first slope and anticipates the bodies (`anticipate_bodies`); both
    /// leave the fixed point as it is, and are on unless a test measures
    /// what they save.
    #[cfg(test)]
    pub(crate) fn aid_secant(&mut self, on: bool) {
        self.secant.plain = !on;
    }

    /// Each contact's structure compliance at its end frame over the step
    /// (`TimeIntegrator::point_compliance`) into `secant.structure`, for
    /// the contacts whose first secant step comes next (0 where unknown):
    /// a function of the frame and the step's factor alone, so a restored
    /// state takes the same slopes.
    fn structure_compliances(&mut self, system: &System, dt: f64) {
        let secant = &mut self.secant;
        secant.structure.clear();
        secant.structure.resize(system.contacts.len(), (0.0, 0.0));
        for (c, frame) in self.end_frames.iter().enumerate() {
            if secant.plain || secant.last[c].is_some() || !frame.on_beam {
                continue;
            }
            let row = frame.shape.n.map(|n| frame.cos * n);
            let compliance = self
                .integrator
                .point_compliance(system, &frame.shape, &row, dt);
            secant.structure[c] = compliance.unwrap_or((0.0, 0.0));
        }
    }

    /// The largest change of a body's velocities (m/s, rad/s) that the
    /// residuals of the integration into `end` would make over the step:
    /// each body's rigid response, through the velocity weight of the
    /// end-of-step force, to the followers' and force elements' changes
    /// of its generalized force. Leaves the laws' forces at the end in
    /// `secant.at_end`.
    fn residual_change(&mut self, system: &System, dt: f64, end: &DynamicState) -> f64 {
        let secant = &mut self.secant;
        let frames = &self.end_frames;
        let bodies = &end.bodies;
        // `follower_forces`, with each gap and rate kept for the next
        // integration (`laws_at_end`).
        let contacts = system.contacts.iter().zip(frames);
        let kept = secant.at_end.iter_mut().zip(&mut secant.gaps);
        for ((contact, frame), (force, gaps)) in contacts.zip(kept) {
            if let Some(follower) = contact.follower {
                let (gap, rate) = follower_gap(system, contact, frame, bodies, &end.beam_velocity);
                *gaps = (gap, rate);
                *force = ContactForce {
                    tangential: 0.0,
                    normal: follower.force(gap, rate),
                };
            }
        }
        secant.change.clear();
        secant.change.resize(bodies.len(), Vector3::zeros());
        secant.elements.clear();
        secant.elements.resize(bodies.len(), Vector3::zeros());
        let power = add_element_forces(&system.force_elements, bodies, &mut secant.elements);
        secant.elements_power = Some(power);
        if let Some((used, _)) = self.integrator.body_predictions() {
            for (change, (at_end, used)) in secant
                .change
                .iter_mut()
                .zip(secant.elements.iter().zip(used))
            {
                *change = at_end - used;
            }
        }
        let held = self.integrator.held_follower_forces();
        for (c, contact) in system.contacts.iter().enumerate() {
            let residual = secant.at_end[c].normal - held[c].normal;
            let on_body = frames[c].normal() * residual;
            let b = contact.body;
            let q = Vector3::new(on_body.x, on_body.y, contact.torque(&bodies[b], &on_body));
            secant.change[b] += q;
        }
        let velocity_weight = self.integrator.body_weights(dt).0;
        let (mut largest, mut nan) = (0.0f64, false);
        for (body, q) in system.bodies.iter().zip(&secant.change) {
            let x = velocity_weight * response(body, q).amax();
            nan |= x.is_nan();
            largest = largest.max(x);
        }
        // NaN must win the maximum so that it is reported (tested once,
        // not per body: the per-body test was a third of this sweep).
        if nan {
            f64::NAN
        } else {
            largest
        }
    }
}

#[cfg(test)]
mod tests {
    use super::secant_step;

    #[test]
    fn a_linear_law_is_solved_by_one_secant_step() {
        // F(end(f)) = 100 − 3 f: the plain fixed point diverges (slope −3),
        // its fixed point is f = 25.
        let law = |f: f64| 100.0 - 3.0 * f;
        let first = (10.0, law(10.0));
        let second_held = secant_step(first, None);
        assert_eq!(second_held, 70.0);
        let second = (second_held, law(second_held));
        let third = secant_step(second, Some(first));
        assert!((third - 25.0).abs() < 1e-12, "{third}");
    }

    #[test]
    fn a_slack_law_holds_no_tension() {
        assert_eq!(secant_step((5.0, -0.0), None), 0.0);
        assert_eq!(secant_step((5.0, 0.0), Some((6.0, 1.0))), 0.0);
    }
}
