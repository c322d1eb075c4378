//! The sweeps over a system's force elements (their loads on the bodies,
//! their dampers' power, their potential energy), from a plan made once
//! per system: each element's bodies, attachment points and constants laid
//! out flat, and which bodies' rotations a sweep needs, so that a sweep
//! takes each rotation once and then runs a tight loop over the elements.
//!
//! Every sweep gives the bits of the elements' general formulas
//! (`ForceElement::forces`, `ForceElement::potential_energy`): the same
//! floating-point operations in the same order, with the arithmetic of
//! each element's one direction only (see `Link::separation`).

use std::ops::Deref;

use nalgebra::{Vector2, Vector3};

use crate::body::{is_centre, rotated, BodyState};
use crate::force_element::{Direction, ForceElement};

/// How many bodies' rotations one block of the plan keeps: a vehicle's
/// elements turn with at most its car body and bogies (three for a bogie
/// vehicle), so a block covers several vehicles, and its table of
/// rotations stays on the stack.
const BLOCK_TURNS: usize = 16;

/// A point at its body's centre: no rotation (`Link::turns`).
const CENTRE: usize = usize::MAX;

/// The system's force elements, with the plan their sweeps follow. Read
/// as a slice of elements; changed only through `update` and `extend`,
/// which make the plan again.
#[derive(Debug, Clone, Default)]
pub struct ForceElements {
    elements: Vec<ForceElement>,
    blocks: Vec<Block>,
}

/// Consecutive elements whose off-centre attachment points turn with at
/// most `BLOCK_TURNS` bodies.
#[derive(Debug, Clone, Default)]
struct Block {
    /// The bodies whose rotations the block's elements use, each once.
    turning: Vec<usize>,
    links: Vec<Link>,
}

/// One element as a sweep reads it.
#[derive(Debug, Clone, Copy)]
struct Link {
    /// Bodies a and b.
    ends: [usize; 2],
    /// Per end: its body's slot in the block's rotations, or `CENTRE`.
    turns: [usize; 2],
    /// The attachment points in body coordinates.
    points: [Vector2<f64>; 2],
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
        ForceElements { elements, blocks }
    }
}

impl ForceElements {
    /// Change the elements with `change`, then make the plan again.
    pub fn update(&mut self, change: impl FnOnce(&mut [ForceElement])) {
        change(&mut self.elements);
        self.blocks = plan(&self.elements);
    }

    /// Append `more`, then make the plan again.
    pub fn extend(&mut self, more: impl IntoIterator<Item = ForceElement>) {
        self.elements.extend(more);
        self.blocks = plan(&self.elements);
    }
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
        block.links.push(Link {
            ends: [e.body_a, e.body_b],
            turns,
            points: [e.point_a, e.point_b],
            vertical: e.direction == Direction::Vertical,
            stiffness: e.stiffness,
            damping: e.damping,
            preload: e.preload,
            rest: e.rest,
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
            *slot = bodies[b].angle.sin_cos();
        }
    }
}

/// The two ends' states and their attachment points' world offsets.
type Ends<'a> = ((&'a BodyState, &'a BodyState), (Vector2<f64>, Vector2<f64>));

impl Link {
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

    /// The element's generalized forces added to `loads`; returns the
    /// damper's power c δ̇².
    #[inline(always)]
    fn add_loads(&self, bodies: &[BodyState], table: &Table, loads: &mut [Vector3<f64>]) -> f64 {
        let ends = self.ends(bodies, table);
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
        loads[self.ends[0]] += on_a;
        loads[self.ends[1]] += on_b;
        self.damping * rate * rate
    }

    /// The damper's power c δ̇².
    #[inline(always)]
    fn power(&self, bodies: &[BodyState], table: &Table) -> f64 {
        let rate = self.rate(self.ends(bodies, table));
        self.damping * rate * rate
    }

    /// ½ k δ² − preload δ.
    #[inline(always)]
    fn energy(&self, bodies: &[BodyState], table: &Table) -> f64 {
        let delta = self.separation(self.ends(bodies, table)) - self.rest;
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
        for link in &block.links {
            sum += link.add_loads(bodies, &table, loads);
        }
        dissipation = sum;
    }
    dissipation
}

/// Power the dampers dissipate (W): the sum of each element's
/// `forces(..).dissipation`, in their order.
pub fn dissipation_power(elements: &ForceElements, bodies: &[BodyState]) -> f64 {
    sum_over_links(elements, bodies, Link::power)
}

/// Potential energy of all `elements` (J): the sum of each element's
/// `potential_energy`, in their order.
pub fn spring_energy(elements: &ForceElements, bodies: &[BodyState]) -> f64 {
    sum_over_links(elements, bodies, Link::energy)
}

/// The sum of `term` over every link, in the elements' order, each
/// block's rotations taken once.
fn sum_over_links(
    elements: &ForceElements,
    bodies: &[BodyState],
    term: impl Fn(&Link, &[BodyState], &Table) -> f64 + Copy,
) -> f64 {
    let mut table = [(0.0, 0.0); BLOCK_TURNS];
    let each = elements.blocks.iter().flat_map(|block| {
        block.rotations(bodies, &mut table);
        block
            .links
            .iter()
            .map(move |link| term(link, bodies, &table))
    });
    each.sum()
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
                    position: Vector2::new(2.0 * s, 0.1 * s.sin()),
                    velocity: Vector2::new(0.3, 0.2 * s.cos()),
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

    #[test]
    fn a_changed_element_changes_the_sweeps() {
        // `update` makes the plan again: the sweeps follow the change.
        let (elements, bodies) = chain(5);
        let mut planned = ForceElements::from(elements);
        planned.update(|elements| {
            elements[3].preload += 1e4;
            elements[3].stiffness *= 2.0;
        });
        planned.extend(chain(5).0.into_iter().take(1));
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
