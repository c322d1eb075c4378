//! The structure's products at an accepted step's end state, kept for
//! what reads that same state again: the next step's start (HHT-α's
//! C v₀ + K u₀, the energy books' start terms) and the output rows of the
//! state (the design outputs' accelerations). A product of the same
//! matrix and the same vector is the same bits, so recalling it where the
//! state's bits are the ones it was taken at is exact; any other state
//! (an event, a restart, a restored state) misses and is computed afresh.
//! The force elements' dampers' power and potential energy at the end's
//! bodies are kept the same way (`ElementSums`): the next step's books
//! start from that power, and the output row of the state reads that
//! energy.

use nalgebra::DVector;

use crate::body::BodyState;
use crate::force_element::power_and_energy;
use crate::system::System;

/// K u + C v at one state (u, v), the state's copy to recognise it by.
#[derive(Debug, Clone, Default)]
pub struct EndForces {
    displacement: DVector<f64>,
    velocity: DVector<f64>,
    /// K u + C v, as `Structure::internal_forces` gives it.
    internal: DVector<f64>,
    /// The damping forces C v alone, where asked for (`keep`).
    damping: Option<DVector<f64>>,
    /// The elastic forces K u alone, where kept with C v and the
    /// structure's strain energy is ½ u·(K u) (`energies_are_products`).
    stiffness: Option<DVector<f64>>,
    kept: bool,
    /// The force elements' sums at the end's bodies, where kept.
    elements: ElementSums,
}

/// The force elements' dampers' power and potential energy at one state
/// of the bodies (`power_and_energy`), with the state's copy and the
/// elements' plan (`ForceElements::plan_id`) to recognise it by.
#[derive(Debug, Clone, Default)]
struct ElementSums {
    bodies: Vec<BodyState>,
    plan: Option<u64>,
    power: f64,
    energy: f64,
}

impl ElementSums {
    fn keep(&mut self, system: &System, bodies: &[BodyState]) {
        let elements = &system.force_elements;
        (self.power, self.energy) = power_and_energy(elements, bodies);
        self.bodies.clear();
        self.bodies.extend_from_slice(bodies);
        self.plan = Some(elements.plan_id());
    }

    /// (power, energy) if `bodies` and the elements are the kept ones.
    fn recall(&self, system: &System, bodies: &[BodyState]) -> Option<(f64, f64)> {
        let plan = Some(system.force_elements.plan_id());
        let same = self.plan == plan && same_states(&self.bodies, bodies);
        same.then_some((self.power, self.energy))
    }
}

/// Whether the bodies' states `a` and `b` hold the same bits
/// (`same_bits_in` over each body's fields).
fn same_states(a: &[BodyState], b: &[BodyState]) -> bool {
    let fields = |s: &BodyState| {
        let (p, v) = (s.position, s.velocity);
        [p.x, p.y, v.x, v.y, s.angle, s.angular_velocity]
    };
    a.len() == b.len() && (a.iter().zip(b)).all(|(x, y)| same_bits_in(&fields(x), &fields(y)))
}

/// Whether `a` and `b` hold the same bits (on slices: nalgebra's element
/// iterators cost several times the comparison).
pub(super) fn same_bits(a: &DVector<f64>, b: &DVector<f64>) -> bool {
    same_bits_in(a.as_slice(), b.as_slice())
}

/// `same_bits` on slices (`linalg::bits::same_bits`).
pub(super) use crate::linalg::bits::same_bits as same_bits_in;

/// A built-in scene, or one of `scenes/` by its name (tests).
#[cfg(test)]
pub(super) fn scene_named(name: &str) -> crate::Scene {
    match name {
        "train-8-coaches-20m-300-rail" => {
            let text = include_str!("../../../scenes/train-8-coaches-20m-300-rail.toml");
            crate::Scene::from_toml_str(text).unwrap()
        }
        _ => crate::scene::builtin(name).unwrap(),
    }
}

