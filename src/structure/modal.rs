//! The modal structure (`solver.structure = "modal"`): the beam in its
//! lowest k natural modes, mass-normalised (Φᵀ M Φ = I, Φᵀ K Φ = Ω²).
//!
//! The structure's state is the k modal coordinates q and their rates, not
//! the nodal DOFs: in these coordinates the mass is the identity, the
//! stiffness Ω² and Rayleigh damping α + β ω² per mode are diagonal, so
//! the integrators advance k decoupled oscillators (support dampers add
//! Φᵀ D Φ, a k×k matrix). A nodal DOF's value is a row of Φ times q, and a
//! load on it adds that row to the modal load: a contact reads and loads
//! the structure through the Φ rows of its element's four DOFs, O(k) per
//! contact, never O(n k). Nodal fields (sensors, sections, the nodes
//! output) are reconstructed only where an output asks for them. The
//! modal coordinates are integrated by the scene's own integrator (not
//! exactly per mode: the contact forces vary within the step, and the same
//! scheme keeps modal and full runs comparable step for step). With every
//! mode kept the run is the full model's in other coordinates, equal to
//! round-off.

use std::sync::Arc;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use serde::{Deserialize, Serialize};

use crate::beam::{lowest_modes_by_subspace, HermiteBeam, Wanted, DENSE_MODE_DOFS};

/// The scene's `solver.structure`: how the beam is represented.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StructureKind {
    /// Every finite-element DOF of the beam (the paper's model).
    #[default]
    Full,
    /// The beam's lowest natural modes of the finite-element model.
    Modal,
}

impl StructureKind {
    pub fn is_full(&self) -> bool {
        *self == StructureKind::Full
    }
}

/// Which modes a modal structure keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModeSelection {
    /// The lowest `k`.
    Count(usize),
    /// Every mode up to this frequency (Hz).
    UpTo(f64),
}

/// The kept modes: shapes on the free DOFs (one per column) and their
/// circular frequencies, lowest first, with the modal damping; and the
/// structure's operations in modal coordinates.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    shapes: Arc<DMatrix<f64>>,
    omega: Vec<f64>,
    /// Φᵀ (k × n): row i of Φ stored contiguously as column i, what a
    /// contact on DOF i reads and loads.
    rows: DMatrix<f64>,
    /// ω² per mode.
    stiffness: DVector<f64>,
    /// Damping per mode (1/s): Rayleigh's α + β ω², plus 2 ζ ω with one
    /// ratio ζ for every mode.
    damping: DVector<f64>,
    /// Φᵀ D Φ of the support dampers (k × k); `None` without dampers.
    dampers: Option<DMatrix<f64>>,
}

impl ModalBasis {
    /// The modes of `beam` that `selection` keeps (`Beam::modes` chooses
    /// the dense eigenproblem or the subspace iteration). Undamped until
    /// `with_damping`.
    pub fn new(beam: &HermiteBeam, selection: ModeSelection) -> Result<ModalBasis, String> {
        let n = beam.free_dofs();
        if let ModeSelection::Count(k) = selection {
            if k > n {
                return Err(format!(
                    "solver.modes = {k}: must be at most the beam's {n} free DOFs"
                ));
            }
        }
        let (omega, shapes) = match selection {
            ModeSelection::Count(k) => {
                let modes = beam.modes(k).map_err(|e| format!("solver.modes: {e}"))?;
                (modes.omega, modes.shapes)
            }
            ModeSelection::UpTo(_) if n <= DENSE_MODE_DOFS => {
                let modes = beam.modes(n)?;
                (modes.omega, modes.shapes)
            }
            ModeSelection::UpTo(hz) => {
                modes_up_to(beam, hz).map_err(|e| format!("solver.max_frequency: {e}"))?
            }
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
        let shapes = shapes.columns(0, keep).into_owned();
        let omega = omega[..keep].to_vec();
        Ok(ModalBasis {
            rows: shapes.transpose(),
            shapes: Arc::new(shapes),
            stiffness: DVector::from_iterator(keep, omega.iter().map(|w| w * w)),
            damping: DVector::zeros(keep),
            dampers: None,
            omega,
        })
    }

    /// The basis with Rayleigh damping `mass` M + `stiffness` K and the
    /// support dampers `dampers` (DOF, coefficient) projected onto it.
    pub fn with_damping(
        mut self,
        rayleigh: (f64, f64),
        dampers: impl Iterator<Item = (usize, f64)>,
    ) -> ModalBasis {
        let (alpha, beta) = rayleigh;
        self.damping = self.stiffness.map(|w2| alpha + beta * w2);
        let k = self.modes();
        for (dof, c) in dampers {
            let row = self.rows.column(dof);
            let d = self.dampers.get_or_insert_with(|| DMatrix::zeros(k, k));
            d.ger(c, &row, &row, 1.0);
        }
        self
    }

    /// The basis with `ratio` ζ of critical damping added in every kept
    /// mode: 2 ζ ω per mode, which is C = Σ 2 ζ ωᵢ (M φᵢ)(M φᵢ)ᵀ on the
    /// mesh, diagonal and exact here.
    pub fn with_modal_ratio(mut self, ratio: f64) -> ModalBasis {
        for (c, w) in self.damping.iter_mut().zip(&self.omega) {
            *c += 2.0 * ratio * w;
        }
        self
    }

    /// The damping of each kept mode (1/s): q̈ᵢ + cᵢ q̇ᵢ + ωᵢ² qᵢ = fᵢ.
    pub fn mode_damping(&self) -> &DVector<f64> {
        &self.damping
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

    /// The value on free DOF `dof` of the field whose modal coordinates
    /// are `q`: (Φ q)_dof, O(k).
    pub fn value(&self, dof: usize, q: &DVector<f64>) -> f64 {
        self.rows.column(dof).dot(q)
    }

    /// `out += scale Φᵀ e_dof`: a load `scale` on free DOF `dof` in modal
    /// coordinates, O(k).
    pub fn add_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        out.axpy(scale, &self.rows.column(dof), 1.0);
    }

    /// (Φ Φᵀ)_dof,dof: the reduced structure's (M⁻¹)ᵢᵢ.
    pub fn inverse_mass_diagonal(&self, dof: usize) -> f64 {
        self.rows.column(dof).norm_squared()
    }

    /// `out = Ω² q`.
    pub fn stiffness_times(&self, q: &DVector<f64>, out: &mut DVector<f64>) {
        out.copy_from(q);
        out.component_mul_assign(&self.stiffness);
    }

    /// `out += scale C v`, C the modal damping.
    fn add_damping(&self, v: &DVector<f64>, scale: f64, out: &mut DVector<f64>) {
        out.zip_zip_apply(v, &self.damping, |o, v, c| *o += scale * c * v);
        if let Some(d) = &self.dampers {
            out.gemv(scale, d, v, 1.0);
        }
    }

    /// `out = C v`: the damping forces.
    pub fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        out.fill(0.0);
        self.add_damping(v, 1.0, out);
    }

