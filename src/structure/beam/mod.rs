//! Euler-Bernoulli beam on Hermite cubic elements.
//!
//! Two DOFs per node: transverse displacement w and section rotation ψ = w'.
//! Consistent mass, supports removed from the free DOF set. The free DOFs are
//! numbered node by node, so mass and stiffness are band matrices of
//! half-bandwidth 3 (`crate::band`) and every per-step operation is linear
//! in the number of elements.

use crate::band::{BandLdlt, SymBand};
use crate::bending::Bending;
use crate::mesh::{GroundSpring, Mesh, Segment};
use crate::modal::ModalFactor;
use crate::structure::ops::StructureOps;
use nalgebra::{DMatrix, DVector, Matrix4, SymmetricEigen};
use two_level::{CoarseMesh, Effective, FineMesh, TwoLevelFactor, PLAIN_FACTOR_ERROR};

pub mod bending;
mod dynamics;
pub mod mesh;
mod spec;
mod sturm;
mod subspace;
pub mod two_level;
pub use spec::{
    BeamSpec, DampingSpec, EndSupport, FoundationPreset, FoundationSpec, JointKind, JointSpec,
    SpringSpec, SupportsSpec,
};
#[cfg(test)]
pub(crate) use subspace::start_value;
pub(crate) use subspace::{lowest as lowest_modes_by_subspace, Wanted};
pub use subspace::{DENSE_MODE_DOFS, MAX_SUBSPACE_ENTRIES, MAX_SUBSPACE_WORK};

/// The callers' name of the structure seam (`crate::structure::Structure`).
pub type Beam = crate::structure::Structure;

/// Beyond this ratio of track length to shortest element, K u is
/// computed element by element (`Beam::stiffness_times`).
const ELEMENTWISE_RATIO: f64 = 4096.0;

/// Most free DOFs for which the natural modes may come from the dense
/// generalized eigenproblem (O(n³)); beyond, the subspace iteration.
pub const MAX_MODE_DOFS: usize = 600;

/// Rayleigh damping C = `mass` M + `stiffness` K (1/s and s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rayleigh {
    pub mass: f64,
    pub stiffness: f64,
}

impl Rayleigh {
    /// The coefficients giving damping ratios ζ₁, ζ₂ at circular frequencies
    /// ω₁ ≠ ω₂: ζ(ω) = α / 2ω + β ω / 2 through both points.
    pub fn from_ratios(omega: [f64; 2], zeta: [f64; 2]) -> Rayleigh {
        let [w1, w2] = omega;
        let [z1, z2] = zeta;
        let denominator = w2 * w2 - w1 * w1;
        Rayleigh {
            mass: 2.0 * w1 * w2 * (z1 * w2 - z2 * w1) / denominator,
            stiffness: 2.0 * (z2 * w2 - z1 * w1) / denominator,
        }
    }

    /// Damping ratio of a mode of circular frequency ω.
    pub fn ratio(&self, omega: f64) -> f64 {
        self.mass / (2.0 * omega) + self.stiffness * omega / 2.0
    }

    pub fn is_zero(&self) -> bool {
        self.mass == 0.0 && self.stiffness == 0.0
    }
}

/// Natural modes of the beam, lowest first.
pub struct Modes {
    /// Circular frequencies ω (rad/s).
    pub omega: Vec<f64>,
    /// Mass-normalized shapes on the free DOFs (φᵀ M φ = 1), one per column.
    pub shapes: DMatrix<f64>,
}

/// Hermite shape functions of one element evaluated at one abscissa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    pub element: usize,
    /// Free-DOF index of each of the element's four DOFs (w_i, ψ_i, w_j, ψ_j),
    /// `None` where a support holds the DOF.
    pub dofs: [Option<usize>; 4],
    /// Row N1: w(x) = n · q.
    pub n: [f64; 4],
    /// Row N2 = dN1/dx: w'(x).
    pub dn: [f64; 4],
    /// d²N1/dx²: w''(x).
    pub ddn: [f64; 4],
}

impl Shape {
    /// Dot a row of shape values with the element's entries of a nodal
    /// free-DOF vector (a full structure's state; `Beam::dot` reads any
    /// structure's).
    pub fn dot(&self, row: &[f64; 4], q: &DVector<f64>) -> f64 {
        self.dofs
            .iter()
            .zip(row)
            .filter_map(|(dof, r)| dof.map(|i| r * q[i]))
            .sum()
    }

    /// Add `scale * row` into the element's entries of a nodal free-DOF
    /// vector (`Beam::scatter` loads any structure's).
    pub fn scatter(&self, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        for (dof, r) in self.dofs.iter().zip(row) {
            if let Some(i) = *dof {
                out[i] += scale * r;
            }
        }
    }
}

/// The full-mesh implementation of the structure seam
/// (`crate::structure::Structure`): every free DOF is a state entry.
pub struct HermiteBeam {
    pub length: f64,
    pub surface_offset: f64,
    pub mass_per_length: f64,
    pub bending_stiffness: f64,
    /// Start abscissa of each element, increasing, then the last one's end
    /// (`length`); with one beam, the node abscissae.
    pub node_x: Vec<f64>,
    /// Free-DOF index of each element's four DOFs, `None` where held.
    element_dofs: Vec<[Option<usize>; 4]>,
    /// End abscissa of each element.
    element_end: Vec<f64>,
    /// The beams of the track (one unless there are separate joints).
    segments: Vec<Segment>,
    /// Per element: whether it is the first, the last element of its beam.
    segment_ends: Vec<(bool, bool)>,
    /// Free rotation DOFs.
    rotation_dofs: Vec<usize>,
    /// Elastic supports: stiffness in `stiffness`, dampers here.
    springs: Vec<GroundSpring>,
    free_dofs: usize,
    /// Length of each element (m), and the shortest.
    element_length: Vec<f64>,
    min_element_length: f64,
    mass: SymBand,
    stiffness: SymBand,
    /// K applied element by element (accurate where the band's products
    /// cancel: `crate::bending`), for the energies always and for the
    /// products on fine meshes (`elementwise_products`).
    bending: Bending,
    elementwise_products: bool,
    mass_factor: BandLdlt,
    damping: Rayleigh,
    /// One damping ratio for every mode (`beam.damping = { ratio }`): the
    /// modal structure applies it; the mesh itself carries no Rayleigh.
    modal_ratio: Option<f64>,
    /// k / μ of the Winkler foundation (1/s², 0 without): its matrix is
    /// (k / μ) M, so it shifts every ω² by this much.
    foundation_rate: f64,
    foundation: Option<Foundation>,
}

