//! What every kind of structure implements behind the seam
//! (`crate::structure::Structure`): the mesh the contacts run on, and the
//! operations whose meaning depends on the state's coordinates (reading
//! and loading a mesh DOF, products, factors, energies, frequency bounds).
//!
//! A new kind is one file implementing `StructureOps` (and
//! `kinds::ChosenKind`) and one line in the list of kinds
//! (`structure/mod.rs`). A kind whose state is not the mesh's free DOFs (the modal reduction, the rail over the deck)
//! implements `dof_value` and `add_dof_load` and takes the element-wise
//! gathers, dots and scatters below as they are; the full mesh overrides
//! them with direct reads.
//!
//! The trait is private to `structure`: outside it, only `Structure`'s
//! methods reach these operations, so no caller can apply a mesh's
//! full-DOF operation to a reduced structure's state.

use nalgebra::DVector;

use crate::beam::{EffectiveFactor, Foundation, HermiteBeam, Modes, Shape, VelocityFreeBand};

/// The operations of one kind of structure, in its state's coordinates.
pub(in crate::structure) trait StructureOps {
    /// The Hermite mesh the contacts run on: geometry, elements, shapes.
    fn mesh(&self) -> &HermiteBeam;

    /// Entries of a state vector (displacements, velocities, loads).
    fn coordinates(&self) -> usize;

    /// Value on the mesh's free DOF `dof` of the field of state `u`.
    fn dof_value(&self, dof: usize, u: &DVector<f64>) -> f64;

