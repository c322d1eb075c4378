//! The sweeps over a system's force elements (their loads on the bodies,
//! their dampers' power, their potential energy), from a plan made once
//! per system: each element's bodies, attachment points and constants laid
//! out flat, and which bodies' rotations a sweep needs, so that a sweep
//! takes each rotation once and then runs a tight loop over the elements.
//! Consecutive elements between the same two points of the same two bodies
//! (a suspension's vertical and longitudinal elements) are one joint, whose
//! ends' states and offsets a sweep takes once for both.
//!
//! Every sweep gives the bits of the elements' general formulas
//! (`ForceElement::forces`, `ForceElement::potential_energy`): the same
//! floating-point operations in the same order, with the arithmetic of
//! each element's one direction only (see `Law::separation`).

use std::ops::Deref;
use std::sync::atomic::{AtomicU64, Ordering};

use nalgebra::{Vector2, Vector3};

use crate::body::{is_centre, rotated, BodyState};
use crate::force_element::{Direction, ForceElement};

/// How many bodies' rotations one block of the plan keeps: a vehicle's
/// elements turn with at most its car body and bogies (three for a bogie
/// vehicle), so a block covers several vehicles, and its table of
/// rotations stays on the stack.
const BLOCK_TURNS: usize = 16;

/// How many elements one joint holds: a suspension's vertical and
/// longitudinal pair.
const JOINT_LAWS: usize = 2;

/// A point at its body's centre: no rotation (`Joint::turns`).
const CENTRE: usize = usize::MAX;

/// The system's force elements, with the plan their sweeps follow. Read
/// as a slice of elements; changed only through `update` and `extend`,
/// which make the plan again.
#[derive(Debug, Clone, Default)]
pub struct ForceElements {
    elements: Vec<ForceElement>,
    blocks: Vec<Block>,
    /// The plan's number, new with every plan (`plan_id`).
    plan: u64,
}

/// The last plan's number (`ForceElements::plan_id`).
static PLANS: AtomicU64 = AtomicU64::new(0);

/// Consecutive elements whose off-centre attachment points turn with at
/// most `BLOCK_TURNS` bodies.
#[derive(Debug, Clone, Default)]
struct Block {
    /// The bodies whose rotations the block's elements use, each once.
    turning: Vec<usize>,
    joints: Vec<Joint>,
}

/// Consecutive elements (up to `JOINT_LAWS`) between the same points of
/// the same bodies, as a sweep reads them.
#[derive(Debug, Clone, Copy)]
struct Joint {
    /// Bodies a and b.
    ends: [usize; 2],
    /// Per end: its body's slot in the block's rotations, or `CENTRE`.
    turns: [usize; 2],
    /// The attachment points in body coordinates.
    points: [Vector2<f64>; 2],
    /// The elements' own constants, in their order: the first, and the
    /// second where `pair`.
    laws: [Law; JOINT_LAWS],
    pair: bool,
}

/// One element's direction and constants.
#[derive(Debug, Clone, Copy, Default)]
struct Law {
    vertical: bool,
    stiffness: f64,
    damping: f64,
    preload: f64,
    rest: f64,
}

/// The sines and cosines of a block's turning bodies, in its slots.
type Table = [(f64, f64); BLOCK_TURNS];

impl Deref for ForceElements {
    type Target = [ForceElement];
    fn deref(&self) -> &[ForceElement] {
        &self.elements
    }
}

impl From<Vec<ForceElement>> for ForceElements {
    fn from(elements: Vec<ForceElement>) -> ForceElements {
        let blocks = plan(&elements);
        let plan = new_plan_id();
        ForceElements {
            elements,
            blocks,
            plan,
        }
    }
}

impl ForceElements {
    /// Change the elements with `change`, then make the plan again.
    pub fn update(&mut self, change: impl FnOnce(&mut [ForceElement])) {
        change(&mut self.elements);
        self.blocks = plan(&self.elements);
        self.plan = new_plan_id();
    }

    /// Append `more`, then make the plan again.
    pub fn extend(&mut self, more: impl IntoIterator<Item = ForceElement>) {
        self.elements.extend(more);
        self.blocks = plan(&self.elements);
        self.plan = new_plan_id();
    }

    /// A number that changes with the elements (`update`, `extend`): a
    /// sum kept at one plan is the sum of the same elements while it is
    /// unchanged (clones share it with the elements they copy).
    pub fn plan_id(&self) -> u64 {
        self.plan
    }
}

fn new_plan_id() -> u64 {
    PLANS.fetch_add(1, Ordering::Relaxed) + 1
}

