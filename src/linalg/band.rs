//! Symmetric band matrices of half-bandwidth 3 and their LDLᵀ factors.
//!
//! A Hermite beam element couples four consecutive DOFs (w, ψ of its two
//! nodes), so with the free DOFs numbered node by node every beam matrix
//! (mass, stiffness, M + c K) has nonzeros only within three places of the
//! diagonal, whatever the supports remove. Stored as rows of four numbers
//! (three below the diagonal and the diagonal), a product costs 7
//! multiply-adds per row and a factor solve 7 with no index arrays.
//!
//! Written here, not taken from a crate: nalgebra-sparse's and faer's
//! sparse Cholesky factorizations go through index arrays and a symbolic
//! phase (≈ 7 instructions per flop on the 4×4 matrix of a 2-element beam),
//! and the banded LAPACK routines (dpbtrf) need a system LAPACK that the FMU
//! must not depend on; a fixed bandwidth of 3 makes the factorization a
//! short loop.

use nalgebra::DVector;

/// Half-bandwidth: the farthest a nonzero lies from the diagonal.
pub const HALF_BANDWIDTH: usize = 3;

/// Up to this size (a beam of up to 4 elements) products and solves use a
/// dense copy of the matrix, or of the factor's inverse: n² multiply-adds in
/// one loop beat the band sweeps' edge cases when n is this small.
pub const DENSE_LIMIT: usize = 8;

/// Row `i` of LDLᵀ without pivoting: L(i, j) for j = i−3..i at places
/// 3 − (i − j), and the pivot D(i), from the matrix's row `a` and the
/// earlier rows' (L, D, 1/D) as `earlier(m)` gives them.
#[inline(always)]
fn ldlt_row(
    a: &[f64; 4],
    i: usize,
    earlier: impl Fn(usize) -> ([f64; 3], f64, f64),
) -> ([f64; 3], f64) {
    let first = i.saturating_sub(3);
    // L(i, j) for j = first..i, left to right.
    let mut l = [0.0f64; 3];
    for j in first..i {
        let mut s = a[3 - (i - j)];
        let (lower_j, _, inverse_pivot_j) = earlier(j);
        // Σ over m < j within both rows' bands: L(i,m) D(m) L(j,m).
        for m in first..j {
            if j - m <= 3 {
                s -= l[3 - (i - m)] * earlier(m).1 * lower_j[3 - (j - m)];
            }
        }
        l[3 - (i - j)] = s * inverse_pivot_j;
    }
    let mut d = a[3];
    for m in first..i {
        let lim = l[3 - (i - m)];
        d -= lim * lim * earlier(m).1;
    }
    (l, d)
}

/// A symmetric matrix whose row i holds A(i, i−3), A(i, i−2), A(i, i−1),
/// A(i, i) (entries before the first column are zero).
#[derive(Debug, Clone, PartialEq)]
pub struct SymBand {
    rows: Vec<[f64; 4]>,
    /// Row-major dense copy when n ≤ `DENSE_LIMIT`, else empty.
    dense: Vec<f64>,
}

impl SymBand {
    pub fn zeros(n: usize) -> SymBand {
        SymBand {
            rows: vec![[0.0; 4]; n],
            dense: if n <= DENSE_LIMIT {
                vec![0.0; n * n]
            } else {
                Vec::new()
            },
        }
    }

    pub fn size(&self) -> usize {
        self.rows.len()
    }

    /// Add `value` at (i, j) and, when i ≠ j, at (j, i). Panics if |i − j| > 3.
    pub fn add_symmetric(&mut self, i: usize, j: usize, value: f64) {
        let (row, col) = if i >= j { (i, j) } else { (j, i) };
        let offset = row - col;
        assert!(
            offset <= HALF_BANDWIDTH,
            "entry ({i}, {j}) outside the band"
        );
        self.rows[row][3 - offset] += value;
        if !self.dense.is_empty() {
            let n = self.size();
            self.dense[row * n + col] = self.rows[row][3 - offset];
            self.dense[col * n + row] = self.rows[row][3 - offset];
        }
    }