    /// `out = Ω² q + C v`: the elastic and damping forces.
    pub fn internal_forces(&self, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.stiffness_times(q, out);
        self.add_damping(v, 1.0, out);
    }

    /// `out = load − Ω² q − C v`: the modal accelerations (M = I).
    pub fn accelerations(
        &self,
        (q, v): (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        out.copy_from(load);
        out.zip_zip_apply(q, &self.stiffness, |a, q, w2| *a -= w2 * q);
        self.add_damping(v, -1.0, out);
    }

    /// ½ q̇ᵀ q̇.
    pub fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        0.5 * v.norm_squared()
    }

    /// ½ qᵀ Ω² q.
    pub fn strain_energy(&self, q: &DVector<f64>) -> f64 {
        0.5 * q.zip_fold(&self.stiffness, 0.0, |s, q, w2| s + w2 * q * q)
    }

    /// q̇ᵀ C q̇ (W).
    pub fn damping_power(&self, v: &DVector<f64>) -> f64 {
        let rayleigh = v.zip_fold(&self.damping, 0.0, |s, v, c| s + c * v * v);
        let dampers = self
            .dampers
            .as_ref()
            .map_or(0.0, |d| d.dot(&(v * v.transpose())));
        rayleigh + dampers
    }

    /// The factor of I + `damping_weight` C + `stiffness_weight` Ω², the
    /// implicit scheme's effective matrix in modal coordinates: diagonal
    /// (one division per mode) unless support dampers couple the modes.
    pub fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Option<ModalFactor> {
        let diagonal = DVector::from_fn(self.modes(), |j, _| {
            1.0 + damping_weight * self.damping[j] + stiffness_weight * self.stiffness[j]
        });
        match &self.dampers {
            None if diagonal.iter().all(|&d| d > 0.0) => {
                Some(ModalFactor::Diagonal(diagonal.map(|d| 1.0 / d)))
            }
            None => None,
            Some(d) => {
                let s = DMatrix::from_diagonal(&diagonal) + damping_weight * d;
                s.cholesky().map(ModalFactor::Dense)
            }
        }
    }

    /// The modal coordinates of the static deflection under the modal
    /// load `load`: Ω⁻² `load`.
    pub fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        if self.omega.iter().any(|&w| w.is_nan() || w <= 0.0) {
            return Err(
                "beam.supports: a kept mode has zero frequency (the supports leave the \
                 beam free to move), so solver.start = \"static\" has no static deflection"
                    .into(),
            );
        }
        Ok(load.component_div(&self.stiffness))
    }
}

/// The inverse of an effective matrix in modal coordinates.
#[derive(Debug, Clone)]
pub enum ModalFactor {
    /// Reciprocals of the diagonal: the modes are decoupled.
    Diagonal(DVector<f64>),
    /// Support dampers couple the modes: a k × k Cholesky factor.
    Dense(Cholesky<f64, Dyn>),
}

impl ModalFactor {
    /// `rhs ← S⁻¹ rhs`.
    pub fn solve_mut(&self, rhs: &mut DVector<f64>) {
        match self {
            ModalFactor::Diagonal(reciprocal) => rhs.component_mul_assign(reciprocal),
            ModalFactor::Dense(factor) => factor.solve_mut(rhs),
        }
    }
}

