//! The lowest natural frequencies of a band eigenproblem K x = λ M x by
//! bisection on Sturm counts: the number of eigenvalues below σ is the
//! number of negative pivots of K − σ M (M positive definite). Hand-written
//! because it needs only the band's own LDLᵀ recurrence; nalgebra has no
//! band eigen-solver. Unlike subspace iteration it does not slow down when
//! frequencies cluster (many equal spans put as many frequencies close to
//! the first), and each eigenvalue comes to the bisection's own tolerance.

use crate::band::SymBand;

/// Relative width at which an eigenvalue's bracket is closed (the counts'
/// own error, about 1e-16 λ_max, is larger on fine meshes).
const RELATIVE_TOLERANCE: f64 = 1e-12;
/// Bisections of one eigenvalue at most (2⁻²⁰⁰ of the first bracket is far
/// below the tolerance; the bound keeps every call finite).
const MAX_BISECTIONS: usize = 200;
/// Doublings of the upper bound at most (from 1 to beyond 1e300).
const MAX_DOUBLINGS: usize = 1100;
/// Relative distance beyond which a known count decides a bisection step
/// (far above the counts' rounding, about 1e-16 λ_max, for meshes with
/// λ_max below 1e12 times the frequencies sought).
const DEDUCTION_MARGIN: f64 = 1e-3;
/// Doublings of the upper bound taken at once before bisecting on the
/// exponent (16 times the bound: 6 factorizations instead of 14 to 2¹⁴).
const GALLOP_EXPONENT: usize = 4;

/// How many eigenvalues of (K, M) lie below `sigma`, shifting σ by a few
/// rounding units where K − σ M has a zero pivot.
fn count_below(mass: &SymBand, stiffness: &SymBand, sigma: f64) -> Result<usize, String> {
    let mut shifted = sigma;
    for _ in 0..8 {
        if let Some(count) = stiffness.combined_negative_pivots(1.0, mass, -shifted) {
            return Ok(count);
        }
        shifted = shifted * (1.0 + 4.0 * f64::EPSILON) + f64::MIN_POSITIVE;
    }
    Err(format!(
        "the Sturm count at λ = {sigma:e} meets a zero pivot whatever the shift"
    ))
}

/// The counts already factorized, so that a bisection step whose answer
/// they imply (the count grows with σ) costs no factorization: the steps
/// and the frequencies are those of factorizing at every step.
struct KnownCounts<'a> {
    mass: &'a SymBand,
    stiffness: &'a SymBand,
    known: Vec<(f64, usize)>,
}

impl KnownCounts<'_> {
    /// Whether at least `j` eigenvalues lie below `sigma`. A known count
    /// decides only from beyond `DEDUCTION_MARGIN` of σ, where rounding
    /// (about 1e-16 λ_max) cannot reverse the order of two counts.
    fn at_least(&mut self, sigma: f64, j: usize) -> Result<bool, String> {
        for &(point, count) in &self.known {
            if point == sigma
                || (point <= sigma * (1.0 - DEDUCTION_MARGIN) && count >= j)
                || (point >= sigma * (1.0 + DEDUCTION_MARGIN) && count < j)
            {
                return Ok(count >= j);
            }
        }
        let count = count_below(self.mass, self.stiffness, sigma)?;
        self.known.push((sigma, count));
        Ok(count >= j)
    }

    /// The least power of two 2ⁱ (i ≤ `MAX_DOUBLINGS`) with at least `k`
    /// eigenvalues below it, as doubling from 1 finds it: by steps of
    /// `GALLOP_EXPONENT` in i, then bisection on i in the last step.
    fn upper_bound(&mut self, k: usize) -> Result<f64, String> {
        let power = |i: usize| 2f64.powi(i as i32);
        let (mut below, mut above) = (None, 0);
        while !self.at_least(power(above), k)? {
            below = Some(above);
            above += GALLOP_EXPONENT;
            if above > MAX_DOUBLINGS || !power(above).is_finite() {
                return Err(format!(
                    "no bound above the lowest {k} eigenvalues below λ = {:e}",
                    power(above)
                ));
            }
        }
        let Some(mut below) = below else {
            return Ok(power(above));
        };
        while above - below > 1 {
            let middle = (below + above) / 2;
            if self.at_least(power(middle), k)? {
                above = middle;
            } else {
                below = middle;
            }
        }
        Ok(power(above))
    }
}

/// The lowest `k` circular frequencies (rad/s, ascending) of K x = ω² M x.
pub(crate) fn lowest_frequencies(
    mass: &SymBand,
    stiffness: &SymBand,
    k: usize,
) -> Result<Vec<f64>, String> {
    let k = k.min(mass.size());
    let mut counts = KnownCounts {
        mass,
        stiffness,
        known: Vec::new(),
    };
    let upper = counts.upper_bound(k)?;
    let mut lambda = Vec::with_capacity(k);
    let mut lower = 0.0f64;
    for j in 1..=k {
        // The j-th eigenvalue: the least σ with at least j below it.
        let (mut lo, mut hi) = (lower, upper);
        for _ in 0..MAX_BISECTIONS {
            if hi - lo <= RELATIVE_TOLERANCE * hi {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if counts.at_least(mid, j)? {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lambda.push(0.5 * (lo + hi));
        lower = lo;
    }
    Ok(lambda.into_iter().map(|l| l.max(0.0).sqrt()).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K = tridiag(−1, 2, −1), M = I: λⱼ = 2 − 2 cos θⱼ = 4 sin²(θⱼ/2),
    /// θⱼ = jπ/(n+1) (the sine form without cancellation).
    #[test]
    fn the_string_of_springs_has_its_closed_form_eigenvalues() {
        let n = 40;
        let (mut k, mut m) = (SymBand::zeros(n), SymBand::zeros(n));
        for i in 0..n {
            k.add_symmetric(i, i, 2.0);
            m.add_symmetric(i, i, 1.0);
            if i + 1 < n {
                k.add_symmetric(i + 1, i, -1.0);
            }
        }
        let omega = lowest_frequencies(&m, &k, 5).unwrap();
        for (j, w) in omega.iter().enumerate() {
            let theta = (j + 1) as f64 * std::f64::consts::PI / (n + 1) as f64;
            let exact = 4.0 * libm::sin(0.5 * theta).powi(2);
            assert!(
                (w * w - exact).abs() <= 2.0 * RELATIVE_TOLERANCE * exact,
                "{j}: {} vs {exact}",
                w * w
            );
        }
    }

    /// Equal eigenvalues are each found (a multiplicity the count sees).
    #[test]
    fn a_repeated_eigenvalue_is_found_as_often_as_it_occurs() {
        let n = 6;
        let (mut k, mut m) = (SymBand::zeros(n), SymBand::zeros(n));
        for (i, d) in [3.0, 1.0, 3.0, 2.0, 1.0, 5.0].into_iter().enumerate() {
            k.add_symmetric(i, i, d);
            m.add_symmetric(i, i, 1.0);
        }
        let omega = lowest_frequencies(&m, &k, 4).unwrap();
        let lambda: Vec<f64> = omega.iter().map(|w| w * w).collect();
        for (got, want) in lambda.iter().zip([1.0, 1.0, 2.0, 3.0]) {
            assert!(
                (got - want).abs() <= 2.0 * RELATIVE_TOLERANCE * want,
                "{lambda:?}"
            );
        }
    }
}