    /// A(i, j) (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (row, col) = if i >= j { (i, j) } else { (j, i) };
        if row - col > HALF_BANDWIDTH {
            0.0
        } else {
            self.rows[row][3 - (row - col)]
        }
    }

    /// `a A + b B` (same size).
    pub fn combine(&self, a: f64, other: &SymBand, b: f64) -> SymBand {
        assert_eq!(self.size(), other.size());
        let rows = self
            .rows
            .iter()
            .zip(&other.rows)
            .map(|(x, y)| [0, 1, 2, 3].map(|k| a * x[k] + b * y[k]))
            .collect();
        let dense = self
            .dense
            .iter()
            .zip(&other.dense)
            .map(|(x, y)| a * x + b * y)
            .collect();
        SymBand { rows, dense }
    }

    /// Row i of A x from the band, for any i (the edge rows and tiny sizes).
    fn row_times(&self, i: usize, x: &[f64]) -> f64 {
        let n = self.size();
        let lo = i.saturating_sub(3);
        let hi = (i + 3).min(n - 1);
        (lo..=hi).map(|j| self.get(i, j) * x[j]).sum()
    }

    /// `out = A x`.
    pub fn mul_to(&self, x: &[f64], out: &mut [f64]) {
        let n = self.size();
        assert!(x.len() == n && out.len() == n);
        if !self.dense.is_empty() {
            dense_times(&self.dense, x, out);
            return;
        }
        for i in (0..3).chain(n - 3..n) {
            out[i] = self.row_times(i, x);
        }
        // Interior rows: a 7-point stencil, rows i..i+3 give A(i, i−3..i+3).
        for ((o, xw), rw) in out[3..n - 3]
            .iter_mut()
            .zip(x.windows(7))
            .zip(self.rows[3..].windows(4))
        {
            *o = stencil(rw, xw);
        }
    }

    /// `out += scale · A x`, row by row (no scratch vector).
    pub fn mul_add_to(&self, scale: f64, x: &[f64], out: &mut [f64]) {
        let n = self.size();
        assert!(x.len() == n && out.len() == n);
        for (i, o) in out.iter_mut().enumerate() {
            *o += scale * self.row_times(i, x);
        }
    }

    /// xᵀ A x.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        let n = self.size();
        assert_eq!(x.len(), n);
        // Diagonal once, each off-diagonal pair twice; the three previous
        // entries of x ride along in registers.
        let (mut x3, mut x2, mut x1) = (0.0, 0.0, 0.0);
        let mut sum = 0.0;
        for (&xi, r) in x.iter().zip(&self.rows) {
            let off = r[0] * x3 + r[1] * x2 + r[2] * x1;
            sum += xi * (r[3] * xi + 2.0 * off);
            (x3, x2, x1) = (x2, x1, xi);
        }
        sum
    }

    /// How many pivots of the LDLᵀ factor (without pivoting) are negative:
    /// by Sylvester's law of inertia the count of negative eigenvalues.
    /// `None` when a pivot is zero or not finite (the count is then not
    /// defined by the factor: shift the matrix a little).
    pub fn negative_pivots(&self) -> Option<usize> {
        negative_pivots_of_rows(self.rows.iter().copied())
    }

    /// `negative_pivots` of a A + b B, each row formed as `combine` forms
    /// it (the same bits) and dropped: no matrix is allocated (a Sturm
    /// bisection counts dozens of shifts).
    pub fn combined_negative_pivots(&self, a: f64, other: &SymBand, b: f64) -> Option<usize> {
        assert_eq!(self.size(), other.size());
        let rows = (self.rows.iter().zip(&other.rows))
            .map(|(x, y)| [0, 1, 2, 3].map(|k| a * x[k] + b * y[k]));
        negative_pivots_of_rows(rows)
    }
}

/// `SymBand::negative_pivots` of the band with these rows.
fn negative_pivots_of_rows(rows: impl Iterator<Item = [f64; 4]>) -> Option<usize> {
    // The last three rows of L and D are all a row needs.
    let mut kept = [([0.0f64; 3], 0.0f64, 0.0f64); 4];
    let mut negative = 0;
    for (i, a) in rows.enumerate() {
        let (l, d) = ldlt_row(&a, i, |m| kept[m % 4]);
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        negative += usize::from(d < 0.0);
        kept[i % 4] = (l, d, 1.0 / d);
    }
    Some(negative)
}