impl EndForces {
    /// K u + C v (and, with `damping`, C v) at (u, v), kept; `scratch`
    /// is the products' work vector.
    pub fn keep(
        &mut self,
        system: &System,
        (u, v): (&DVector<f64>, &DVector<f64>),
        damping: bool,
        scratch: &mut DVector<f64>,
    ) {
        let n = u.len();
        for x in [
            &mut self.displacement,
            &mut self.velocity,
            &mut self.internal,
        ] {
            if x.len() != n {
                *x = DVector::zeros(n);
            }
        }
        self.displacement.copy_from(u);
        self.velocity.copy_from(v);
        let beam = &system.beam;
        let sized = |x: &mut Option<DVector<f64>>| {
            let x = x.get_or_insert_with(|| DVector::zeros(n));
            if x.len() != n {
                *x = DVector::zeros(n);
            }
        };
        // The buffers stay from step to step (the rail's 922 entries
        // were a fresh zeroed K u every step); a product writes every entry.
        match damping {
            true if beam.energies_are_products() => {
                sized(&mut self.damping);
                sized(&mut self.stiffness);
                let (k, c) = (self.stiffness.as_mut(), self.damping.as_mut());
                let (Some(k), Some(c)) = (k, c) else {
                    unreachable!()
                };
                beam.stiffness_and_damping_forces((u, v), (k, c), &mut self.internal);
            }
            true => {
                self.stiffness = None;
                sized(&mut self.damping);
                let Some(c) = self.damping.as_mut() else {
                    unreachable!()
                };
                beam.internal_and_damping_forces((u, v), c, &mut self.internal);
            }
            false => {
                (self.damping, self.stiffness) = (None, None);
                beam.internal_forces(u, v, scratch, &mut self.internal);
            }
        }
        self.kept = true;
    }

    /// ½ u·(K u) at (u, v) from the kept K u, where kept: the bits of
    /// `strain_energy` where the structure's energies are its products
    /// (the same product, the same dot).
    pub fn strain_energy_at(&self, (u, v): (&DVector<f64>, &DVector<f64>)) -> Option<f64> {
        let stiffness = self.stiffness.as_ref()?;
        self.recall((u, v)).map(|_| 0.5 * u.dot(stiffness))
    }

    /// Keep the force elements' power and energy at `bodies` (the end's).
    pub fn keep_element_sums(&mut self, system: &System, bodies: &[BodyState]) {
        self.elements.keep(system, bodies);
    }

    /// The force elements' dampers' power and potential energy at
    /// `bodies` where they were kept there (`keep_element_sums`): the bits
    /// of `dissipation_power` and `spring_energy`.
    pub fn element_sums_at(&self, system: &System, bodies: &[BodyState]) -> Option<(f64, f64)> {
        self.elements.recall(system, bodies)
    }

    /// Forget the kept state (the next recall misses).
    pub fn forget(&mut self) {
        self.kept = false;
    }

    /// K u + C v if (u, v) is the kept state, bit for bit.
    pub fn recall(&self, (u, v): (&DVector<f64>, &DVector<f64>)) -> Option<&DVector<f64>> {
        let same = self.kept && same_bits(&self.displacement, u) && same_bits(&self.velocity, v);
        same.then_some(&self.internal)
    }

    /// K u + C v at the kept state (whatever it is: see `recall`).
    pub(super) fn internal(&self) -> &DVector<f64> {
        &self.internal
    }