/// A Winkler foundation's modulus and damping per metre of beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foundation {
    /// k (N/m²).
    pub stiffness: f64,
    /// c (N s/m²).
    pub damping: f64,
}

/// The band operators of accelerations `M⁻¹ (f − K u) − α v`
/// (`Beam::velocity_free_band`); `accelerations` gives the same bits.
#[derive(Debug, Clone, Copy)]
pub struct VelocityFreeBand<'a> {
    pub stiffness: &'a SymBand,
    pub mass_factor: &'a BandLdlt,
    /// α of the Rayleigh damping α M + β K (β is zero here).
    pub mass_damping: f64,
}

/// The inverse of an implicit scheme's effective matrix: the band factor,
/// or on a modal structure the modal one (diagonal without support dampers).
#[derive(Debug, Clone)]
pub enum EffectiveFactor {
    Band(BandLdlt),
    Modal(ModalFactor),
    /// Fine meshes, where the band factor alone loses the smooth modes.
    TwoLevel(Box<TwoLevelFactor>),
    /// The rail over the deck's interleaved DOFs (`structure::track_seam`),
    /// with its last solve (`solve_recalling`).
    Wide(crate::wide_band::RecallingLdlt),
}

/// The entries of an effective matrix's inverse within its band, where
/// its factor is a plain band (the beam's or the rail over the deck's).
#[derive(Debug, Clone)]
pub enum InverseWithinBand {
    Band(crate::linalg::band_inverse::InverseBand),
    Wide(crate::wide_band::InverseWideBand),
}

impl InverseWithinBand {
    /// Z(a, b), or None outside the band.
    pub fn entry(&self, a: usize, b: usize) -> Option<f64> {
        match self {
            InverseWithinBand::Band(inverse) => inverse.entry(a, b),
            InverseWithinBand::Wide(inverse) => inverse.entry(a, b),
        }
    }
}

impl EffectiveFactor {
    /// The entries of S⁻¹ within S's band (one sweep of the factor), where
    /// the factor is a plain band; None for the modal and two-level ones.
    pub fn inverse_within_band(&self) -> Option<InverseWithinBand> {
        match self {
            EffectiveFactor::Band(factor) => Some(InverseWithinBand::Band(
                crate::linalg::band_inverse::InverseBand::new(factor),
            )),
            EffectiveFactor::Wide(factor) => Some(InverseWithinBand::Wide(
                crate::wide_band::InverseWideBand::new(factor.factor()),
            )),
            EffectiveFactor::Modal(_) | EffectiveFactor::TwoLevel(_) => None,
        }
    }

    /// Whether the solves have the coarse-mesh correction.
    pub fn is_two_level(&self) -> bool {
        matches!(self, EffectiveFactor::TwoLevel(_))
    }

    /// `rhs ← S⁻¹ rhs`.
    pub fn solve_mut(&self, rhs: &mut DVector<f64>) {
        match self {
            EffectiveFactor::Band(factor) => factor.solve_mut(rhs),
            EffectiveFactor::Modal(factor) => factor.solve_mut(rhs),
            EffectiveFactor::TwoLevel(factor) => factor.solve_mut(rhs),
            EffectiveFactor::Wide(factor) => factor.factor().solve_in_place(rhs.as_mut_slice()),
        }
    }

    /// `solve_mut` for a right-hand side that differs from the last one
    /// in some rows: the same bits, the rows it cannot change recalled
    /// from the last solve where the factor keeps it (the rail's).
    pub fn solve_recalling(&mut self, rhs: &mut DVector<f64>) {
        match self {
            EffectiveFactor::Wide(factor) => {
                factor.solve_in_place(rhs.as_mut_slice());
            }
            factor => factor.solve_mut(rhs),
        }
    }
}

pub(crate) fn element_stiffness(len: f64, ei: f64) -> Matrix4<f64> {
    let l = len;
    let c = ei / (l * l * l);
    Matrix4::new(
        12.0,
        6.0 * l,
        -12.0,
        6.0 * l,
        6.0 * l,
        4.0 * l * l,
        -6.0 * l,
        2.0 * l * l,
        -12.0,
        -6.0 * l,
        12.0,
        -6.0 * l,
        6.0 * l,
        2.0 * l * l,
        -6.0 * l,
        4.0 * l * l,
    ) * c
}

pub(crate) fn element_mass(len: f64, mu: f64) -> Matrix4<f64> {
    let l = len;
    let c = mu * l / 420.0;
    Matrix4::new(
        156.0,
        22.0 * l,
        54.0,
        -13.0 * l,
        22.0 * l,
        4.0 * l * l,
        13.0 * l,
        -3.0 * l * l,
        54.0,
        13.0 * l,
        156.0,
        -22.0 * l,
        -13.0 * l,
        -3.0 * l * l,
        -22.0 * l,
        4.0 * l * l,
    ) * c
}

/// The consistent mass and stiffness band matrices of `mesh` (with the
/// Winkler `foundation`'s k ∫ NᵀN dx and the support springs in K).
fn assemble_bands(mesh: &Mesh, spec: &BeamSpec, foundation: f64) -> (SymBand, SymBand) {
    let mut mass = SymBand::zeros(mesh.free_dofs);
    let mut stiffness = SymBand::zeros(mesh.free_dofs);
    for (&len, dofs) in mesh.element_length.iter().zip(&mesh.element_dofs) {
        let me = element_mass(len, spec.mass_per_length);
        let mut ke = element_stiffness(len, spec.bending_stiffness);
        if foundation > 0.0 {
            // The Winkler foundation's consistent matrix k ∫ NᵀN dx.
            ke += element_mass(len, foundation);
        }
        for a in 0..4 {
            for b in 0..=a {
                if let (Some(i), Some(j)) = (dofs[a], dofs[b]) {
                    mass.add_symmetric(i, j, me[(a, b)]);
                    stiffness.add_symmetric(i, j, ke[(a, b)]);
                }
            }
        }
    }
    for spring in &mesh.springs {
        stiffness.add_symmetric(spring.dof, spring.dof, spring.stiffness);
    }
    (mass, stiffness)
}

