//! Euler-Bernoulli beam on Hermite cubic elements.
//!
//! Two DOFs per node: transverse displacement w and section rotation ψ = w'.
//! Consistent mass, supports removed from the free DOF set, sparse storage so
//! that every per-step operation is linear in the number of elements.

use crate::scene::{BeamSpec, EndSupport};
use nalgebra::{DMatrix, DVector, Matrix4, SymmetricEigen};
use nalgebra_sparse::factorization::CscCholesky;
use nalgebra_sparse::{coo::CooMatrix, CscMatrix, CsrMatrix};

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
    /// Dot a row of shape values with the element's entries of a free-DOF vector.
    pub fn dot(&self, row: &[f64; 4], q: &DVector<f64>) -> f64 {
        self.dofs
            .iter()
            .zip(row)
            .filter_map(|(dof, r)| dof.map(|i| r * q[i]))
            .sum()
    }

    /// Add `scale * row` into the element's entries of a free-DOF vector.
    pub fn scatter(&self, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        for (dof, r) in self.dofs.iter().zip(row) {
            if let Some(i) = *dof {
                out[i] += scale * r;
            }
        }
    }
}

pub struct Beam {
    pub length: f64,
    pub surface_offset: f64,
    pub mass_per_length: f64,
    pub bending_stiffness: f64,
    /// Node abscissae, increasing, from 0 to `length`.
    pub node_x: Vec<f64>,
    /// Free-DOF index of each global DOF (2 per node), `None` where held.
    dof_map: Vec<Option<usize>>,
    free_dofs: usize,
    mass: CsrMatrix<f64>,
    stiffness: CsrMatrix<f64>,
    mass_factor: CscCholesky<f64>,
}