    /// C v at the kept state, where it was kept with it.
    pub fn damping(&self) -> Option<&DVector<f64>> {
        self.damping.as_ref().filter(|_| self.kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assemble::assemble;

    #[test]
    fn the_kept_forces_are_recalled_only_at_their_state_and_are_a_new_products_bits() {
        let scene = scene_named("train-8-coaches-20m-300-rail");
        let system = assemble(&scene).unwrap().system;
        let n = system.beam.coordinates();
        let u = DVector::from_fn(n, |i, _| 1e-3 * libm::sin(0.37 * i as f64));
        let v = DVector::from_fn(n, |i, _| 2e-2 * libm::cos(0.11 * i as f64));
        let mut scratch = DVector::zeros(n);
        let mut expected = DVector::zeros(n);
        system
            .beam
            .internal_forces(&u, &v, &mut scratch, &mut expected);
        let mut memo = EndForces::default();
        assert!(memo.recall((&u, &v)).is_none());
        for damping in [false, true] {
            memo.keep(&system, (&u, &v), damping, &mut scratch);
            let recalled = memo.recall((&u, &v)).unwrap();
            assert!(same_bits(recalled, &expected));
            assert_eq!(memo.damping().is_some(), damping);
        }
        // C v alone: the internal forces at u = 0.
        let mut c_v = DVector::zeros(n);
        let zero = DVector::zeros(n);
        system
            .beam
            .internal_forces(&zero, &v, &mut scratch, &mut c_v);
        let kept = memo.damping().unwrap();
        assert!((kept - &c_v).norm() <= 1e-12 * c_v.norm() && c_v.norm() > 0.0);
        let mut moved = v.clone();
        moved[n / 2] = f64::from_bits(moved[n / 2].to_bits() + 1); // one ulp
        assert!(memo.recall((&u, &moved)).is_none());
        let mut negative_zero = u.clone();
        negative_zero[0] = -0.0;
        assert!(
            memo.recall((&negative_zero, &v)).is_none(),
            "u[0] = +0.0 kept"
        );
        memo.forget();
        assert!(memo.recall((&u, &v)).is_none());
    }

    #[test]
    fn the_kept_element_sums_are_recalled_only_at_their_bodies_and_plan() {
        use crate::force_element::{dissipation_power, spring_energy};
        let scene = scene_named("train-8-coaches-3x25-300");
        let mut system = assemble(&scene).unwrap().system;
        let start = crate::Simulation::new(&scene).unwrap().state();
        let mut bodies = start.dynamic.bodies;
        for (i, b) in bodies.iter_mut().enumerate() {
            b.angle += 1e-4 * libm::sin(i as f64);
            b.velocity.y += 0.01 * libm::cos(i as f64);
            b.angular_velocity -= 2e-3 * i as f64;
        }
        let elements = &system.force_elements;
        let expected = (
            dissipation_power(elements, &bodies),
            spring_energy(elements, &bodies),
        );
        assert!(expected.0 > 0.0 && expected.1 != 0.0);
        let mut memo = EndForces::default();
        assert!(memo.element_sums_at(&system, &bodies).is_none());
        memo.keep_element_sums(&system, &bodies);
        let kept = memo.element_sums_at(&system, &bodies).unwrap();
        assert_eq!(
            (kept.0.to_bits(), kept.1.to_bits()),
            (expected.0.to_bits(), expected.1.to_bits())
        );
        let mut moved = bodies.clone();
        moved[5].angular_velocity = f64::from_bits(moved[5].angular_velocity.to_bits() + 1);
        assert!(memo.element_sums_at(&system, &moved).is_none(), "one ulp");
        assert!(
            memo.element_sums_at(&system, &bodies[1..]).is_none(),
            "one body fewer"
        );
        // The elements changed under the kept sums: a miss.
        system
            .force_elements
            .update(|elements| elements[0].stiffness *= 2.0);
        assert!(
            memo.element_sums_at(&system, &bodies).is_none(),
            "another plan"
        );
    }

    #[test]
    fn the_kept_strain_energy_is_strain_energys_bits_on_the_rail_only() {
        for (name, products) in [
            ("train-8-coaches-20m-300-rail", true),
            ("train-8-coaches-20m-300-hertz", false),
        ] {
            let system = assemble(&scene_named(name)).unwrap().system;
            let n = system.beam.coordinates();
            let u = DVector::from_fn(n, |i, _| 1e-3 * libm::sin(0.37 * i as f64));
            let v = DVector::from_fn(n, |i, _| 2e-2 * libm::cos(0.11 * i as f64));
            let (mut scratch, mut expected) = (DVector::zeros(n), DVector::zeros(n));
            system
                .beam
                .internal_forces(&u, &v, &mut scratch, &mut expected);
            let mut memo = EndForces::default();
            memo.keep(&system, (&u, &v), true, &mut scratch);
            assert!(
                same_bits(memo.recall((&u, &v)).unwrap(), &expected),
                "{name}"
            );
            let strain = system.beam.strain_energy(&u);
            let kept = memo.strain_energy_at((&u, &v));
            assert_eq!(
                kept.map(f64::to_bits),
                products.then_some(strain.to_bits()),
                "{name}"
            );
            assert!(strain > 0.0);
            // Another state kept over it (K u's buffer reused): its
            // entries the new state's, none left of the first.
            let other = -0.5 * &u;
            memo.keep(&system, (&other, &v), true, &mut scratch);
            assert_eq!(
                memo.strain_energy_at((&other, &v)).map(f64::to_bits),
                products.then_some(system.beam.strain_energy(&other).to_bits()),
                "{name}"
            );
            memo.keep(&system, (&u, &v), true, &mut scratch);
            let mut moved = u.clone();
            moved[0] += 1e-6;
            assert!(memo.strain_energy_at((&moved, &v)).is_none());
            memo.keep(&system, (&u, &v), false, &mut scratch);
            assert!(
                memo.strain_energy_at((&u, &v)).is_none(),
                "{name}: without C v"
            );
        }
    }
}
