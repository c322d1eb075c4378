//! Second-order coupling: over a communication step the inputs follow a
//! polynomial in time instead of being held: the Taylor polynomial of the
//! derivatives a master sent (fmi2SetRealInputDerivatives), or else the line
//! through the inputs at the last two communication points.
//!
//! Holding an input over a step of length H errs by O(H) in the load; a
//! line through the last two values errs by O(H²), which makes a Jacobi
//! coupling second order. Each internal step gets the polynomial's mean
//! over that step, so the load's impulse over the step is the polynomial's.
//! A line from history is extrapolated over at most the span of its two
//! points and held beyond: a step input followed by a longer step must not
//! overshoot by more than its own jump.

use crate::scene::MAX_MAGNITUDE;
use serde::{Deserialize, Serialize};

/// The inputs at the start of the last completed communication step (its
/// communication time): one end of the extrapolation line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InputHistory {
    pub time: f64,
    pub values: Vec<f64>,
}

impl InputHistory {
    /// Whether the history can be one of `inputs` model inputs (it may come
    /// from a forged serialized state).
    pub fn check(&self, inputs: usize) -> Result<(), String> {
        if self.values.len() != inputs {
            return Err(format!(
                "its input history has {} inputs, this model {inputs}",
                self.values.len()
            ));
        }
        // (the rule fmi2SetReal applies to the inputs themselves)
        let allowed = |x: &f64| x.is_finite() && x.abs() <= MAX_MAGNITUDE;
        if !(self.time.is_finite() && self.values.iter().all(allowed)) {
            return Err(format!(
                "its input history is not finite or not within ±{MAX_MAGNITUDE:e} \
                 (the magnitude limit)"
            ));
        }
        Ok(())
    }
}

/// The inputs over one communication step from dynamics time `origin`:
/// input i is `values[i] + d1 σ + d2 σ²/2` at `origin + s`, σ = min(s,
/// horizon).
#[derive(Debug, Clone, PartialEq)]
pub struct Ramp {
    origin: f64,
    values: Vec<f64>,
    rates: Vec<[f64; 2]>,
    /// How far each input's polynomial reaches (infinite for derivatives
    /// the master gave).
    horizons: Vec<f64>,
}

impl Ramp {
    /// The ramp of a step from communication time `now` (dynamics time
    /// `origin`) with inputs `values`: each input's derivatives as `given`
    /// by the master, else its slope from `history`. None when every rate
    /// is zero: the step is then the held step, bit for bit.
    pub fn new(
        origin: f64,
        now: f64,
        values: &[f64],
        given: &[Option<[f64; 2]>],
        history: Option<&InputHistory>,
    ) -> Option<Ramp> {
        let elapsed = history.map_or(0.0, |h| now - h.time);
        let rates: Vec<[f64; 2]> = values
            .iter()
            .enumerate()
            .map(|(i, &u)| match (given.get(i).copied().flatten(), history) {
                (Some(d), _) => d,
                (None, Some(h)) if elapsed > 0.0 && h.values.len() == values.len() => {
                    [(u - h.values[i]) / elapsed, 0.0]
                }
                _ => [0.0, 0.0],
            })
            .collect();
        let finite = rates.iter().flatten().all(|r| r.is_finite());
        if !finite || rates.iter().flatten().all(|&r| r == 0.0) {
            return None;
        }
        let horizons = (0..values.len())
            .map(|i| match given.get(i).copied().flatten() {
                Some(_) => f64::INFINITY,
                None => elapsed,
            })
            .collect();
        Some(Ramp {
            origin,
            values: values.to_vec(),
            rates,
            horizons,
        })
    }

    /// Each input's mean over the dynamics times `[a, b]` into `out`,
    /// within the inputs' magnitude limit (a steep line extrapolated over a
    /// long step must not leave it).
    pub fn mean_over(&self, a: f64, b: f64, out: &mut Vec<f64>) {
        let (sa, sb) = (a - self.origin, b - self.origin);
        out.clear();
        let inputs = self.values.iter().zip(&self.rates).zip(&self.horizons);
        out.extend(inputs.map(|((&u, &[d1, d2]), &reach)| {
            let (mean_s, mean_s2) = clipped_means(sa, sb, reach);
            (u + d1 * mean_s + d2 * mean_s2).clamp(-MAX_MAGNITUDE, MAX_MAGNITUDE)
        }));
    }
}

