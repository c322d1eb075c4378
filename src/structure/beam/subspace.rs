//! The lowest natural modes of a beam too large for the dense
//! eigenproblem, by subspace iteration: p vectors repeatedly multiplied by
//! (K + s M)⁻¹ M through the band LDLᵀ factor, then Rayleigh–Ritz on the
//! p-dimensional subspace, until the wanted eigenvalues settle. O(n p²)
//! per iteration where the dense eigenproblem is O(n³).
//!
//! Hand-written: nalgebra's and faer's eigensolvers are dense (O(n³), an
//! n×n matrix), and the sparse ones available as crates (Lanczos, LOBPCG)
//! need a sparse-matrix type and a linear solver of their own, where the
//! beam already has an O(n) band factor and band products.

use nalgebra::{DMatrix, DVector};

use super::{HermiteBeam, ELEMENTWISE_RATIO};
use crate::band::{BandLdlt, SymBand};
use crate::dense_modes::{product, reduced_eigen};

/// Largest n·p² (free DOFs times the squared subspace size) the subspace
/// iteration is run for: about a second of work per iteration.
pub const MAX_SUBSPACE_WORK: f64 = 2e9;

/// Up to this many free DOFs the modes come from the dense eigenproblem;
/// beyond, when a quarter of them or fewer are wanted, from the subspace
/// iteration.
pub const DENSE_MODE_DOFS: usize = 64;

/// Largest n·p (free DOFs times subspace size) the subspace iteration
/// holds: its four n×p matrices then take at most 128 MB.
pub const MAX_SUBSPACE_ENTRIES: usize = 4_000_000;

/// Most iterations of the subspace iteration.
const MAX_SUBSPACE_ITERATIONS: usize = 300;

/// Relative change of the wanted Ritz values between two iterations at
/// which they count as settled (above the rounding floor of `worst_change`).
const SETTLED: f64 = 1e-10;

/// What the subspace iteration is run for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Wanted {
    /// The circular frequencies alone: done once the Ritz values settle.
    Frequencies,
    /// Frequencies and shapes.
    Modes,
}

/// The lowest `k` modes by subspace iteration (with `Wanted::Frequencies`,
/// an n × 0 matrix for the shapes).
pub(crate) fn lowest(
    beam: &HermiteBeam,
    k: usize,
    wanted: Wanted,
) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let (mass, stiffness) = (beam.mass_band(), beam.stiffness_band());
    let n = mass.size();
    let p = (2 * k).max(k + 8).min(n);
    refuse_beyond_bounds(beam, (n, k, p))?;
    let (mut factor, mut shift) = stiffness_factor(beam)?;
    let mut x = DMatrix::from_fn(n, p, start_value);
    let mut previous = vec![f64::INFINITY; k];
    let (mut y, mut mx) = (DMatrix::zeros(n, p), DMatrix::zeros(n, p));
    let mut column = DVector::zeros(n);
    let mut settled_at = None;
    for iteration in 0..MAX_SUBSPACE_ITERATIONS {
        for j in 0..p {
            mass.mul_to(x.column(j).as_slice(), column.as_mut_slice());
            mx.set_column(j, &column);
            factor.solve_mut(&mut column);
            y.set_column(j, &column);
        }
        // Columns of y shrink as 1/λ of the mode they converge to: with
        // many modes their Gram matrix loses rank in rounding. Only then
        // (results elsewhere stay bit for bit) each column is scaled to
        // unit M-norm first, which spans the same space. From random start
        // vectors every column is mode 1 to within λ₁/λ_p (1e-8 for 120
        // vectors): the Gram matrix squares that below ε, and only an
        // explicit M-orthonormalization keeps the other directions.
        let (lambda, ritz) = robust_rayleigh_ritz(&mut y, &mut mx, mass, shift)?;
        x = ritz;
        // A shift far above the wanted eigenvalues slows the iteration to
        // a crawl: once, move it down to the k-th Ritz value (an upper
        // bound of λ_k, so K + s M stays positive definite).
        if shift > 0.0 && iteration == 2 && lambda[k - 1] > 0.0 && lambda[k - 1] < shift {
            if let Some(f) = mass.combine(lambda[k - 1], stiffness, 1.0).ldlt() {
                (factor, shift) = (f, lambda[k - 1]);
            }
        }
        let change = worst_change(&lambda, &previous);
        previous.copy_from_slice(&lambda[..k]);
        // The Ritz values converge twice as fast as the vectors: once they
        // settle, as many iterations again bring the vectors to the same
        // accuracy.
        let omega = || lambda[..k].iter().map(|l| l.max(0.0).sqrt()).collect();
        match settled_at {
            None if change <= 1.0 && wanted == Wanted::Frequencies => {
                return Ok((omega(), DMatrix::zeros(n, 0)));
            }
            None if change <= 1.0 => settled_at = Some(iteration),
            Some(at) if iteration > 2 * at => return Ok((omega(), x.columns(0, k).into_owned())),
            _ => {}
        }
    }
    Err(format!(
        "the subspace iteration for {k} modes did not converge in \
         {MAX_SUBSPACE_ITERATIONS} iterations (clustered frequencies; ask for fewer modes)"
    ))
}

