//! Solves with the implicit scheme's effective matrix S = a M + b K + c C
//! on fine meshes, where its band factor alone is not accurate enough.
//!
//! S's entries are of order b EI/h³, and on a smooth field its action is
//! of order a M: at 65,536 elements and Δt = 2.5 ms the two differ by
//! 1e17, so the rounding of the band (and of its LDLᵀ factor) swamps the
//! mass where the smooth modes live. The factor solved the first mode with
//! a relative error of 6e-4 at 16,384 elements, 7e-3 at 65,536 and 1.8 at
//! 100,000 (the run blew up), though it stays accurate on the rough
//! modes, where b K dominates. Two corrections, repeated until they stop
//! changing the answer, make the solve as accurate as the residual:
//! - on a coarse mesh whose nodes are fine nodes: its Hermite cubics are
//!   fine-mesh fields, so the coarse S is exactly the fine S restricted to
//!   them (Galerkin), assembled from coarse elements, small and well
//!   conditioned; it corrects the smooth part of the error;
//! - with the fine band factor, which corrects the rough part.
//!
//! Each residual r − S x is computed with K element by element
//! (`crate::bending`), which keeps its accuracy on smooth fields.
//! (A two-level multigrid cycle written for this banded structure: no
//! crate offers one for a user-supplied operator and nested Hermite
//! meshes.)

use nalgebra::DVector;

use crate::band::{BandLdlt, SymBand};
use crate::bending::Bending;

/// Coarse elements hold at most this many fine ones (fewer where a
/// support, spring, joint or hinge ends them).
const COARSE_ELEMENTS: usize = 512;

/// The plain band factor is kept where its relative error on a smooth
/// field is below this (6e-4 at 16,384 elements of the paper's beam at
/// 2.5 ms, where the exit speed stays within 2.2e-4 m/s of 1,024's; 4e-2
/// at 65,536, 1.9 at 100,000): the corrections cost two to three times a
/// plain solve, and make the contact iteration take up to twice as many
/// iterations at a sudden start (`examples/step_cost.rs`). One cycle (fine
/// solve, coarse correction) is used where its error is below
/// `ONE_CYCLE_ERROR`, else two.
pub const PLAIN_FACTOR_ERROR: f64 = 1e-3;
const ONE_CYCLE_ERROR: f64 = 1e-6;

/// The fine mesh as the coarse mesh sees it.
pub struct FineMesh<'a> {
    pub element_start: &'a [f64],
    pub element_end: &'a [f64],
    pub element_dofs: &'a [[Option<usize>; 4]],
    /// DOFs with a spring or damper: coarse nodes must keep them.
    pub special_dofs: &'a [usize],
    pub free_dofs: usize,
}

/// A fine node inside a coarse element: its two fine DOFs are the coarse
/// element's cubic and slope there.
#[derive(Debug, Clone, PartialEq)]
struct Interior {
    w: usize,
    psi: usize,
    element: usize,
    n: [f64; 4],
    dn: [f64; 4],
}

/// A coarse element: length and coarse DOFs (w₁, ψ₁, w₂, ψ₂), `None` where held.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseElement {
    pub length: f64,
    pub dofs: [Option<usize>; 4],
}

/// Coarse mesh with nodes at fine nodes, and the maps between the two.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseMesh {
    /// Fine DOF of each coarse DOF.
    fine_of: Vec<usize>,
    interior: Vec<Interior>,
    pub elements: Vec<CoarseElement>,
}

fn hermite(s: f64, len: f64) -> ([f64; 4], [f64; 4]) {
    let (s2, s3) = (s * s, s * s * s);
    (
        [
            1.0 - 3.0 * s2 + 2.0 * s3,
            len * (s - 2.0 * s2 + s3),
            3.0 * s2 - 2.0 * s3,
            len * (s3 - s2),
        ],
        [
            (-6.0 * s + 6.0 * s2) / len,
            1.0 - 4.0 * s + 3.0 * s2,
            (6.0 * s - 6.0 * s2) / len,
            3.0 * s2 - 2.0 * s,
        ],
    )
}

