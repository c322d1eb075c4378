//! Symmetric band matrices whose half-bandwidth is chosen at run time, and
//! their LDLᵀ factors: for assemblies whose DOFs couple farther than a
//! single beam's three places, such as a rail and a deck interleaved node
//! by node (w, ψ of the rail and of the deck: seven places).
//!
//! `band::SymBand` stays the beam's own (fixed bandwidth 3, unrolled
//! stencils, the bits every recorded run depends on); this type trades
//! those unrolled loops for a bandwidth read from the matrix. Hand-written
//! for the same reason as `band` (no crate factors a band matrix without
//! index arrays or a system LAPACK).

/// A symmetric matrix stored by rows of its lower band: row i holds
/// A(i, i − b), …, A(i, i) (entries before the first column are zero).
#[derive(Debug, Clone, PartialEq)]
pub struct WideBand {
    half_bandwidth: usize,
    /// Row-major, `half_bandwidth + 1` entries per row, the diagonal last.
    rows: Vec<f64>,
}

impl WideBand {
    /// The n × n zero matrix of half-bandwidth `half_bandwidth`.
    pub fn zeros(n: usize, half_bandwidth: usize) -> WideBand {
        WideBand {
            half_bandwidth,
            rows: vec![0.0; n * (half_bandwidth + 1)],
        }
    }

    pub fn size(&self) -> usize {
        self.rows.len() / (self.half_bandwidth + 1)
    }

    pub fn half_bandwidth(&self) -> usize {
        self.half_bandwidth
    }

    /// Index in `rows` of A(row, col), row ≥ col, within the band.
    fn index(&self, row: usize, col: usize) -> usize {
        row * (self.half_bandwidth + 1) + self.half_bandwidth - (row - col)
    }

    /// Add `value` at (i, j) and, when i ≠ j, at (j, i); an entry outside
    /// the band or the matrix is refused, naming it.
    pub fn add_symmetric(&mut self, i: usize, j: usize, value: f64) -> Result<(), String> {
        let (row, col) = if i >= j { (i, j) } else { (j, i) };
        if row >= self.size() || row - col > self.half_bandwidth {
            return Err(format!(
                "entry ({i}, {j}) lies outside the {n}×{n} band of half-bandwidth {b}",
                n = self.size(),
                b = self.half_bandwidth
            ));
        }
        let at = self.index(row, col);
        self.rows[at] += value;
        Ok(())
    }

    /// A(i, j) (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (row, col) = if i >= j { (i, j) } else { (j, i) };
        if row - col > self.half_bandwidth {
            0.0
        } else {
            self.rows[self.index(row, col)]
        }
    }

    /// `out = A x`: each stored entry of the lower band once, for its own
    /// row and its mirror (the product is most of a rail-over-deck step).
    pub fn mul_to(&self, x: &[f64], out: &mut [f64]) {
        let (n, b) = (self.size(), self.half_bandwidth);
        assert!(x.len() == n && out.len() == n);
        out.fill(0.0);
        for (i, row) in self.rows.chunks_exact(b + 1).enumerate() {
            // row[k] = A(i, i − b + k); row[b] the diagonal.
            let mut sum = row[b] * x[i];
            for (k, a) in row.iter().enumerate().take(b).skip(b.saturating_sub(i)) {
                let j = i + k - b;
                sum += a * x[j];
                out[j] += a * x[i];
            }
            out[i] += sum;
        }
    }

    /// LDLᵀ factor without pivoting; `None` unless every pivot is positive
    /// and finite (the matrix is then positive definite, by Sylvester's law
    /// of inertia). L keeps A's band: O(n b²) operations.
    pub fn ldlt(&self) -> Option<WideLdlt> {
        let (n, b) = (self.size(), self.half_bandwidth);
        let mut factor = WideLdlt {
            half_bandwidth: b,
            lower: vec![0.0; n * b],
            pivot: vec![0.0; n],
        };
        for i in 0..n {
            let first = i.saturating_sub(b);
            for j in first..i {
                // Σ over m < j within both rows' bands: L(i,m) D(m) L(j,m).
                let shared = first.max(j.saturating_sub(b));
                let sum: f64 = (shared..j)
                    .map(|m| factor.l(i, m) * factor.pivot[m] * factor.l(j, m))
                    .sum();
                let l = (self.get(i, j) - sum) / factor.pivot[j];
                factor.lower[i * b + b - (i - j)] = l;
            }
            let d = self.get(i, i)
                - (first..i)
                    .map(|m| factor.l(i, m).powi(2) * factor.pivot[m])
                    .sum::<f64>();
            if !(d > 0.0 && d.is_finite()) {
                return None;
            }
            factor.pivot[i] = d;
        }
        Some(factor)
    }
}