impl HermiteBeam {
    /// Assemble the beam of a (validated) spec.
    pub fn new(spec: &BeamSpec) -> Result<HermiteBeam, String> {
        let mesh = Mesh::new(spec)?;
        let free_dofs = mesh.free_dofs;
        let foundation = spec.foundation.map_or(0.0, |f| f.stiffness());
        let (mass, stiffness) = assemble_bands(&mesh, spec, foundation);
        let mass_factor = mass
            .ldlt()
            .ok_or("beam mass matrix is not positive definite")?;
        if !spec.joints.is_empty() && stiffness.ldlt().is_none() {
            return Err(format!(
                "beam.joints: the supports, springs and joints ({} joints) leave a beam of the \
                 track free to move as a mechanism; hold each beam against rigid motion",
                spec.joints.len()
            ));
        }
        let element_length = mesh.element_length;
        let bending = Bending::new(
            &element_length,
            &mesh.element_dofs,
            spec.bending_stiffness,
            mesh.springs.iter().map(|s| (s.dof, s.stiffness)).collect(),
        )
        .with_foundation(foundation);
        let mut node_x = mesh.element_start;
        node_x.extend(mesh.element_end.last());
        let mut segment_ends = vec![(false, false); element_length.len()];
        for segment in &mesh.segments {
            segment_ends[segment.elements.start].0 = true;
            segment_ends[segment.elements.end - 1].1 = true;
        }
        let min_element_length = element_length.iter().copied().fold(f64::INFINITY, f64::min);
        let beam = HermiteBeam {
            length: spec.length,
            surface_offset: spec.surface_offset,
            mass_per_length: spec.mass_per_length,
            bending_stiffness: spec.bending_stiffness,
            node_x,
            element_dofs: mesh.element_dofs,
            element_end: mesh.element_end,
            segments: mesh.segments,
            segment_ends,
            rotation_dofs: mesh.rotation_dofs,
            springs: mesh.springs,
            free_dofs,
            element_length,
            min_element_length,
            mass,
            stiffness,
            bending,
            elementwise_products: false,
            mass_factor,
            damping: Rayleigh::default(),
            modal_ratio: None,
            foundation_rate: foundation / spec.mass_per_length,
            foundation: None,
        };
        beam.with_damping(spec)
    }

    /// The beam with the spec's damping, modal ratio and foundation, and
    /// its way of taking K u.
    fn with_damping(mut self, spec: &BeamSpec) -> Result<HermiteBeam, String> {
        self.modal_ratio = match spec.damping {
            Some(DampingSpec::Modal { ratio }) => Some(ratio),
            _ => None,
        };
        self.foundation = spec.foundation.map(|f| Foundation {
            stiffness: f.stiffness(),
            damping: f.damping(),
        });
        self.damping = self.rayleigh(spec.damping.as_ref())?;
        if let Some(damping) = spec.foundation.map(|f| f.damping()) {
            // With a uniform mass per length, c ∫ NᵀN dx is exactly
            // (c / μ) M: the foundation's damper is mass-proportional.
            self.damping.mass += damping / spec.mass_per_length;
        }
        // The band's K u of a smooth field is off by about ε (L/h)⁴ of
        // itself: harmless up to a few thousand elements (the dynamics
        // then stay bit for bit as before), not beyond (at 100,000 it gave
        // the first mode a negative stiffness). The element sum costs
        // about twice the band product.
        self.elementwise_products = self.length / self.min_element_length > ELEMENTWISE_RATIO;
        Ok(self)
    }

    /// The Rayleigh coefficients of a (validated) damping spec.
    fn rayleigh(&self, spec: Option<&DampingSpec>) -> Result<Rayleigh, String> {
        use std::f64::consts::TAU;
        Ok(match spec {
            // One ratio in every mode is the modal structure's (`modal_ratio`).
            None | Some(DampingSpec::Modal { .. }) => Rayleigh::default(),
            Some(&DampingSpec::Coefficients { alpha, beta }) => Rayleigh {
                mass: alpha,
                stiffness: beta,
            },
            Some(&DampingSpec::Frequencies {
                ratios,
                frequencies,
            }) => Rayleigh::from_ratios(frequencies.map(|f| TAU * f), ratios),
            Some(&DampingSpec::Modes { ratio, modes }) => {
                let highest = modes[0].max(modes[1]);
                if highest > self.free_dofs {
                    return Err(format!(
                        "beam.damping.modes = {modes:?} names mode {highest}, but the beam has \
                         only {} free DOFs (modes)",
                        self.free_dofs
                    ));
                }
                let omega = self.frequencies(highest).map_err(|e| {
                    format!(
                        "beam.damping.modes = {modes:?}: {e}; or give the two \
                             frequencies (beam.damping.frequencies, Hz) instead of modes"
                    )
                })?;
                Rayleigh::from_ratios([omega[modes[0] - 1], omega[modes[1] - 1]], [ratio; 2])
            }
        })
    }

    /// The Winkler foundation under the beam, if any.
    pub fn foundation(&self) -> Option<Foundation> {
        self.foundation
    }

    /// Rayleigh damping coefficients of the beam (zero when undamped).
    pub fn damping(&self) -> Rayleigh {
        self.damping
    }

    /// The damping ratio of every mode, when the scene gives one ratio for
    /// all (`beam.damping = { ratio }`, modal structures only).
    pub fn modal_ratio(&self) -> Option<f64> {
        self.modal_ratio
    }

    /// The lowest `count` natural modes, K φ = ω² M φ, mass-normalized. The
    /// dense eigenproblem up to `DENSE_MODE_DOFS` free DOFs, or up to
    /// `MAX_MODE_DOFS` when more than a quarter of the modes are wanted;
    /// the subspace iteration otherwise (O(n p²) where the dense one is
    /// O(n³): damping given by modes 1 and 3 of a 1,000-element beam takes
    /// milliseconds, not seconds).
    pub fn modes(&self, count: usize) -> Result<Modes, String> {
        let n = self.free_dofs;
        let count = count.min(n);
        if count == 0 {
            return Ok(Modes {
                omega: Vec::new(),
                shapes: DMatrix::zeros(n, 0),
            });
        }
        if self.dense_for(count) {
            self.dense_modes(count)
        } else {
            let (omega, shapes) = subspace::lowest(self, count, Wanted::Modes)?;
            Ok(Modes { omega, shapes })
        }
    }

    /// The lowest `count` circular frequencies (rad/s), as `modes` finds
    /// them but without the shapes: the subspace iteration stops once its
    /// Ritz values settle.
    pub fn frequencies(&self, count: usize) -> Result<Vec<f64>, String> {
        if count == 0 || self.dense_for(count) {
            return Ok(self.modes(count)?.omega);
        }
        Ok(subspace::lowest(self, count.min(self.free_dofs), Wanted::Frequencies)?.0)
    }

