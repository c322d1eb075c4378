//! The band solve of a sequence of right-hand sides each of which differs
//! from the last in some rows only (an implicit step's integrations, whose
//! loads move at the contacts alone): the rows whose result cannot change
//! are recalled from the last solve instead of solved again, to the bit.
//!
//! Row i of the forward sweep L z = r reads r_i and z over its profile;
//! if from row p on every r_i has the last solve's bits, and z over the
//! profiles of rows p… before p too, every z_i from p on has its bits
//! (the same operations on the same operands). The back substitution
//! Lᵀ x = D⁻¹ z then has the last x from the end down to p, and the rows
//! above p receive the recalled rows' terms in the order the full sweep
//! subtracts them. On a rail the response to a contact's change of load
//! decays along the track until it is below the rounding of the rows it
//! reaches: ahead of a train the rows keep their bits.

use super::*;
use crate::linalg::bits::copy_in_blocks;

/// Rows a piece of the sweeps holds at most: where the forward sweep may
/// stop. A stop test reads up to a profile's width of entries, and a piece
/// costs its set-up: a few dozen rows.
const PIECE_ROWS: usize = 48;

/// The last solve: its right-hand side, forward sweep L⁻¹ r and solution.
#[derive(Debug, Clone)]
struct LastSolve {
    rhs: Vec<f64>,
    forward: Vec<f64>,
    solution: Vec<f64>,
}

/// A `WideLdlt` with its last solve kept (`solve_in_place`).
#[derive(Debug, Clone)]
pub struct RecallingLdlt {
    factor: WideLdlt,
    /// The factor's runs cut into pieces of at most `PIECE_ROWS` rows
    /// (whole periods of their patterns).
    pieces: Vec<Run>,
    /// Per row i, the first column any row from i on reads: min over
    /// k ≥ i of the profile's first column.
    reach_from: Vec<usize>,
    last: Option<LastSolve>,
}

/// The same factor, whatever each solved last.
impl PartialEq for RecallingLdlt {
    fn eq(&self, other: &RecallingLdlt) -> bool {
        self.factor == other.factor
    }
}

impl RecallingLdlt {
    pub fn new(factor: WideLdlt) -> RecallingLdlt {
        let pieces = pieces_of(&factor.runs);
        let mut reach_from = factor.first.clone();
        for i in (0..reach_from.len().saturating_sub(1)).rev() {
            reach_from[i] = reach_from[i].min(reach_from[i + 1]);
        }
        RecallingLdlt {
            factor,
            pieces,
            reach_from,
            last: None,
        }
    }

    pub fn factor(&self) -> &WideLdlt {
        &self.factor
    }

    /// `x ← A⁻¹ x` with the bits of `WideLdlt::solve_in_place`, the rows
    /// it cannot change since the last solve recalled. Returns how many
    /// rows of the solution were recalled (from the end).
    pub fn solve_in_place(&mut self, x: &mut [f64]) -> usize {
        let (n, b) = (self.factor.size(), self.factor.half_bandwidth);
        assert_eq!(x.len(), n);
        if b == 0 || n == 0 {
            self.factor.solve_in_place(x);
            return 0;
        }
        let (h, q) = match &self.last {
            Some(last) => changed_rows(&last.rhs, x),
            None => (0, n),
        };
        let last = self.last.get_or_insert_with(|| LastSolve {
            rhs: vec![0.0; n],
            forward: vec![0.0; n],
            solution: vec![0.0; n],
        });
        if h == n {
            copy_in_blocks(x, &last.solution);
            return n;
        }
        copy_in_blocks(&mut last.rhs[h..q], &x[h..q]);
        // From the piece holding the first changed row: the rows before it
        // are the last forward sweep's, those after it in the piece
        // still the right-hand side's (the last one's too).
        let from = self.pieces.partition_point(|piece| piece.end <= h);
        let start = self.pieces[from].start;
        copy_in_blocks(&mut x[..start], &last.forward[..start]);
        let factor = &self.factor;
        let lower = (&factor.lower[..], b, 0, &factor.first[..]);
        let (mut p, mut solved) = (n, self.pieces.len());
        for (k, &piece) in self.pieces.iter().enumerate().skip(from) {
            let i = piece.start;
            let read = self.reach_from[i]..i;
            if i >= q && same_bits(&x[read.clone()], &last.forward[read]) {
                (p, solved) = (i, k);
                break;
            }
            over_run!(piece, lower, forward_row([], [x]));
        }
        copy_in_blocks(&mut last.forward[start..p], &x[start..p]);
        for (xi, d) in x[..p].iter_mut().zip(&factor.pivot) {
            *xi /= d;
        }
        factor.subtract_recalled(p, &last.solution, x);
        copy_in_blocks(&mut x[p..], &last.solution[p..]);
        for &piece in self.pieces[..solved].iter().rev() {
            over_run!(piece, lower, backward_row([], [x]), rev);
        }
        copy_in_blocks(&mut last.solution[..p], &x[..p]);
        n - p
    }
}