/// The runs of fine elements each coarse element spans: at most
/// `per_coarse` elements each, broken at every node that is not plain.
fn coarse_groups(fine: &FineMesh) -> Vec<std::ops::RangeInclusive<usize>> {
    let n = fine.element_dofs.len();
    let per_coarse = n.div_ceil(COARSE_ELEMENTS).max(1);
    // A node between fine elements e and e + 1 may be skipped only if
    // it is plain: shared, free, no spring, no gap.
    let plain = |e: usize| {
        let (left, right) = (fine.element_dofs[e], fine.element_dofs[e + 1]);
        left[2..] == right[..2]
            && left[2..]
                .iter()
                .all(|d| d.is_some_and(|d| !fine.special_dofs.contains(&d)))
            && fine.element_end[e] == fine.element_start[e + 1]
    };
    let mut groups = Vec::new();
    let mut first = 0;
    for e in 0..n {
        if e + 1 == n || e + 1 - first >= per_coarse || !plain(e) {
            groups.push(first..=e);
            first = e + 1;
        }
    }
    groups
}

impl CoarseMesh {
    /// The coarse mesh of `fine`: each group of its elements
    /// (`coarse_groups`) one coarse element.
    pub fn new(fine: &FineMesh) -> CoarseMesh {
        let groups = coarse_groups(fine);
        let mut fine_of: Vec<usize> = groups
            .iter()
            .flat_map(|g| {
                let (l, r) = (fine.element_dofs[*g.start()], fine.element_dofs[*g.end()]);
                [l[0], l[1], r[2], r[3]]
            })
            .flatten()
            .collect();
        fine_of.sort_unstable();
        fine_of.dedup();
        let mut coarse_of = vec![usize::MAX; fine.free_dofs];
        for (c, &f) in fine_of.iter().enumerate() {
            coarse_of[f] = c;
        }
        let mut elements = Vec::new();
        let mut interior = Vec::new();
        for (k, g) in groups.iter().enumerate() {
            let (a, b) = (*g.start(), *g.end());
            let x0 = fine.element_start[a];
            let length = fine.element_end[b] - x0;
            let (l, r) = (fine.element_dofs[a], fine.element_dofs[b]);
            let dofs = [l[0], l[1], r[2], r[3]].map(|d| d.map(|d| coarse_of[d]));
            elements.push(CoarseElement { length, dofs });
            for e in a..b {
                let [_, _, w, psi] = fine.element_dofs[e];
                let (n, dn) = hermite((fine.element_end[e] - x0) / length, length);
                interior.push(Interior {
                    w: w.expect("plain node"),
                    psi: psi.expect("plain node"),
                    element: k,
                    n,
                    dn,
                });
            }
        }
        CoarseMesh {
            fine_of,
            interior,
            elements,
        }
    }

    pub fn size(&self) -> usize {
        self.fine_of.len()
    }

    /// `fine += P coarse`: the coarse cubics evaluated at the fine nodes.
    fn prolong_add(&self, coarse: &[f64], fine: &mut [f64]) {
        for (&f, &c) in self.fine_of.iter().zip(coarse) {
            fine[f] += c;
        }
        for node in &self.interior {
            let dofs = &self.elements[node.element].dofs;
            let (mut w, mut psi) = (0.0, 0.0);
            for ((dof, n), dn) in dofs.iter().zip(node.n).zip(node.dn) {
                if let Some(c) = *dof {
                    w += n * coarse[c];
                    psi += dn * coarse[c];
                }
            }
            fine[node.w] += w;
            fine[node.psi] += psi;
        }
    }

    /// `coarse = Pᵀ fine`.
    fn restrict(&self, fine: &[f64], coarse: &mut [f64]) {
        for (c, &f) in coarse.iter_mut().zip(&self.fine_of) {
            *c = fine[f];
        }
        for node in &self.interior {
            let dofs = &self.elements[node.element].dofs;
            for ((dof, n), dn) in dofs.iter().zip(node.n).zip(node.dn) {
                if let Some(c) = *dof {
                    coarse[c] += n * fine[node.w] + dn * fine[node.psi];
                }
            }
        }
    }

    /// `fine += P 1`: a smooth fine field (every coarse DOF at one).
    pub fn prolong_ones(&self, fine: &mut [f64]) {
        self.prolong_add(&vec![1.0; self.size()], fine);
    }

