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
//!
//! Each row also keeps its profile, the first column an entry was added
//! at: a rail off the deck couples three places, not the interleave's
//! seven, and the product, the factor and the solve skip the zeros before
//! it. The factor's fill stays inside the profile, and the skipped terms
//! are exact zeros added at the start of each sum, so the results are the
//! full band's to the bit.
//!
//! The rows are also cut once into runs that repeat one pattern of
//! profile widths (a rail's w and ψ: two, three, two, three…): each run
//! goes period by period with its widths compiled in, without a look-up,
//! a dispatch or a loop set-up by row, the same operations in the same
//! order as row by row (the rows no pattern covers still go one by one).

use std::sync::OnceLock;

/// Runs `$body` with the constant `$P` equal to the profile width `$width`
/// (0 to 8: a rail's rows couple two or three places, the deck's up to
/// eight), or with `$P` = `WIDER` (a loop over the slices) beyond: the
/// fixed widths unroll, where a loop of two or three terms cost more in
/// its set-up than in its terms (the product, the solve and the quadratic
/// form were about 85 instructions a row of three terms).
macro_rules! by_width {
    ($width:expr, $P:ident => $body:expr) => {
        match $width {
            0 => {
                const $P: usize = 0;
                $body
            }
            1 => {
                const $P: usize = 1;
                $body
            }
            2 => {
                const $P: usize = 2;
                $body
            }
            3 => {
                const $P: usize = 3;
                $body
            }
            4 => {
                const $P: usize = 4;
                $body
            }
            5 => {
                const $P: usize = 5;
                $body
            }
            6 => {
                const $P: usize = 6;
                $body
            }
            7 => {
                const $P: usize = 7;
                $body
            }
            8 => {
                const $P: usize = 8;
                $body
            }
            _ => {
                const $P: usize = WIDER;
                $body
            }
        }
    };
}

/// The width `by_width` passes beyond its fixed ones (any above 8): the
/// kernels then run over their slices' whole length.
const WIDER: usize = 9;

/// The first `P` entries of `a` (all where `P` is `WIDER`) as an array's
/// slice: the bounds checked once, so that a fixed `P` unrolls.
#[inline(always)]
fn first<const P: usize>(a: &[f64]) -> &[f64] {
    if P == WIDER {
        a
    } else {
        let fixed: &[f64; P] = a[..P].try_into().expect("P entries");
        fixed
    }
}

/// `first` of a mutable slice.
#[inline(always)]
fn first_mut<const P: usize>(a: &mut [f64]) -> &mut [f64] {
    if P == WIDER {
        a
    } else {
        let fixed: &mut [f64; P] = (&mut a[..P]).try_into().expect("P entries");
        fixed
    }
}

/// Σ l x in order, as `Iterator::sum` adds (from −0), over `P` entries
/// (both slices the row's profile width long).
#[inline(always)]
fn dot_of<const P: usize>(l: &[f64], x: &[f64]) -> f64 {
    let (l, x) = (first::<P>(l), first::<P>(x));
    l.iter().zip(x).map(|(a, b)| a * b).sum()
}

/// `x ← x − l xᵢ` over `P` entries (the back substitution's row).
#[inline(always)]
fn subtract<const P: usize>(l: &[f64], xi: f64, x: &mut [f64]) {
    for (l, xj) in first::<P>(l).iter().zip(first_mut::<P>(x)) {
        *xj -= l * xi;
    }
}

/// One row of `WideBand::mul_to` with `P` entries `left` of the diagonal
/// `diagonal`: returns the row's sum Aᵢᵢ xᵢ + Σ Aᵢⱼ xⱼ and adds the mirror
/// terms Aᵢⱼ xᵢ into `mirror`.
#[inline(always)]
fn row_times<const P: usize>(
    (left, diagonal): (&[f64], f64),
    (xi, before): (f64, &[f64]),
    mirror: &mut [f64],
) -> f64 {
    let mut sum = diagonal * xi;
    let left = first::<P>(left);
    for ((a, xj), oj) in left
        .iter()
        .zip(first::<P>(before))
        .zip(first_mut::<P>(mirror))
    {
        sum += a * xj;
        *oj += a * xi;
    }
    sum
}