/// The blocks of `elements`, in their order.
fn plan(elements: &[ForceElement]) -> Vec<Block> {
    let mut blocks: Vec<Block> = Vec::new();
    for e in elements {
        let ends = [(e.body_a, e.point_a), (e.body_b, e.point_b)];
        let mut needs: Vec<usize> = (ends.iter())
            .filter(|(_, point)| !is_centre(point))
            .map(|&(body, _)| body)
            .collect();
        needs.dedup();
        let fits = |block: &Block| {
            let new = needs.iter().filter(|b| !block.turning.contains(b));
            block.turning.len() + new.count() <= BLOCK_TURNS
        };
        if !blocks.last().is_some_and(fits) {
            blocks.push(Block::default());
        }
        let block = blocks.last_mut().expect("a block was pushed");
        let law = Law {
            vertical: e.direction == Direction::Vertical,
            stiffness: e.stiffness,
            damping: e.damping,
            preload: e.preload,
            rest: e.rest,
        };
        if let Some(joint) = block.joints.last_mut().filter(|j| j.joins(e)) {
            (joint.laws[1], joint.pair) = (law, true);
            continue;
        }
        let turns = ends.map(|(body, point)| {
            if is_centre(&point) {
                return CENTRE;
            }
            let slot = block.turning.iter().position(|&t| t == body);
            slot.unwrap_or_else(|| {
                block.turning.push(body);
                block.turning.len() - 1
            })
        });
        let mut laws = [Law::default(); JOINT_LAWS];
        laws[0] = law;
        block.joints.push(Joint {
            ends: [e.body_a, e.body_b],
            turns,
            points: [e.point_a, e.point_b],
            laws,
            pair: false,
        });
    }
    blocks
}

impl Block {
    /// The rotations of the block's turning bodies in `bodies`, into its
    /// first slots of `table`.
    #[inline]
    fn rotations(&self, bodies: &[BodyState], table: &mut Table) {
        for (slot, &b) in table.iter_mut().zip(&self.turning) {
            *slot = libm::sincos(bodies[b].angle);
        }
    }
}

/// The two ends' states and their attachment points' world offsets.
type Ends<'a> = ((&'a BodyState, &'a BodyState), (Vector2<f64>, Vector2<f64>));

impl Joint {
    /// Whether element `e` is one more of this joint's: the same bodies
    /// and the same points' bits (their offsets are then the same bits),
    /// and room left.
    fn joins(&self, e: &ForceElement) -> bool {
        let bits = |p: &Vector2<f64>| [p.x.to_bits(), p.y.to_bits()];
        !self.pair
            && self.ends == [e.body_a, e.body_b]
            && bits(&self.points[0]) == bits(&e.point_a)
            && bits(&self.points[1]) == bits(&e.point_b)
    }

    /// The sum of `term` over the joint's elements, in their order, onto
    /// `sum` (unrolled: a loop over one or two cost a tenth of a sweep).
    #[inline(always)]
    fn fold(&self, sum: f64, mut term: impl FnMut(&Law) -> f64) -> f64 {
        let first = sum + term(&self.laws[0]);
        match self.pair {
            true => first + term(&self.laws[1]),
            false => first,
        }
    }

    /// The ends' states in `bodies` and the offsets of their points:
    /// `BodyState::offset_of`'s bits (zero at a centre).
    #[inline(always)]
    fn ends<'a>(&self, bodies: &'a [BodyState], table: &Table) -> Ends<'a> {
        let offset = |end: usize| match table.get(self.turns[end]) {
            Some(&rotation) => rotated(rotation, &self.points[end]),
            None => Vector2::zeros(),
        };
        let states = (&bodies[self.ends[0]], &bodies[self.ends[1]]);
        (states, (offset(0), offset(1)))
    }

    /// Each element's generalized forces added to `loads`, in their
    /// order; returns `sum` plus each damper's power c δ̇², in their order.
    #[inline(always)]
    fn add_loads(
        &self,
        bodies: &[BodyState],
        table: &Table,
        loads: &mut [Vector3<f64>],
        sum: f64,
    ) -> f64 {
        let ends = self.ends(bodies, table);
        self.fold(sum, |law| {
            let (on_a, on_b, power) = law.forces(ends);
            loads[self.ends[0]] += on_a;
            loads[self.ends[1]] += on_b;
            power
        })
    }
}

