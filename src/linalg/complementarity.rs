//! A small mixed linear complementarity problem: find P with
//! w = W P − b, where each row is either an equality (w = 0, P free) or
//! unilateral (P ≥ 0, w ≥ 0, P w = 0), for a symmetric positive definite W.
//!
//! Solved by Murty's least-index principal pivoting (K. G. Murty, "Note on
//! a Bard-type scheme for solving the complementarity problem", Opsearch
//! 11, 1974): keep a set of unilateral rows held at w = 0, solve the
//! equalities on it, and switch the first row (least index) whose P or w
//! has the wrong sign. For P-matrices (the Schur complement of an SPD W on
//! its unilateral rows is one) it ends from any starting set: the last
//! unilateral row switches at most once, and between its switches the
//! rows before it are solved the same way, so m unilateral rows take at
//! most 2^m − 1 switches (in practice none, one or two). Written here because the problem has a handful of rows and needs
//! exact complementarity (to round-off), which the iterative QP solvers
//! among the crates (interior point, ADMM) give only to a tolerance.

use nalgebra::{DMatrix, DVector};

/// How a row of the problem is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Row {
    /// w = 0, P of either sign.
    Equality,
    /// P ≥ 0 and w ≥ 0, one of them zero.
    Unilateral,
}

/// The solution: P, w and which unilateral rows ended held (w = 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub p: DVector<f64>,
    pub w: DVector<f64>,
    pub held: Vec<bool>,
    /// Rows switched on the way (0 when every row was held at once).
    pub switches: usize,
}

/// At most this many switches are tried (2^20 − 1, the bound for 20
/// unilateral rows); past it the problem is refused rather than run on.
const MAX_SWITCHES: usize = (1 << 20) - 1;

/// Solve the problem, starting with every row held (the bilateral
/// solution, which is the answer whenever it has no tensile row).
pub fn solve(w: &DMatrix<f64>, b: &DVector<f64>, rows: &[Row]) -> Result<Solution, String> {
    let n = b.len();
    let unilateral = rows.iter().filter(|&&r| r == Row::Unilateral).count();
    let bound = if unilateral >= 20 {
        MAX_SWITCHES
    } else {
        (1usize << unilateral) - 1
    };
    // Round-off scales: a velocity error of 1e-12 of the largest target,
    // and the impulse that causes it on each row.
    let scale = b.amax().max(f64::MIN_POSITIVE);
    let tolerance_w = 1e-12 * scale;
    let tolerance_p: Vec<f64> = (0..n).map(|i| tolerance_w / w[(i, i)].abs()).collect();
    let mut held = vec![true; n];
    for switches in 0..=bound {
        let p = solve_held(w, b, &held)?;
        let residual = w * &p - b;
        let wrong = (0..n).find(|&i| {
            rows[i] == Row::Unilateral
                && if held[i] {
                    p[i] < -tolerance_p[i]
                } else {
                    residual[i] < -tolerance_w
                }
        });
        match wrong {
            Some(i) => held[i] = !held[i],
            None => {
                return Ok(Solution {
                    p,
                    w: residual,
                    held,
                    switches,
                })
            }
        }
    }
    Err(format!(
        "the impact's complementarity problem ({n} rows) was not solved in {bound} switches"
    ))
}

/// P on the held rows from W_hh P_h = b_h, zero on the others.
fn solve_held(w: &DMatrix<f64>, b: &DVector<f64>, held: &[bool]) -> Result<DVector<f64>, String> {
    let index: Vec<usize> = (0..b.len()).filter(|&i| held[i]).collect();
    let k = index.len();
    let mut p = DVector::zeros(b.len());
    if k == 0 {
        // Nothing held (nalgebra's LU does not take an empty system).
        return Ok(p);
    }
    let sub = DMatrix::from_fn(k, k, |i, j| w[(index[i], index[j])]);
    let rhs = DVector::from_iterator(k, index.iter().map(|&i| b[i]));
    let x = sub
        .lu()
        .solve(&rhs)
        .filter(|x| x.iter().all(|v| v.is_finite()))
        .ok_or("the impact's Delassus operator is singular")?;
    for (&i, &v) in index.iter().zip(x.iter()) {
        p[i] = v;
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(w: &DMatrix<f64>, b: &DVector<f64>, rows: &[Row], s: &Solution) {
        let residual = w * &s.p - b;
        for i in 0..b.len() {
            assert!((residual[i] - s.w[i]).abs() < 1e-12);
            match rows[i] {
                Row::Equality => assert!(s.w[i].abs() < 1e-12, "row {i}: {s:?}"),
                Row::Unilateral => {
                    assert!(s.p[i] >= -1e-12 && s.w[i] >= -1e-12, "row {i}: {s:?}");
                    assert!((s.p[i] * s.w[i]).abs() < 1e-12, "row {i}: {s:?}");
                }
            }
        }
    }

    #[test]
    fn a_row_that_would_pull_is_released_and_moves_away() {
        // Two rows coupled positively: holding both makes the second pull.
        let w = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let b = DVector::from_vec(vec![3.0, 0.0]);
        let rows = [Row::Unilateral, Row::Unilateral];
        let s = solve(&w, &b, &rows).unwrap();
        check(&w, &b, &rows, &s);
        assert_eq!(s.held, vec![true, false]);
        assert_eq!(s.p[0], 1.5);
        assert_eq!(s.w[1], 1.5);
        assert_eq!(s.switches, 1);
    }

    #[test]
    fn rows_that_all_move_away_take_no_impulse() {
        let w = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let b = DVector::from_vec(vec![-1.0, -1.0]);
        let rows = [Row::Unilateral, Row::Unilateral];
        let s = solve(&w, &b, &rows).unwrap();
        check(&w, &b, &rows, &s);
        assert_eq!(s.held, vec![false, false]);
        assert_eq!(s.p, DVector::zeros(2));
    }

    #[test]
    fn an_equality_row_may_pull() {
        let w = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let b = DVector::from_vec(vec![3.0, 0.0]);
        let rows = [Row::Unilateral, Row::Equality];
        let s = solve(&w, &b, &rows).unwrap();
        check(&w, &b, &rows, &s);
        assert!(s.p[1] < 0.0);
    }

    #[test]
    fn random_definite_problems_are_complementary() {
        // A fixed pseudo-random sequence (no dependency for a test): W = A Aᵀ
        // + I, b of both signs, a mix of row kinds.
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for n in 1..9 {
            for _ in 0..50 {
                let a = DMatrix::from_fn(n, n, |_, _| next());
                let w = &a * a.transpose() + DMatrix::identity(n, n);
                let b = DVector::from_fn(n, |_, _| next());
                let rows: Vec<Row> = (0..n)
                    .map(|i| {
                        if i % 3 == 2 {
                            Row::Equality
                        } else {
                            Row::Unilateral
                        }
                    })
                    .collect();
                let s = solve(&w, &b, &rows).unwrap();
                check(&w, &b, &rows, &s);
            }
        }
    }
}