impl WideLdlt {
    /// The back substitution's terms of the rows from `p` on (their
    /// solution `solution`) in the rows before `p`, row by row from the
    /// last that reaches before `p`, as `solve_in_place` subtracts them.
    fn subtract_recalled(&self, p: usize, solution: &[f64], x: &mut [f64]) {
        let (n, b) = (self.size(), self.half_bandwidth);
        for k in (p..(p + b).min(n)).rev() {
            let first = self.first[k];
            if first >= p {
                continue;
            }
            let row = &self.lower[k * b + b - (k - first)..k * b + b - (k - p)];
            let xk = solution[k];
            for (xj, l) in x[first..p].iter_mut().zip(row) {
                *xj -= l * xk;
            }
        }
    }
}

/// The runs cut into pieces of at most `PIECE_ROWS` rows, each a whole
/// number of its pattern's periods.
fn pieces_of(runs: &[Run]) -> Vec<Run> {
    let mut pieces = Vec::new();
    for run in runs {
        let period = run.pattern.map_or(1, |k| PATTERNS[k].len());
        let rows = PIECE_ROWS - PIECE_ROWS % period;
        for start in (run.start..run.end).step_by(rows) {
            pieces.push(Run {
                start,
                end: (start + rows).min(run.end),
                ..*run
            });
        }
    }
    pieces
}

/// The rows `h..q` outside which `new` has `last`'s bits: (n, n) where
/// every row has them. Compared a block of rows at a time, each block
/// without a branch by row.
fn changed_rows(last: &[f64], new: &[f64]) -> (usize, usize) {
    let n = new.len();
    let same_blocks = (last
        .chunks_exact(BLOCK_ROWS)
        .zip(new.chunks_exact(BLOCK_ROWS)))
    .take_while(|(a, b)| same_block(a, b))
    .count();
    let h = same_blocks * BLOCK_ROWS;
    let h = h + same_rows(last[h..].iter().zip(&new[h..]));
    if h == n {
        return (n, n);
    }
    let same_blocks = (last
        .rchunks_exact(BLOCK_ROWS)
        .zip(new.rchunks_exact(BLOCK_ROWS)))
    .take_while(|(a, b)| same_block(a, b))
    .count();
    let end = n - same_blocks * BLOCK_ROWS;
    (
        h,
        end - same_rows(last[..end].iter().zip(&new[..end]).rev()),
    )
}

/// Rows `changed_rows` compares at once.
const BLOCK_ROWS: usize = 8;

fn same_block(a: &[f64], b: &[f64]) -> bool {
    let (a, b): (&[f64; BLOCK_ROWS], &[f64; BLOCK_ROWS]) = (
        a.try_into().expect("a block"),
        b.try_into().expect("a block"),
    );
    let mut differ = 0;
    for k in 0..BLOCK_ROWS {
        differ |= a[k].to_bits() ^ b[k].to_bits();
    }
    differ == 0
}