impl Law {
    /// (p_a − p_b)·d with the arithmetic of the element's one direction:
    /// the general dot product with d multiplies the other component by 0
    /// and adds the zero, which the compiler may not drop (it would change
    /// a NaN or the sign of a zero). The same bits for finite states but
    /// the sign of a zero separation, which no sweep's result keeps (an
    /// elongation ±0 − δ₀, a force, a power c δ̇², an energy ½ k δ² −
    /// preload δ are each the same bits for either zero).
    #[inline(always)]
    fn separation(&self, ((a, b), (ra, rb)): Ends) -> f64 {
        if self.vertical {
            (a.position.y + ra.y) - (b.position.y + rb.y)
        } else {
            (a.position.x + ra.x) - (b.position.x + rb.x)
        }
    }

    /// δ̇ = (v_a − v_b)·d of the attachment points in the element's one
    /// direction (ω × r = ω (−r_y, r_x)); see `separation`.
    #[inline(always)]
    fn rate(&self, ((a, b), (ra, rb)): Ends) -> f64 {
        if self.vertical {
            (a.velocity.y + a.angular_velocity * ra.x) - (b.velocity.y + b.angular_velocity * rb.x)
        } else {
            (a.velocity.x - a.angular_velocity * ra.y) - (b.velocity.x - b.angular_velocity * rb.y)
        }
    }

    /// The element's generalized forces on bodies a and b, and the
    /// damper's power c δ̇².
    #[inline(always)]
    fn forces(&self, ends: Ends) -> (Vector3<f64>, Vector3<f64>, f64) {
        let (ra, rb) = ends.1;
        let elongation = self.separation(ends) - self.rest;
        let rate = self.rate(ends);
        let magnitude = self.preload - self.stiffness * elongation - self.damping * rate;
        // The torque of f d about the centre: r × f d.
        let (on_a, on_b) = if self.vertical {
            (
                Vector3::new(0.0, magnitude, ra.x * magnitude),
                Vector3::new(0.0, -magnitude, -(rb.x * magnitude)),
            )
        } else {
            (
                Vector3::new(magnitude, 0.0, -(ra.y * magnitude)),
                Vector3::new(-magnitude, 0.0, rb.y * magnitude),
            )
        };
        (on_a, on_b, self.damping * rate * rate)
    }

    /// The damper's power c δ̇².
    #[inline(always)]
    fn power(&self, ends: Ends) -> f64 {
        let rate = self.rate(ends);
        self.damping * rate * rate
    }

    /// ½ k δ² − preload δ.
    #[inline(always)]
    fn energy(&self, ends: Ends) -> f64 {
        let delta = self.separation(ends) - self.rest;
        0.5 * self.stiffness * delta * delta - self.preload * delta
    }
}

/// Add every element's forces to `loads` (one generalized force per body)
/// and return the power the dampers dissipate (the sum from zero in the
/// elements' order).
pub fn add_element_forces(
    elements: &ForceElements,
    bodies: &[BodyState],
    loads: &mut [Vector3<f64>],
) -> f64 {
    if elements.blocks.is_empty() {
        return 0.0; // the empty sum's bits, without the sweep's set-up
    }
    // Both slices cut to one length: an element's index check on `bodies`
    // then also covers `loads` (a tenth of the loop's instructions).
    let n = bodies.len().min(loads.len());
    let (bodies, loads) = (&bodies[..n], &mut loads[..n]);
    let (mut dissipation, mut table) = (0.0, [(0.0, 0.0); BLOCK_TURNS]);
    for block in &elements.blocks {
        block.rotations(bodies, &mut table);
        // The running sum in a local: kept in a register through the loop.
        let mut sum = dissipation;
        for joint in &block.joints {
            sum = joint.add_loads(bodies, &table, loads, sum);
        }
        dissipation = sum;
    }
    dissipation
}

/// Power the dampers dissipate (W): the sum of each element's
/// `forces(..).dissipation`, in their order.
pub fn dissipation_power(elements: &ForceElements, bodies: &[BodyState]) -> f64 {
    sum_over_laws(elements, bodies, Law::power)
}

/// Potential energy of all `elements` (J): the sum of each element's
/// `potential_energy`, in their order.
pub fn spring_energy(elements: &ForceElements, bodies: &[BodyState]) -> f64 {
    sum_over_laws(elements, bodies, Law::energy)
}

/// `dissipation_power` and `spring_energy` at once, their bits: each
/// block's rotations and each joint's ends taken once for both.
pub fn power_and_energy(elements: &ForceElements, bodies: &[BodyState]) -> (f64, f64) {
    let (mut power, mut energy) = (-0.0, -0.0);
    let mut table = [(0.0, 0.0); BLOCK_TURNS];
    for block in &elements.blocks {
        block.rotations(bodies, &mut table);
        let (mut p, mut e) = (power, energy);
        for joint in &block.joints {
            let ends = joint.ends(bodies, &table);
            p = joint.fold(p, |law| law.power(ends));
            e = joint.fold(e, |law| law.energy(ends));
        }
        (power, energy) = (p, e);
    }
    (power, energy)
}

