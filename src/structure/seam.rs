//! The structure seam: the one type the system, the contacts and the
//! integrators see. Each kind of structure (the full Hermite mesh, its
//! modal reduction, the rail over the deck) implements `StructureOps`
//! (`structure/ops.rs`); `Structure` is the enum of the kinds (generated
//! from their list in `structure/mod.rs`) and passes every call to the
//! kind it holds through the one `each!` macro: static dispatch, one
//! `match` per call, no `dyn` in the step. Nothing here names a kind but
//! the accessors of the modal and the track kinds' own data.
//!
//! Geometry (node abscissae, elements, shapes, supports, segments) is the
//! mesh's whatever the kind, so `Structure` dereferences to the kind's
//! `HermiteBeam` for it. The operations whose meaning depends on the
//! state's coordinates are the trait's, private to `structure`, so a
//! caller cannot reach the full-mesh operation on a reduced structure.

use std::ops::Deref;

use nalgebra::DVector;

use crate::beam::{EffectiveFactor, Foundation, HermiteBeam, Modes, Shape, VelocityFreeBand};
use crate::modal::{ModalBasis, ModeSelection};
use crate::structure::beam::BeamSpec;
use crate::structure::ops::StructureOps;
use crate::structure::reduced::ModalBeam;
use crate::structure::track_seam::TrackBeam;
use crate::structure::track_spec::TrackSpec;
use crate::structure::Structure;

impl Deref for Structure {
    type Target = HermiteBeam;

    /// The mesh: geometry shared by every kind.
    fn deref(&self) -> &HermiteBeam {
        each!(self, b => b.mesh())
    }
}

impl Structure {
    /// The structure of a (validated) beam spec on a track with no layer
    /// over the deck: the Hermite mesh, or the kind the spec's own fields
    /// choose.
    pub fn new(spec: &BeamSpec) -> Result<Structure, String> {
        Structure::of_scene(spec, &TrackSpec::default())
    }

    /// The structure of a (validated) scene's beam and track: the first
    /// kind of the list (`structure/mod.rs`) they choose (the rail over
    /// the deck when the track has `on_deck`), else the beam's mesh.
    pub fn of_scene(spec: &BeamSpec, track: &TrackSpec) -> Result<Structure, String> {
        Structure::chosen_kind(spec, track)
            .unwrap_or_else(|| HermiteBeam::new(spec).map(Structure::Hermite))
    }

    /// The rail over the deck, when the structure is one.
    pub fn track(&self) -> Option<&TrackBeam> {
        match self {
            Structure::Track(track) => Some(track),
            _ => None,
        }
    }

    /// The structure reduced to the modes `selection` keeps: from here on
    /// its state vectors are modal coordinates. A reduced structure is
    /// reduced again from its mesh.
    pub fn reduce_to_modes(self, selection: ModeSelection) -> Result<Structure, String> {
        let mesh = each!(self, b => b.into_mesh())?;
        ModalBeam::new(mesh, selection).map(Structure::Modal)
    }

    /// The damping ratio of every mode when the scene gives one for all
    /// (a modal structure's only).
    pub fn modal_ratio(&self) -> Option<f64> {
        match self {
            Structure::Modal(modal) => modal.mesh().modal_ratio(),
            _ => None,
        }
    }

    /// 2 ζ ωᵢ per kept mode when the scene gives one damping ratio ζ for
    /// every mode (a modal structure's only): C v = M Φ (2 ζ ω ⊙ q̇).
    pub fn modal_ratio_rates(&self) -> Option<DVector<f64>> {
        let ratio = self.modal_ratio()?;
        let omega = self.modal()?.omega();
        Some(DVector::from_iterator(
            omega.len(),
            omega.iter().map(|w| 2.0 * ratio * w),
        ))
    }

    /// The kept modes when the structure is modal.
    pub fn modal(&self) -> Option<&ModalBasis> {
        match self {
            Structure::Modal(modal) => Some(modal.basis()),
            _ => None,
        }
    }

    /// Entries of a state vector (displacements, velocities, loads): the
    /// free DOFs, or the kept modes.
    pub fn coordinates(&self) -> usize {
        each!(self, b => b.coordinates())
    }

    /// Value on free DOF `dof` of the field a state vector `u` describes.
    pub fn dof_value(&self, dof: usize, u: &DVector<f64>) -> f64 {
        each!(self, b => b.dof_value(dof, u))
    }