    /// The coarse DOF of fine DOF `fine`, if it is one.
    pub fn coarse_dof(&self, fine: usize) -> Option<usize> {
        self.fine_of.binary_search(&fine).ok()
    }
}

/// S = `mass` M + `stiffness` K + `damping` × (the support dampers).
#[derive(Debug, Clone, PartialEq)]
pub struct Effective {
    pub mass_matrix: SymBand,
    pub bending: Bending,
    /// (free DOF, damper coefficient) of each support damper.
    pub dampers: Vec<(usize, f64)>,
    pub mass: f64,
    pub stiffness: f64,
    pub damping: f64,
}

impl Effective {
    /// `out = rhs − S x`.
    fn residual(&self, rhs: &[f64], x: &DVector<f64>, out: &mut DVector<f64>) {
        self.mass_matrix.mul_to(x.as_slice(), out.as_mut_slice());
        out.scale_mut(-self.mass);
        self.bending.add_times(-self.stiffness, x, out);
        for &(i, c) in &self.dampers {
            out[i] -= self.damping * c * x[i];
        }
        for (o, b) in out.iter_mut().zip(rhs) {
            *o += b;
        }
    }
}

/// The band factor of S with the coarse-mesh and fine-factor corrections.
#[derive(Debug, Clone)]
pub struct TwoLevelFactor {
    fine: BandLdlt,
    coarse: BandLdlt,
    mesh: CoarseMesh,
    operator: Effective,
    cycles: usize,
}

/// Relative difference of two solutions (largest entries).
fn relative_error(x: &DVector<f64>, reference: &DVector<f64>) -> f64 {
    (x - reference).amax() / reference.amax()
}

impl TwoLevelFactor {
    pub fn new(fine: BandLdlt, coarse: BandLdlt, mesh: CoarseMesh, operator: Effective) -> Self {
        TwoLevelFactor {
            fine,
            coarse,
            mesh,
            operator,
            cycles: 2,
        }
    }

    /// Measures the plain factor's error on a smooth field (S⁻¹ M t, t the
    /// fine field of every coarse DOF at one) against three cycles, sets
    /// the cycles per solve, and returns that error.
    pub fn calibrate(&mut self) -> f64 {
        let mut smooth = DVector::zeros(self.operator.mass_matrix.size());
        self.mesh.prolong_ones(smooth.as_mut_slice());
        let mut rhs = smooth.clone();
        self.operator
            .mass_matrix
            .mul_to(smooth.as_slice(), rhs.as_mut_slice());
        let solve = |cycles: usize| {
            let mut x = rhs.clone();
            self.solve_cycles(cycles, &mut x);
            x
        };
        let reference = solve(3);
        let one_cycle = relative_error(&solve(1), &reference);
        let plain = relative_error(&solve(0), &reference);
        self.cycles = if one_cycle <= ONE_CYCLE_ERROR { 1 } else { 2 };
        plain
    }

    /// The plain band factor, for meshes that need no correction.
    pub fn into_band(self) -> BandLdlt {
        self.fine
    }

    /// `rhs ← S⁻¹ rhs`.
    pub fn solve_mut(&self, rhs: &mut DVector<f64>) {
        self.solve_cycles(self.cycles, rhs);
    }

    /// The fine solve, then `cycles` × (coarse correction, and but for the
    /// last cycle a fine correction).
    fn solve_cycles(&self, cycles: usize, rhs: &mut DVector<f64>) {
        let b = rhs.clone();
        let x = rhs;
        self.fine.solve_mut(x);
        let mut r = DVector::zeros(x.len());
        let mut coarse = vec![0.0; self.mesh.size()];
        for cycle in 0..cycles {
            // The smooth part of the error on the coarse mesh ...
            self.operator.residual(b.as_slice(), x, &mut r);
            self.mesh.restrict(r.as_slice(), &mut coarse);
            self.coarse.solve_in_place(&mut coarse);
            r.fill(0.0);
            self.mesh.prolong_add(&coarse, r.as_mut_slice());
            *x += &r;
            if cycle + 1 == cycles {
                break;
            }
            // ... then the rough part with the fine factor.
            self.operator.residual(b.as_slice(), x, &mut r);
            self.fine.solve_mut(&mut r);
            *x += &r;
        }
    }
}