/// The patterns of profile widths a run of rows repeats, each with its
/// kernels: a rail alone (w, ψ at each node), a rail on sleepers, a rail
/// and a deck interleaved on a layer, the same on sleepers (the track
/// assembly's numbering, `rail_on_deck::number_dofs`), and bands of one
/// width (0 to 8). Rows that follow none (the ends, the joins) go one by
/// one through `by_width`.
const PATTERNS: [&[usize]; 13] = [
    &[2, 3],
    &[2, 3, 4],
    &[4, 5, 6, 7],
    &[6, 2, 5, 6, 5],
    &[0],
    &[1],
    &[2],
    &[3],
    &[4],
    &[5],
    &[6],
    &[7],
    &[8],
];

/// The rows `over_run` writes out at most in a block of whole periods of
/// a pattern (at least one period of each).
const UNROLLED_ROWS: usize = 8;
const _: () = {
    let mut k = 0;
    while k < PATTERNS.len() {
        assert!(!PATTERNS[k].is_empty() && PATTERNS[k].len() <= UNROLLED_ROWS);
        k += 1;
    }
};

/// Runs `$body` with the constant `$K` equal to the pattern index
/// `$index`: each pattern's kernels are compiled for its widths, so that a
/// run of rows has no dispatch, profile look-up or loop set-up by row.
macro_rules! by_pattern {
    ($index:expr, $K:ident => $body:expr) => {
        by_pattern!(@arms $index, $K, $body, 0 1 2 3 4 5 6 7 8 9 10 11 12)
    };
    (@arms $index:expr, $K:ident, $body:expr, $($k:literal)*) => {
        match $index {
            $($k => {
                const $K: usize = $k;
                $body
            })*
            _ => unreachable!("a run's pattern is an index of PATTERNS"),
        }
    };
}

/// Rows `start..end` of a band: with `pattern` Some(k), the profile widths
/// `PATTERNS[k]` repeated a whole number of times from `start`; with None,
/// rows of any widths, taken one by one.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    start: usize,
    end: usize,
    pattern: Option<usize>,
}

/// How many rows from `start` repeat `pattern` a whole number of times
/// (each row's profile width `widths(i)`, `n` rows in all).
fn rows_repeating(
    pattern: &[usize],
    start: usize,
    n: usize,
    width: &dyn Fn(usize) -> usize,
) -> usize {
    let matching = (start..n)
        .zip(pattern.iter().cycle())
        .take_while(|&(i, &w)| width(i) == w)
        .count();
    matching - matching % pattern.len()
}

/// The rows of a profile (`first[i]` the first column of row i) cut into
/// runs: from each row the pattern covering the most rows, at least two
/// of its periods, or the row alone, joined to the rows one by one before
/// it.
fn runs_of(first: &[usize]) -> Vec<Run> {
    let (n, width) = (first.len(), |i: usize| i - first[i]);
    let mut runs: Vec<Run> = Vec::new();
    let mut start = 0;
    while start < n {
        let best = (PATTERNS.iter().enumerate())
            .map(|(k, p)| (rows_repeating(p, start, n, &width), k))
            .filter(|&(rows, k)| rows >= 2 * PATTERNS[k].len())
            .max_by_key(|&(rows, k)| (rows, std::cmp::Reverse(k)));
        let (end, pattern) = match best {
            Some((rows, k)) => (start + rows, Some(k)),
            None => (start + 1, None),
        };
        match runs.last_mut() {
            Some(last) if last.pattern.is_none() && pattern.is_none() => last.end = end,
            _ => runs.push(Run {
                start,
                end,
                pattern,
            }),
        }
        start = end;
    }
    runs
}

/// Row i of `WideBand::mul_to` (`row` its profile's `width` entries and
/// the diagonal; `P` = `width` unless `WIDER`): writes out[i] and adds
/// the row's mirror terms to out[i − width..i].
#[inline(always)]
fn product_row<const P: usize>(
    row: &[f64],
    (i, width): (usize, usize),
    x: &[f64],
    out: &mut [f64],
) {
    let (left, diagonal) = row.split_at(width);
    let sum = row_times::<P>(
        (left, diagonal[0]),
        (x[i], &x[i - width..i]),
        &mut out[i - width..i],
    );
    // 0 + sum: the bits of the sum onto a zeroed vector (see `mul_to`).
    out[i] = 0.0 + sum;
}

