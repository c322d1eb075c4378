//! The modal structure (`solver.structure = "modal"`): the beam in its
//! lowest k natural modes, mass-normalised (Φᵀ M Φ = I, Φᵀ K Φ = Ω²).
//!
//! The beam's state stays on its nodal DOFs, u = Φ q and v = Φ q̇, so the
//! contact frames, sensors, sections and energies read the modal expansion
//! through the same shape functions as before. What changes is the
//! structure's response: where the full model applies M⁻¹ (accelerations,
//! impulses) or the effective matrix's inverse S⁻¹ (HHT-α), the modal one
//! applies Φ Φᵀ and Φ (Φᵀ S Φ)⁻¹ Φᵀ, the Galerkin projection onto the k
//! modes. A contact load f therefore enters as Φᵀ f (Φᵀ times the shape
//! functions at the contact), and the Delassus operator, which the
//! iteration builds from the integrator's response to unit loads, is the
//! modal compliance. The modal coordinates are integrated by the scene's
//! own integrator (RK4 or HHT-α act linearly, so integrating u in span Φ is
//! integrating q): the contact forces vary within the step, so exact
//! per-mode integration would not be exact for the coupled system, and the
//! same scheme keeps modal and full runs comparable step for step. With
//! every mode kept, Φ Φᵀ = M⁻¹ and the run is the full model's to round-off.

use std::sync::Arc;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn, SymmetricEigen};

use crate::band::SymBand;
use crate::beam::{Beam, MAX_MODE_DOFS};
use crate::scene::{SolverSpec, StructureKind};

/// Largest n·p² (free DOFs times the squared subspace size) the subspace
/// iteration is run for: about a second of work per iteration.
pub const MAX_SUBSPACE_WORK: f64 = 2e9;

/// Up to this many free DOFs the modes come from the dense eigenproblem;
/// beyond, when a quarter of them or fewer are wanted, from the subspace
/// iteration.
pub const DENSE_MODAL_DOFS: usize = 64;

/// Largest n·p (free DOFs times subspace size) the subspace iteration
/// holds: its four n×p matrices then take at most 128 MB.
pub const MAX_SUBSPACE_ENTRIES: usize = 4_000_000;

/// Most iterations of the subspace iteration.
const MAX_SUBSPACE_ITERATIONS: usize = 300;

/// Relative change of the wanted Ritz values between two iterations at
/// which they count as settled.
const SETTLED: f64 = 1e-10;

/// Which modes a modal structure keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModeSelection {
    /// The lowest `k`.
    Count(usize),
    /// Every mode up to this frequency (Hz).
    UpTo(f64),
}

impl ModeSelection {
    /// The selection a (validated) solver spec asks for, `None` for the
    /// full structure.
    pub fn of(solver: &SolverSpec) -> Option<ModeSelection> {
        if solver.structure == StructureKind::Full {
            return None;
        }
        match (solver.modes, solver.max_frequency) {
            (Some(k), _) => Some(ModeSelection::Count(k)),
            (None, Some(f)) => Some(ModeSelection::UpTo(f)),
            (None, None) => None,
        }
    }
}

/// The kept modes: shapes on the free DOFs (one per column) and their
/// circular frequencies, lowest first.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    shapes: Arc<DMatrix<f64>>,
    omega: Vec<f64>,
}

