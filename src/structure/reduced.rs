//! The modal implementation of the structure seam
//! (`crate::structure::Structure`): the Hermite mesh kept for its geometry
//! and its shape rows, the state in the kept modes' coordinates
//! (`crate::modal::ModalBasis`).

use nalgebra::DVector;

use crate::beam::{EffectiveFactor, HermiteBeam, Shape};
use crate::modal::{ModalBasis, ModeSelection};

/// The beam reduced to the modes a selection keeps.
pub struct ModalBeam {
    /// The mesh the modes were found on: geometry, shapes, supports.
    pub(in crate::structure) mesh: HermiteBeam,
    basis: ModalBasis,
}

impl ModalBeam {
    /// The modes of `mesh` that `selection` keeps, damped by the mesh's
    /// Rayleigh damping and support dampers projected onto them.
    pub fn new(mesh: HermiteBeam, selection: ModeSelection) -> Result<ModalBeam, String> {
        let rayleigh = (mesh.damping().mass, mesh.damping().stiffness);
        let mut basis =
            ModalBasis::new(&mesh, selection)?.with_damping(rayleigh, mesh.damper_coefficients());
        if let Some(ratio) = mesh.modal_ratio() {
            basis = basis.with_modal_ratio(ratio);
        }
        Ok(ModalBeam { mesh, basis })
    }

    /// The kept modes.
    pub fn basis(&self) -> &ModalBasis {
        &self.basis
    }

    /// The number of kept modes: the entries of a state vector.
    pub fn coordinates(&self) -> usize {
        self.basis.modes()
    }

    /// Value on free DOF `dof` of the field of modal coordinates `q`.
    pub fn dof_value(&self, dof: usize, q: &DVector<f64>) -> f64 {
        self.basis.value(dof, q)
    }

    /// `out += scale` × a unit load on free DOF `dof`, in modal coordinates.
    pub fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        self.basis.add_load(dof, scale, out);
    }

    /// The field on an element's four DOFs `dofs` (0 where held): one
    /// product with the kept modes per DOF.
    pub fn gather(&self, dofs: &[Option<usize>; 4], q: &DVector<f64>) -> [f64; 4] {
        dofs.map(|dof| dof.map_or(0.0, |i| self.dof_value(i, q)))
    }

    /// Dot a row of `shape` with the field of `q`.
    pub fn dot(&self, shape: &Shape, row: &[f64; 4], q: &DVector<f64>) -> f64 {
        let local = self.gather(&shape.dofs, q);
        local.iter().zip(row).map(|(a, b)| a * b).sum()
    }

    /// `dot` of two rows with the element's field gathered once for both.
    pub fn dot_rows(
        &self,
        shape: &Shape,
        (first, second): (&[f64; 4], &[f64; 4]),
        q: &DVector<f64>,
    ) -> (f64, f64) {
        let local = self.gather(&shape.dofs, q);
        let dot = |row: &[f64; 4]| local.iter().zip(row).map(|(a, b)| a * b).sum();
        (dot(first), dot(second))
    }

    /// Two loads at `shape`, `scale_1 row_1 + scale_2 row_2`: one product
    /// with the kept modes per DOF, not two.
    pub fn scatter_rows(
        &self,
        shape: &Shape,
        (first, scale_1): (&[f64; 4], f64),
        (second, scale_2): (&[f64; 4], f64),
        out: &mut DVector<f64>,
    ) {
        for (k, dof) in shape.dofs.iter().enumerate() {
            if let Some(i) = *dof {
                self.add_dof_load(i, scale_1 * first[k] + scale_2 * second[k], out);
            }
        }
    }

    /// Add the load `scale * row` at `shape` into modal load `out`.
    pub fn scatter(&self, shape: &Shape, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        for (dof, r) in shape.dofs.iter().zip(row) {
            if let Some(i) = *dof {
                self.add_dof_load(i, scale * r, out);
            }
        }
    }

    /// The modal factor of I + `damping_weight` C + `stiffness_weight` Ω².
    pub fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<EffectiveFactor, String> {
        let factor = self
            .basis
            .effective_factor(damping_weight, stiffness_weight);
        factor.map(EffectiveFactor::Modal).ok_or_else(|| {
            "the implicit scheme's effective matrix on the modes is not positive definite".into()
        })
    }

    /// Σ c (Φ Φᵀ)ᵢᵢ over the support dampers (1/s).
    pub fn damper_rate_bound(&self) -> f64 {
        self.mesh
            .damper_coefficients()
            .map(|(dof, c)| c * self.basis.inverse_mass_diagonal(dof))
            .sum()
    }

    /// The highest kept circular frequency: the kept modes are exact
    /// eigenpairs.
    pub fn highest_frequency(&self) -> f64 {
        self.basis.omega().last().copied().unwrap_or(0.0)
    }
}