    /// `out += scale` × a unit load on the mesh's free DOF `dof`.
    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>);

    /// The one state entry `add_dof_load(dof, ..)` writes, or None where a
    /// DOF's load spreads over several (a modal basis).
    fn load_coordinate(&self, _dof: usize) -> Option<usize> {
        None
    }

    /// The field on an element's four DOFs `dofs` (0 where held).
    fn gather(&self, dofs: &[Option<usize>; 4], u: &DVector<f64>) -> [f64; 4] {
        // A plain loop: `array::map` over the Options compiled to a
        // generic `try_map` of about 100 instructions a gather, and the
        // foot-point search and the contact rows gather several times an
        // integration per contact (the rail over the deck: 50 M of 2.4 G).
        let mut local = [0.0; 4];
        for (value, dof) in local.iter_mut().zip(dofs) {
            if let Some(i) = *dof {
                *value = self.dof_value(i, u);
            }
        }
        local
    }

    /// Dot a row of `shape` with the field of `u`.
    fn dot(&self, shape: &Shape, row: &[f64; 4], u: &DVector<f64>) -> f64 {
        let local = self.gather(&shape.dofs, u);
        local.iter().zip(row).map(|(a, b)| a * b).sum()
    }

    /// `dot` of two rows with the element's field gathered once for both.
    fn dot_rows(
        &self,
        shape: &Shape,
        (first, second): (&[f64; 4], &[f64; 4]),
        u: &DVector<f64>,
    ) -> (f64, f64) {
        let local = self.gather(&shape.dofs, u);
        let dot = |row: &[f64; 4]| local.iter().zip(row).map(|(a, b)| a * b).sum();
        (dot(first), dot(second))
    }

    /// Two loads at `shape`, `scale_1 row_1 + scale_2 row_2`: one load per
    /// DOF, not two.
    fn scatter_rows(
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

    /// Add the load `scale * row` at `shape` into `out`.
    fn scatter(&self, shape: &Shape, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        for (dof, r) in shape.dofs.iter().zip(row) {
            if let Some(i) = *dof {
                self.add_dof_load(i, scale * r, out);
            }
        }
    }

    /// Transverse deflection w at `x` (m) of state `u`, where the sensors
    /// read it: by default the mesh's.
    fn deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        let shape = self.mesh().shape(self.mesh().element_at(x), x);
        self.dot(&shape, &shape.n, u)
    }

    /// Element `element`'s end forces K_e u + M_e a from its local fields
    /// (`u`, `a`) on (w_i, ψ_i, w_j, ψ_j): by default the Hermite mesh's
    /// element matrices; a kind with another element stiffness gives its
    /// own section forces here.
    fn element_end_forces(&self, element: usize, local: ([f64; 4], [f64; 4])) -> [f64; 4] {
        self.mesh().element_end_forces_of(element, local)
    }

    /// `out = K u`.
    fn stiffness_times(&self, u: &DVector<f64>, out: &mut DVector<f64>);

    /// `out = M v`.
    fn mass_times(&self, v: &DVector<f64>, out: &mut DVector<f64>);

    /// `rhs ← M⁻¹ rhs`.
    fn solve_mass(&self, rhs: &mut DVector<f64>);

    /// The inverse of M + `damping_weight` C + `stiffness_weight` K, the
    /// effective matrix of implicit schemes.
    fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<EffectiveFactor, String>;

    /// The static deflection u with K u = `load`.
    fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String>;

    /// `out = K u + C v`: the elastic and damping forces, using `scratch`.
    fn internal_forces(
        &self,
        u: &DVector<f64>,
        v: &DVector<f64>,
        scratch: &mut DVector<f64>,
        out: &mut DVector<f64>,
    );

    /// `out = C v`: the damping forces alone.
    fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>);

    /// `out = K u + C v`, the bits of `internal_forces`, and `damping =
    /// C v` (by default two passes; a kind whose internal forces sum the
    /// two products shares C v).
    fn internal_and_damping_forces(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        damping: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.internal_forces(u, v, damping, out);
        self.damping_times(v, damping);
    }

    /// Whether `strain_energy` is ½ u·(K u) with the product of
    /// `stiffness_and_damping_forces` and nalgebra's dot, so that a kept
    /// K u gives its bits.
    fn energies_are_products(&self) -> bool {
        false
    }

    /// `internal_and_damping_forces` with K u kept too (`stiffness`);
    /// `out` has `internal_forces`' bits where `energies_are_products`.
    fn stiffness_and_damping_forces(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        (stiffness, damping): (&mut DVector<f64>, &mut DVector<f64>),
        out: &mut DVector<f64>,
    ) {
        self.internal_and_damping_forces((u, v), damping, out);
        self.stiffness_times(u, stiffness);
    }

    /// Whether `accelerations_from_internal` gives `accelerations`' bits
    /// (else it does nothing, and the internal forces need not be found).
    fn accelerations_read_internal_forces(&self) -> bool {
        false
    }

    /// `accelerations` from the state's internal forces `internal` =
    /// K u + C v, where they are how `accelerations` forms them (the same
    /// bits): false, `out` untouched, where they are not.
    fn accelerations_from_internal(
        &self,
        _load: &DVector<f64>,
        _internal: &DVector<f64>,
        _out: &mut DVector<f64>,
    ) -> bool {
        false
    }

    /// Accelerations `M⁻¹ (load − K u − C v)`.
    fn accelerations(
        &self,
        state: (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    );

    /// K, M's factor and α when the accelerations are `M⁻¹ (f − K u) − α v`
    /// on band matrices (`HermiteBeam::velocity_free_band`): none by default.
    fn velocity_free_band(&self) -> Option<VelocityFreeBand<'_>> {
        None
    }

    /// ½ vᵀ M v.
    fn kinetic_energy(&self, v: &DVector<f64>) -> f64;

    /// ½ uᵀ K u.
    fn strain_energy(&self, u: &DVector<f64>) -> f64;

    /// Power dissipated by the structural damping, vᵀ C v (W).
    fn damping_power(&self, v: &DVector<f64>) -> f64;

    /// Σ c (M⁻¹)ᵢᵢ over the support dampers (1/s): at least the decay rate
    /// of any mode they damp (the explicit scheme's stability limit).
    fn damper_rate_bound(&self) -> f64;

    /// Highest natural circular frequency (rad/s), never below the true
    /// one: the explicit schemes' step limit.
    fn highest_frequency(&self) -> f64;

    /// Whether the structure has any damping: by default the mesh's.
    fn is_damped(&self) -> bool {
        self.mesh().is_damped()
    }

    /// The Winkler foundation under the structure: by default the mesh's.
    fn foundation(&self) -> Option<Foundation> {
        self.mesh().foundation()
    }

    /// The lowest `count` natural modes, shapes in the state's
    /// coordinates: by default the mesh's. A kind that overrides it
    /// overrides `frequencies` too.
    fn modes(&self, count: usize) -> Result<Modes, String> {
        self.mesh().modes(count)
    }

    /// The lowest `count` natural circular frequencies (rad/s): by default
    /// the mesh's (without the shapes when the subspace iteration finds them).
    fn frequencies(&self, count: usize) -> Result<Vec<f64>, String> {
        self.mesh().frequencies(count)
    }

    /// The mesh to reduce to its modes (`Structure::reduce_to_modes`), or
    /// why this kind has no modal route.
    fn into_mesh(self) -> Result<HermiteBeam, String>
    where
        Self: Sized;
}