impl ModalBasis {
    /// The modes of `beam` that `selection` keeps: a dense eigenproblem up
    /// to `MAX_MODE_DOFS` free DOFs, a subspace iteration on the band
    /// factor beyond.
    pub fn new(beam: &Beam, selection: ModeSelection) -> Result<ModalBasis, String> {
        let n = beam.free_dofs();
        if let ModeSelection::Count(k) = selection {
            if k > n {
                return Err(format!(
                    "solver.modes = {k}: must be at most the beam's {n} free DOFs"
                ));
            }
        }
        let few = match selection {
            ModeSelection::Count(k) => 4 * k < n,
            ModeSelection::UpTo(_) => true,
        };
        // The dense eigenproblem loses about ε ω_max² / ω² of a low mode's
        // ω² on a fine mesh; the subspace iteration does not.
        let (omega, shapes) = if n <= MAX_MODE_DOFS && !(few && n > DENSE_MODAL_DOFS) {
            let modes = beam.modes(n)?;
            (modes.omega, modes.shapes)
        } else {
            subspace_modes(beam, selection)?
        };
        let keep = match selection {
            ModeSelection::Count(k) => k,
            ModeSelection::UpTo(hz) => {
                let cut = std::f64::consts::TAU * hz;
                omega.iter().take_while(|&&w| w <= cut).count()
            }
        };
        if keep == 0 {
            let lowest = omega.first().map_or(0.0, |w| w / std::f64::consts::TAU);
            return Err(format!(
                "solver.max_frequency = {:?} Hz keeps no mode: the beam's lowest is {lowest:.6} Hz",
                match selection {
                    ModeSelection::UpTo(hz) => hz,
                    ModeSelection::Count(_) => 0.0,
                }
            ));
        }
        Ok(ModalBasis {
            shapes: Arc::new(shapes.columns(0, keep).into_owned()),
            omega: omega[..keep].to_vec(),
        })
    }

    /// How many modes are kept.
    pub fn modes(&self) -> usize {
        self.omega.len()
    }

    /// Circular frequencies of the kept modes (rad/s), lowest first.
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// Mass-normalised shapes on the free DOFs, one per column.
    pub fn shapes(&self) -> &DMatrix<f64> {
        &self.shapes
    }

    /// `x ← Φ Φᵀ x`: M⁻¹ of the reduced structure (Φ Φᵀ = M⁻¹ when every
    /// mode is kept).
    pub fn project(&self, x: &mut DVector<f64>) {
        let q = self.shapes.tr_mul(x);
        self.shapes.mul_to(&q, x);
    }

    /// The static deflection Φ Ω⁻² Φᵀ `load`.
    pub fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        if self.omega.iter().any(|&w| w.is_nan() || w <= 0.0) {
            return Err(
                "beam.supports: a kept mode has zero frequency (the supports leave the \
                 beam free to move), so solver.start = \"static\" has no static deflection"
                    .into(),
            );
        }
        let mut q = self.shapes.tr_mul(load);
        q.iter_mut().zip(&self.omega).for_each(|(q, w)| *q /= w * w);
        Ok(&*self.shapes * q)
    }

    /// The factor of Φᵀ S Φ for the symmetric matrix S that `apply` multiplies by.
    pub fn reduced_factor(
        &self,
        apply: impl Fn(&DVector<f64>, &mut DVector<f64>),
    ) -> Option<ReducedFactor> {
        let (n, k) = self.shapes.shape();
        let mut product = DMatrix::zeros(n, k);
        let mut out = DVector::zeros(n);
        for j in 0..k {
            apply(&self.shapes.column(j).into_owned(), &mut out);
            product.set_column(j, &out);
        }
        let reduced = self.shapes.tr_mul(&product);
        let symmetric = 0.5 * (&reduced + reduced.transpose());
        Some(ReducedFactor {
            shapes: Arc::clone(&self.shapes),
            factor: symmetric.cholesky()?,
        })
    }
}

/// Φ (Φᵀ S Φ)⁻¹ Φᵀ: the inverse of an effective matrix S on the modes.
#[derive(Debug, Clone)]
pub struct ReducedFactor {
    shapes: Arc<DMatrix<f64>>,
    factor: Cholesky<f64, Dyn>,
}

impl ReducedFactor {
    /// `rhs ← Φ (Φᵀ S Φ)⁻¹ Φᵀ rhs`.
    pub fn solve_mut(&self, rhs: &mut DVector<f64>) {
        let mut q = self.shapes.tr_mul(rhs);
        self.factor.solve_mut(&mut q);
        self.shapes.mul_to(&q, rhs);
    }
}