/// The sum of `term` over every element, in their order, each block's
/// rotations and each joint's ends taken once: `Iterator::sum`'s bits (it
/// starts from −0.0, which an empty plan returns).
fn sum_over_laws(
    elements: &ForceElements,
    bodies: &[BodyState],
    term: impl Fn(&Law, Ends) -> f64 + Copy,
) -> f64 {
    let (mut sum, mut table) = (-0.0, [(0.0, 0.0); BLOCK_TURNS]);
    for block in &elements.blocks {
        block.rotations(bodies, &mut table);
        let mut running = sum;
        for joint in &block.joints {
            let ends = joint.ends(bodies, &table);
            running = joint.fold(running, |law| term(law, ends));
        }
        sum = running;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of `n` turned bodies, each joined to the next by a vertical
    /// element off both centres, and by a longitudinal one to the
    /// centre of the last: more turning bodies than a block holds.
    fn chain(n: usize) -> (Vec<ForceElement>, Vec<BodyState>) {
        let bodies: Vec<BodyState> = (0..n)
            .map(|i| {
                let s = i as f64;
                BodyState {
                    position: Vector2::new(2.0 * s, 0.1 * libm::sin(s)),
                    velocity: Vector2::new(0.3, 0.2 * libm::cos(s)),
                    angle: 0.01 * s - 0.1,
                    angular_velocity: 0.05 * (s - 3.0),
                }
            })
            .collect();
        let mut elements = Vec::new();
        for i in 0..n - 1 {
            for (direction, point_b) in [
                (Direction::Vertical, Vector2::new(-0.8, 0.2)),
                (Direction::Longitudinal, Vector2::zeros()),
            ] {
                let s = i as f64;
                let mut e = ForceElement {
                    name: format!("e{i}"),
                    body_a: i,
                    point_a: Vector2::new(0.9, -0.1 * s),
                    body_b: if point_b.x == 0.0 { n - 1 } else { i + 1 },
                    point_b,
                    direction,
                    stiffness: 1e5 * (1.0 + s),
                    damping: 2e3,
                    preload: 3e3 * s,
                    rest: 0.0,
                };
                e.rest = e.separation(&bodies[e.body_a], &bodies[e.body_b]) - 1e-3 * s;
                elements.push(e);
            }
        }
        (elements, bodies)
    }

    /// The loads, power and energy of the elements' general formulas.
    fn general(elements: &[ForceElement], bodies: &[BodyState]) -> (Vec<Vector3<f64>>, f64, f64) {
        let mut loads = vec![Vector3::zeros(); bodies.len()];
        let mut power = 0.0;
        for e in elements {
            let f = e.forces(bodies);
            loads[e.body_a] += f.on_a;
            loads[e.body_b] += f.on_b;
            power += f.dissipation;
        }
        let dissipation: f64 = elements.iter().map(|e| e.forces(bodies).dissipation).sum();
        assert_eq!(dissipation.to_bits(), power.to_bits());
        let energy = elements.iter().map(|e| e.potential_energy(bodies)).sum();
        (loads, power, energy)
    }

    fn bits(loads: &[Vector3<f64>]) -> Vec<[u64; 3]> {
        loads
            .iter()
            .map(|l| [l.x, l.y, l.z].map(f64::to_bits))
            .collect()
    }

    #[test]
    fn sweeps_over_several_blocks_give_the_general_formulas_bits() {
        let (elements, bodies) = chain(40);
        let planned = ForceElements::from(elements.clone());
        assert!(planned.blocks.len() >= 3, "{} blocks", planned.blocks.len());
        let (loads, power, energy) = general(&elements, &bodies);
        let mut swept = vec![Vector3::zeros(); bodies.len()];
        let swept_power = add_element_forces(&planned, &bodies, &mut swept);
        assert_eq!(bits(&swept), bits(&loads));
        assert_eq!(swept_power.to_bits(), power.to_bits());
        let alone = dissipation_power(&planned, &bodies);
        assert_eq!(alone.to_bits(), power.to_bits());
        let swept_energy = spring_energy(&planned, &bodies);
        assert_eq!(swept_energy.to_bits(), energy.to_bits());
        assert!(power > 0.0 && energy != 0.0 && loads.iter().all(|l| l.y != 0.0));
    }

    /// `chain(n)`'s bodies with suspensions: between each body and the
    /// next, a vertical and a longitudinal element between the same
    /// points (one joint), then a vertical one alone, off-centre on a and
    /// at b's centre; three elements (two joints) per link of the chain.
    fn suspensions(n: usize) -> (Vec<ForceElement>, Vec<BodyState>) {
        let (_, bodies) = chain(n);
        let mut elements = Vec::new();
        for i in 0..n - 1 {
            let s = i as f64;
            let (a, b) = (Vector2::new(1.1, -0.2 * s), Vector2::new(-0.7, 0.3));
            for (direction, point_b) in [
                (Direction::Vertical, b),
                (Direction::Longitudinal, b),
                (Direction::Vertical, Vector2::zeros()),
            ] {
                let mut e = ForceElement {
                    name: format!("s{i}"),
                    body_a: i,
                    point_a: a,
                    body_b: i + 1,
                    point_b,
                    direction,
                    stiffness: 2e5 * (1.0 + s),
                    damping: 3e3 + s,
                    preload: -1e3 * s,
                    rest: 0.0,
                };
                e.rest = e.separation(&bodies[i], &bodies[i + 1]) + 2e-3 * s;
                elements.push(e);
            }
        }
        (elements, bodies)
    }

    #[test]
    fn joints_give_the_general_formulas_bits() {
        let (elements, bodies) = suspensions(30);
        let planned = ForceElements::from(elements.clone());
        let joints: usize = planned.blocks.iter().map(|b| b.joints.len()).sum();
        let pairs = (planned.blocks.iter().flat_map(|b| &b.joints)).filter(|j| j.pair);
        assert_eq!((joints, pairs.count()), (2 * 29, 29));
        assert!(planned.blocks.len() >= 2, "{} blocks", planned.blocks.len());
        let (loads, power, energy) = general(&elements, &bodies);
        let mut swept = vec![Vector3::zeros(); bodies.len()];
        let swept_power = add_element_forces(&planned, &bodies, &mut swept);
        assert_eq!(bits(&swept), bits(&loads));
        assert_eq!(swept_power.to_bits(), power.to_bits());
        let alone = (
            dissipation_power(&planned, &bodies),
            spring_energy(&planned, &bodies),
        );
        let both = power_and_energy(&planned, &bodies);
        assert_eq!(alone.0.to_bits(), power.to_bits());
        assert_eq!(alone.1.to_bits(), energy.to_bits());
        assert_eq!(
            (both.0.to_bits(), both.1.to_bits()),
            (power.to_bits(), energy.to_bits())
        );
        assert!(power > 0.0 && energy != 0.0 && loads.iter().all(|l| l.x != 0.0));
    }

    #[test]
    fn no_elements_sum_as_an_empty_iterator() {
        // `Iterator::sum` of no reals is −0.0; the sweeps keep its bits.
        let none = ForceElements::from(Vec::new());
        let empty: f64 = std::iter::empty::<f64>().sum();
        let (_, bodies) = chain(3);
        let sums = [
            spring_energy(&none, &bodies),
            dissipation_power(&none, &bodies),
            power_and_energy(&none, &bodies).0,
            power_and_energy(&none, &bodies).1,
        ];
        assert!(sums.iter().all(|s| s.to_bits() == empty.to_bits()));
    }

    #[test]
    fn a_changed_element_changes_the_sweeps() {
        // `update` makes the plan again: the sweeps follow the change.
        let (elements, bodies) = chain(5);
        let mut planned = ForceElements::from(elements);
        let first = planned.plan_id();
        planned.update(|elements| {
            elements[3].preload += 1e4;
            elements[3].stiffness *= 2.0;
        });
        let updated = planned.plan_id();
        planned.extend(chain(5).0.into_iter().take(1));
        assert!(updated != first && updated != planned.plan_id());
        assert_eq!(planned.clone().plan_id(), planned.plan_id());
        let (loads, power, energy) = general(&planned, &bodies);
        let mut swept = vec![Vector3::zeros(); bodies.len()];
        let swept_power = add_element_forces(&planned, &bodies, &mut swept);
        assert_eq!(bits(&swept), bits(&loads));
        assert_eq!(swept_power.to_bits(), power.to_bits());
        assert_eq!(spring_energy(&planned, &bodies).to_bits(), energy.to_bits());
        let (unchanged, ..) = general(&chain(5).0, &bodies);
        assert_ne!(bits(&unchanged), bits(&loads));
    }
}
