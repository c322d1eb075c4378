//! The structure's internal forces recovered from its state (the design
//! outputs read them): velocity and acceleration at a point, bending
//! moment and shear at a section, support reactions.
//!
//! Conventions (x along the beam, w up): deflection, velocity and
//! acceleration are positive upward. The bending moment M is positive
//! sagging (tension at the bottom fibre, M = EI w'' in the elastic
//! beam). The shear V = dM/dx is the upward force the part of the beam left
//! of the section exerts on the part right of it. A reaction is the force
//! a support exerts on the beam, positive upward; a clamp's moment is
//! positive counter-clockwise.
//!
//! Moment and shear are not EI w'' and EI w''' of the element's cubic
//! (one and two orders less accurate); they are the element's end forces
//! from its own equations, f = K_e q + M_e q̈ − r_e (with the damping
//! forces), carried from the element's left node to the section by
//! equilibrium of the piece between them: the point loads on that piece
//! and its distributed inertia. For static point loads this is exact at
//! any mesh (Hermite elements give the exact nodal displacements).

use crate::beam::{Beam, Rayleigh};
use nalgebra::DVector;
use std::borrow::Cow;
use std::cell::OnceCell;

/// A concentrated load on the beam's axis at `x`, on element `element`:
/// an upward force (N) and a counter-clockwise couple (N m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLoad {
    pub x: f64,
    pub element: usize,
    pub force: f64,
    pub couple: f64,
}

impl PointLoad {
    /// A vertical force at `x`.
    pub fn vertical(beam: &Beam, x: f64, force: f64) -> PointLoad {
        PointLoad {
            x,
            element: beam.element_at(x),
            force,
            couple: 0.0,
        }
    }
}

/// The consistent load vector of `loads` on the free DOFs.
pub fn load_vector(beam: &Beam, loads: &[PointLoad]) -> DVector<f64> {
    let mut r = DVector::zeros(beam.coordinates());
    add_loads(beam, loads, &mut r);
    r
}

/// Add the consistent load vector of `loads` to `r`.
fn add_loads(beam: &Beam, loads: &[PointLoad], r: &mut DVector<f64>) {
    for load in loads {
        let shape = beam.shape(load.element, load.x);
        beam.scatter(&shape, &shape.n, load.force, r);
        beam.scatter(&shape, &shape.dn, load.couple, r);
    }
}

/// The beam at one instant: displacement, velocity, the loads on it and
/// the acceleration they give, M⁻¹ (r − K u − C v).
#[derive(Debug, Clone)]
pub struct BeamDynamics<'a> {
    /// u, v and a: owned, or lent by the state they are read from (an
    /// output row of a long structure copied them, O(n) a row: len29).
    displacement: Cow<'a, DVector<f64>>,
    velocity: Cow<'a, DVector<f64>>,
    acceleration: Cow<'a, DVector<f64>>,
    loads: Vec<PointLoad>,
    /// u + β v and a + α v: the displacement and acceleration that carry
    /// the damping forces C v = α M v + β K v along with K u and M a
    /// (`None` when undamped: u and a themselves), computed when first
    /// asked for (deflections and accelerations do without).
    damped: OnceCell<Option<(DVector<f64>, DVector<f64>)>>,
    damping: Rayleigh,
    /// With one damping ratio for every mode, 2 ζ ωᵢ per mode: a + 2 ζ ω ⊙ v
    /// carries that damping as a + α v carries α M.
    modal_rates: Option<DVector<f64>>,
}

/// u, v and a, each owned or lent.
pub type StateVectors<'a> = (
    Cow<'a, DVector<f64>>,
    Cow<'a, DVector<f64>>,
    Cow<'a, DVector<f64>>,
);