impl SymBand {
    /// LDLᵀ factor without pivoting; `None` unless every pivot is positive
    /// and finite (the matrix is then positive definite, by Sylvester's law
    /// of inertia).
    pub fn ldlt(&self) -> Option<BandLdlt> {
        let n = self.size();
        let mut lower = vec![[0.0f64; 3]; n];
        let mut pivot = vec![0.0f64; n];
        let mut inverse_pivot = vec![0.0f64; n];
        for (i, a) in self.rows.iter().enumerate() {
            let (l, d) = ldlt_row(a, i, |m| (lower[m], pivot[m], inverse_pivot[m]));
            if !(d > 0.0 && d.is_finite()) {
                return None;
            }
            lower[i] = l;
            pivot[i] = d;
            inverse_pivot[i] = 1.0 / d;
        }
        // Column i of L below the diagonal, stored with row i for the
        // backward sweep: L(i+1, i), L(i+2, i), L(i+3, i).
        let below = (0..n)
            .map(|i| [1, 2, 3].map(|k| if i + k < n { lower[i + k][3 - k] } else { 0.0 }))
            .collect();
        let mut factor = BandLdlt {
            lower,
            below,
            inverse_pivot,
            dense_inverse: Vec::new(),
            serial: NEXT_SERIAL.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        };
        if n <= DENSE_LIMIT {
            // Columns of A⁻¹ by the band solve; A⁻¹ is symmetric.
            let mut inverse = vec![0.0; n * n];
            let mut column = vec![0.0; n];
            for j in 0..n {
                column.fill(0.0);
                column[j] = 1.0;
                factor.band_solve(&mut column);
                for i in 0..n {
                    inverse[i * n + j] = column[i];
                }
            }
            factor.dense_inverse = inverse;
        }
        Some(factor)
    }
}

/// Interior row i of A x: `rows` are A's rows i..i+3 (row i's own entries
/// and, in rows i+1..i+3, the column i of the upper triangle), `x` is
/// x(i−3..=i+3).
#[inline(always)]
fn stencil(rows: &[[f64; 4]], x: &[f64]) -> f64 {
    let (x, rw): (&[f64; 7], &[[f64; 4]; 4]) =
        (x.try_into().expect("7"), rows.try_into().expect("4"));
    let lower = rw[0][0] * x[0] + rw[0][1] * x[1] + rw[0][2] * x[2];
    let upper = rw[1][2] * x[4] + rw[2][1] * x[5] + rw[3][0] * x[6];
    lower + rw[0][3] * x[3] + upper
}

/// `[f(0), f(1)]`: the two columns' entries (inlined, unlike `array::map`).
#[inline(always)]
fn both(f: impl Fn(usize) -> f64) -> [f64; 2] {
    [f(0), f(1)]
}

/// `out = A x` for a row-major dense n×n `a`.
fn dense_times(a: &[f64], x: &[f64], out: &mut [f64]) {
    // The 2-element beam (4 free DOFs) is the paper's mesh: unrolled.
    if let (Ok(a), Ok(x), Ok(out)) = (
        <&[f64; 16]>::try_from(a),
        <&[f64; 4]>::try_from(x),
        <&mut [f64; 4]>::try_from(&mut *out),
    ) {
        for (i, o) in out.iter_mut().enumerate() {
            let r = &a[4 * i..4 * i + 4];
            *o = (r[0] * x[0] + r[1] * x[1]) + (r[2] * x[2] + r[3] * x[3]);
        }
        return;
    }
    for (o, row) in out.iter_mut().zip(a.chunks_exact(x.len())) {
        *o = row.iter().zip(x).map(|(r, v)| r * v).sum();
    }
}