/// Every mode up to `hz` of a beam above `DENSE_MODE_DOFS` free DOFs: the
/// subspace iteration for 8 modes, doubled until the highest found is
/// above the cut-off.
fn modes_up_to(beam: &HermiteBeam, hz: f64) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let n = beam.free_dofs();
    let mut wanted = 8.min(n);
    loop {
        let (omega, shapes) = lowest_modes_by_subspace(beam, wanted, Wanted::Modes)?;
        let more = omega
            .last()
            .is_some_and(|&w| w <= std::f64::consts::TAU * hz)
            && wanted < n;
        if !more {
            return Ok((omega, shapes));
        }
        wanted = (2 * wanted).min(n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::start_value;
    use crate::structure::beam::{BeamSpec, DampingSpec, EndSupport, SupportsSpec};
    use crate::structure::ops::StructureOps;

    fn beam(elements: usize, supports: SupportsSpec) -> HermiteBeam {
        HermiteBeam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements,
            supports,
            ..BeamSpec::default()
        })
        .expect("beam")
    }

    /// The subspace iteration's modes against the dense eigenproblem's.
    /// On a fine mesh the entries of K, rounded, fix a low mode's ω² only
    /// to about ε |x|ᵀ|K||x| / xᵀKx ≈ 1e-7 (200 elements): both methods
    /// agree to that, not to ε.
    fn assert_matches_dense(beam: &HermiteBeam, k: usize) {
        let (omega, shapes) = lowest_modes_by_subspace(beam, k, Wanted::Modes).expect("converges");
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
    fn with_every_mode_the_modal_round_trip_is_the_inverse_mass() {
        let beam = beam(5, SupportsSpec::default());
        let n = beam.free_dofs();
        let x = DVector::from_fn(n, |i, _| start_value(i, 7));
        let mut exact = x.clone();
        beam.solve_mass(&mut exact);
        // Nodal loads into modal coordinates and back, DOF by DOF: Φ Φᵀ x.
        let basis = ModalBasis::new(&beam, ModeSelection::Count(n)).expect("modes");
        let mut q = DVector::zeros(n);
        for (i, &xi) in x.iter().enumerate() {
            basis.add_load(i, xi, &mut q);
        }
        let back = DVector::from_fn(n, |i, _| basis.value(i, &q));
        assert!((&back - &exact).amax() <= 1e-12 * exact.amax());
        let diagonal = (0..n).map(|i| {
            let mut e = DVector::zeros(n);
            e[i] = 1.0;
            beam.solve_mass(&mut e);
            (e[i] - basis.inverse_mass_diagonal(i)).abs() / e[i]
        });
        assert!(diagonal.fold(0.0, f64::max) < 1e-12);
        // Fewer modes: the kept shapes stay mass-orthonormal, Φᵀ M Φ = I.
        let few = ModalBasis::new(&beam, ModeSelection::Count(3)).expect("modes");
        let mut m_phi = DVector::zeros(n);
        for j in 0..3 {
            beam.mass_times(&few.shapes().column(j).into_owned(), &mut m_phi);
            for i in 0..3 {
                let entry = few.shapes().column(i).dot(&m_phi);
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((entry - expected).abs() < 1e-12, "({i}, {j}): {entry}");
            }
        }
    }

    #[test]
    fn modal_operations_are_the_nodal_ones_in_modal_coordinates() {
        // On every mode: energies and damping power of q equal those of
        // the nodal field Φ q under Rayleigh damping.
        let spec_beam = HermiteBeam::new(&BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements: 4,
            damping: Some(DampingSpec::Coefficients {
                alpha: 0.3,
                beta: 2e-4,
            }),
            ..BeamSpec::default()
        })
        .expect("beam");
        let n = spec_beam.free_dofs();
        let q = DVector::from_fn(n, |i, _| start_value(i, 3));
        let v = DVector::from_fn(n, |i, _| start_value(i, 5));
        let basis = ModalBasis::new(&spec_beam, ModeSelection::Count(n))
            .expect("modes")
            .with_damping((0.3, 2e-4), std::iter::empty());
        let (u, w) = (basis.shapes() * &q, basis.shapes() * &v);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-10 * a.abs().max(b.abs());
        assert!(close(basis.strain_energy(&q), spec_beam.strain_energy(&u)));
        assert!(close(
            basis.kinetic_energy(&v),
            spec_beam.kinetic_energy(&w)
        ));
        assert!(close(basis.damping_power(&v), spec_beam.damping_power(&w)));
        // The effective factor inverts I + c C + d Ω².
        let factor = basis.effective_factor(0.01, 1e-6).expect("positive");
        let mut x = q.clone();
        factor.solve_mut(&mut x);
        let mut back = DVector::zeros(n);
        basis.internal_forces(&x, &x, &mut back);
        let rebuilt = &x
            + 0.01 * (&back - basis.stiffness.component_mul(&x))
            + 1e-6 * basis.stiffness.component_mul(&x);
        assert!((&rebuilt - &q).amax() <= 1e-12 * q.amax());
    }
}
