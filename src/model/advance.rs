//! One communication step of the dynamics under a wall-time budget, and the
//! classification of a failure: can a smaller communication step get
//! further, or will every retry fail the same way?
//!
//! fmi2DoStep is synchronous and fmi2CancelStep is not available to a
//! synchronous co-simulation slave, so the budget is the importer's only
//! guard against a step that runs for hours. The dynamics are advanced in
//! chunks that end on their own grid of internal steps (`k · step`), which
//! is where an uninterrupted advance passes anyway: chunking changes no
//! result, only lets the clock be read.

use super::extrapolate::Ramp;
use super::{apply_inputs, Dynamics};
use crate::simulation::{Advance, SolverError};
use std::time::{Duration, Instant};

/// Why an advance stopped short of its target. The dynamics are left where
/// they stopped; the caller rolls them back.
#[derive(Debug)]
pub enum Stop {
    Solver(SolverError),
    /// The budget ran out at `reached` (dynamics time), or an internal step
    /// was refused up front: `foreseen` says what it would have needed.
    OverBudget {
        reached: f64,
        foreseen: Option<String>,
    },
}

/// Advance `sim` to `target`, reading the wall clock between chunks of whole
/// internal steps of length `step`; past `budget` seconds with the target
/// not yet reached, stop. With `until_event`, the chunks are single steps
/// and the advance ends (`Reached`, short of `target`) after the one in
/// which a simulation event happened; the flag returned says whether it did.
/// With a `ramp` (and the scene's number of vehicles, whose forces lead
/// the inputs), the chunks are single internal steps, each under the
/// ramp's mean inputs over it.
pub fn advance_within<D: Dynamics>(
    sim: &mut D,
    target: f64,
    step: f64,
    budget: f64,
    (until_event, ramp): (bool, Option<(&Ramp, usize)>),
) -> Result<(Advance, bool), Stop> {
    let budget = Duration::try_from_secs_f64(budget).unwrap_or(Duration::MAX);
    let started = Instant::now();
    // Inside an internal step the contact iteration reads the deadline.
    let deadline = started.checked_add(budget);
    crate::deadline::within(deadline, || {
        advance_chunks(sim, target, step, (started, budget), (until_event, ramp)).map_err(|stop| {
            match stop {
                Stop::Solver(_) if crate::deadline::passed() => Stop::OverBudget {
                    reached: sim.time(),
                    foreseen: crate::deadline::foreseen(),
                },
                stop => stop,
            }
        })
    })
}

/// `advance_within`'s chunks, the clock read between them.
fn advance_chunks<D: Dynamics>(
    sim: &mut D,
    target: f64,
    step: f64,
    (started, budget): (Instant, Duration),
    (until_event, ramp): (bool, Option<(&Ramp, usize)>),
) -> Result<(Advance, bool), Stop> {
    let mut loads = Vec::new();
    let mut to = |sim: &mut D, end: f64| {
        if let Some((ramp, vehicles)) = ramp {
            ramp.mean_over(sim.time(), end, &mut loads);
            apply_inputs(sim, &loads, vehicles);
        }
        sim.advance_to(end)
    };
    // Within one internal step the clock is read inside it only.
    if chunk_end(sim.time(), step, 1.0) >= target - 1e-6 * step {
        return to(sim, target).map(|a| (a, false)).map_err(Stop::Solver);
    }
    let events_before = sim.event_count();
    // Chunk length in internal steps: doubled while a chunk takes under a
    // sixteenth of the budget, so that checks are rare on fast models and a
    // slow model overshoots the budget by little.
    let mut chunk = 1.0_f64;
    loop {
        let end = chunk_end(sim.time(), step, chunk);
        if end >= target - 1e-6 * step {
            return to(sim, target).map(|a| (a, false)).map_err(Stop::Solver);
        }
        let chunk_started = Instant::now();
        if let Advance::Exited { time } = to(sim, end).map_err(Stop::Solver)? {
            return Ok((Advance::Exited { time }, false));
        }
        if until_event && sim.event_count() > events_before {
            return Ok((Advance::Reached, true));
        }
        if started.elapsed() > budget {
            return Err(Stop::OverBudget {
                reached: sim.time(),
                foreseen: None,
            });
        }
        chunk = if until_event || ramp.is_some() {
            1.0
        } else if chunk_started.elapsed() < budget / 16 {
            (2.0 * chunk).min(65536.0)
        } else {
            (chunk / 2.0).max(1.0)
        };
    }
}

/// The grid point `chunk` internal steps after the one at or below `now`
/// (strictly after `now`), computed as the dynamics compute theirs.
fn chunk_end(now: f64, step: f64, chunk: f64) -> f64 {
    let k = (now / step).floor() + chunk;
    let end = k * step;
    if end > now {
        end
    } else {
        (k + 1.0) * step
    }
}

/// Whether the step that failed can be cured by a smaller communication
/// step: `Ok(message)` naming a step that succeeds, or `Err(message)` saying
/// that even a tiny one fails. `start` is the dynamics time the communication
/// step began at; `sim` is where the failure left it (at the start of the
/// failing internal step) and is left anywhere: the caller rolls it back.
pub fn curable<D: Dynamics>(
    sim: &mut D,
    start: f64,
    saved: &D::State,
    probe: f64,
) -> Result<String, String> {
    let failed_at = sim.time();
    if failed_at > start {
        return Ok(format!(
            "a communication step of {:e} s succeeds",
            failed_at - start
        ));
    }
    if let Err(e) = sim.restore(saved) {
        return Err(format!("(cannot probe a smaller step: {e})"));
    }
    // A probe that does not move the time (below the time's resolution or
    // the dynamics' tolerance) proves nothing.
    match sim.advance_to(start + probe) {
        Ok(_) if sim.time() > start => Ok(format!("a communication step of {probe:e} s succeeds")),
        _ => Err(format!(
            "even a communication step of {probe:e} s fails: no step size cures this; \
             change the inputs or the parameters"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunk_ends_are_grid_points_after_now() {
        assert_eq!(chunk_end(0.0, 0.0025, 1.0), 0.0025);
        assert_eq!(chunk_end(0.0101, 0.0025, 1.0), 5.0 * 0.0025);
        assert_eq!(chunk_end(5.0 * 0.0025, 0.0025, 2.0), 7.0 * 0.0025);
        // just below a grid point (a shortened step landed there)
        let just_below = 4.0 * 0.0025 * (1.0 - 1e-15);
        assert!(chunk_end(just_below, 0.0025, 1.0) > just_below);
    }
}
