//! Signal processing of a run's records: the deck acceleration as
//! EN 1991-2 §6.4.6.5(4) counts it, for the run's summary (report) and the
//! speed sweeps (study). Only frequencies
//! up to max(30 Hz, 1.5 f1, f3) are taken into account, so the record is
//! low-passed there with zero phase (a Butterworth filter run forwards and
//! backwards) before its peak is read.
//!
//! Hand-written rather than a crate: two second-order sections and a
//! reflection at the ends are a screenful, and no maintained Rust crate
//! offers a zero-phase (forward–backward) Butterworth filter.

use std::f64::consts::PI;

/// Acceleration samples one run keeps for the filtered peak (steps ×
/// sensors; 8 bytes each: 200 MB).
pub const MAX_RECORDED_SAMPLES: u64 = 25_000_000;

/// Butterworth order of each pass (the forward–backward pair has twice the
/// order, zero phase, and the magnitude of one pass squared).
pub const ORDER: usize = 4;

/// EN 1991-2 §6.4.6.5(4): the highest frequency counted for the deck
/// acceleration, max(30 Hz, 1.5 f1, f3) (Hz), from the first and third
/// natural frequencies of the deck (Hz).
pub fn cut_off(f1: f64, f3: f64) -> f64 {
    30.0_f64.max(1.5 * f1).max(f3)
}

/// Frequency of one pass's −3 dB point that puts the −3 dB point of the
/// forward–backward pair at `cut_off`: |H|⁴ = 1/2 at the cut-off, i.e.
/// (fc/fp)^(2n) = √2 − 1.
fn pass_corner(cut_off: f64) -> f64 {
    cut_off / libm::pow(2f64.sqrt() - 1.0, 1.0 / (2.0 * ORDER as f64))
}

/// The gain of the forward–backward pair at `frequency` for a cut-off
/// `cut_off` (the analogue prototype; the bilinear transform is
/// pre-warped at the corner): 1 / (1 + (f/fp)^(2n)).
pub fn zero_phase_gain(frequency: f64, cut_off: f64) -> f64 {
    1.0 / (1.0 + (frequency / pass_corner(cut_off)).powi(2 * ORDER as i32))
}

/// One second-order section (direct form II transposed).
#[derive(Debug, Clone, Copy)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    /// Low-pass section of quality `q` at the pre-warped `k = tan(π fp/fs)`.
    fn low_pass(k: f64, q: f64) -> Biquad {
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b0 = k * k * norm;
        Biquad {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) * norm, (1.0 - k / q + k * k) * norm],
        }
    }

    /// Filter `x` in place, starting from the steady state of its first
    /// value (unit DC gain: no start-up transient for a constant).
    fn run(&self, x: &mut [f64]) {
        let Some(&first) = x.first() else { return };
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let mut z2 = (b2 - a2) * first;
        let mut z1 = (b1 - a1) * first + z2;
        for value in x.iter_mut() {
            let input = *value;
            let output = b0 * input + z1;
            z1 = b1 * input - a1 * output + z2;
            z2 = b2 * input - a2 * output;
            *value = output;
        }
    }
}

/// The record `samples` (step `dt`, s) low-passed at `cut_off` (Hz) with
/// zero phase; `None` when the cut-off is at or above 0.45 of the sampling
/// rate (the step is too coarse to filter there: every frequency the
/// record holds is counted).
pub fn low_pass_zero_phase(samples: &[f64], dt: f64, cut_off: f64) -> Option<Vec<f64>> {
    let rate = 1.0 / dt;
    if !(cut_off > 0.0 && cut_off < 0.45 * rate && dt > 0.0) {
        return None;
    }
    let corner = pass_corner(cut_off).min(0.49 * rate);
    let k = libm::tan(PI * corner / rate);
    let sections: Vec<Biquad> = (0..ORDER / 2)
        .map(|i| {
            let angle = PI * (2 * i + 1) as f64 / (2 * ORDER) as f64;
            Biquad::low_pass(k, 1.0 / (2.0 * libm::cos(angle)))
        })
        .collect();
    // Odd reflection at both ends (as in the usual filtfilt) so the ends
    // carry no start-up transient; three periods of the corner frequency.
    let pad = ((3.0 * rate / corner).ceil() as usize).min(samples.len().saturating_sub(1));
    let mut x = reflected(samples, pad);
    for _forward_then_backward in 0..2 {
        for section in &sections {
            section.run(&mut x);
        }
        x.reverse();
    }
    Some(x[pad..pad + samples.len()].to_vec())
}