/// The means of σ and σ²/2 over s in [sa, sb], σ = min(s, reach): the
/// polynomial's part inside its reach and its end value held beyond.
fn clipped_means(sa: f64, sb: f64, reach: f64) -> (f64, f64) {
    // the means of s and s²/2 over [a, b], a < b
    let means = |a: f64, b: f64| (0.5 * (a + b), (a * a + a * b + b * b) / 6.0);
    if sb <= reach || sb <= sa {
        return means(sa, sb);
    }
    let held = (reach, 0.5 * reach * reach);
    if sa >= reach {
        return held;
    }
    let inside = means(sa, reach);
    let w = (reach - sa) / (sb - sa);
    (
        w * inside.0 + (1.0 - w) * held.0,
        w * inside.1 + (1.0 - w) * held.1,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_inputs_give_no_ramp() {
        let h = InputHistory {
            time: 0.0,
            values: vec![1.0, -2.0],
        };
        assert_eq!(Ramp::new(0.0, 0.1, &[1.0, -2.0], &[], Some(&h)), None);
        assert_eq!(Ramp::new(0.0, 0.1, &[1.0, -2.0], &[], None), None);
    }

    #[test]
    fn the_line_through_the_last_two_points_is_extrapolated() {
        // u(t) = 3 + 2 t seen at t = 0.5 and t = 1.0: over [1.25, 1.5] its
        // mean is u(1.375) = 5.75.
        let h = InputHistory {
            time: 0.5,
            values: vec![4.0],
        };
        let ramp = Ramp::new(10.0, 1.0, &[5.0], &[], Some(&h)).unwrap();
        let mut out = Vec::new();
        ramp.mean_over(10.25, 10.5, &mut out);
        assert!((out[0] - 5.75).abs() < 1e-14, "{out:?}");
    }

    #[test]
    fn given_derivatives_win_and_their_quadratic_mean_is_exact() {
        // u(s) = 1 + 2 s + 3 s² (d2 = 6): mean over [0, 1] is 1 + 1 + 1 = 3.
        let h = InputHistory {
            time: 0.0,
            values: vec![100.0],
        };
        let ramp = Ramp::new(0.0, 1.0, &[1.0], &[Some([2.0, 6.0])], Some(&h)).unwrap();
        let mut out = Vec::new();
        ramp.mean_over(0.0, 1.0, &mut out);
        assert!((out[0] - 3.0).abs() < 1e-15, "{out:?}");
    }

    #[test]
    fn a_line_from_history_is_held_beyond_the_span_of_its_points() {
        // u = 0 at t = 0, 1 at t = 1: over [1, 3] it rises to 2 at t = 2,
        // then is held: mean (1.5 + 2) / 2 = 1.75.
        let h = InputHistory {
            time: 0.0,
            values: vec![0.0],
        };
        let ramp = Ramp::new(1.0, 1.0, &[1.0], &[], Some(&h)).unwrap();
        let mut out = Vec::new();
        ramp.mean_over(1.0, 3.0, &mut out);
        assert!((out[0] - 1.75).abs() < 1e-15, "{out:?}");
        ramp.mean_over(2.5, 3.0, &mut out);
        assert_eq!(out[0], 2.0);
    }

    #[test]
    fn extrapolation_stays_within_the_magnitude_limit() {
        let h = InputHistory {
            time: 0.0,
            values: vec![0.0],
        };
        let ramp = Ramp::new(0.0, 1.0, &[MAX_MAGNITUDE], &[Some([1e300, 0.0])], Some(&h)).unwrap();
        let mut out = Vec::new();
        ramp.mean_over(0.0, 1e3, &mut out);
        assert_eq!(out[0], MAX_MAGNITUDE);
    }

    #[test]
    fn a_forged_history_is_refused() {
        let h = InputHistory {
            time: f64::NAN,
            values: vec![0.0],
        };
        assert!(h.check(1).unwrap_err().contains("not finite"));
        assert!(h.check(2).unwrap_err().contains("2"));
    }
}
