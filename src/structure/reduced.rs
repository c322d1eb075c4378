//! The modal implementation of the structure seam
//! (`crate::structure::Structure`): the Hermite mesh kept for its geometry
//! and its shape rows, the state in the kept modes' coordinates
//! (`crate::modal::ModalBasis`).

use nalgebra::DVector;

use crate::beam::{EffectiveFactor, HermiteBeam};
use crate::modal::{ModalBasis, ModeSelection};
use crate::structure::kinds::ChosenKind;
use crate::structure::ops::StructureOps;

/// Never chosen by the beam and track: the build reduces any structure
/// whose scene has `solver.modes` (`Structure::reduce_to_modes`).
impl ChosenKind for ModalBeam {}

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
}

/// Every operation on the kept modes' coordinates; the geometry, the
/// modes and the damping flag are the mesh's (the defaults).
impl StructureOps for ModalBeam {
    fn mesh(&self) -> &HermiteBeam {
        &self.mesh
    }

    /// The number of kept modes.
    fn coordinates(&self) -> usize {
        self.basis.modes()
    }

    fn dof_value(&self, dof: usize, q: &DVector<f64>) -> f64 {
        self.basis.value(dof, q)
    }

    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        self.basis.add_load(dof, scale, out);
    }

    fn stiffness_times(&self, q: &DVector<f64>, out: &mut DVector<f64>) {
        self.basis.stiffness_times(q, out)
    }

    /// The identity: the modes are mass-normalised.
    fn mass_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        out.copy_from(v)
    }

    /// The identity.
    fn solve_mass(&self, _rhs: &mut DVector<f64>) {}

    /// The modal factor of I + `damping_weight` C + `stiffness_weight` Ω².
    fn effective_factor(
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

    fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        self.basis.static_deflection(load)
    }

    /// Diagonal in the modes but for the support dampers: no scratch needed.
    fn internal_forces(
        &self,
        q: &DVector<f64>,
        v: &DVector<f64>,
        _scratch: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.basis.internal_forces(q, v, out)
    }

    fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.basis.damping_times(v, out)
    }

    fn accelerations(
        &self,
        state: (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.basis.accelerations(state, load, out)
    }

    fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        self.basis.kinetic_energy(v)
    }

    fn strain_energy(&self, q: &DVector<f64>) -> f64 {
        self.basis.strain_energy(q)
    }

    fn damping_power(&self, v: &DVector<f64>) -> f64 {
        self.basis.damping_power(v)
    }

    /// Σ c (Φ Φᵀ)ᵢᵢ over the support dampers (1/s).
    fn damper_rate_bound(&self) -> f64 {
        self.mesh
            .damper_coefficients()
            .map(|(dof, c)| c * self.basis.inverse_mass_diagonal(dof))
            .sum()
    }

    /// The highest kept circular frequency: the kept modes are exact
    /// eigenpairs.
    fn highest_frequency(&self) -> f64 {
        self.basis.omega().last().copied().unwrap_or(0.0)
    }

    /// Reduced again from its mesh.
    fn into_mesh(self) -> Result<HermiteBeam, String> {
        Ok(self.mesh)
    }
}