/// `samples` with `pad` values reflected oddly about each end.
fn reflected(samples: &[f64], pad: usize) -> Vec<f64> {
    let n = samples.len();
    let mut x = Vec::with_capacity(n + 2 * pad);
    if n == 0 {
        return x;
    }
    let (first, last) = (samples[0], samples[n - 1]);
    x.extend((1..=pad).rev().map(|i| 2.0 * first - samples[i]));
    x.extend_from_slice(samples);
    x.extend((1..=pad).map(|i| 2.0 * last - samples[n - 1 - i]));
    x
}

/// The largest magnitude of `samples`.
pub fn peak_magnitude(samples: &[f64]) -> f64 {
    samples.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The value of largest magnitude, sign kept.
pub fn signed_peak(samples: &[f64]) -> f64 {
    let peak = peak_magnitude(samples);
    samples
        .iter()
        .copied()
        .find(|x| x.abs() == peak)
        .unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EN 1991-2 §6.4.6.5(4): max(30 Hz, 1.5 f1, f3), by hand.
    #[test]
    fn cut_off_is_the_largest_of_the_three() {
        assert_eq!(cut_off(5.5, 49.5), 49.5); // 20 m bridge: f3 = 9 f1
        assert_eq!(cut_off(25.0, 29.0), 37.5); // 1.5 × 25
        assert_eq!(cut_off(2.0, 18.0), 30.0);
    }

    fn sine(frequency: f64, dt: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| libm::sin(2.0 * PI * frequency * i as f64 * dt))
            .collect()
    }

    /// A sine's amplitude away from the ends is the analogue
    /// Butterworth gain 1/(1 + (f/fp)^8) squared-magnitude of the pair,
    /// computed here from the prototype, and its phase is zero (the
    /// filtered sine crosses zero where the sine does).
    #[test]
    fn sines_pass_with_the_butterworth_gain_and_no_phase() {
        let dt = 1e-3;
        let fc = 49.5;
        for (f, expected) in [(5.5, 1.0), (49.5, 1.0 / 2f64.sqrt()), (100.0, 0.0)] {
            let x = sine(f, dt, 20_000);
            let y = low_pass_zero_phase(&x, dt, fc).unwrap();
            let middle = &y[5_000..15_000];
            let amplitude = peak_magnitude(middle);
            let by_hand = if expected == 0.0 {
                // (100/fp)^8 with fp = 49.5 / (√2 − 1)^(1/8)
                let fp = 49.5 / libm::pow(2f64.sqrt() - 1.0, 0.125);
                1.0 / (1.0 + (100.0 / fp).powi(8))
            } else {
                expected
            };
            assert!(
                (amplitude - by_hand).abs() < 2e-3 + 0.01 * by_hand,
                "{f} Hz: {amplitude} vs {by_hand}"
            );
            // zero phase: y and x in proportion at the middle's peaks
            let i = 10_000
                + (0..200)
                    .max_by(|&a, &b| x[10_000 + a].total_cmp(&x[10_000 + b]))
                    .unwrap();
            if by_hand > 0.1 {
                assert!((y[i] / x[i] - by_hand).abs() < 0.02 * by_hand + 2e-3);
            }
        }
    }

    #[test]
    fn coarse_records_are_not_filtered() {
        assert!(low_pass_zero_phase(&[0.0; 10], 0.02, 30.0).is_none());
    }

    #[test]
    fn a_constant_passes_unchanged() {
        let y = low_pass_zero_phase(&[2.5; 500], 1e-3, 30.0).unwrap();
        assert!(y.iter().all(|v| (v - 2.5).abs() < 1e-9));
    }
}