impl BeamDynamics<'static> {
    /// The state (u, v) under `loads`, its acceleration from the equation
    /// of motion (not the integrator's: RK4 keeps none, HHT-α's balances
    /// the loads at t_{n+1+α}), with the state's internal forces K u + C v
    /// where they are known (`internal`; used where that gives the bits of
    /// computing them, `Beam::accelerations_from_internal`).
    pub fn new(
        beam: &Beam,
        (displacement, velocity): (DVector<f64>, DVector<f64>),
        loads: Vec<PointLoad>,
        internal: Option<&DVector<f64>>,
    ) -> BeamDynamics<'static> {
        let state = (Cow::Owned(displacement), Cow::Owned(velocity));
        BeamDynamics::solved(beam, state, loads, internal)
    }

    /// The state (u, v) under `loads` with an acceleration `a` that
    /// already satisfies M a + C v + K u = r (Newmark's, at a step's end).
    pub fn with_acceleration(
        beam: &Beam,
        (u, v, a): (DVector<f64>, DVector<f64>, DVector<f64>),
        loads: Vec<PointLoad>,
    ) -> BeamDynamics<'static> {
        let state = (Cow::Owned(u), Cow::Owned(v), Cow::Owned(a));
        BeamDynamics::assembled(beam, state, loads)
    }
}