/// Refuses a subspace of `p` vectors for `k` modes of `n` free DOFs
/// beyond the memory and work bounds, and a beam whose band stiffness
/// cannot fix a low mode.
fn refuse_beyond_bounds(
    beam: &HermiteBeam,
    (n, k, p): (usize, usize, usize),
) -> Result<(), String> {
    let work = n as f64 * (p * p) as f64;
    if n * p > MAX_SUBSPACE_ENTRIES {
        return Err(format!(
            "{k} modes of a beam of {n} free DOFs need a subspace of {p} vectors \
             (n·p = {}); at most {MAX_SUBSPACE_ENTRIES} (fewer modes or elements)",
            n * p
        ));
    }
    if work > MAX_SUBSPACE_WORK {
        return Err(format!(
            "{k} modes of a beam of {n} free DOFs need a subspace of {p} vectors \
             (n·p² = {work:.1e}); at most {MAX_SUBSPACE_WORK:.0e} (fewer modes or elements)"
        ));
    }
    let ratio = beam.length / beam.min_element_length;
    if ratio > ELEMENTWISE_RATIO {
        return Err(format!(
            "the beam is {ratio:.0} of its shortest elements long; beyond {ELEMENTWISE_RATIO} the \
             band stiffness fixes a low mode's ω² only to about ε (L/h)⁴ of itself, so natural \
             modes are computed up to that ratio (fewer elements)"
        ));
    }
    Ok(())
}

/// The factor the iteration solves with: K itself when the supports hold
/// the beam, K + s M with a small shift s otherwise; and s.
fn stiffness_factor(beam: &HermiteBeam) -> Result<(BandLdlt, f64), String> {
    let (mass, stiffness) = (beam.mass_band(), beam.stiffness_band());
    // K itself when the supports hold the beam; shifted by s M otherwise
    // (the eigenvectors are the same, the Ritz values use K alone).
    Ok(match stiffness.ldlt() {
        Some(f) => (f, 0.0),
        None => {
            let shift = 1e-6 * beam.max_element_frequency().powi(2);
            let factor = mass
                .combine(shift, stiffness, 1.0)
                .ldlt()
                .ok_or("beam stiffness K + s M is not positive definite")?;
            (factor, shift)
        }
    })
}

/// The Rayleigh–Ritz step on the subspace `y` (with M y in `mx`), with the
/// columns scaled to unit M-norm, then M-orthonormalized, where the Gram
/// matrix loses rank.
fn robust_rayleigh_ritz(
    y: &mut DMatrix<f64>,
    mx: &mut DMatrix<f64>,
    mass: &SymBand,
    shift: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    rayleigh_ritz(y, mx, mass, shift)
        .or_else(|_| {
            scale_to_unit_mass_norm(y, mx, mass);
            rayleigh_ritz(y, mx, mass, shift)
        })
        .or_else(|_| {
            mass_orthonormalize(y, mx, mass);
            rayleigh_ritz(y, mx, mass, shift)
        })
}

/// The largest change of a wanted Ritz value since the last iteration, as
/// a multiple of what counts as settled: `SETTLED` of the value (rigid-body
/// modes, ω = 0, measured against the highest wanted), but never less than
/// the rounding of the p × p eigenproblem, p ε λ_p (its backward error is
/// ε times its norm, the largest Ritz value): with 120 vectors on 4,096
/// elements mode 2 jitters at 1e-9 of itself from that rounding alone.
fn worst_change(lambda: &[f64], previous: &[f64]) -> f64 {
    let k = previous.len();
    let rigid_floor = 1e-6 * lambda[k - 1].abs().max(f64::MIN_POSITIVE);
    let largest = lambda.iter().fold(0.0, |a: f64, l| a.max(l.abs()));
    let rounding = lambda.len() as f64 * f64::EPSILON * largest;
    lambda[..k]
        .iter()
        .zip(previous)
        .map(|(l, p)| (l - p).abs() / (SETTLED * l.abs().max(rigid_floor)).max(rounding))
        .fold(0.0, f64::max)
}

