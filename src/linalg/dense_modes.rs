//! The lowest natural modes of a small structure by the dense generalized
//! eigenproblem K φ = ω² M φ, through the Cholesky factor of M (nalgebra's
//! symmetric eigensolver has no generalized form, so it is reduced by hand).

use nalgebra::{DMatrix, DVector, Dyn, SymmetricEigen};

/// The lowest `count` circular frequencies (rad/s, ascending) and their
/// M-orthonormal shapes (columns; n × 0 for none) of dense `mass` and
/// `stiffness`; `what` names the structure in the errors.
pub fn lowest_modes(
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    count: usize,
    what: &str,
) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let n = mass.nrows();
    let l_inv = mass
        .cholesky()
        .ok_or(format!("{what} mass matrix is not positive definite"))?
        .l()
        .try_inverse()
        .ok_or(format!("{what} mass matrix is singular"))?;
    let (eig, mut order) = reduced_eigen(&l_inv, &stiffness);
    order.truncate(count.min(n));
    let omega = order
        .iter()
        .map(|&i| eig.eigenvalues[i].max(0.0).sqrt())
        .collect();
    // φ = L⁻ᵀ y: M-orthonormal because the y are orthonormal.
    let columns: Vec<_> = order
        .iter()
        .map(|&i| l_inv.transpose() * eig.eigenvectors.column(i))
        .collect();
    let shapes = if columns.is_empty() {
        DMatrix::zeros(n, 0)
    } else {
        DMatrix::from_columns(&columns)
    };
    Ok((omega, shapes))
}

/// The eigenpairs of K φ = λ M φ reduced by the inverse `l_inv` of M's
/// Cholesky factor: those of L⁻¹ K L⁻ᵀ (symmetrised; its eigenvectors are
/// y = Lᵀ φ), with their indices in ascending order of λ.
pub fn reduced_eigen(
    l_inv: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
) -> (SymmetricEigen<f64, Dyn>, Vec<usize>) {
    let a = product(&product(l_inv, stiffness), &l_inv.transpose());
    let eig = SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..a.nrows()).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    (eig, order)
}

/// `a b` a column at a time (nalgebra's matrix-vector product). nalgebra
/// multiplies matrices above 5 × 5 through `matrixmultiply`, which picks
/// its kernel (FMA or not) by the CPU at run time: the modes, and every
/// result damped by them, would then differ in their last bits from one
/// CPU to another.
pub fn product(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let columns: Vec<DVector<f64>> = b.column_iter().map(|column| a * column).collect();
    DMatrix::from_columns(&columns)
}