impl<'a> BeamDynamics<'a> {
    /// `new` with u and v lent by their owner.
    pub fn lent(
        beam: &Beam,
        (u, v): (&'a DVector<f64>, &'a DVector<f64>),
        loads: Vec<PointLoad>,
        internal: Option<&DVector<f64>>,
    ) -> BeamDynamics<'a> {
        BeamDynamics::solved(beam, (Cow::Borrowed(u), Cow::Borrowed(v)), loads, internal)
    }

    /// `with_acceleration` with the state's vectors owned or lent.
    pub fn assembled(
        beam: &Beam,
        (displacement, velocity, acceleration): StateVectors<'a>,
        loads: Vec<PointLoad>,
    ) -> BeamDynamics<'a> {
        BeamDynamics {
            displacement,
            velocity,
            acceleration,
            loads,
            damped: OnceCell::new(),
            damping: beam.damping(),
            modal_rates: beam.modal_ratio_rates(),
        }
    }

    fn solved(
        beam: &Beam,
        (displacement, velocity): (Cow<'a, DVector<f64>>, Cow<'a, DVector<f64>>),
        loads: Vec<PointLoad>,
        internal: Option<&DVector<f64>>,
    ) -> BeamDynamics<'a> {
        let r = load_vector(beam, &loads);
        let mut acceleration = DVector::zeros(beam.coordinates());
        let recalled = internal
            .is_some_and(|forces| beam.accelerations_from_internal(&r, forces, &mut acceleration));
        if !recalled {
            beam.accelerations((&displacement, &velocity), &r, &mut acceleration);
        }
        let state = (displacement, velocity, Cow::Owned(acceleration));
        Self::assembled(beam, state, loads)
    }

    /// Replace the state and the loads, keeping the storage (one state per
    /// step without allocating).
    pub fn update(
        &mut self,
        (u, v, a): (&DVector<f64>, &DVector<f64>, &DVector<f64>),
        loads: impl IntoIterator<Item = PointLoad>,
    ) {
        self.displacement.to_mut().copy_from(u);
        self.velocity.to_mut().copy_from(v);
        self.acceleration.to_mut().copy_from(a);
        self.loads.clear();
        self.loads.extend(loads);
        // Damped copies that were asked for last time are refreshed in place.
        match self.damped.get_mut() {
            Some(Some((du, da))) => {
                let c = self.damping;
                du.copy_from(u);
                du.axpy(c.stiffness, v, 1.0);
                da.copy_from(a);
                da.axpy(c.mass, v, 1.0);
                if let Some(rates) = &self.modal_rates {
                    da.zip_zip_apply(v, rates, |a, v, c| *a += c * v);
                }
            }
            Some(None) => {}
            None => self.damped = OnceCell::new(),
        }
    }

    /// The static equilibrium K u = r under `loads`, at rest.
    pub fn static_response(
        beam: &Beam,
        loads: Vec<PointLoad>,
    ) -> Result<BeamDynamics<'static>, String> {
        let displacement = beam.static_deflection(&load_vector(beam, &loads))?;
        Ok(BeamDynamics::at_rest(beam, displacement, loads))
    }

    /// The static equilibrium under `loads` with K's factor at hand.
    pub fn static_response_with(
        beam: &Beam,
        stiffness: &crate::band::BandLdlt,
        loads: Vec<PointLoad>,
    ) -> BeamDynamics<'static> {
        let mut displacement = load_vector(beam, &loads);
        stiffness.solve_mut(&mut displacement);
        BeamDynamics::at_rest(beam, displacement, loads)
    }

    /// This state at rest under `loads`, as `static_response_with`: with a
    /// stiffness factor the displacement holds their load vector, for the
    /// caller to solve (the envelope solves thousands, four side by side:
    /// `BandLdlt::solve_each`); a modal structure's (no factor) is its
    /// modes' static response.
    pub(crate) fn set_static_loads(
        &mut self,
        beam: &Beam,
        stiffness: Option<&crate::band::BandLdlt>,
        loads: impl IntoIterator<Item = PointLoad>,
    ) -> Result<(), String> {
        self.loads.clear();
        self.loads.extend(loads);
        match stiffness {
            Some(_) => {
                let displacement = self.displacement.to_mut();
                displacement.fill(0.0);
                add_loads(beam, &self.loads, displacement);
            }
            None => {
                let deflection = beam.static_deflection(&load_vector(beam, &self.loads))?;
                self.displacement = Cow::Owned(deflection);
            }
        }
        Ok(())
    }

    pub(crate) fn at_rest(
        beam: &Beam,
        displacement: DVector<f64>,
        loads: Vec<PointLoad>,
    ) -> BeamDynamics<'static> {
        let zero = DVector::zeros(beam.coordinates());
        BeamDynamics {
            damped: OnceCell::from(None),
            damping: Rayleigh::default(),
            modal_rates: None,
            displacement: Cow::Owned(displacement),
            velocity: Cow::Owned(zero.clone()),
            acceleration: Cow::Owned(zero),
            loads,
        }
    }

    /// The loads and the displacement of a response at rest, for a caller
    /// that finds the static displacement its own way (the envelope's
    /// influence rows).
    pub(crate) fn static_parts_mut(&mut self) -> (&mut Vec<PointLoad>, &mut DVector<f64>) {
        (&mut self.loads, self.displacement.to_mut())
    }

    /// The free DOFs' displacements.
    pub fn displacement(&self) -> &DVector<f64> {
        &self.displacement
    }

    /// The free DOFs' displacements, for a caller that solves the load
    /// vectors `set_static_loads` leaves there.
    pub(crate) fn displacement_mut(&mut self) -> &mut DVector<f64> {
        self.displacement.to_mut()
    }

    /// The free DOFs' velocities.
    pub fn velocity(&self) -> &DVector<f64> {
        &self.velocity
    }

    /// The free DOFs' accelerations.
    pub fn acceleration(&self) -> &DVector<f64> {
        &self.acceleration
    }

    /// Deflection at `x` (m, up positive).
    pub fn deflection_at(&self, beam: &Beam, x: f64) -> f64 {
        beam.deflection(&self.displacement, x)
    }

    /// u + β v and a + α v (u and a when undamped).
    pub(crate) fn damped_state(&self) -> (&DVector<f64>, &DVector<f64>) {
        let damped = self.damped.get_or_init(|| {
            damped(
                (self.damping, self.modal_rates.as_ref()),
                &self.displacement,
                &self.velocity,
                &self.acceleration,
            )
        });
        match damped {
            Some((u, a)) => (u, a),
            None => (&self.displacement, &self.acceleration),
        }
    }

    /// Vertical velocity at `x` (m/s, up positive).
    pub fn velocity_at(&self, beam: &Beam, x: f64) -> f64 {
        beam.deflection(&self.velocity, x)
    }

    /// Vertical acceleration at `x` (m/s², up positive).
    pub fn acceleration_at(&self, beam: &Beam, x: f64) -> f64 {
        beam.deflection(&self.acceleration, x)
    }

    /// Element `element`'s end forces K_e ũ + M_e ã − r_e: what its nodes
    /// exert on it (w_i, ψ_i, w_j, ψ_j).
    fn end_forces(
        &self,
        beam: &Beam,
        element: usize,
        u: &DVector<f64>,
        a: &DVector<f64>,
    ) -> [f64; 4] {
        let mut f = beam.element_end_forces(element, u, a);
        self.subtract_loads(beam, element, &mut f);
        f
    }

    /// `f −= r_e`: the consistent loads of the point loads on `element`.
    fn subtract_loads(&self, beam: &Beam, element: usize, f: &mut [f64; 4]) {
        for load in self.loads.iter().filter(|l| l.element == element) {
            let shape = beam.shape(element, load.x);
            for ((f, n), dn) in f.iter_mut().zip(shape.n).zip(shape.dn) {
                *f -= load.force * n + load.couple * dn;
            }
        }
    }

    /// Shear and moment at `x` in `element` from its end forces `f` and
    /// the point loads between its left node and `x` (a load exactly on
    /// the section counts as right of it); without the piece's inertia.
    fn carried_to(&self, beam: &Beam, (element, x): (usize, f64), f: &[f64; 4]) -> (f64, f64) {
        let left = beam.node_x[element];
        // From the left node: V_i = f₀, M_i = −f₁ (the node's couple on the
        // element is −M), then the loads on the piece up to x.
        let mut shear = f[0];
        let mut moment = -f[1] + f[0] * (x - left);
        for load in self
            .loads
            .iter()
            .filter(|l| l.element == element && l.x < x)
        {
            shear += load.force;
            moment += load.force * (x - load.x) - load.couple;
        }
        (shear, moment)
    }

    /// The point loads' share of `section_forces` at `x`: what they give
    /// on the beam at rest and undeformed (the rest is linear in the
    /// damped state, which a modal structure's probes read as rows).
    pub(crate) fn section_load_share(&self, beam: &Beam, x: f64) -> SectionForces {
        let e = beam.element_at(x);
        let mut f = [0.0; 4];
        self.subtract_loads(beam, e, &mut f);
        let (shear, moment) = self.carried_to(beam, (e, x), &f);
        SectionForces { moment, shear }
    }

    /// Bending moment (N m, sagging positive) and shear (N) at `x`. A load
    /// exactly on the section counts as right of it.
    pub fn section_forces(&self, beam: &Beam, x: f64) -> SectionForces {
        let (u, a) = self.damped_state();
        let e = beam.element_at(x);
        let f = self.end_forces(beam, e, u, a);
        let left = beam.node_x[e];
        let (mut shear, mut moment) = self.carried_to(beam, (e, x), &f);
        // The piece's inertia −μ ã(ξ): ã is cubic, so three Gauss points
        // integrate ∫ ã and ∫ ã (x − ξ) exactly.
        let half = 0.5 * (x - left);
        let middle = 0.5 * (x + left);
        let mu = beam.mass_per_length;
        for (point, weight) in GAUSS_3 {
            let xi = middle + half * point;
            let shape = beam.shape(e, xi);
            let inertia = mu * beam.dot(&shape, &shape.n, a) * weight * half;
            shear -= inertia;
            moment -= inertia * (x - xi);
        }
        SectionForces { moment, shear }
    }

    /// The force (N, up positive) and, where the rotation is held or
    /// sprung, the moment (N m, counter-clockwise positive) support `node`
    /// exerts on the beam: the residual of the held DOFs plus the forces
    /// of its springs and dampers, −k u − c v.
    pub fn reaction(&self, beam: &Beam, node: usize) -> [f64; 2] {
        let mut reaction = self.held_reaction(beam, node);
        for (spring, vertical) in beam.springs_at(node) {
            let dof = spring.dof;
            let (w, rate) = (
                beam.dof_value(dof, &self.displacement),
                beam.dof_value(dof, &self.velocity),
            );
            let force = -spring.stiffness * w - spring.damping * rate;
            reaction[usize::from(!vertical)] += force;
        }
        reaction
    }

    /// The residual of the held DOFs of `node`.
    fn held_reaction(&self, beam: &Beam, node: usize) -> [f64; 2] {
        let (u, a) = self.damped_state();
        let mut reaction = [0.0; 2];
        let elements = beam.elements();
        // The element ending at the node (its DOFs 2, 3) and the one
        // starting there (0, 1).
        for (element, first) in [(node.wrapping_sub(1), 2), (node, 0)] {
            if element >= elements {
                continue;
            }
            let f = self.end_forces(beam, element, u, a);
            for (k, r) in reaction.iter_mut().enumerate() {
                if beam.is_held_in(element, first + k) {
                    *r += f[first + k];
                }
            }
        }
        reaction
    }
}