    /// `out += scale` × a unit load on free DOF `dof`, in the structure's
    /// coordinates.
    pub fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        each!(self, b => b.add_dof_load(dof, scale, out))
    }

    /// The one state entry a load on the mesh's free DOF `dof` is added
    /// to, or None where it spreads over several (a modal basis).
    pub fn load_coordinate(&self, dof: usize) -> Option<usize> {
        each!(self, b => b.load_coordinate(dof))
    }

    /// The field of state vector `u` on the four DOFs `dofs` of an element
    /// (0 where held).
    pub fn gather(&self, dofs: &[Option<usize>; 4], u: &DVector<f64>) -> [f64; 4] {
        each!(self, b => b.gather(dofs, u))
    }

    /// Dot a row of `shape`'s values with the field of state vector `u`.
    pub fn dot(&self, shape: &Shape, row: &[f64; 4], u: &DVector<f64>) -> f64 {
        each!(self, b => b.dot(shape, row, u))
    }

    /// `dot` of two rows of `shape` with the same `u`.
    pub fn dot_rows(
        &self,
        shape: &Shape,
        rows: (&[f64; 4], &[f64; 4]),
        u: &DVector<f64>,
    ) -> (f64, f64) {
        each!(self, b => b.dot_rows(shape, rows, u))
    }

    /// `scatter` of two loads at `shape`, `scale_1 row_1 + scale_2 row_2`.
    pub fn scatter_rows(
        &self,
        shape: &Shape,
        first: (&[f64; 4], f64),
        second: (&[f64; 4], f64),
        out: &mut DVector<f64>,
    ) {
        each!(self, b => b.scatter_rows(shape, first, second, out))
    }

    /// Add the load `scale * row` at `shape` into state vector `out`.
    pub fn scatter(&self, shape: &Shape, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        each!(self, b => b.scatter(shape, row, scale, out))
    }

    /// The field of state vector `u` on the four DOFs of `element` (0
    /// where held): what `axis_of_field` reads.
    pub fn element_field(&self, element: usize, u: &DVector<f64>) -> [f64; 4] {
        self.gather(self.element_dofs(element), u)
    }

    /// w and its first three derivatives along the deformed axis at `x` in
    /// `element` (`HermiteBeam::axis_of_field`).
    pub fn axis(&self, element: usize, x: f64, u: &DVector<f64>) -> [f64; 4] {
        self.axis_of_field(element, x, &self.element_field(element, u))
    }

    /// Transverse deflection w at `x` (m): the deck's at its abscissa `x`
    /// under a rail (the sensors read the deck; the contacts the rail).
    pub fn deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        each!(self, b => b.deflection(u, x))
    }

    /// Element `element`'s end forces K_e q(`u`) + M_e q(`a`) on its DOFs
    /// (w_i, ψ_i, w_j, ψ_j), held DOFs taken as zero: what its nodes exert
    /// on it, before the loads on the element itself.
    pub fn element_end_forces(
        &self,
        element: usize,
        u: &DVector<f64>,
        a: &DVector<f64>,
    ) -> [f64; 4] {
        let local = (
            self.element_field(element, u),
            self.element_field(element, a),
        );
        each!(self, b => b.element_end_forces(element, local))
    }
}

/// The dynamics: products, factors, energies in the state's coordinates
/// (`StructureOps` has what each means).
impl Structure {
    /// `out = K u`.
    pub fn stiffness_times(&self, u: &DVector<f64>, out: &mut DVector<f64>) {
        each!(self, b => b.stiffness_times(u, out))
    }