    /// The lowest `count` circular frequencies (rad/s) for a filter's
    /// cut-off: beyond the dense eigenproblem by bisection on Sturm counts
    /// (`sturm.rs`), which clustered frequencies (many equal spans) do not
    /// slow down as they slow the subspace iteration. Their error is
    /// rounding relative to the highest frequency of the mesh (about
    /// 1e-16 λ_max absolute in λ): ample for a cut-off, not for damping
    /// ratios tied to a mode (`frequencies`).
    pub fn cut_off_frequencies(&self, count: usize) -> Result<Vec<f64>, String> {
        if count == 0 || self.dense_for(count) {
            return Ok(self.modes(count)?.omega);
        }
        sturm::lowest_frequencies(&self.mass, &self.stiffness, count.min(self.free_dofs))
    }

    /// Whether `count` modes come from the dense eigenproblem.
    fn dense_for(&self, count: usize) -> bool {
        let n = self.free_dofs;
        let few = 4 * count.min(n) < n;
        n <= MAX_MODE_DOFS && !(few && n > DENSE_MODE_DOFS)
    }

    /// The lowest `count` modes by the dense eigenproblem, through the
    /// Cholesky factor of M.
    fn dense_modes(&self, count: usize) -> Result<Modes, String> {
        let n = self.free_dofs;
        let dense = |a: &SymBand| DMatrix::from_fn(n, n, |i, j| a.get(i, j));
        let (mass, stiffness) = (dense(&self.mass), dense(&self.stiffness));
        let (omega, shapes) = crate::dense_modes::lowest_modes(mass, stiffness, count, "beam")?;
        Ok(Modes { omega, shapes })
    }

    pub fn free_dofs(&self) -> usize {
        self.free_dofs
    }

    pub fn elements(&self) -> usize {
        self.node_x.len() - 1
    }

    /// The element whose span holds `x`; abscissae beyond the ends map to the
    /// end elements (their cubics are extended past the beam).
    #[inline]
    pub fn element_at(&self, x: f64) -> usize {
        if self.segments.len() == 1 && x.is_finite() {
            // On a track of one beam, from the element x would be in on a
            // uniform mesh: a walk of an element or two where bisection
            // took a dozen comparisons (the foot-point search starts here
            // at every call). Saturating: before the beam 0, past it the
            // last element.
            let first = self.node_x[0];
            let span = self.node_x[self.node_x.len() - 1] - first;
            let uniform = ((x - first) / span * self.elements() as f64) as usize;
            return self.element_near(x, uniform);
        }
        self.element_by_bisection(x)
    }

    /// `element_at` by bisecting the nodes: on several beams, and at a NaN
    /// or infinite `x`.
    fn element_by_bisection(&self, x: f64) -> usize {
        let last = self.elements() - 1;
        if x.is_nan() {
            // Where a total order puts it.
            return if x.is_sign_negative() { 0 } else { last };
        }
        // The nodes at or before x, by plain comparisons.
        self.node_x
            .partition_point(|&n| n <= x)
            .saturating_sub(1)
            .min(last)
    }

    /// The element whose span holds `x`, searched from element `hint`
    /// outwards within the hint's beam: a walk of a few elements when `x`
    /// is near, bisection when it is far. Same answer as `element_at` on a
    /// track of one beam; on several, abscissae beyond the hint's beam map
    /// to its end elements.
    pub fn element_near(&self, x: f64, hint: usize) -> usize {
        let last = self.elements() - 1;
        let mut e = hint.min(last);
        for _ in 0..4 {
            let (first_of_beam, last_of_beam) = self.segment_ends[e];
            if !first_of_beam && x < self.node_x[e] {
                e -= 1;
            } else if !last_of_beam && x >= self.node_x[e + 1] {
                e += 1;
            } else {
                return e;
            }
        }
        let range = self.segment_of_element(e).elements.clone();
        let starts = &self.node_x[range.clone()];
        let offset = match starts.binary_search_by(|n| n.total_cmp(&x)) {
            Ok(i) => i,
            Err(0) => 0,
            Err(i) => i - 1,
        };
        range.start + offset.min(range.len() - 1)
    }

    /// The beams of the track, in order.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The beam element `element` belongs to.
    pub fn segment_of_element(&self, element: usize) -> &Segment {
        let i = self
            .segments
            .partition_point(|s| s.elements.end <= element)
            .min(self.segments.len() - 1);
        &self.segments[i]
    }

    /// Length of element `element` (m).
    pub fn element_length(&self, element: usize) -> f64 {
        self.element_length[element]
    }

    /// Where `x` lies past an end of the element's beam, the end element's abscissa
    /// of that end (0 or 1) and the distance past it (m); otherwise `x`'s
    /// own abscissa and 0.
    #[inline]
    fn abscissa(&self, element: usize, x: f64) -> (f64, f64) {
        let len = self.element_length[element];
        let s = (x - self.node_x[element]) / len;
        let (first_of_beam, last_of_beam) = self.segment_ends[element];
        if last_of_beam && s > 1.0 {
            (1.0, x - self.element_end[element])
        } else if first_of_beam && s < 0.0 {
            (0.0, x - self.node_x[element])
        } else {
            (s, 0.0)
        }
    }

    /// Shape functions of element `element` at abscissa `x`.
    ///
    /// Past an end of the beam (where the exit is located) the axis goes on
    /// as the quadratic Taylor polynomial of the end element at the end:
    /// value, slope and curvature continuous, no cubic term. Extrapolating
    /// the cubic itself grows as (distance / element length)³, which on
    /// fine meshes (a step's travel spans tens of elements) made the exit
    /// step diverge.
    pub fn shape(&self, element: usize, x: f64) -> Shape {
        let len = self.element_length[element];
        let (s, past) = self.abscissa(element, x);
        let (s2, s3) = (s * s, s * s * s);
        let n = [
            1.0 - 3.0 * s2 + 2.0 * s3,
            len * (s - 2.0 * s2 + s3),
            3.0 * s2 - 2.0 * s3,
            len * (s3 - s2),
        ];
        let dn = [
            (-6.0 * s + 6.0 * s2) / len,
            1.0 - 4.0 * s + 3.0 * s2,
            (6.0 * s - 6.0 * s2) / len,
            3.0 * s2 - 2.0 * s,
        ];
        let ddn = [
            (-6.0 + 12.0 * s) / (len * len),
            (-4.0 + 6.0 * s) / len,
            (6.0 - 12.0 * s) / (len * len),
            (6.0 * s - 2.0) / len,
        ];
        let (mut n, mut dn) = (n, dn);
        if past != 0.0 {
            for k in 0..4 {
                n[k] += past * (dn[k] + 0.5 * past * ddn[k]);
                dn[k] += past * ddn[k];
            }
        }
        let dofs = self.element_dofs[element];
        Shape {
            element,
            dofs,
            n,
            dn,
            ddn,
        }
    }

