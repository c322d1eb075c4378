//! The modal implementation of the structure seam
//! (`crate::structure::Structure`): the Hermite mesh kept for its geometry
//! and its shape rows, the state in the kept modes' coordinates
//! (`crate::modal::ModalBasis`).

use nalgebra::DVector;

use crate::beam::{EffectiveFactor, HermiteBeam};
use crate::modal::{ModalBasis, ModeSelection};
use crate::structure::dof_access::DofAccess;

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

impl DofAccess for ModalBeam {
    fn dof_value(&self, dof: usize, q: &DVector<f64>) -> f64 {
        self.basis.value(dof, q)
    }

    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        self.basis.add_load(dof, scale, out);
    }
}