/// A = L D Lᵀ of a positive definite `SymBand`: L unit lower triangular with
/// half-bandwidth 3 (row i holds L(i, i−3), L(i, i−2), L(i, i−1)), and the
/// reciprocals of D's pivots so that a solve never divides.
#[derive(Debug, Clone)]
pub struct BandLdlt {
    lower: Vec<[f64; 3]>,
    below: Vec<[f64; 3]>,
    inverse_pivot: Vec<f64>,
    /// Row-major A⁻¹ when n ≤ `DENSE_LIMIT`, else empty.
    dense_inverse: Vec<f64>,
    /// Which factorization this is (`serial`).
    serial: u64,
}

/// The serial of the next factorization (`BandLdlt::serial`).
static NEXT_SERIAL: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Equal factors: the same entries, whichever factorization made them.
impl PartialEq for BandLdlt {
    fn eq(&self, other: &BandLdlt) -> bool {
        (self.lower == other.lower && self.below == other.below)
            && self.inverse_pivot == other.inverse_pivot
            && self.dense_inverse == other.dense_inverse
    }
}

impl BandLdlt {
    /// Names this factorization: a clone keeps it, each `SymBand::ldlt`
    /// takes a new one, and nothing changes a factor after it is made, so
    /// one serial means one set of entries. What is derived from a factor
    /// (`band_inverse`'s band) is kept against it in O(1), where comparing
    /// the pivots cost O(n) at every use (issue 29, len29).
    pub fn serial(&self) -> u64 {
        self.serial
    }

    pub fn size(&self) -> usize {
        self.lower.len()
    }

    /// Per column i, L(i+1, i), L(i+2, i), L(i+3, i) (0 past the last row),
    /// and D's reciprocal pivots: what `band_inverse` recurs on.
    pub(crate) fn columns_below_and_inverse_pivots(&self) -> (&[[f64; 3]], &[f64]) {
        (&self.below, &self.inverse_pivot)
    }