/// How many of the pairs `rows` give have the same bits, from the first.
fn same_rows<'a>(rows: impl Iterator<Item = (&'a f64, &'a f64)>) -> usize {
    rows.take_while(|(a, b)| a.to_bits() == b.to_bits()).count()
}

/// Whether the few entries a piece's first row reads have the last
/// solve's bits: an early exit per entry (`linalg::bits::same_bits`,
/// which or-s every entry's bits, took 1.7 M more instructions on
/// `rail.toml`).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rail (two DOFs a node, each element coupling four places) of
    /// `rail` nodes each side of `deck` nodes where a deck's two DOFs are
    /// interleaved (four a node): rows of three profiles, half-bandwidth
    /// 7, diagonally dominant, so that a change of one row's load decays
    /// along the band below the rounding of the rows it reaches.
    fn long_rail_over_a_deck(rail: usize, deck: usize) -> WideBand {
        let widths: Vec<usize> = [vec![2; rail], vec![4; deck], vec![2; rail]].concat();
        super::super::tests::band_of_node_widths(&widths)
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn a_solve_recalling_the_last_has_the_plain_solves_bits_and_recalls_the_unchanged_rows() {
        let a = long_rail_over_a_deck(80, 12);
        let n = a.size();
        let factor = a.ldlt().expect("positive definite");
        let mut recalling = RecallingLdlt::new(factor.clone());
        let base: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 * 0.37 - 1.9).collect();
        let changed = |rows: &[(usize, f64)]| {
            let mut rhs = base.clone();
            for &(i, value) in rows {
                rhs[i] = value;
            }
            rhs
        };
        // (right-hand side, how many rows at least and at most are recalled)
        let sequence = [
            (base.clone(), 0, 0),
            // A load moved in the deck's rows: the rail far ahead keeps
            // its bits, the rows behind and the deck's are solved again.
            (changed(&[(170, 3.5), (171, -0.25)]), n / 4, n - 171),
            (changed(&[(170, 3.5), (171, -0.25)]), n, n),
            // A −0 where +0 was is a change too; so are the first and
            // last rows.
            (changed(&[(0, 1.0), (n - 1, 0.0)]), 0, 0),
            (changed(&[(0, 1.0), (n - 1, -0.0)]), 0, 0),
            (changed(&[(40, 2.0), (n - 1, -0.0)]), n / 2, n - 41),
            (changed(&[(n - 30, f64::NAN)]), 0, 30),
            (base.clone(), 0, 30),
        ];
        for (k, (rhs, fewest, most)) in sequence.into_iter().enumerate() {
            let mut plain = rhs.clone();
            factor.solve_in_place(&mut plain);
            let mut recalled = rhs;
            let rows = recalling.solve_in_place(&mut recalled);
            assert_eq!(bits(&recalled), bits(&plain), "solve {k}");
            assert!(
                (fewest..=most).contains(&rows),
                "solve {k}: {rows} rows recalled, not {fewest} to {most}"
            );
        }
    }

    #[test]
    fn the_pieces_cover_the_runs_in_whole_periods() {
        let a = long_rail_over_a_deck(80, 12);
        let factor = a.ldlt().expect("positive definite");
        let pieces = pieces_of(&factor.runs);
        assert!(pieces.len() > factor.runs.len());
        assert_eq!(
            (pieces[0].start, pieces[pieces.len() - 1].end),
            (0, a.size())
        );
        for (piece, next) in pieces.iter().zip(&pieces[1..]) {
            assert_eq!(piece.end, next.start);
        }
        for piece in &pieces {
            let period = piece.pattern.map_or(1, |k| PATTERNS[k].len());
            let run = (factor.runs.iter())
                .find(|run| run.start <= piece.start && piece.end <= run.end)
                .expect("within a run");
            assert_eq!(run.pattern, piece.pattern);
            assert_eq!((piece.start - run.start) % period, 0);
            assert!(piece.end - piece.start <= PIECE_ROWS);
        }
    }
}