/// Adds row i's term of `WideBand::quadratic_form` to `total`:
/// xᵢ (Aᵢᵢ xᵢ + 2 Σ_{j<i} Aᵢⱼ xⱼ).
#[inline(always)]
fn quadratic_row<const P: usize>(
    row: &[f64],
    (i, width): (usize, usize),
    x: &[f64],
    total: &mut f64,
) {
    let (left, diagonal) = row.split_at(width);
    let off = dot_of::<P>(left, &x[i - width..i]);
    *total += x[i] * (diagonal[0] * x[i] + 2.0 * off);
}

/// Row i of L z = x in place (`row` L's row over its profile, `width`
/// entries).
#[inline(always)]
fn forward_row<const P: usize>(row: &[f64], (i, width): (usize, usize), x: &mut [f64]) {
    let (before, rest) = x.split_at_mut(i);
    rest[0] -= dot_of::<P>(row, &before[i - width..]);
}

/// Row i of Lᵀ x = y in place: the final xᵢ subtracted from those above.
#[inline(always)]
fn backward_row<const P: usize>(row: &[f64], (i, width): (usize, usize), x: &mut [f64]) {
    let (before, rest) = x.split_at_mut(i);
    subtract::<P>(row, rest[0], &mut before[i - width..]);
}

/// How far before its period's first row a pattern's rows reach: the
/// most of `width − r` over its rows r.
const fn reach(pattern: &[usize]) -> usize {
    let (mut r, mut most) = (0, 0);
    while r < pattern.len() {
        if pattern[r] > r && pattern[r] - r > most {
            most = pattern[r] - r;
        }
        r += 1;
    }
    most
}

/// `reach` of each of `PATTERNS`.
const REACHES: [usize; PATTERNS.len()] = {
    let mut reaches = [0; PATTERNS.len()];
    let mut k = 0;
    while k < PATTERNS.len() {
        reaches[k] = reach(PATTERNS[k]);
        k += 1;
    }
    reaches
};

/// Runs `$row::<P>` (a row kernel above) over the rows of `$run` in
/// `$band` (the rows' entries, `stride` a row of which `tail` after the
/// profile, and the profile's first columns), its arguments `[read]`,
/// `[written]` vectors then others: a pattern's run in blocks of whole
/// periods (as many as `UNROLLED_ROWS` rows hold), then its remaining
/// periods one by one; the vectors cut once a block to the window its
/// rows read (`REACHES` before it, so that every index within is a
/// constant), the block's rows written out with their widths constants,
/// so that each row is its unrolled terms and a row's result reaches the
/// next rows of its block in registers, not through memory (a sweep's
/// rows are a chain: a solve's row waits for the one before it); rows
/// one by one with their widths from the profile. `rev` runs the rows
/// backward. The literal row lists below count to `UNROLLED_ROWS`.
macro_rules! over_run {
    ($run:expr, $band:expr, $row:ident $args:tt) => {
        over_run!(@rows $run, $band, $row $args, [0 1 2 3 4 5 6 7], )
    };
    ($run:expr, $band:expr, $row:ident $args:tt, rev) => {
        over_run!(@rows $run, $band, $row $args, [7 6 5 4 3 2 1 0], rev)
    };
    (@window ($start:expr, $len:expr), ([$($read:ident),*], [$($write:ident),*] $(, $arg:expr)*)) => {
        $(let $read = &$read[$start..][..$len];)*
        $(let $write = &mut $write[$start..][..$len];)*
    };
    (@call $P:ident, $row:ident, ($($at:expr),*),
        ([$($read:ident),*], [$($write:ident),*] $(, $arg:expr)*)) => {
        $row::<$P>($($at,)* $($read,)* $($write,)* $($arg),*)
    };
    (@in_order , $first:expr, $then:expr) => {{
        $first;
        $then;
    }};
    (@in_order rev, $first:expr, $then:expr) => {{
        $then;
        $first;
    }};
    // Chunks of `$n` rows of `$part` (its first row `$start`), each row
    // r of a chunk of width `pattern[r % period]`.
    (@chunks ($part:expr, $start:expr, $n:expr), $band:expr,
        $row:ident $args:tt, [$($r:literal)*], $($rev:ident)?) => {
        let (pattern, reach, stride, tail): (&[usize], usize, usize, usize) = $band;
        for (chunk, rows) in $part.chunks_exact($n * stride).enumerate() $(.$rev())? {
            // Every row's width is at most its index: i ≥ reach.
            let i = $start + chunk * $n;
            over_run!(@window (i - reach, reach + $n), $args);
            $(if $r < $n {
                let width = pattern[$r % pattern.len()];
                let row = &rows[($r + 1) * stride - tail - width..($r + 1) * stride];
                by_width!(width, P => over_run!(@call P, $row, (row, (reach + $r, width)), $args));
            })*
        }
    };
    (@rows $run:expr, $band:expr, $row:ident $args:tt, [$($r:literal)*], $($rev:ident)?) => {{
        let (run, (rows, stride, tail, first)): (Run, (&[f64], usize, usize, &[usize])) =
            ($run, $band);
        match run.pattern {
            Some(k) => by_pattern!(k, K => {
                const PERIOD: usize = PATTERNS[K].len();
                const BLOCK: usize = PERIOD * (UNROLLED_ROWS / PERIOD);
                let (pattern, reach) = (PATTERNS[K], REACHES[K]);
                let all = &rows[run.start * stride..run.end * stride];
                let (blocks, rest) = all.split_at(all.len() / (BLOCK * stride) * (BLOCK * stride));
                let rest_start = run.start + blocks.len() / stride;
                over_run!(@in_order $($rev)?,
                    over_run!(@chunks (blocks, run.start, BLOCK), (pattern, reach, stride, tail),
                        $row $args, [$($r)*], $($rev)?),
                    over_run!(@chunks (rest, rest_start, PERIOD), (pattern, reach, stride, tail),
                        $row $args, [$($r)*], $($rev)?))
            }),
            None => {
                for i in (run.start..run.end) $(.$rev())? {
                    let width = i - first[i];
                    let row = &rows[(i + 1) * stride - tail - width..(i + 1) * stride];
                    by_width!(width, P => over_run!(@call P, $row, (row, (i, width)), $args));
                }
            }
        }
    }};
}