    /// `x ← A⁻¹ x`.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.size());
        if !self.dense_inverse.is_empty() {
            let mut b = [0.0; DENSE_LIMIT];
            b[..x.len()].copy_from_slice(x);
            dense_times(&self.dense_inverse, &b[..x.len()], x);
            return;
        }
        self.band_solve(x);
    }

    fn band_solve(&self, x: &mut [f64]) {
        // L z = b, then y = D⁻¹ z, Lᵀ x = y. The three latest values ride
        // along in registers (entries before the first row are zero, so the
        // first rows need no special case); the terms of the older two are
        // summed first, so each row waits on one multiply-add.
        let (mut z3, mut z2, mut z1) = (0.0, 0.0, 0.0);
        for (xi, l) in x.iter_mut().zip(&self.lower) {
            let partial = *xi - l[0] * z3 - l[1] * z2;
            let z = partial - l[2] * z1;
            *xi = z;
            (z3, z2, z1) = (z2, z1, z);
        }
        let (mut y3, mut y2, mut y1) = (0.0, 0.0, 0.0);
        for ((xi, b), d) in x.iter_mut().zip(&self.below).zip(&self.inverse_pivot).rev() {
            let partial = *xi * d - b[2] * y3 - b[1] * y2;
            let y = partial - b[0] * y1;
            *xi = y;
            (y3, y2, y1) = (y2, y1, y);
        }
    }

    /// Two columns c = 0, 1 of `A⁻¹ (f_c − K u_c)`, A the factored matrix
    /// and K a band matrix of the same size, handed row by row from the
    /// last to `each` with that row's item of `rows` (one item per row):
    /// `each([y₀(i), y₁(i)], item i)`. The same operations in the same
    /// order as `K.mul_to`, `f − K u` and `solve_in_place` column by column
    /// (the same bits), but in two passes over the rows: the products,
    /// right-hand sides and forward sweep in the first, the backward sweep
    /// and the caller's use of each row in the second. A sweep of one
    /// column waits at every row on the row before (a multiply and a
    /// subtraction); the two columns' chains are independent and run side
    /// by side, and the other work fills that wait. `scratch` holds the
    /// forward sweep.
    #[inline]
    pub fn solve_residual_pair<R>(
        &self,
        stiffness: &SymBand,
        (u, f): ([&[f64]; 2], [&[f64]; 2]),
        scratch: &mut Vec<[f64; 2]>,
        rows: impl DoubleEndedIterator<Item = R> + ExactSizeIterator,
        mut each: impl FnMut([f64; 2], R),
    ) {
        let n = self.size();
        assert!(stiffness.size() == n && u.iter().chain(&f).all(|x| x.len() == n));
        assert_eq!(rows.len(), n);
        // Every entry is written before it is read.
        scratch.resize(n, [0.0; 2]);
        if !self.dense_inverse.is_empty() {
            let mut columns = [[0.0; DENSE_LIMIT]; 2];
            for (c, column) in columns.iter_mut().enumerate() {
                let g = &mut column[..n];
                stiffness.mul_to(u[c], g);
                for (g, f) in g.iter_mut().zip(f[c]) {
                    *g = f - *g;
                }
                self.solve_in_place(g);
            }
            for (i, row) in rows.enumerate().rev() {
                each([columns[0][i], columns[1][i]], row);
            }
            return;
        }
        self.forward_residual_pair(stiffness, (u, f), scratch);
        let (mut y3, mut y2, mut y1) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        let sweep = scratch.iter().zip(&self.below).zip(&self.inverse_pivot);
        for (((zi, b), d), row) in sweep.zip(rows).rev() {
            let y = both(|c| {
                let partial = zi[c] * d - b[2] * y3[c] - b[1] * y2[c];
                partial - b[0] * y1[c]
            });
            (y3, y2, y1) = (y2, y1, y);
            each(y, row);
        }
    }

    /// `z = L⁻¹ (f_c − K u_c)` for both columns (n > `DENSE_LIMIT`).
    #[inline]
    fn forward_residual_pair(
        &self,
        stiffness: &SymBand,
        (u, f): ([&[f64]; 2], [&[f64]; 2]),
        z: &mut [[f64; 2]],
    ) {
        let n = self.size();
        // z(i−3), z(i−2), z(i−1) of both columns.
        let mut last = [[0.0; 2]; 3];
        let forward = |last: &mut [[f64; 2]; 3], l: &[f64; 3], g: [f64; 2]| {
            let next = both(|c| {
                let partial = g[c] - l[0] * last[0][c] - l[1] * last[1][c];
                partial - l[2] * last[2][c]
            });
            *last = [last[1], last[2], next];
            next
        };
        let edge = |i: usize| both(|c| f[c][i] - stiffness.row_times(i, u[c]));
        for (i, (zi, l)) in z.iter_mut().zip(&self.lower).enumerate().take(3) {
            *zi = forward(&mut last, l, edge(i));
        }
        let rhs = f[0][3..n - 3].iter().zip(&f[1][3..n - 3]);
        let windows = u[0].windows(7).zip(u[1].windows(7));
        let interior = z[3..n - 3]
            .iter_mut()
            .zip(&self.lower[3..n - 3])
            .zip(rhs.zip(windows))
            .zip(stiffness.rows[3..].windows(4));
        for (((zi, l), ((f0, f1), (u0, u1))), k) in interior {
            let g = [f0 - stencil(k, u0), f1 - stencil(k, u1)];
            *zi = forward(&mut last, l, g);
        }
        for (i, (zi, l)) in z.iter_mut().zip(&self.lower).enumerate().skip(n - 3) {
            *zi = forward(&mut last, l, edge(i));
        }
    }

    /// `x = A⁻¹ b` with b's rows from `rhs` (first to last), each row of
    /// x handed with its item of `rows` (one item per row) to
    /// `each(x_i, item i)` from the last row to the first. The same
    /// operations in the same order as filling b and `solve_in_place` (the
    /// same bits), but the right-hand side is made inside the forward sweep
    /// and the rows are used inside the backward one: a step of the
    /// implicit scheme then passes over its vectors once each (issue 29),
    /// and that work fills the sweeps' waits on the row before. `scratch`
    /// holds the forward sweep.
    #[inline]
    pub fn solve_rows<R>(
        &self,
        scratch: &mut Vec<f64>,
        rhs: impl Iterator<Item = f64>,
        rows: impl DoubleEndedIterator<Item = R> + ExactSizeIterator,
        mut each: impl FnMut(f64, R),
    ) {
        let n = self.size();
        assert_eq!(rows.len(), n);
        scratch.clear();
        scratch.extend(rhs);
        assert_eq!(scratch.len(), n);
        if !self.dense_inverse.is_empty() {
            self.solve_in_place(scratch);
            for (x, row) in scratch.iter().zip(rows).rev() {
                each(*x, row);
            }
            return;
        }
        let (mut z3, mut z2, mut z1) = (0.0, 0.0, 0.0);
        for (xi, l) in scratch.iter_mut().zip(&self.lower) {
            let partial = *xi - l[0] * z3 - l[1] * z2;
            let z = partial - l[2] * z1;
            *xi = z;
            (z3, z2, z1) = (z2, z1, z);
        }
        let (mut y3, mut y2, mut y1) = (0.0, 0.0, 0.0);
        let sweep = scratch.iter().zip(&self.below).zip(&self.inverse_pivot);
        for (((xi, b), d), row) in sweep.zip(rows).rev() {
            let partial = *xi * d - b[2] * y3 - b[1] * y2;
            let y = partial - b[0] * y1;
            each(y, row);
            (y3, y2, y1) = (y2, y1, y);
        }
    }

    /// `solve_in_place` of K right-hand sides side by side: each column's
    /// operations, in their order, are those of its own solve (the same
    /// bits), but the columns' sweeps, each waiting at every row on the row
    /// before, overlap. The static envelope solves thousands (issue 29).
    pub fn solve_each<const K: usize>(&self, mut xs: [&mut [f64]; K]) {
        let n = self.size();
        assert!(xs.iter().all(|x| x.len() == n));
        if !self.dense_inverse.is_empty() {
            for x in xs {
                self.solve_in_place(x);
            }
            return;
        }
        let mut z = [[0.0f64; 3]; K];
        for (i, l) in self.lower.iter().enumerate() {
            for (x, [z3, z2, z1]) in xs.iter_mut().zip(&mut z) {
                let partial = x[i] - l[0] * *z3 - l[1] * *z2;
                let next = partial - l[2] * *z1;
                x[i] = next;
                (*z3, *z2, *z1) = (*z2, *z1, next);
            }
        }
        let mut y = [[0.0f64; 3]; K];
        for i in (0..n).rev() {
            let (b, d) = (&self.below[i], self.inverse_pivot[i]);
            for (x, [y3, y2, y1]) in xs.iter_mut().zip(&mut y) {
                let partial = x[i] * d - b[2] * *y3 - b[1] * *y2;
                let next = partial - b[0] * *y1;
                x[i] = next;
                (*y3, *y2, *y1) = (*y2, *y1, next);
            }
        }
    }

    /// `x ← A⁻¹ x` for a free-DOF vector.
    pub fn solve_mut(&self, x: &mut DVector<f64>) {
        self.solve_in_place(x.as_mut_slice());
    }

    /// Solve for several right-hand sides at once: `columns[i][c]` is row i
    /// of column c. The rows are swept once for all columns (one pass over
    /// the factor, the columns' multiply-adds independent of each other).
    pub fn solve_columns<const C: usize>(&self, columns: &mut [[f64; C]]) {
        let n = self.size();
        assert_eq!(columns.len(), n);
        let lower = &self.lower[..n];
        for i in 1..n {
            let l = &lower[i];
            let mut row = columns[i];
            for k in 1..=i.min(3) {
                let coefficient = l[3 - k];
                let earlier = columns[i - k];
                for c in 0..C {
                    row[c] -= coefficient * earlier[c];
                }
            }
            columns[i] = row;
        }
        for (row, d) in columns.iter_mut().zip(&self.inverse_pivot) {
            for value in row.iter_mut() {
                *value *= d;
            }
        }
        for i in (0..n).rev() {
            let mut row = columns[i];
            for k in 1..(n - i).min(4) {
                let coefficient = lower[i + k][3 - k];
                let later = columns[i + k];
                for c in 0..C {
                    row[c] -= coefficient * later[c];
                }
            }
            columns[i] = row;
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use nalgebra::DMatrix;

    #[test]
    fn the_combined_count_is_the_formed_combinations() {
        let n = 40;
        let a = sample(n);
        let mut b = SymBand::zeros(n);
        for i in 0..n {
            b.add_symmetric(i, i, 1.0 + 0.01 * i as f64);
        }
        let dense = |m: &SymBand| {
            DMatrix::from_fn(n, n, |i, j| {
                let (r, c) = (i.max(j), i.min(j));
                if r - c > 3 {
                    0.0
                } else {
                    m.rows[r][3 - (r - c)]
                }
            })
        };
        let mut seen = std::collections::BTreeSet::new();
        for sigma in [0.0, 4.0, 6.0, 7.0, 8.0, 9.0, 10.0, 12.0, 40.0] {
            let formed = a.combine(1.0, &b, -sigma);
            let count = a.combined_negative_pivots(1.0, &b, -sigma);
            assert_eq!(count, formed.negative_pivots(), "σ = {sigma}");
            // A pivot lost to cancellation has no count (both say so).
            let Some(count) = count else { continue };
            // Sylvester: the negative eigenvalues of the dense A − σ B.
            let eigen = dense(&formed).symmetric_eigen().eigenvalues;
            let below = eigen.iter().filter(|&&l| l < 0.0).count();
            assert_eq!(count, below, "σ = {sigma}");
            seen.insert(below);
        }
        assert!(seen.len() >= 4, "{seen:?}");
    }

    #[test]
    fn a_serial_names_one_factorization_and_its_clones() {
        // What is kept against a serial (`band_inverse`'s band) is right
        // for a clone and never for another factorization, even of the
        // same matrix (equal entries, another serial: computed again).
        let a = sample(30);
        let first = a.ldlt().expect("SPD");
        let again = a.ldlt().expect("SPD");
        assert_eq!(first.clone().serial(), first.serial());
        assert_ne!(again.serial(), first.serial());
        assert_eq!(again, first, "equal entries stay equal factors");
        let mut other = sample(30);
        other.add_symmetric(4, 4, 1.0);
        let other = other.ldlt().expect("SPD");
        assert_ne!(other.serial(), first.serial());
        assert_ne!(other, first);
    }

    /// A random-ish SPD band matrix: diagonally dominant (the band
    /// inverse's tests use it too).
    pub(crate) fn sample(n: usize) -> SymBand {
        let mut a = SymBand::zeros(n);
        for i in 0..n {
            for k in 1..=3.min(i) {
                a.add_symmetric(i, i - k, libm::sin((i * 7 + k * 3) as f64 * 0.37));
            }
            a.add_symmetric(i, i, 8.0 + libm::cos(i as f64));
        }
        a
    }

    fn dense(a: &SymBand) -> DMatrix<f64> {
        DMatrix::from_fn(a.size(), a.size(), |i, j| a.get(i, j))
    }

    #[test]
    fn product_solve_and_quadratic_form_match_dense_algebra() {
        for n in [1usize, 2, 3, 4, 5, 7, 8, 9, 10, 12, 40] {
            let a = sample(n);
            let full = dense(&a);
            let x = DVector::from_fn(n, |i, _| libm::cos(i as f64 * 1.3) + 0.1);
            let mut y = vec![0.0; n];
            a.mul_to(x.as_slice(), &mut y);
            let expected = &full * &x;
            for i in 0..n {
                assert!((y[i] - expected[i]).abs() < 1e-12 * expected.amax().max(1.0));
            }
            // out += s A x on a non-zero start.
            let mut added: Vec<f64> = (0..n).map(|i| i as f64).collect();
            a.mul_add_to(-0.5, x.as_slice(), &mut added);
            for i in 0..n {
                let want = i as f64 - 0.5 * expected[i];
                assert!(
                    (added[i] - want).abs() < 1e-12 * want.abs().max(1.0),
                    "n = {n}"
                );
            }
            let q = a.quadratic_form(x.as_slice());
            assert!(
                (q - x.dot(&expected)).abs() < 1e-12 * q.abs().max(1.0),
                "n = {n}"
            );

            let factor = a.ldlt().expect("SPD");
            let mut solved = expected.clone();
            factor.solve_mut(&mut solved);
            assert!((&solved - &x).amax() < 1e-12, "n = {n}");

            let mut columns: Vec<[f64; 3]> = (0..n)
                .map(|i| [expected[i], 2.0 * expected[i], -expected[i]])
                .collect();
            factor.solve_columns(&mut columns);
            for i in 0..n {
                assert!((columns[i][0] - x[i]).abs() < 1e-12);
                assert!((columns[i][1] - 2.0 * x[i]).abs() < 1e-12);
                assert!((columns[i][2] + x[i]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_paired_residual_solve_gives_the_bits_of_product_then_solve() {
        for n in [1usize, 2, 4, 7, 8, 9, 10, 13, 40] {
            let (mass, stiffness) = (sample(n), sample(n).combine(0.3, &sample(n), -0.1));
            let factor = mass.ldlt().expect("SPD");
            let vector = |phase: f64| -> Vec<f64> {
                (0..n).map(|i| libm::sin(i as f64 * 0.7 + phase)).collect()
            };
            let (u, f) = ([vector(0.1), vector(2.0)], [vector(0.5), vector(-1.0)]);
            let mut expected = [vec![0.0; n], vec![0.0; n]];
            for c in 0..2 {
                stiffness.mul_to(&u[c], &mut expected[c]);
                for (e, f) in expected[c].iter_mut().zip(&f[c]) {
                    *e = f - *e;
                }
                factor.solve_in_place(&mut expected[c]);
            }
            let mut seen = Vec::new();
            let columns = ([&u[0][..], &u[1][..]], [&f[0][..], &f[1][..]]);
            factor.solve_residual_pair(&stiffness, columns, &mut Vec::new(), 0..n, |y, i| {
                seen.push(i);
                assert_eq!(y, [expected[0][i], expected[1][i]], "n = {n}, row {i}");
            });
            assert_eq!(seen, (0..n).rev().collect::<Vec<_>>());
        }
    }

    #[test]
    fn solving_by_rows_gives_the_bits_of_filling_then_solving() {
        for n in [1usize, 2, 5, 8, 9, 10, 40] {
            let factor = sample(n).ldlt().expect("SPD");
            let b: Vec<f64> = (0..n).map(|i| libm::sin(i as f64 * 0.9 + 0.3)).collect();
            let mut expected = b.clone();
            factor.solve_in_place(&mut expected);
            let mut seen = Vec::new();
            let rhs = b.iter().copied();
            factor.solve_rows(&mut Vec::new(), rhs, 0..n, |x, i| {
                assert_eq!(x.to_bits(), expected[i].to_bits(), "n = {n}, row {i}");
                seen.push(i);
            });
            assert_eq!(seen, (0..n).rev().collect::<Vec<_>>());
        }
    }

    #[test]
    fn solving_side_by_side_gives_the_bits_of_one_solve_each() {
        for n in [1usize, 5, 8, 9, 10, 40] {
            let factor = sample(n).ldlt().expect("SPD");
            let column = |c: usize| -> Vec<f64> {
                (0..n)
                    .map(|i| libm::sin(i as f64 * 0.9 + c as f64))
                    .collect()
            };
            let mut xs: Vec<Vec<f64>> = (0..4).map(column).collect();
            let expected: Vec<Vec<f64>> = (0..4)
                .map(|c| {
                    let mut x = column(c);
                    factor.solve_in_place(&mut x);
                    x
                })
                .collect();
            let [a, b, c, d] = &mut xs[..] else {
                unreachable!()
            };
            factor.solve_each([&mut a[..], &mut b[..], &mut c[..], &mut d[..]]);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            for (x, want) in xs.iter().zip(&expected) {
                assert_eq!(bits(x), bits(want), "n = {n}");
            }
        }
    }

    #[test]
    fn an_indefinite_matrix_has_no_factor() {
        let mut a = sample(6);
        a.add_symmetric(4, 4, -20.0);
        assert!(a.ldlt().is_none());
        assert!(dense(&a).cholesky().is_none());
    }
}