    /// `out = M v` (the identity in modal coordinates).
    pub fn mass_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        each!(self, b => b.mass_times(v, out))
    }

    /// `rhs ← M⁻¹ rhs` (the identity in modal coordinates).
    pub fn solve_mass(&self, rhs: &mut DVector<f64>) {
        each!(self, b => b.solve_mass(rhs))
    }

    /// The inverse of M + `damping_weight` C + `stiffness_weight` K, the
    /// effective matrix of implicit schemes.
    pub fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<EffectiveFactor, String> {
        each!(self, b => b.effective_factor(damping_weight, stiffness_weight))
    }

    /// The static deflection u with K u = `load` (modal coordinates on a
    /// modal structure).
    pub fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        each!(self, b => b.static_deflection(load))
    }

    /// `out = K u + C v`: the elastic and damping forces, using `scratch`.
    pub fn internal_forces(
        &self,
        u: &DVector<f64>,
        v: &DVector<f64>,
        scratch: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        each!(self, b => b.internal_forces(u, v, scratch, out))
    }

    /// `out = C v`: the damping forces alone.
    pub fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        each!(self, b => b.damping_times(v, out))
    }

    /// `out = K u + C v` (the bits of `internal_forces`) and `damping = C v`.
    pub fn internal_and_damping_forces(
        &self,
        state: (&DVector<f64>, &DVector<f64>),
        damping: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        each!(self, b => b.internal_and_damping_forces(state, damping, out))
    }

    /// See `StructureOps::energies_are_products`.
    pub fn energies_are_products(&self) -> bool {
        each!(self, b => b.energies_are_products())
    }

    /// See `StructureOps::stiffness_and_damping_forces`.
    pub fn stiffness_and_damping_forces(
        &self,
        state: (&DVector<f64>, &DVector<f64>),
        forces: (&mut DVector<f64>, &mut DVector<f64>),
        out: &mut DVector<f64>,
    ) {
        each!(self, b => b.stiffness_and_damping_forces(state, forces, out))
    }

    /// Whether `accelerations_from_internal` gives `accelerations`' bits.
    pub fn accelerations_read_internal_forces(&self) -> bool {
        each!(self, b => b.accelerations_read_internal_forces())
    }

    /// `accelerations` from the internal forces K u + C v of the state,
    /// where that gives its bits; false (nothing done) elsewhere.
    pub fn accelerations_from_internal(
        &self,
        load: &DVector<f64>,
        internal: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> bool {
        each!(self, b => b.accelerations_from_internal(load, internal, out))
    }

    /// Accelerations `M⁻¹ (load − K u − C v)`.
    pub fn accelerations(
        &self,
        state: (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        each!(self, b => b.accelerations(state, load, out))
    }

    /// K, M's factor and α when the accelerations are `M⁻¹ (f − K u) − α v`
    /// (`HermiteBeam::velocity_free_band`); `None` but on the full mesh.
    pub fn velocity_free_band(&self) -> Option<VelocityFreeBand<'_>> {
        each!(self, b => b.velocity_free_band())
    }

    /// ½ vᵀ M v.
    pub fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        each!(self, b => b.kinetic_energy(v))
    }

    /// ½ uᵀ K u.
    pub fn strain_energy(&self, u: &DVector<f64>) -> f64 {
        each!(self, b => b.strain_energy(u))
    }

    /// Power dissipated by the structural damping, vᵀ C v (W).
    pub fn damping_power(&self, v: &DVector<f64>) -> f64 {
        each!(self, b => b.damping_power(v))
    }

    /// Σ c (M⁻¹)ᵢᵢ over the support dampers (1/s): at least the decay rate
    /// of any mode they damp (the explicit scheme's stability limit).
    pub fn damper_rate_bound(&self) -> f64 {
        each!(self, b => b.damper_rate_bound())
    }

    /// Highest natural circular frequency (rad/s), never below the true
    /// one: the explicit schemes' step limit.
    pub fn highest_frequency(&self) -> f64 {
        each!(self, b => b.highest_frequency())
    }

    /// Whether the structure has any damping: under a rail the deck's,
    /// the track's and the ground's (the rail mesh has none of its own).
    pub fn is_damped(&self) -> bool {
        each!(self, b => b.is_damped())
    }

    /// The Winkler foundation under the beam; none under a rail over a
    /// deck (its track and ground layers are the assembly's).
    pub fn foundation(&self) -> Option<Foundation> {
        each!(self, b => b.foundation())
    }

    /// The lowest `count` natural modes; under a rail those of the coupled
    /// rail and deck (dense, `track_on_deck::MAX_DENSE_DOFS`), their shapes
    /// in the state's coordinates.
    pub fn modes(&self, count: usize) -> Result<Modes, String> {
        each!(self, b => b.modes(count))
    }

    /// The lowest `count` natural circular frequencies (rad/s).
    pub fn frequencies(&self, count: usize) -> Result<Vec<f64>, String> {
        each!(self, b => b.frequencies(count))
    }
}

/// Why a rail over the deck has no modal route.
pub const TRACK_NOT_MODAL: &str = "solver.modes: the rail over the deck (track.on_deck) is \
     stepped on its full mesh only; a modal reduction of the coupled rail and deck is not \
     built: leave solver.modes out";