/// Rayleigh–Ritz on the columns of y = (K + s M)⁻¹ M x: the Ritz values,
/// ascending, and the M-orthonormal Ritz vectors. K y is taken as
/// M x − s M y, not multiplied out: on a fine mesh K y of a smooth y
/// cancels terms some 1e8 times larger than the result.
fn rayleigh_ritz(
    y: &DMatrix<f64>,
    mx: &DMatrix<f64>,
    mass: &SymBand,
    shift: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let (n, p) = y.shape();
    let mut my = DMatrix::zeros(n, p);
    for j in 0..p {
        let column = y.column(j);
        mass.mul_to(column.as_slice(), my.column_mut(j).as_mut_slice());
    }
    let mr = y.tr_mul(&my);
    let kr = y.tr_mul(mx) - shift * &mr;
    let chol = (0.5 * (&mr + mr.transpose()))
        .cholesky()
        .ok_or("the subspace iteration lost rank (fewer modes or elements)")?;
    let l_inv = chol
        .l()
        .try_inverse()
        .ok_or("the subspace iteration lost rank")?;
    let (eig, order) = reduced_eigen(&l_inv, &kr);
    let z = product(&l_inv.transpose(), &eig.eigenvectors);
    let columns: Vec<DVector<f64>> = order.iter().map(|&i| y * z.column(i)).collect();
    let lambda = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    Ok((lambda, DMatrix::from_columns(&columns)))
}

/// Scale each column of `y` (and of `mx` alike, which `rayleigh_ritz`
/// uses as K y) to unit M-norm; a zero column is left.
fn scale_to_unit_mass_norm(y: &mut DMatrix<f64>, mx: &mut DMatrix<f64>, mass: &SymBand) {
    let mut my = DVector::zeros(y.nrows());
    for j in 0..y.ncols() {
        mass.mul_to(y.column(j).as_slice(), my.as_mut_slice());
        let norm = y.column(j).dot(&my).max(0.0).sqrt();
        if norm > 0.0 && norm.is_finite() {
            y.column_mut(j).scale_mut(1.0 / norm);
            mx.column_mut(j).scale_mut(1.0 / norm);
        }
    }
}

/// M-orthonormalize the columns of `y` by modified Gram–Schmidt, run
/// twice ("twice is enough": the second pass removes what rounding left of
/// the first), applying the same column operations to `mx` so that
/// (K + s M) y = mx still holds. Works on the columns themselves, never on
/// their Gram matrix, whose condition is the square of theirs. A column
/// that vanishes is left at zero (Rayleigh–Ritz then reports lost rank).
fn mass_orthonormalize(y: &mut DMatrix<f64>, mx: &mut DMatrix<f64>, mass: &SymBand) {
    let (n, p) = y.shape();
    // M times each finished column, so that y_iᵀ M y_j is one dot product.
    let mut my = DMatrix::zeros(n, p);
    let mut column = DVector::zeros(n);
    for j in 0..p {
        for _pass in 0..2 {
            for i in 0..j {
                let c = my.column(i).dot(&y.column(j));
                let (yi, mxi) = (y.column(i).into_owned(), mx.column(i).into_owned());
                y.column_mut(j).axpy(-c, &yi, 1.0);
                mx.column_mut(j).axpy(-c, &mxi, 1.0);
            }
        }
        mass.mul_to(y.column(j).as_slice(), column.as_mut_slice());
        let norm = y.column(j).dot(&column).max(0.0).sqrt();
        let scale = if norm > 0.0 && norm.is_finite() {
            1.0 / norm
        } else {
            0.0
        };
        y.column_mut(j).scale_mut(scale);
        mx.column_mut(j).scale_mut(scale);
        my.set_column(j, &(&column * scale));
    }
}

/// A deterministic pseudo-random start vector entry in [−1, 1).
pub(crate) fn start_value(i: usize, j: usize) -> f64 {
    let mut h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64 + 1).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    h ^= h >> 31;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 29;
    (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}