    /// `axis` from the element's field `element_field(element, u)`: the
    /// foot-point search gathers it once per element, not at each iterate
    /// (on a modal structure a gather is a product with the kept modes).
    #[inline]
    pub fn axis_of_field(&self, element: usize, x: f64, field: &[f64; 4]) -> [f64; 4] {
        let len = self.element_length[element];
        let (s, past) = self.abscissa(element, x);
        let [a, b, c, d] = *field;
        let (b, d) = (b * len, d * len);
        let c2 = -3.0 * a - 2.0 * b + 3.0 * c - d;
        let c3 = 2.0 * a + b - 2.0 * c + d;
        let w = a + s * (b + s * (c2 + s * c3));
        let dw = (b + s * (2.0 * c2 + 3.0 * s * c3)) / len;
        let ddw = (2.0 * c2 + 6.0 * s * c3) / (len * len);
        let dddw = 6.0 * c3 / (len * len * len);
        if past != 0.0 {
            // The quadratic continuation past the end (see `shape`).
            return [
                w + past * (dw + 0.5 * past * ddw),
                dw + past * ddw,
                ddw,
                0.0,
            ];
        }
        [w, dw, ddw, dddw]
    }

    /// LDLᵀ factor of M + `damping_weight` C + `stiffness_weight` K, the
    /// effective matrix of implicit schemes.
    pub fn factor_effective(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<BandLdlt, String> {
        let c = self.damping;
        let mass_weight = 1.0 + damping_weight * c.mass;
        let stiffness_weight = stiffness_weight + damping_weight * c.stiffness;
        let mut effective = self
            .mass
            .combine(mass_weight, &self.stiffness, stiffness_weight);
        for spring in self.dampers() {
            effective.add_symmetric(spring.dof, spring.dof, damping_weight * spring.damping);
        }
        effective.ldlt().ok_or_else(|| {
            format!(
                "the implicit scheme's effective matrix {mass_weight:e} M + \
                     {stiffness_weight:e} K is not positive definite"
            )
        })
    }

    /// The band factor of M + `damping_weight` C + `stiffness_weight` K,
    /// or, where its error on a smooth field exceeds
    /// `two_level::PLAIN_FACTOR_ERROR`, the factor with coarse-mesh and
    /// fine corrections (`crate::two_level`).
    fn accurate_factor(
        &self,
        band: BandLdlt,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> EffectiveFactor {
        let c = self.damping;
        // ε times the ratio of the stiffest element's b K to its M: the
        // plain factor's relative error on smooth fields is about this or
        // less (4e-9 against 1.5e-8 at 1,024 elements of the paper's beam
        // at 2.5 ms), and far below it nothing needs checking.
        let h = self.min_element_length;
        let ratio = (stiffness_weight + damping_weight * c.stiffness)
            * (12.0 * self.bending_stiffness / (h * h * h))
            / (self.mass_per_length * h * 156.0 / 420.0);
        if ratio * f64::EPSILON < 10.0 * PLAIN_FACTOR_ERROR {
            return EffectiveFactor::Band(band);
        }
        let special: Vec<usize> = self.springs.iter().map(|s| s.dof).collect();
        let n = self.elements();
        let mesh = CoarseMesh::new(&FineMesh {
            element_start: &self.node_x[..n],
            element_end: &self.element_end,
            element_dofs: &self.element_dofs,
            special_dofs: &special,
            free_dofs: self.free_dofs,
        });
        if mesh.size() == self.free_dofs {
            return EffectiveFactor::Band(band);
        }
        let operator = Effective {
            mass_matrix: self.mass.clone(),
            bending: self.bending.clone(),
            dampers: self.dampers().map(|s| (s.dof, s.damping)).collect(),
            mass: 1.0 + damping_weight * c.mass,
            stiffness: stiffness_weight + damping_weight * c.stiffness,
            damping: damping_weight,
        };
        let Some(coarse) = self.coarse_effective(&mesh, &operator).ldlt() else {
            return EffectiveFactor::Band(band);
        };
        let mut two_level = TwoLevelFactor::new(band, coarse, mesh, operator);
        if two_level.calibrate() <= PLAIN_FACTOR_ERROR {
            return EffectiveFactor::Band(two_level.into_band());
        }
        EffectiveFactor::TwoLevel(Box::new(two_level))
    }

    /// The effective matrix `operator` on the coarse mesh `mesh`: its
    /// elements' M and K weighted as the operator's, the springs and their
    /// dampers on their coarse nodes.
    fn coarse_effective(&self, mesh: &CoarseMesh, operator: &Effective) -> SymBand {
        let mut coarse = SymBand::zeros(mesh.size());
        for element in &mesh.elements {
            let me = element_mass(element.length, self.mass_per_length);
            let ke = element_stiffness(element.length, self.bending_stiffness);
            let se = me * operator.mass + ke * operator.stiffness;
            for a in 0..4 {
                for b in 0..=a {
                    if let (Some(i), Some(j)) = (element.dofs[a], element.dofs[b]) {
                        coarse.add_symmetric(i, j, se[(a, b)]);
                    }
                }
            }
        }
        for spring in &self.springs {
            let i = mesh
                .coarse_dof(spring.dof)
                .expect("springs are coarse nodes");
            let value = operator.stiffness * spring.stiffness + operator.damping * spring.damping;
            coarse.add_symmetric(i, i, value);
        }
        coarse
    }

    /// The support dampers as (free DOF, coefficient): what a modal
    /// reduction projects onto its modes.
    pub(in crate::structure) fn damper_coefficients(
        &self,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.dampers().map(|s| (s.dof, s.damping))
    }

    /// The mass and stiffness band matrices (the modal eigensolver's input).
    pub(crate) fn mass_band(&self) -> &SymBand {
        &self.mass
    }

    pub(crate) fn stiffness_band(&self) -> &SymBand {
        &self.stiffness
    }

    /// Whether the structure dissipates: Rayleigh damping or support dampers.
    pub fn is_damped(&self) -> bool {
        !self.damping.is_zero() || self.dampers().next().is_some()
    }

    /// The elastic supports that have a damper.
    fn dampers(&self) -> impl Iterator<Item = &GroundSpring> {
        self.springs.iter().filter(|s| s.damping != 0.0)
    }

    /// Power dissipated by the support dampers, Σ c v² (W).
    fn damper_power(&self, v: &DVector<f64>) -> f64 {
        self.dampers()
            .map(|s| s.damping * v[s.dof] * v[s.dof])
            .sum()
    }

    /// (M⁻¹)ᵢᵢ, by one band solve.
    fn inverse_mass_diagonal(&self, i: usize) -> f64 {
        let mut e = DVector::zeros(self.free_dofs);
        e[i] = 1.0;
        self.solve_mass(&mut e);
        e[i]
    }

    /// Whether σ M − K is positive definite, i.e. σ exceeds every eigenvalue.
    fn exceeds_spectrum(&self, sigma: f64) -> bool {
        self.mass
            .combine(sigma, &self.stiffness, -1.0)
            .ldlt()
            .is_some()
    }

    /// A lower bound of λ_max: the Rayleigh quotient xᵀKx / xᵀMx of a few
    /// power iterations of M⁻¹K from the vector of equal section rotations
    /// and no displacement, the highest mode of a uniform mesh (every
    /// element bent into the same S): on uniform meshes the bracket then
    /// closes at the first trial.
    fn rayleigh_lower_bound(&self) -> f64 {
        let n = self.free_dofs;
        let mut x = DVector::zeros(n);
        for &i in &self.rotation_dofs {
            x[i] = 1.0;
        }
        let mut work = DVector::zeros(n);
        let mut quotient = 0.0f64;
        for _ in 0..3 {
            let kx = self.stiffness.quadratic_form(x.as_slice());
            let mx = self.mass.quadratic_form(x.as_slice());
            if mx > 0.0 {
                quotient = quotient.max(kx / mx);
            }
            self.stiffness_times(&x, &mut work);
            self.solve_mass(&mut work);
            let scale = work.amax();
            if !(scale > 0.0 && scale.is_finite()) {
                break;
            }
            x.copy_from(&work);
            x.unscale_mut(scale);
        }
        quotient
    }

    /// Highest natural circular frequency of any single free-free element,
    /// an upper bound of the assembled beam's (rad/s).
    /// Every element shares μ and EI, so its eigenvalues scale as ℓ⁻⁴ and
    /// the shortest element's are the highest: one 4×4 eigenproblem.
    pub fn max_element_frequency(&self) -> f64 {
        let len = self.min_element_length;
        let m = element_mass(len, self.mass_per_length);
        let k = element_stiffness(len, self.bending_stiffness);
        let Some(chol) = m.cholesky() else {
            return f64::INFINITY;
        };
        let l_inv = chol.l().try_inverse().unwrap_or_else(Matrix4::zeros);
        let a = l_inv * k * l_inv.transpose();
        let eig = SymmetricEigen::new(0.5 * (a + a.transpose()));
        eig.eigenvalues.max().max(0.0).sqrt()
    }

    /// Shortest element length (m).
    pub fn min_element_length(&self) -> f64 {
        self.min_element_length
    }

    /// LDLᵀ factor of K, to solve many static load cases (`None` when the
    /// supports leave a rigid-body motion).
    pub fn stiffness_factor(&self) -> Option<BandLdlt> {
        self.stiffness.ldlt()
    }

    /// Whether a support holds DOF `k` (0: w, 1: ψ) of node `node`, the
    /// start of element `node` (the end of the last element for the last
    /// node).
    pub fn is_held(&self, node: usize, k: usize) -> bool {
        match node.checked_sub(self.elements()) {
            None => self.element_dofs[node][k].is_none(),
            Some(_) => self.element_dofs[self.elements() - 1][2 + k].is_none(),
        }
    }

    /// The elastic supports at `node` (its springs and dampers to the
    /// ground), each with whether it acts on the deflection (else on a
    /// rotation).
    pub fn springs_at(&self, node: usize) -> Vec<(GroundSpring, bool)> {
        if self.springs.is_empty() {
            return Vec::new();
        }
        let elements = self.elements();
        let (left, right) = (node.checked_sub(1), (node < elements).then_some(node));
        let w = [right.and_then(|e| self.element_dofs[e][0])]
            .into_iter()
            .chain([left.and_then(|e| self.element_dofs[e][2])])
            .flatten()
            .collect::<Vec<_>>();
        let psi = [right.and_then(|e| self.element_dofs[e][1])]
            .into_iter()
            .chain([left.and_then(|e| self.element_dofs[e][3])])
            .flatten()
            .collect::<Vec<_>>();
        self.springs
            .iter()
            .filter_map(|s| {
                if w.contains(&s.dof) {
                    Some((*s, true))
                } else {
                    psi.contains(&s.dof).then_some((*s, false))
                }
            })
            .collect()
    }

    /// Whether a support holds local DOF `local` (w_i, ψ_i, w_j, ψ_j) of
    /// `element`: at a joint the two sides of a node can differ.
    pub fn is_held_in(&self, element: usize, local: usize) -> bool {
        self.element_dofs[element][local].is_none()
    }

    /// Element `element`'s end forces K_e `u` + M_e `a` from its local
    /// fields (w_i, ψ_i, w_j, ψ_j) of displacement and acceleration, held
    /// DOFs taken as zero: what its nodes exert on it, before the loads on
    /// the element itself.
    pub(in crate::structure) fn element_end_forces_of(
        &self,
        element: usize,
        (u, a): ([f64; 4], [f64; 4]),
    ) -> [f64; 4] {
        let len = self.element_length[element];
        let ke = element_stiffness(len, self.bending_stiffness);
        let me = element_mass(len, self.mass_per_length);
        let f = ke * nalgebra::Vector4::from(u) + me * nalgebra::Vector4::from(a);
        [f[0], f[1], f[2], f[3]]
    }

    /// Free-DOF index of `element`'s four DOFs, `None` where held.
    pub fn element_dofs(&self, element: usize) -> &[Option<usize>; 4] {
        &self.element_dofs[element]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn paper_beam(elements: usize) -> BeamSpec {
        BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements,
            ..BeamSpec::default()
        }
    }

    /// The paper's 24 m beam on `spans` equal pinned spans of
    /// `elements_per_span` elements each.
    fn equal_spans(spans: usize, elements_per_span: usize) -> Beam {
        let span = 24.0 / spans as f64;
        let spec = BeamSpec {
            supports: SupportsSpec {
                intermediate: (1..spans).map(|k| k as f64 * span).collect(),
                ..SupportsSpec::default()
            },
            ..paper_beam(elements_per_span * spans)
        };
        Beam::new(&spec).expect("continuous beam")
    }

    /// Twelve equal pinned spans: their first frequency is one span's (each
    /// span bends as if simply supported, neighbours in opposite senses),
    /// Euler–Bernoulli's (π/l)²√(EI/m) within the mesh's error, and the
    /// bisection's first three agree with the dense eigenproblem's.
    #[test]
    fn equal_spans_share_the_first_frequency_of_one_span() {
        let spans = 12;
        let span = 24.0 / spans as f64;
        let beam = equal_spans(spans, 8);
        assert!(!beam.dense_for(3), "the test is meant for the bisection");
        let omega = beam.cut_off_frequencies(3).expect("frequencies");
        let dense = beam.dense_modes(3).expect("dense modes").omega;
        for (w, d) in omega.iter().zip(&dense) {
            assert!((w - d).abs() <= 1e-9 * d, "{omega:?} against {dense:?}");
        }
        let one = Beam::new(&BeamSpec {
            length: span,
            ..paper_beam(8)
        })
        .expect("one span");
        let single = one.dense_modes(1).expect("one span's mode").omega[0];
        assert!(
            (omega[0] - single).abs() <= 1e-9 * single,
            "{} vs {single}",
            omega[0]
        );
        let exact = (std::f64::consts::PI / span).powi(2) * (1e9f64 / 1250.0).sqrt();
        assert!(
            (omega[0] - exact).abs() <= 1e-4 * exact,
            "{} vs {exact}",
            omega[0]
        );
    }

    /// The bisection as first written: doubling from 1, then a band
    /// factorization at every step (the reference for the known counts).
    fn bisect_factorizing_every_step(beam: &Beam, k: usize) -> Vec<f64> {
        let count = |sigma: f64| {
            beam.stiffness
                .combined_negative_pivots(1.0, &beam.mass, -sigma)
                .expect("no zero pivot")
        };
        let mut upper = 1.0f64;
        while count(upper) < k {
            upper *= 2.0;
        }
        let (mut lower, mut omega) = (0.0f64, Vec::new());
        for j in 1..=k {
            let (mut lo, mut hi) = (lower, upper);
            while hi - lo > 1e-12 * hi {
                let mid = 0.5 * (lo + hi);
                if count(mid) >= j {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            omega.push((0.5 * (lo + hi)).max(0.0).sqrt());
            lower = lo;
        }
        omega
    }

    /// Sixty equal spans cluster their first frequencies: the bisection that
    /// reuses known counts gives the bits of factorizing at every step.
    #[test]
    fn known_counts_give_the_bits_of_factorizing_every_step() {
        let beam = equal_spans(60, 4);
        assert!(!beam.dense_for(3), "the test is meant for the bisection");
        let omega = beam.cut_off_frequencies(3).expect("frequencies");
        let reference = bisect_factorizing_every_step(&beam, 3);
        let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&omega), bits(&reference), "{omega:?} vs {reference:?}");
    }

    /// Damping given by modes on a mesh beyond the dense eigenproblem's
    /// reach: the subspace iteration's frequencies give the two modes
    /// exactly the ratio asked, and on a mesh both methods can solve the
    /// coefficients agree with the dense ones.
    #[test]
    fn damping_by_modes_needs_no_dense_eigenproblem() {
        let damped = |elements| {
            let spec = BeamSpec {
                damping: Some(DampingSpec::Modes {
                    ratio: 0.02,
                    modes: [1, 3],
                }),
                ..paper_beam(elements)
            };
            Beam::new(&spec).expect("damped beam")
        };
        let fine = damped(1000);
        assert!(fine.free_dofs() > MAX_MODE_DOFS);
        let modes = fine.modes(3).expect("subspace modes");
        for mode in [0, 2] {
            let zeta = fine.damping().ratio(modes.omega[mode]);
            assert!((zeta - 0.02).abs() < 1e-9, "mode {}: ζ = {zeta}", mode + 1);
        }
        // 200 elements: the subspace iteration (as `Beam::new` now takes
        // it) against the dense eigenproblem it replaced.
        let medium = damped(200);
        let dense = medium.dense_modes(3).expect("dense modes").omega;
        let expected = Rayleigh::from_ratios([dense[0], dense[2]], [0.02; 2]);
        let found = medium.damping();
        assert!(
            (found.mass / expected.mass - 1.0).abs() < 1e-6,
            "{found:?} {expected:?}"
        );
        assert!((found.stiffness / expected.stiffness - 1.0).abs() < 1e-6);
    }

    #[test]
    fn element_at_is_the_bisections() {
        // Uniform meshes and one with nodes at intermediate supports (not
        // uniform), at abscissae along and past the beam, at every node and
        // just before it, and at the non-finite ones.
        let mut continuous = paper_beam(13);
        continuous.supports.intermediate = vec![3.7, 15.0];
        for spec in [paper_beam(1), paper_beam(7), paper_beam(199), continuous] {
            let beam = Beam::new(&spec).unwrap();
            let length = beam.length;
            let mut xs: Vec<f64> = (0..=4000)
                .map(|i| length * (-0.2 + 1.4 * i as f64 / 4000.0))
                .collect();
            for &node in &beam.node_x {
                xs.push(node);
                xs.push(if node > 0.0 {
                    f64::from_bits(node.to_bits() - 1)
                } else {
                    -f64::MIN_POSITIVE
                });
            }
            xs.extend([f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
            xs.extend([-0.0, 1e300, -1e300]);
            for x in xs {
                assert_eq!(beam.element_at(x), beam.element_by_bisection(x), "{x}");
            }
        }
    }

    /// Dense copies of mass and stiffness.
    fn dense(beam: &Beam) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = beam.free_dofs();
        (
            DMatrix::from_fn(n, n, |i, j| beam.mass.get(i, j)),
            DMatrix::from_fn(n, n, |i, j| beam.stiffness.get(i, j)),
        )
    }

    /// λ_max by the dense generalized eigenproblem.
    fn dense_highest_frequency(beam: &Beam) -> f64 {
        let (m, k) = dense(beam);
        let l_inv = m.cholesky().unwrap().l().try_inverse().unwrap();
        let a = &l_inv * k * l_inv.transpose();
        let eig = nalgebra::SymmetricEigen::new(0.5 * (&a + a.transpose()));
        eig.eigenvalues.max().sqrt()
    }

    #[test]
    fn highest_frequency_is_a_tight_upper_bound() {
        // Uniform and non-uniform meshes, pinned, clamped, free and
        // continuous: never below the dense eigenvalue, at most 2e-4 above.
        let mut specs = Vec::new();
        for elements in [1usize, 2, 3, 7, 16, 64, 199] {
            specs.push(paper_beam(elements));
        }
        let mut clamped = paper_beam(9);
        clamped.supports.left = EndSupport::Clamped;
        clamped.supports.right = EndSupport::Free;
        specs.push(clamped);
        let mut continuous = paper_beam(13);
        continuous.supports.intermediate = vec![3.7, 15.0];
        specs.push(continuous);
        let mut free = paper_beam(6);
        free.supports.left = EndSupport::Free;
        free.supports.right = EndSupport::Free;
        specs.push(free.clone());
        // Stiff springs raise the highest frequency above the elements' bound.
        let spring = |at, vertical| SpringSpec {
            at,
            vertical,
            rotational: 1e12,
            ..Default::default()
        };
        free.supports.springs = vec![spring(0.0, 1e12), spring(24.0, 1e8), spring(10.0, 1e10)];
        specs.push(free);
        for spec in specs {
            let beam = Beam::new(&spec).unwrap();
            let exact = dense_highest_frequency(&beam);
            let fast = beam.highest_frequency();
            assert!(
                fast >= exact,
                "{} elements: {fast} < {exact}",
                spec.elements
            );
            assert!(
                fast <= exact * (1.0 + 2e-4),
                "{} elements: {fast} vs {exact}",
                spec.elements
            );
        }
    }

    #[test]
    fn static_midspan_deflection_matches_closed_form() {
        // Hermite cubics reproduce the exact static deflection of a point load at nodes.
        let beam = Beam::new(&paper_beam(2)).unwrap();
        let p = 600e3;
        let mut load = DVector::zeros(beam.free_dofs());
        let shape = beam.shape(beam.element_at(12.0), 12.0);
        shape.scatter(&shape.n, -p, &mut load);
        let (_, k) = dense(&beam);
        let u = k.lu().solve(&load).unwrap();
        let w = beam.deflection(&u, 12.0);
        assert!((w + 0.1728).abs() < 1e-12, "w = {w}");
    }

    #[test]
    fn total_mass_is_consistent() {
        // A rigid vertical translation (w = 1, ψ = 0 everywhere) of a free-free
        // beam has kinetic energy ½ μ L.
        let mut spec = paper_beam(3);
        spec.supports.left = EndSupport::Free;
        spec.supports.right = EndSupport::Free;
        let beam = Beam::new(&spec).unwrap();
        let mut v = DVector::zeros(beam.free_dofs());
        for i in 0..beam.node_x.len() {
            v[2 * i] = 1.0;
        }
        let ke = beam.kinetic_energy(&v);
        assert!((ke - 0.5 * 1250.0 * 24.0).abs() < 1e-8 * ke);
        assert!(beam.strain_energy(&v).abs() < 1e-6);
    }

    #[test]
    fn highest_frequency_gives_the_known_rk4_limit() {
        // For a pinned-pinned Hermite mesh the highest frequency is
        // ω = c/ℓ² √(EI/μ) with c ≈ 50.2, i.e. the RK4 limit 2√2/ω ≈
        // 0.0563 ℓ² √(μ/EI): 9 ms for 2 elements, 0.57 ms for 8 elements.
        for (elements, limit) in [(2, 9.06e-3), (8, 5.66e-4)] {
            let beam = Beam::new(&paper_beam(elements)).unwrap();
            let dt = 2.0 * std::f64::consts::SQRT_2 / beam.highest_frequency();
            assert!((dt / limit - 1.0).abs() < 0.02, "{elements} elements: {dt}");
            // The element bound is conservative, never optimistic.
            assert!(beam.max_element_frequency() >= beam.highest_frequency());
        }
    }

    /// Beams of every kind of support and joint, uniform and not.
    fn varied_beams() -> Vec<BeamSpec> {
        let mut specs = vec![paper_beam(1), paper_beam(2), paper_beam(7)];
        let mut clamped = paper_beam(9);
        clamped.supports.left = EndSupport::Clamped;
        clamped.supports.right = EndSupport::Free;
        specs.push(clamped);
        let mut continuous = paper_beam(13);
        continuous.supports.intermediate = vec![3.7, 15.0];
        specs.push(continuous);
        let mut free = paper_beam(6);
        free.supports.left = EndSupport::Free;
        free.supports.right = EndSupport::Free;
        free.supports.springs = vec![SpringSpec {
            at: 10.0,
            vertical: 1e10,
            rotational: 1e8,
            ..Default::default()
        }];
        specs.push(free);
        let mut joined = paper_beam(12);
        joined.supports.intermediate = vec![8.0];
        let joint = |at, kind, gap| JointSpec { at, kind, gap };
        joined.joints = vec![
            joint(8.0, JointKind::Hinge, 0.0),
            joint(16.0, JointKind::Separate, 0.5),
        ];
        specs.push(joined);
        specs
    }

    #[test]
    fn element_by_element_stiffness_matches_the_assembled_band() {
        for spec in varied_beams() {
            let beam = Beam::new(&spec).unwrap();
            let (_, k) = dense(&beam);
            let n = beam.free_dofs();
            let u = DVector::from_fn(n, |i, _| libm::sin(i as f64 * 0.7) * 1e-2);
            let want = &k * &u;
            let mut got = DVector::zeros(n);
            beam.bending.times(&u, &mut got);
            let scale = want.amax();
            assert!((&got - &want).amax() < 1e-12 * scale, "{spec:?}");
            let q = u.dot(&want);
            assert!(
                (2.0 * beam.strain_energy(&u) - q).abs() < 1e-12 * q,
                "{spec:?}"
            );
        }
    }

    #[test]
    fn strain_energy_of_a_smooth_field_survives_fine_meshes() {
        // w = sin(π x / L) on 100,000 elements: the band's uᵀ K u gave a
        // negative energy (its entries are 1e20 times the field's own
        // stiffness); the element sum gives ½ EI ∫ w''² = EI π⁴ / (4 L³).
        let beam = Beam::new(&paper_beam(100_000)).unwrap();
        let (l, pi) = (24.0, std::f64::consts::PI);
        let mut u = DVector::zeros(beam.free_dofs());
        for e in 0..beam.elements() {
            let shape = beam.shape(e, beam.node_x[e]);
            for (node, x) in [(0, beam.node_x[e]), (2, beam.node_x[e + 1])] {
                let values = [libm::sin(pi * x / l), pi / l * libm::cos(pi * x / l)];
                for (dof, value) in shape.dofs[node..node + 2].iter().zip(values) {
                    if let Some(i) = *dof {
                        u[i] = value;
                    }
                }
            }
        }
        let exact = 1e9 * pi.powi(4) / (4.0 * l.powi(3));
        let energy = beam.strain_energy(&u);
        assert!((energy / exact - 1.0).abs() < 1e-9, "{energy} vs {exact}");
    }

    #[test]
    fn intermediate_supports_fall_on_nodes() {
        let mut spec = paper_beam(5);
        spec.supports.intermediate = vec![10.0];
        let beam = Beam::new(&spec).unwrap();
        assert_eq!(beam.elements(), 5);
        assert!(beam.node_x.contains(&10.0));
        let mut u = DVector::zeros(beam.free_dofs());
        u.fill(1.0);
        assert_eq!(beam.deflection(&u, 10.0), 0.0);
    }
}