/// The lowest modes of a beam too large for the dense eigenproblem, by
/// subspace iteration: p vectors repeatedly multiplied by (K + s M)⁻¹ M
/// through the band LDLᵀ factor, then Rayleigh–Ritz on the p-dimensional
/// subspace, until the wanted eigenvalues settle.
///
/// Hand-written: nalgebra's and faer's eigensolvers are dense (O(n³), an
/// n×n matrix), and the sparse ones available as crates (Lanczos, LOBPCG)
/// need a sparse-matrix type and a linear solver of their own, where the
/// beam already has an O(n) band factor and band products.
fn subspace_modes(
    beam: &Beam,
    selection: ModeSelection,
) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let n = beam.free_dofs();
    let mut wanted = match selection {
        ModeSelection::Count(k) => k,
        ModeSelection::UpTo(_) => 8.min(n),
    };
    loop {
        let (omega, shapes) = subspace_lowest(beam, wanted)?;
        let more = match selection {
            ModeSelection::UpTo(hz) => {
                omega
                    .last()
                    .is_some_and(|&w| w <= std::f64::consts::TAU * hz)
                    && wanted < n
            }
            ModeSelection::Count(_) => false,
        };
        if !more {
            return Ok((omega, shapes));
        }
        wanted = (2 * wanted).min(n);
    }
}

/// The lowest `k` modes by subspace iteration (see `subspace_modes`).
fn subspace_lowest(beam: &Beam, k: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let (mass, stiffness) = (beam.mass_band(), beam.stiffness_band());
    let n = mass.size();
    let p = (2 * k).max(k + 8).min(n);
    let work = n as f64 * (p * p) as f64;
    if n * p > MAX_SUBSPACE_ENTRIES {
        return Err(format!(
            "solver.modes: {k} modes of a beam of {n} free DOFs need a subspace of {p} vectors \
             (n·p = {}); at most {MAX_SUBSPACE_ENTRIES} (fewer modes or elements)",
            n * p
        ));
    }
    if work > MAX_SUBSPACE_WORK {
        return Err(format!(
            "solver.modes: {k} modes of a beam of {n} free DOFs need a subspace of {p} vectors \
             (n·p² = {work:.1e}); at most {MAX_SUBSPACE_WORK:.0e} (fewer modes or elements)"
        ));
    }
    // K itself when the supports hold the beam; shifted by s M otherwise
    // (the eigenvectors are the same, the Ritz values use K alone).
    let (mut factor, mut shift) = match stiffness.ldlt() {
        Some(f) => (f, 0.0),
        None => {
            let shift = 1e-6 * beam.max_element_frequency().powi(2);
            let factor = mass
                .combine(shift, stiffness, 1.0)
                .ldlt()
                .ok_or("beam stiffness K + s M is not positive definite")?;
            (factor, shift)
        }
    };
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
        let (lambda, ritz) = rayleigh_ritz(&y, &mx, mass, shift)?;
        x = ritz;
        // A shift far above the wanted eigenvalues slows the iteration to
        // a crawl: once, move it down to the k-th Ritz value (an upper
        // bound of λ_k, so K + s M stays positive definite).
        if shift > 0.0 && iteration == 2 && lambda[k - 1] > 0.0 && lambda[k - 1] < shift {
            if let Some(f) = mass.combine(lambda[k - 1], stiffness, 1.0).ldlt() {
                (factor, shift) = (f, lambda[k - 1]);
            }
        }
        // Rigid-body modes (ω = 0) are measured against the highest wanted.
        let floor = 1e-6 * lambda[k - 1].abs().max(f64::MIN_POSITIVE);
        let change = lambda[..k]
            .iter()
            .zip(&previous)
            .map(|(l, p)| (l - p).abs() / l.abs().max(floor))
            .fold(0.0, f64::max);
        previous.copy_from_slice(&lambda[..k]);
        // The Ritz values converge twice as fast as the vectors: once they
        // settle, as many iterations again bring the vectors to the same
        // accuracy.
        match settled_at {
            None if change <= SETTLED => settled_at = Some(iteration),
            Some(at) if iteration > 2 * at => {
                let omega = lambda[..k].iter().map(|l| l.max(0.0).sqrt()).collect();
                return Ok((omega, x.columns(0, k).into_owned()));
            }
            _ => {}
        }
    }
    Err(format!(
        "solver.modes: the subspace iteration for {k} modes did not converge in \
         {MAX_SUBSPACE_ITERATIONS} iterations (clustered frequencies; ask for fewer modes)"
    ))
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
    let a = &l_inv * kr * l_inv.transpose();
    let eig = SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..p).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let z = l_inv.transpose() * &eig.eigenvectors;
    let columns: Vec<DVector<f64>> = order.iter().map(|&i| y * z.column(i)).collect();
    let lambda = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    Ok((lambda, DMatrix::from_columns(&columns)))
}