/// A symmetric matrix stored by rows of its lower band: row i holds
/// A(i, i − b), …, A(i, i) (entries before the first column are zero).
#[derive(Debug, Clone)]
pub struct WideBand {
    half_bandwidth: usize,
    /// Row-major, `half_bandwidth + 1` entries per row, the diagonal last.
    rows: Vec<f64>,
    /// Per row, the first column any entry was added at (the row's own
    /// index where none was): every entry before it is zero.
    first: Vec<usize>,
    /// The rows' runs (`runs_of(first)`), cut at the first product after
    /// the profile last changed.
    runs: OnceLock<Vec<Run>>,
}

/// Equal entries and profiles (the runs follow from the profile).
impl PartialEq for WideBand {
    fn eq(&self, other: &WideBand) -> bool {
        (self.half_bandwidth, &self.rows, &self.first)
            == (other.half_bandwidth, &other.rows, &other.first)
    }
}

impl WideBand {
    /// The n × n zero matrix of half-bandwidth `half_bandwidth`.
    pub fn zeros(n: usize, half_bandwidth: usize) -> WideBand {
        WideBand {
            half_bandwidth,
            rows: vec![0.0; n * (half_bandwidth + 1)],
            first: (0..n).collect(),
            runs: OnceLock::new(),
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

    fn runs(&self) -> &[Run] {
        self.runs.get_or_init(|| runs_of(&self.first))
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
        if col < self.first[row] {
            self.first[row] = col;
            self.runs.take();
        }
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

    /// `out = A x`: each stored entry of the row's profile once, for its
    /// own row and its mirror (the product is most of a rail-over-deck
    /// step), run by run.
    pub fn mul_to(&self, x: &[f64], out: &mut [f64]) {
        assert!(x.len() == self.size() && out.len() == self.size());
        // Row i adds its mirror terms to out[first..i] only: out[i] is
        // first written at row i, as 0 + sum (the bits of the sum onto a
        // zeroed vector, −0 included), so the vector needs no zeroing.
        let bands = (&self.rows[..], self.half_bandwidth + 1, 1, &self.first[..]);
        for &run in self.runs() {
            over_run!(run, bands, product_row([x], [out]));
        }
    }

    /// xᵀ A x in one pass over the rows, Σᵢ xᵢ (Aᵢᵢ xᵢ + 2 Σ_{j<i} Aᵢⱼ xⱼ):
    /// half the multiplications of `mul_to` and a dot, no product vector
    /// (the rail's kinetic energy at every output row). Its rounding is
    /// not `mul_to`'s and a dot's: a quadratic form's, to ε ‖A‖ ‖x‖².
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        assert!(x.len() == self.size());
        let mut total = 0.0;
        let bands = (&self.rows[..], self.half_bandwidth + 1, 1, &self.first[..]);
        for &run in self.runs() {
            over_run!(run, bands, quadratic_row([x], [], &mut total));
        }
        total
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
            first: self.first.clone(),
            runs: self.runs().to_vec(),
        };
        for i in 0..n {
            let first = self.first[i];
            for j in first..i {
                // Σ over m < j within both rows' profiles: L(i,m) D(m) L(j,m).
                let shared = first.max(self.first[j]);
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
/// with A's half-bandwidth and profile.
#[derive(Debug, Clone, PartialEq)]
pub struct WideLdlt {
    half_bandwidth: usize,
    /// Row i: L(i, i − b), …, L(i, i − 1).
    lower: Vec<f64>,
    pivot: Vec<f64>,
    /// A's profile, which is L's: row i is zero before column `first[i]`.
    first: Vec<usize>,
    /// A's runs of rows, which are L's.
    runs: Vec<Run>,
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
    /// final entry of x subtracted from those above it; each row over its
    /// profile only, run by run.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.size());
        let b = self.half_bandwidth;
        // Without a band every row's profile is empty: L is the identity
        // (and rows of no entries cannot be cut into chunks).
        let lower = (&self.lower[..], b, 0, &self.first[..]);
        if b > 0 {
            for &run in &self.runs {
                over_run!(run, lower, forward_row([], [x]));
            }
        }
        for (xi, d) in x.iter_mut().zip(&self.pivot) {
            *xi /= d;
        }
        if b > 0 {
            for &run in self.runs.iter().rev() {
                over_run!(run, lower, backward_row([], [x]), rev);
            }
        }
    }
}

mod inverse;
mod recall;
pub use inverse::InverseWideBand;
pub use recall::RecallingLdlt;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::band::SymBand;
    use nalgebra::{DMatrix, DVector};

    /// A rail on a deck, interleaved per node (rail w, ψ, deck w, ψ): each
    /// element couples eight consecutive DOFs, half-bandwidth 7; diagonally
    /// dominant, so positive definite.
    pub(crate) fn coupled(nodes: usize) -> WideBand {
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

    /// `solved` is A⁻¹ `x` to 1e-12 of the dense Cholesky solution's size.
    fn assert_solves_as_dense(a: &WideBand, x: Vec<f64>, solved: Vec<f64>) {
        let dense_solution = dense(a)
            .cholesky()
            .expect("spd")
            .solve(&DVector::from_vec(x));
        let error = (DVector::from_vec(solved) - &dense_solution).amax();
        assert!(error < 1e-12 * dense_solution.amax(), "error {error:e}");
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
    fn the_quadratic_form_is_the_dense_xt_a_x_over_every_profile() {
        for a in [coupled(12), rail_then_deck_then_rail()] {
            let n = a.size();
            let x = DVector::from_fn(n, |i, _| ((i * 7) % 5) as f64 * 0.3 - 0.55);
            // Independent: the dense matrix's product, then the dot.
            let expected = x.dot(&(dense(&a) * &x));
            let form = a.quadratic_form(x.as_slice());
            assert!(
                (form - expected).abs() < 1e-13 * expected.abs(),
                "{form} against {expected}"
            );
        }
    }

    /// A rail alone on the approach (two DOFs a node: each element couples
    /// four places), then interleaved with a deck (four a node), then
    /// alone again, in one band of half-bandwidth 7: rows of three profiles.
    pub(crate) fn rail_then_deck_then_rail() -> WideBand {
        band_of_node_widths(&[2, 2, 2, 2, 4, 4, 4, 4, 4, 2, 2, 2, 2])
    }

    /// A band of half-bandwidth 7 over nodes of `widths` DOFs, each
    /// element coupling its two nodes' shared places, diagonally dominant
    /// (also the recalling solve's tests').
    pub(super) fn band_of_node_widths(widths: &[usize]) -> WideBand {
        let starts: Vec<usize> = (widths.iter())
            .scan(0, |at, w| {
                let start = *at;
                *at += w;
                Some(start)
            })
            .collect();
        let n = starts[widths.len() - 1] + 2;
        let mut a = WideBand::zeros(n, 7);
        for e in 0..widths.len() - 1 {
            let shared = widths[e].min(widths[e + 1]);
            let dofs: Vec<usize> = (starts[e]..starts[e] + shared)
                .chain(starts[e + 1]..starts[e + 1] + shared)
                .collect();
            for (p, &i) in dofs.iter().enumerate() {
                for (q, &j) in dofs.iter().enumerate().take(p + 1) {
                    let value = ((p * 5 + q * 3 + e) % 13) as f64 * 0.1 - 0.6;
                    a.add_symmetric(i, j, value).expect("in band");
                }
            }
        }
        for i in 0..n {
            a.add_symmetric(i, i, 12.0 + (i % 5) as f64)
                .expect("diagonal");
        }
        a
    }

    /// The full band's product, factor and solve (every row over its whole
    /// band, as before the profile), for the bit-for-bit comparison.
    fn full_band_product_and_solve(a: &WideBand, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (n, b) = (a.size(), a.half_bandwidth);
        let mut product = vec![0.0; n];
        for (i, row) in a.rows.chunks_exact(b + 1).enumerate() {
            let mut sum = row[b] * x[i];
            for (k, value) in row.iter().enumerate().take(b).skip(b.saturating_sub(i)) {
                sum += value * x[i + k - b];
                product[i + k - b] += value * x[i];
            }
            product[i] += sum;
        }
        let (mut lower, mut pivot) = (vec![0.0; n * b], vec![0.0; n]);
        for i in 0..n {
            let first = i.saturating_sub(b);
            for j in first..i {
                let shared = first.max(j.saturating_sub(b));
                let sum: f64 = (shared..j)
                    .map(|m| lower[i * b + b - (i - m)] * pivot[m] * lower[j * b + b - (j - m)])
                    .sum();
                lower[i * b + b - (i - j)] = (a.get(i, j) - sum) / pivot[j];
            }
            let sum: f64 = (first..i)
                .map(|m| lower[i * b + b - (i - m)].powi(2) * pivot[m])
                .sum();
            pivot[i] = a.get(i, i) - sum;
        }
        let mut y = x.to_vec();
        for i in 0..n {
            let sum: f64 = (b.saturating_sub(i)..b)
                .map(|k| lower[i * b + k] * y[i + k - b])
                .sum();
            y[i] -= sum;
        }
        for (yi, d) in y.iter_mut().zip(&pivot) {
            *yi /= d;
        }
        for i in (0..n).rev() {
            for k in b.saturating_sub(i)..b {
                y[i + k - b] -= lower[i * b + k] * y[i];
            }
        }
        (product, y)
    }

    #[test]
    fn over_each_rows_profile_the_product_and_solve_are_the_full_bands_to_the_bit() {
        let a = rail_then_deck_then_rail();
        let n = a.size();
        assert!(a
            .first
            .iter()
            .enumerate()
            .any(|(i, &f)| i >= 7 && f > i - 7));
        let x: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 * 0.37 - 1.9).collect();
        let (product, solution) = full_band_product_and_solve(&a, &x);
        // Onto a vector of garbage: the product writes every entry.
        let mut fast = vec![f64::NAN; n];
        a.mul_to(&x, &mut fast);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&fast), bits(&product));
        // A zero row's −0 sum is +0, as on a zeroed vector.
        let negative = vec![-0.0; n];
        a.mul_to(&negative, &mut fast);
        assert!(fast.iter().all(|x| x.to_bits() == 0), "{fast:?}");
        let mut solved = x.clone();
        a.ldlt().expect("spd").solve_in_place(&mut solved);
        assert_eq!(bits(&solved), bits(&solution));
        assert_solves_as_dense(&a, x, solved);
    }

    /// Rows of the given profile widths, half-bandwidth 10: a rail's
    /// pattern, a rail and deck's, a rail on sleepers', one on sleepers
    /// and a deck's, a band of one width, rows wider than `by_width`'s
    /// fixed ones and rows between patterns; every entry of each profile
    /// non-zero, diagonally dominant.
    fn band_of_patterns() -> WideBand {
        let repeat = |pattern: &[usize], times: usize| pattern.repeat(times);
        let widths: Vec<usize> = [
            vec![0, 1, 2, 3],
            repeat(&[2, 3], 6),
            repeat(&[4, 5, 6, 7], 3),
            vec![3, 4],
            repeat(&[2, 3, 4], 5),
            vec![0, 4, 5],
            repeat(&[6, 2, 5, 6, 5], 4),
            vec![5],
            repeat(&[7], 4),
            vec![10, 9, 10, 1, 1],
            repeat(&[2, 3], 3),
            vec![2],
        ]
        .concat();
        let mut a = WideBand::zeros(widths.len(), 10);
        for (i, &width) in widths.iter().enumerate() {
            for j in i - width..i {
                let value = ((i * 7 + j * 3) % 13) as f64 * 0.1 - 0.65;
                a.add_symmetric(i, j, if value == 0.0 { 0.05 } else { value })
                    .expect("in band");
            }
        }
        for i in 0..widths.len() {
            a.add_symmetric(i, i, 25.0 + (i % 3) as f64)
                .expect("diagonal");
        }
        a
    }

    /// `a` with its rows in one run taken one by one (the kernels as they
    /// were before the runs).
    fn row_by_row(a: &WideBand) -> WideBand {
        let mut by_rows = a.clone();
        let all = Run {
            start: 0,
            end: a.size(),
            pattern: None,
        };
        by_rows.runs = OnceLock::from(vec![all]);
        by_rows
    }

    #[test]
    fn the_runs_cover_every_row_once_each_repeating_its_pattern_whole() {
        let a = band_of_patterns();
        let runs = a.runs();
        assert_eq!((runs[0].start, runs[runs.len() - 1].end), (0, a.size()));
        for (run, next) in runs.iter().zip(&runs[1..]) {
            assert_eq!(run.end, next.start, "{runs:?}");
        }
        for run in runs {
            let Some(k) = run.pattern else { continue };
            let pattern = PATTERNS[k];
            assert_eq!((run.end - run.start) % pattern.len(), 0, "{run:?}");
            for (i, &width) in (run.start..run.end).zip(pattern.iter().cycle()) {
                assert_eq!(i - a.first[i], width, "row {i} of {run:?}");
            }
        }
        let used = |k: usize| runs.iter().any(|run| run.pattern == Some(k));
        assert!((0..4).all(used) && used(11), "{runs:?}");
        assert!(runs.iter().any(|run| run.pattern.is_none()));
        // A new entry before a row's profile cuts the runs again.
        let mut b = a.clone();
        b.add_symmetric(7, 2, 0.5).expect("in band");
        assert!(b
            .runs()
            .iter()
            .any(|run| run.pattern.is_none() && run.start <= 7 && 7 < run.end));
    }

    #[test]
    fn run_by_run_the_kernels_are_row_by_rows_and_the_full_bands_to_the_bit() {
        let a = band_of_patterns();
        let n = a.size();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        // Signed zeros and a tiny entry among the values: the runs make
        // the same operations in the same order as the rows one by one.
        let signed = |i: usize| match i % 9 {
            0 => -0.0,
            4 => 0.0,
            7 => -1e-310,
            _ => ((i * 7) % 11) as f64 * 0.37 - 1.9,
        };
        let x: Vec<f64> = (0..n).map(signed).collect();
        let (fast, slow) = (a.clone(), row_by_row(&a));
        let (mut by_runs, mut by_rows) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        fast.mul_to(&x, &mut by_runs);
        slow.mul_to(&x, &mut by_rows);
        assert_eq!(bits(&by_runs), bits(&by_rows));
        let forms = [fast.quadratic_form(&x), slow.quadratic_form(&x)];
        assert_eq!(forms[0].to_bits(), forms[1].to_bits());
        let (mut by_runs, mut by_rows) = (x.clone(), x.clone());
        fast.ldlt().expect("spd").solve_in_place(&mut by_runs);
        slow.ldlt().expect("spd").solve_in_place(&mut by_rows);
        assert_eq!(bits(&by_runs), bits(&by_rows));
        // Without signed zeros, the full band's bits too.
        let x: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 * 0.37 - 1.9).collect();
        let (product, solution) = full_band_product_and_solve(&a, &x);
        a.mul_to(&x, &mut by_runs);
        assert_eq!(bits(&by_runs), bits(&product));
        let mut solved = x.clone();
        a.ldlt().expect("spd").solve_in_place(&mut solved);
        assert_eq!(bits(&solved), bits(&solution));
        assert_solves_as_dense(&a, x, solved);
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