/// u + β v and a + α v for the beam's Rayleigh damping (α M + β K), and
/// a + 2 ζ ω ⊙ v for one ratio in every mode (`rates`).
fn damped(
    (c, rates): (Rayleigh, Option<&DVector<f64>>),
    u: &DVector<f64>,
    v: &DVector<f64>,
    a: &DVector<f64>,
) -> Option<(DVector<f64>, DVector<f64>)> {
    if let Some(rates) = rates {
        let (mut u, mut a) = (u.clone(), a.clone());
        u.axpy(c.stiffness, v, 1.0);
        a.axpy(c.mass, v, 1.0);
        a.zip_zip_apply(v, rates, |a, v, c| *a += c * v);
        return Some((u, a));
    }
    if c.is_zero() {
        return None;
    }
    let (mut u, mut a) = (u.clone(), a.clone());
    if c.stiffness != 0.0 {
        u.axpy(c.stiffness, v, 1.0);
    }
    if c.mass != 0.0 {
        a.axpy(c.mass, v, 1.0);
    }
    Some((u, a))
}

/// Three-point Gauss-Legendre rule on [−1, 1]: (point, weight).
const GAUSS_3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Internal forces at a section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionForces {
    /// Bending moment (N m), sagging positive.
    pub moment: f64,
    /// Shear force (N): dM/dx.
    pub shear: f64,
}

