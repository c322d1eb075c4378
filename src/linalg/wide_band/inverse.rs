//! The entries of a wide band matrix's inverse within its band, from its
//! LDLᵀ factor: what the contact iteration reads for the structure's
//! compliance under a contact on the rail (issue 24).
//!
//! Selected inversion (Takahashi, Fagan and Chen, 1973), as
//! `band_inverse` does for the beam's band of three: Z = A⁻¹ satisfies
//! Z = D⁻¹ L⁻¹ + (I − Lᵀ) Z, so for i < j ≤ i + b
//! Z(i, j) = −Σ_{k=i+1..i+b} L(k, i) Z(k, j), and
//! Z(i, i) = 1/D(i) − Σ_{k=i+1..i+b} L(k, i) Z(k, i),
//! where every Z(k, j) read is within the band of the rows below. One
//! sweep from the last row up, O(n b²). L is zero before each row's
//! profile, so the full band's recurrence is exact. Written here: no crate
//! offers selected inversion of a band LDLᵀ factor.

use super::WideLdlt;

/// The entries of A⁻¹ within A's half-bandwidth.
#[derive(Debug, Clone)]
pub struct InverseWideBand {
    half_bandwidth: usize,
    /// Row i: Z(i, i), Z(i, i + 1), …, Z(i, i + b) (0 past the last row).
    rows: Vec<f64>,
}

impl InverseWideBand {
    /// The band of the inverse of the factored matrix, in one sweep.
    pub fn new(factor: &WideLdlt) -> InverseWideBand {
        let (n, b) = (factor.size(), factor.half_bandwidth);
        let width = b + 1;
        let mut rows = vec![0.0; n * width];
        // Column i of L below the diagonal: L(i + 1, i), …, L(i + b, i).
        let mut below = vec![0.0; b];
        for i in (0..n).rev() {
            let last = (i + b).min(n - 1);
            for (d, l) in below.iter_mut().enumerate() {
                let k = i + 1 + d;
                *l = if k <= last && factor.first[k] <= i {
                    factor.l(k, i)
                } else {
                    0.0
                };
            }
            for j in i + 1..=last {
                let sum: f64 = (i + 1..=last)
                    .zip(&below)
                    .map(|(k, l)| l * within(&rows, width, k, j))
                    .sum();
                rows[i * width + (j - i)] = -sum;
            }
            let sum: f64 = (i + 1..=last)
                .zip(&below)
                .map(|(k, l)| l * rows[i * width + (k - i)])
                .sum();
            rows[i * width] = 1.0 / factor.pivot[i] - sum;
        }
        InverseWideBand {
            half_bandwidth: b,
            rows,
        }
    }

    /// Z(a, c), or None where |a − c| exceeds the half-bandwidth or a row
    /// is past the last.
    pub fn entry(&self, a: usize, c: usize) -> Option<f64> {
        let (low, high) = (a.min(c), a.max(c));
        let width = self.half_bandwidth + 1;
        (high - low <= self.half_bandwidth && high < self.rows.len() / width)
            .then(|| self.rows[low * width + (high - low)])
    }
}

/// Z(k, j), |k − j| ≤ b, from the rows already swept.
fn within(rows: &[f64], width: usize, k: usize, j: usize) -> f64 {
    let (low, high) = (k.min(j), k.max(j));
    rows[low * width + (high - low)]
}

#[cfg(test)]
mod tests {
    use super::super::tests::{coupled, rail_then_deck_then_rail};
    use super::*;
    use nalgebra::DMatrix;

    #[test]
    fn the_band_of_the_inverse_is_the_dense_inverse_within_the_band() {
        for a in [coupled(12), rail_then_deck_then_rail()] {
            let n = a.size();
            let dense = DMatrix::from_fn(n, n, |i, j| a.get(i, j));
            let inverse = dense.try_inverse().expect("invertible");
            let band = InverseWideBand::new(&a.ldlt().expect("positive definite"));
            let b = a.half_bandwidth();
            let scale = inverse.amax();
            for i in 0..n {
                for j in 0..n {
                    match band.entry(i, j) {
                        Some(z) => {
                            let error = (z - inverse[(i, j)]).abs();
                            assert!(error < 1e-12 * scale, "({i}, {j}): {error:e}");
                        }
                        None => assert!(i.abs_diff(j) > b, "({i}, {j}) in the band"),
                    }
                }
            }
        }
    }
}