fn element_stiffness(len: f64, ei: f64) -> Matrix4<f64> {
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

fn element_mass(len: f64, mu: f64) -> Matrix4<f64> {
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

/// Split `elements` over spans in proportion to their lengths, at least one each.
fn elements_per_span(spans: &[f64], elements: usize) -> Vec<usize> {
    let total: f64 = spans.iter().sum();
    let mut counts: Vec<usize> = spans
        .iter()
        .map(|s| ((s / total) * elements as f64).floor().max(1.0) as usize)
        .collect();
    while counts.iter().sum::<usize>() < elements {
        // Give the next element to the span with the longest elements.
        let i = (0..spans.len())
            .max_by(|&a, &b| {
                (spans[a] / counts[a] as f64).total_cmp(&(spans[b] / counts[b] as f64))
            })
            .unwrap_or(0);
        counts[i] += 1;
    }
    while counts.iter().sum::<usize>() > elements {
        let i = (0..spans.len())
            .filter(|&i| counts[i] > 1)
            .min_by(|&a, &b| {
                (spans[a] / counts[a] as f64).total_cmp(&(spans[b] / counts[b] as f64))
            })
            .unwrap_or(0);
        counts[i] -= 1;
    }
    counts
}

impl Beam {
    /// Assemble the beam of a (validated) spec.
    pub fn new(spec: &BeamSpec) -> Result<Beam, String> {
        let mut breaks = vec![0.0];
        breaks.extend(spec.supports.intermediate.iter().copied());
        breaks.push(spec.length);
        let spans: Vec<f64> = breaks.windows(2).map(|w| w[1] - w[0]).collect();
        if spec.elements < spans.len() {
            return Err(format!(
                "beam.elements = {} is fewer than the {} spans between supports; \
                 each span needs at least one element",
                spec.elements,
                spans.len()
            ));
        }
        let counts = elements_per_span(&spans, spec.elements);
        let mut node_x = vec![0.0];
        let mut support_nodes = Vec::new();
        for (s, &count) in counts.iter().enumerate() {
            for k in 1..=count {
                node_x.push(breaks[s] + spans[s] * k as f64 / count as f64);
            }
            if s + 1 < spans.len() {
                support_nodes.push(node_x.len() - 1);
            }
        }
        let nodes = node_x.len();
        let mut held = vec![false; 2 * nodes];
        let mut hold_end = |node: usize, support: EndSupport| match support {
            EndSupport::Pinned => held[2 * node] = true,
            EndSupport::Clamped => {
                held[2 * node] = true;
                held[2 * node + 1] = true;
            }
            EndSupport::Free => {}
        };
        hold_end(0, spec.supports.left);
        hold_end(nodes - 1, spec.supports.right);
        for &node in &support_nodes {
            held[2 * node] = true;
        }
        let mut dof_map = vec![None; 2 * nodes];
        let mut free_dofs = 0;
        for (dof, &is_held) in held.iter().enumerate() {
            if !is_held {
                dof_map[dof] = Some(free_dofs);
                free_dofs += 1;
            }
        }
        if free_dofs == 0 {
            return Err("the supports hold every DOF of the beam".into());
        }

        let mut mass = CooMatrix::new(free_dofs, free_dofs);
        let mut stiffness = CooMatrix::new(free_dofs, free_dofs);
        for e in 0..nodes - 1 {
            let len = node_x[e + 1] - node_x[e];
            let me = element_mass(len, spec.mass_per_length);
            let ke = element_stiffness(len, spec.bending_stiffness);
            let dofs: Vec<Option<usize>> = (0..4).map(|k| dof_map[2 * e + k]).collect();
            for a in 0..4 {
                for b in 0..4 {
                    if let (Some(i), Some(j)) = (dofs[a], dofs[b]) {
                        mass.push(i, j, me[(a, b)]);
                        stiffness.push(i, j, ke[(a, b)]);
                    }
                }
            }
        }
        let mass_csc = CscMatrix::from(&mass);
        let mass_factor = CscCholesky::factor(&mass_csc)
            .map_err(|e| format!("beam mass matrix is not positive definite: {e}"))?;
        Ok(Beam {
            length: spec.length,
            surface_offset: spec.surface_offset,
            mass_per_length: spec.mass_per_length,
            bending_stiffness: spec.bending_stiffness,
            node_x,
            dof_map,
            free_dofs,
            mass: CsrMatrix::from(&mass),
            stiffness: CsrMatrix::from(&stiffness),
            mass_factor,
        })
    }

    pub fn free_dofs(&self) -> usize {
        self.free_dofs
    }

    pub fn elements(&self) -> usize {
        self.node_x.len() - 1
    }

    /// The element whose span holds `x`; abscissae beyond the ends map to the
    /// end elements (their cubics are extended past the beam).
    pub fn element_at(&self, x: f64) -> usize {
        let last = self.elements() - 1;
        // Elements are few per span and usually uniform: bisection is enough.
        match self.node_x.binary_search_by(|n| n.total_cmp(&x)) {
            Ok(i) => i.min(last),
            Err(0) => 0,
            Err(i) => (i - 1).min(last),
        }
    }

    /// Shape functions of element `element` at abscissa `x`.
    pub fn shape(&self, element: usize, x: f64) -> Shape {
        let x0 = self.node_x[element];
        let len = self.node_x[element + 1] - x0;
        let s = (x - x0) / len;
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
        let dofs = [
            self.dof_map[2 * element],
            self.dof_map[2 * element + 1],
            self.dof_map[2 * element + 2],
            self.dof_map[2 * element + 3],
        ];
        Shape {
            element,
            dofs,
            n,
            dn,
            ddn,
        }
    }

    /// Transverse deflection w at `x` (m).
    pub fn deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        let shape = self.shape(self.element_at(x), x);
        shape.dot(&shape.n, u)
    }

    /// `out = K u`.
    pub fn stiffness_times(&self, u: &DVector<f64>, out: &mut DVector<f64>) {
        nalgebra_sparse::ops::serial::spmm_csr_dense(
            0.0,
            out,
            1.0,
            nalgebra_sparse::ops::Op::NoOp(&self.stiffness),
            nalgebra_sparse::ops::Op::NoOp(u),
        );
    }

    /// Cholesky factor of M + `stiffness_weight` K, the effective matrix of
    /// implicit schemes.
    pub fn factor_mass_plus_stiffness(
        &self,
        stiffness_weight: f64,
    ) -> Result<CscCholesky<f64>, String> {
        let sum = &self.mass + &(&self.stiffness * stiffness_weight);
        CscCholesky::factor(&CscMatrix::from(&sum))
            .map_err(|e| format!("the implicit scheme's effective matrix cannot be factored: {e}"))
    }

    /// `rhs ← M⁻¹ rhs`.
    pub fn solve_mass(&self, rhs: &mut DVector<f64>) {
        self.mass_factor.solve_mut(rhs);
    }

    /// Nodal accelerations `M⁻¹ (load − K u)`, using `out` as scratch.
    pub fn accelerations(&self, u: &DVector<f64>, load: &DVector<f64>, out: &mut DVector<f64>) {
        self.stiffness_times(u, out);
        out.zip_apply(load, |a, f| *a = f - *a);
        self.solve_mass(out);
    }

    fn quadratic_form(matrix: &CsrMatrix<f64>, q: &DVector<f64>) -> f64 {
        let mut sum = 0.0;
        for (i, row) in matrix.row_iter().enumerate() {
            let mut r = 0.0;
            for (&j, &value) in row.col_indices().iter().zip(row.values()) {
                r += value * q[j];
            }
            sum += q[i] * r;
        }
        sum
    }

    /// ½ vᵀ M v.
    pub fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        0.5 * Self::quadratic_form(&self.mass, v)
    }

    /// ½ uᵀ K u.
    pub fn strain_energy(&self, u: &DVector<f64>) -> f64 {
        0.5 * Self::quadratic_form(&self.stiffness, u)
    }

    /// Highest natural circular frequency of the assembled beam (rad/s).
    ///
    /// Exact (dense generalized eigenproblem) up to `DENSE_EIGEN_LIMIT` free
    /// DOFs; above that, the highest free-free element frequency, which bounds
    /// the assembled beam's from above (a conservative stability estimate).
    pub fn highest_frequency(&self) -> f64 {
        const DENSE_EIGEN_LIMIT: usize = 400;
        if self.free_dofs <= DENSE_EIGEN_LIMIT {
            let m = DMatrix::from(&self.mass);
            let k = DMatrix::from(&self.stiffness);
            if let Some(chol) = m.cholesky() {
                let l = chol.l();
                if let Some(l_inv) = l.try_inverse() {
                    let a = &l_inv * k * l_inv.transpose();
                    let eig = SymmetricEigen::new(0.5 * (&a + a.transpose()));
                    return eig.eigenvalues.max().max(0.0).sqrt();
                }
            }
        }
        self.max_element_frequency()
    }

    /// Highest natural circular frequency of any single free-free element,
    /// an upper bound of the assembled beam's (rad/s).
    pub fn max_element_frequency(&self) -> f64 {
        let mut highest: f64 = 0.0;
        for e in 0..self.elements() {
            let len = self.node_x[e + 1] - self.node_x[e];
            let m = element_mass(len, self.mass_per_length);
            let k = element_stiffness(len, self.bending_stiffness);
            let Some(chol) = m.cholesky() else { continue };
            let l_inv = chol.l().try_inverse().unwrap_or_else(Matrix4::zeros);
            let a = l_inv * k * l_inv.transpose();
            let eig = SymmetricEigen::new(0.5 * (a + a.transpose()));
            highest = highest.max(eig.eigenvalues.max().max(0.0).sqrt());
        }
        highest
    }

    /// Shortest element length (m).
    pub fn min_element_length(&self) -> f64 {
        self.node_x
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SupportsSpec;

    fn paper_beam(elements: usize) -> BeamSpec {
        BeamSpec {
            length: 24.0,
            mass_per_length: 1250.0,
            bending_stiffness: 1e9,
            surface_offset: 0.6,
            elements,
            supports: SupportsSpec::default(),
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
        let k = nalgebra::DMatrix::from(&beam.stiffness);
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