/// A = L D Lᵀ of a positive definite `WideBand`: L unit lower triangular
/// with A's half-bandwidth.
#[derive(Debug, Clone, PartialEq)]
pub struct WideLdlt {
    half_bandwidth: usize,
    /// Row i: L(i, i − b), …, L(i, i − 1).
    lower: Vec<f64>,
    pivot: Vec<f64>,
}

impl WideLdlt {
    pub fn size(&self) -> usize {
        self.pivot.len()
    }

    /// L(i, m) for i − b ≤ m < i.
    fn l(&self, i: usize, m: usize) -> f64 {
        let b = self.half_bandwidth;
        self.lower[i * b + b - (i - m)]
    }

    /// `x ← A⁻¹ x`: L z = x, D y = z, Lᵀ x = y; Lᵀ by rows of L, each
    /// final entry of x subtracted from those above it.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let (n, b) = (self.size(), self.half_bandwidth);
        assert_eq!(x.len(), n);
        let row = |i: usize| &self.lower[i * b..(i + 1) * b];
        for i in 0..n {
            let sum: f64 = (b.saturating_sub(i)..b)
                .map(|k| row(i)[k] * x[i + k - b])
                .sum();
            x[i] -= sum;
        }
        for (xi, d) in x.iter_mut().zip(&self.pivot) {
            *xi /= d;
        }
        for i in (0..n).rev() {
            let xi = x[i];
            for k in b.saturating_sub(i)..b {
                x[i + k - b] -= row(i)[k] * xi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::band::SymBand;
    use nalgebra::{DMatrix, DVector};

    /// A rail on a deck, interleaved per node (rail w, ψ, deck w, ψ): each
    /// element couples eight consecutive DOFs, half-bandwidth 7; diagonally
    /// dominant, so positive definite.
    fn coupled(nodes: usize) -> WideBand {
        let n = 4 * nodes;
        let mut a = WideBand::zeros(n, 7);
        for e in 0..nodes - 1 {
            for p in 0..8 {
                for q in 0..=p {
                    let value = ((p * 7 + q * 3 + e) % 11) as f64 * 0.1 - 0.5;
                    a.add_symmetric(4 * e + p, 4 * e + q, value)
                        .expect("in band");
                }
            }
        }
        for i in 0..n {
            a.add_symmetric(i, i, 20.0).expect("diagonal");
        }
        a
    }

    fn dense(a: &WideBand) -> DMatrix<f64> {
        let n = a.size();
        DMatrix::from_fn(n, n, |i, j| a.get(i, j))
    }

    #[test]
    fn the_band_solve_of_half_bandwidth_seven_matches_a_dense_cholesky_solve() {
        let a = coupled(12);
        let n = a.size();
        let rhs = DVector::from_fn(n, |i, _| ((i * 5) % 7) as f64 - 3.0);
        let expected = dense(&a).cholesky().expect("spd").solve(&rhs);
        let mut x = rhs.as_slice().to_vec();
        a.ldlt().expect("positive definite").solve_in_place(&mut x);
        let error = (DVector::from_vec(x.clone()) - &expected).amax();
        assert!(error < 1e-12 * expected.amax(), "error {error:e}");
        let mut back = vec![0.0; n];
        a.mul_to(&x, &mut back);
        let residual = (DVector::from_vec(back) - rhs).amax();
        assert!(residual < 1e-12, "residual {residual:e}");
    }

    #[test]
    fn at_half_bandwidth_three_it_solves_as_the_beam_band() {
        let n = 10;
        let (mut wide, mut narrow) = (WideBand::zeros(n, 3), SymBand::zeros(n));
        for i in 0..n {
            for j in i.saturating_sub(3)..=i {
                let value = if i == j {
                    8.0
                } else {
                    1.0 / (1 + i + j) as f64
                };
                wide.add_symmetric(i, j, value).expect("in band");
                narrow.add_symmetric(i, j, value);
            }
        }
        let mut x: Vec<f64> = (0..n).map(|i| i as f64 - 4.0).collect();
        let mut y = x.clone();
        wide.ldlt().expect("spd").solve_in_place(&mut x);
        narrow.ldlt().expect("spd").solve_in_place(&mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-14 * b.abs().max(1.0), "{a} vs {b}");
        }
    }

    #[test]
    fn an_indefinite_matrix_has_no_factor_and_an_entry_outside_the_band_is_refused() {
        let mut a = coupled(3);
        a.add_symmetric(5, 5, -100.0).expect("diagonal");
        assert!(a.ldlt().is_none());
        let message = a.add_symmetric(8, 0, 1.0).expect_err("outside");
        assert!(message.contains("(8, 0)") && message.contains("half-bandwidth 7"));
        assert!(a.add_symmetric(12, 12, 1.0).is_err());
    }
}
