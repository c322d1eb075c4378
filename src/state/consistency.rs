//! Whether a state from outside (a forged or corrupted FMU state) is
//! physically one of this model's: each body where its contacts say it is,
//! and every event time within the run.
//!
//! `check_shape` and `SimState::check_values` already refuse wrong lengths
//! and non-finite numbers; a state of the right shape with two bodies
//! swapped (a wheelset 1.5 m above a "closed" contact) passed both and
//! stepped on with an energy balance off by a factor of 300.

use super::SimState;
use crate::system::System;

/// A recomputed gap may differ from the stored one by the foot point's own
/// convergence and rounding: this much (m) beyond `solver.gap_tolerance`.
const GAP_SLACK: f64 = 1e-6;

/// A closed contact's gap stays within its tolerance; one this far (m)
/// from the track is no drift but a body out of place.
const CLOSED_GAP_LIMIT: f64 = 1e-3;

/// A force law's contact (a follower) has no gap to check, but its stored
/// foot point is the one of its body's place, found to 1e-14 of the
/// track's length: a search from it that ends this far away (m) found
/// another body's.
const FOOT_SLACK: f64 = 1e-6;

impl SimState {
    /// Refuse a state (of the right shape) that holds a non-finite number,
    /// whose bodies do not sit where its contacts' gaps and foot points
    /// say, or whose event and exit times lie outside [0, its time];
    /// `gap_tolerance` is the run's (`solver.gap_tolerance`).
    pub fn check_consistent(&self, system: &System, gap_tolerance: f64) -> Result<(), String> {
        let state = self;
        // A NaN compares false with every bound below: refused first (the
        // shape check counts lengths only).
        state.check_finite()?;
        check_times(state)?;
        let d = &state.dynamic;
        // Every contact's frame (a follower's too: each must lie on the
        // track), searched from its stored foot point on its stored part.
        let frames = system
            .contacts
            .iter()
            .enumerate()
            .map(|(c, contact)| {
                let centre = &contact.point(&d.bodies[contact.body]).position;
                let u = &d.beam_displacement;
                system.contact_frame(u, centre, d.contact_x[c], state.parts[c])
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| "the state's contact points do not lie on its track".to_string())?;
        let slack = 10.0 * gap_tolerance + GAP_SLACK;
        for (c, contact) in system.contacts.iter().enumerate() {
            if contact.follower.is_some() {
                check_follower_foot(system, c, frames[c].x, d.contact_x[c])?;
                continue;
            }
            let centre = &contact.point(&d.bodies[contact.body]).position;
            let gap = frames[c].gap(&system.beam, contact.radius(), centre);
            let stored = state.contacts[c].gap;
            let closed = !state.contacts[c].open;
            let fits = (gap - stored).abs() <= slack + 1e-9 * stored.abs()
                && (!closed || gap.abs() <= CLOSED_GAP_LIMIT + slack);
            if !fits {
                return Err(format!(
                    "contact {} is {} with a gap of {stored:.3e} m, but its body {} is {gap:.3e} m \
                     from the track: the bodies are not where the contacts say",
                    contact.name,
                    if closed { "closed" } else { "open" },
                    system.bodies[contact.body].name
                ));
            }
        }
        Ok(())
    }
}

/// A follower's foot point found from the stored one (`found`) is the
/// stored one (`stored`): otherwise its body is not where the contact was
/// (two bodies swapped: a wheelset and its car are 1.25 m apart or more).
fn check_follower_foot(system: &System, c: usize, found: f64, stored: f64) -> Result<(), String> {
    // False for a NaN: refused.
    if (found - stored).abs() <= FOOT_SLACK + 1e-9 * stored.abs() {
        return Ok(());
    }
    let contact = &system.contacts[c];
    Err(format!(
        "contact {} (a force law) is at x = {stored:.6} m on the track, but its body {} is over \
         x = {found:.6} m: the bodies are not where the contacts say",
        contact.name, system.bodies[contact.body].name
    ))
}

/// Every event and the exit at or after 0 and at or before the state's time.
fn check_times(state: &SimState) -> Result<(), String> {
    let within = |t: f64| (0.0..=state.time).contains(&t);
    if let Some(t) = state.exit_time.filter(|&t| !within(t)) {
        return Err(format!(
            "the state's exit time {t} s lies outside [0, {}] s (its time)",
            state.time
        ));
    }
    if let Some(e) = state.events.iter().find(|e| !within(e.time)) {
        return Err(format!(
            "the state's event at {} s lies outside [0, {}] s (its time)",
            e.time, state.time
        ));
    }
    Ok(())
}
