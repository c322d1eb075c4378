//! The full Hermite mesh behind the structure seam (`StructureOps`): every
//! free DOF is a state entry, so gathers and loads read the state directly
//! and the products, factors and energies are the band matrices' (or the
//! element-by-element bending's on fine meshes).

use nalgebra::DVector;

use super::{EffectiveFactor, HermiteBeam, Shape, VelocityFreeBand};
use crate::structure::kinds::ChosenKind;
use crate::structure::ops::StructureOps;

/// The base kind: the structure of any scene no other kind claims
/// (`Structure::of_scene`), so it is never `chosen`.
impl ChosenKind for HermiteBeam {}

impl StructureOps for HermiteBeam {
    fn mesh(&self) -> &HermiteBeam {
        self
    }

    fn into_mesh(self) -> Result<HermiteBeam, String> {
        Ok(self)
    }

    /// Entries of a state vector of the full mesh: its free DOFs.
    fn coordinates(&self) -> usize {
        self.free_dofs
    }

    /// Value on free DOF `dof` of the field a state vector `u` describes.
    fn dof_value(&self, dof: usize, u: &DVector<f64>) -> f64 {
        u[dof]
    }

    /// `out += scale` × a unit load on free DOF `dof`, in the structure's
    /// coordinates.
    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        out[dof] += scale;
    }

    fn load_coordinate(&self, dof: usize) -> Option<usize> {
        Some(dof)
    }

    /// The field of state vector `u` on the four DOFs `dofs` of an element
    /// (0 where held).
    fn gather(&self, dofs: &[Option<usize>; 4], u: &DVector<f64>) -> [f64; 4] {
        // Reads `u` directly: the foot-point search gathers at every
        // iterate, and a match per entry doubled its cost.
        let mut local = [0.0; 4];
        for (value, dof) in local.iter_mut().zip(dofs) {
            if let Some(i) = *dof {
                *value = u[i];
            }
        }
        local
    }

    /// Dot a row of `shape`'s values with the field of state vector `u`.
    fn dot(&self, shape: &Shape, row: &[f64; 4], u: &DVector<f64>) -> f64 {
        shape.dot(row, u)
    }

    /// `dot` of two rows of `shape` with the same `u`.
    fn dot_rows(
        &self,
        shape: &Shape,
        (first, second): (&[f64; 4], &[f64; 4]),
        u: &DVector<f64>,
    ) -> (f64, f64) {
        (shape.dot(first, u), shape.dot(second, u))
    }

    /// `scatter` of two loads at `shape`, `scale_1 row_1 + scale_2 row_2`.
    fn scatter_rows(
        &self,
        shape: &Shape,
        (first, scale_1): (&[f64; 4], f64),
        (second, scale_2): (&[f64; 4], f64),
        out: &mut DVector<f64>,
    ) {
        shape.scatter(first, scale_1, out);
        shape.scatter(second, scale_2, out);
    }

    /// Add the load `scale * row` at `shape` into state vector `out`.
    fn scatter(&self, shape: &Shape, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        shape.scatter(row, scale, out);
    }

    /// `out = K u`.
    fn stiffness_times(&self, u: &DVector<f64>, out: &mut DVector<f64>) {
        if self.elementwise_products {
            self.bending.times(u, out)
        } else {
            self.stiffness.mul_to(u.as_slice(), out.as_mut_slice())
        }
    }

    /// `out = M v`.
    fn mass_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        self.mass.mul_to(v.as_slice(), out.as_mut_slice())
    }

    /// The inverse of M + `damping_weight` C + `stiffness_weight` K: the
    /// band factor (with the coarse correction on fine meshes).
    fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<EffectiveFactor, String> {
        let band = self.factor_effective(damping_weight, stiffness_weight)?;
        Ok(self.accurate_factor(band, damping_weight, stiffness_weight))
    }

    /// The static deflection u with K u = `load`, through the band LDLᵀ
    /// factor of K (refused when the supports leave a rigid-body motion).
    fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        // The scene rules refuse supports that leave the beam free: what is
        // left is rounding on a fine mesh (the condition grows as n⁴).
        let factor = self.stiffness.ldlt().ok_or_else(|| {
            let n = self.elements();
            format!(
                "beam.elements = {n}: the stiffness matrix cannot be factorised in double \
                 precision (its condition number grows as elements⁴, about {:.0e} here), so \
                 solver.start = \"static\" has no static deflection; use fewer elements",
                (n as f64).powi(4)
            )
        })?;
        let mut u = load.clone();
        factor.solve_mut(&mut u);
        Ok(u)
    }

    /// `out = K u + C v`: the beam's elastic and damping forces, using
    /// `scratch` for u + β v.
    fn internal_forces(
        &self,
        u: &DVector<f64>,
        v: &DVector<f64>,
        scratch: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let c = self.damping;
        if c.is_zero() {
            self.stiffness_times(u, out);
        } else {
            // K u + C v = K (u + β v) + α M v.
            scratch.copy_from(u);
            scratch.axpy(c.stiffness, v, 1.0);
            self.stiffness_times(scratch, out);
            self.mass_times(v, scratch);
            out.axpy(c.mass, scratch, 1.0);
        }
        for spring in self.dampers() {
            out[spring.dof] += spring.damping * v[spring.dof];
        }
    }

    /// `out = C v = α M v + β K v` and the support dampers' forces.
    fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        let c = self.damping;
        if c.is_zero() {
            out.fill(0.0);
        } else {
            self.mass_times(v, out);
            out.scale_mut(c.mass);
            if c.stiffness != 0.0 {
                if self.elementwise_products {
                    self.bending.add_times(c.stiffness, v, out);
                } else {
                    (self.stiffness).mul_add_to(c.stiffness, v.as_slice(), out.as_mut_slice());
                }
            }
        }
        for spring in self.dampers() {
            out[spring.dof] += spring.damping * v[spring.dof];
        }
    }

    /// Σ c (M⁻¹)ᵢᵢ over the support dampers (1/s): at least the decay rate
    /// of any mode they damp (the explicit scheme's stability limit).
    fn damper_rate_bound(&self) -> f64 {
        self.dampers()
            .map(|s| s.damping * self.inverse_mass_diagonal(s.dof))
            .sum()
    }

    /// Power dissipated by the structural damping, vᵀ C v (W).
    fn damping_power(&self, v: &DVector<f64>) -> f64 {
        let c = self.damping;
        let supports = self.damper_power(v);
        if c.is_zero() {
            return supports;
        }
        let x = v.as_slice();
        c.mass * self.mass.quadratic_form(x)
            + c.stiffness * self.bending.quadratic_form(v)
            + supports
    }

    /// K, M's factor and α when the accelerations are
    /// `M⁻¹ (f − K u) − α v` with K u from the band: the velocity enters
    /// only after the mass solve (no stiffness-proportional damping, no
    /// support dampers), so an explicit scheme may solve two stages whose
    /// displacements are known at once (`BandLdlt::solve_residual_pair`).
    /// `None` where K u is taken element by element.
    fn velocity_free_band(&self) -> Option<VelocityFreeBand<'_>> {
        let free = !self.elementwise_products;
        let velocity_free = self.damping.stiffness == 0.0 && self.dampers().next().is_none();
        (free && velocity_free).then_some(VelocityFreeBand {
            stiffness: &self.stiffness,
            mass_factor: &self.mass_factor,
            mass_damping: self.damping.mass,
        })
    }

    /// `rhs ← M⁻¹ rhs`.
    fn solve_mass(&self, rhs: &mut DVector<f64>) {
        self.mass_factor.solve_mut(rhs);
    }

    /// Nodal accelerations `M⁻¹ (load − K u − C v)`.
    fn accelerations(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let c = self.damping;
        // M⁻¹ (f − K (u + β v)) − α v: one mass solve, no product with M;
        // K (u + β v) = K u + β K v, accumulated in `out` without scratch.
        self.stiffness_times(u, out);
        out.zip_apply(load, |a, f| *a = f - *a);
        if c.stiffness != 0.0 {
            if self.elementwise_products {
                self.bending.add_times(-c.stiffness, v, out);
            } else {
                self.stiffness
                    .mul_add_to(-c.stiffness, v.as_slice(), out.as_mut_slice());
            }
        }
        for spring in self.dampers() {
            out[spring.dof] -= spring.damping * v[spring.dof];
        }
        self.solve_mass(out);
        if c.mass != 0.0 {
            out.axpy(-c.mass, v, 1.0);
        }
    }

    /// ½ vᵀ M v.
    fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        0.5 * self.mass.quadratic_form(v.as_slice())
    }

    /// ½ uᵀ K u.
    fn strain_energy(&self, u: &DVector<f64>) -> f64 {
        0.5 * self.bending.quadratic_form(u)
    }

    /// Highest natural circular frequency of the assembled beam (rad/s),
    /// never below the true one and within about 1e-4 of it.
    ///
    /// λ_max of K x = λ M x is bracketed: below by the Rayleigh quotient of a
    /// few power iterations from the mesh's zigzag mode, above by the
    /// highest free-free element eigenvalue (the assembled spectrum never
    /// exceeds the elements', `max_element_frequency`) plus the support
    /// springs' bound. The bracket is
    /// narrowed by bisection, each trial σ tested by factoring σ M − K:
    /// every LDLᵀ pivot positive ⇔ σ M − K positive definite ⇔ σ > λ_max
    /// (Sylvester's law of inertia). The upper end is always a σ that
    /// passed (or the element bound), so the result is an upper bound of
    /// ω_max: a step limit from it is safe. Each test costs one band
    /// factorization, O(elements).
    fn highest_frequency(&self) -> f64 {
        const RELATIVE_WIDTH: f64 = 1e-4;
        // Support springs add to K: Rayleigh quotients add, and a spring k
        // on DOF i alone reaches at most k (M⁻¹)ᵢᵢ.
        let springs: f64 = self
            .springs
            .iter()
            .map(|s| s.stiffness * self.inverse_mass_diagonal(s.dof))
            .sum();
        let bound = self.max_element_frequency().powi(2) + springs + self.foundation_rate;
        let mut upper = bound * (1.0 + 1e-12);
        // f64::max drops a NaN: a failed quotient leaves the bracket at 0.
        let mut lower = self.rayleigh_lower_bound().min(upper).max(0.0);
        // Try just above the lower end first: usually the bracket closes at once.
        let first = lower * (1.0 + 0.5 * RELATIVE_WIDTH);
        if first < upper {
            if self.exceeds_spectrum(first) {
                upper = first;
            } else {
                lower = first;
            }
        }
        while upper - lower > RELATIVE_WIDTH * upper {
            let middle = 0.5 * (lower + upper);
            if self.exceeds_spectrum(middle) {
                upper = middle;
            } else {
                lower = middle;
            }
        }
        upper.sqrt()
    }
}