/// A support of the beam: a node whose deflection is held, or that has
/// a spring or damper to the ground.
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    /// `left` and `right` at the ends; inside, `intermediate1`,
    /// `intermediate2`, … where the deflection is held and `spring1`,
    /// `spring2`, … where it is elastic, each from left to right.
    pub name: String,
    pub node: usize,
    /// The support resists rotation (a clamp or a rotational spring or
    /// damper): it has a moment.
    pub has_moment: bool,
}

/// The beam's supports, from left to right: held nodes and elastic
/// supports (named as before when held, so old scenes keep their names).
pub fn supports(beam: &Beam) -> Vec<Support> {
    let last = beam.node_x.len() - 1;
    let (mut intermediate, mut elastic) = (0, 0);
    (0..=last)
        .filter_map(|node| {
            let springs = beam.springs_at(node);
            let held = beam.is_held(node, 0);
            if !held && springs.is_empty() {
                return None;
            }
            let name = if node == 0 {
                "left".to_string()
            } else if node == last {
                "right".to_string()
            } else if held {
                intermediate += 1;
                format!("intermediate{intermediate}")
            } else {
                elastic += 1;
                format!("spring{elastic}")
            };
            let rotational_spring = springs.iter().any(|&(_, vertical)| !vertical);
            Some(Support {
                name,
                node,
                has_moment: beam.is_held(node, 1) || rotational_spring,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests;