/// A deterministic pseudo-random start vector entry in [−1, 1).
fn start_value(i: usize, j: usize) -> f64 {
    let mut h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64 + 1).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    h ^= h >> 31;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 29;
    (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BeamSpec, EndSupport, SupportsSpec};

    fn beam(elements: usize, supports: SupportsSpec) -> Beam {
        Beam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements,
            supports,
            joints: Vec::new(),
            damping: None,
        })
        .expect("beam")
    }

    /// The subspace iteration's modes against the dense eigenproblem's.
    /// On a fine mesh the entries of K, rounded, fix a low mode's ω² only
    /// to about ε |x|ᵀ|K||x| / xᵀKx ≈ 1e-7 (200 elements): both methods
    /// agree to that, not to ε.
    fn assert_matches_dense(beam: &Beam, k: usize) {
        let (omega, shapes) = subspace_lowest(beam, k).expect("converges");
        let dense = beam.modes(k).expect("dense");
        let mut m_phi = DVector::zeros(beam.free_dofs());
        for (j, (&found, &w)) in omega.iter().zip(&dense.omega).enumerate() {
            let close = (found - w).abs() <= 2e-7 * w.max(1e-3 * dense.omega[k - 1]);
            assert!(close, "mode {j}: {found} vs {w}");
            let column = dense.shapes.column(j).into_owned();
            beam.mass_times(&column, &mut m_phi);
            // Rigid-body modes (ω = 0, repeated) are compared as a subspace.
            let rigid = |i: usize| dense.omega[i] < 1e-3 * dense.omega[k - 1];
            let cosine = if rigid(j) {
                let within = (0..k).filter(|&i| rigid(i));
                within
                    .map(|i| shapes.column(i).dot(&m_phi).powi(2))
                    .sum::<f64>()
                    .sqrt()
            } else {
                shapes.column(j).dot(&m_phi).abs()
            };
            assert!((cosine - 1.0).abs() < 1e-6, "mode {j}: |φᵀ M φ| = {cosine}");
        }
    }

    #[test]
    fn subspace_iteration_finds_the_dense_modes() {
        assert_matches_dense(&beam(200, SupportsSpec::default()), 10);
        // A free-free beam (K singular: the shifted factor, two rigid modes).
        let free = SupportsSpec {
            left: EndSupport::Free,
            right: EndSupport::Free,
            ..SupportsSpec::default()
        };
        let free = beam(120, free);
        assert!(free.stiffness_factor().is_none());
        assert_matches_dense(&free, 6);
    }

    #[test]
    fn with_every_mode_the_projection_is_the_inverse_mass() {
        let mut beam = beam(5, SupportsSpec::default());
        let n = beam.free_dofs();
        let x = DVector::from_fn(n, |i, _| start_value(i, 7));
        let mut exact = x.clone();
        beam.solve_mass(&mut exact);
        beam.reduce_to_modes(ModeSelection::Count(n))
            .expect("modes");
        let mut projected = x.clone();
        beam.solve_mass(&mut projected);
        assert!((&projected - &exact).amax() <= 1e-12 * exact.amax());
        // Fewer modes: a projection, Φ Φᵀ M Φ Φᵀ = Φ Φᵀ.
        beam.reduce_to_modes(ModeSelection::Count(3))
            .expect("modes");
        let mut once = x.clone();
        beam.solve_mass(&mut once);
        let mut m_once = DVector::zeros(n);
        beam.mass_times(&once, &mut m_once);
        beam.solve_mass(&mut m_once);
        assert!((&m_once - &once).amax() <= 1e-12 * once.amax());
    }
}
