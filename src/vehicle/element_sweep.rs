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
    let mut table = [(0.0, 0.0); BLOCK_TURNS];
    let each = elements.blocks.iter().flat_map(|block| {
        block.rotations(bodies, &mut table);
        block
            .links
            .iter()
            .map(move |link| link.power(bodies, &table))
    });
    each.sum()
}

/// Potential energy of all `elements` (J): the sum of each element's
/// `potential_energy`, in their order.
pub fn spring_energy(elements: &ForceElements, bodies: &[BodyState]) -> f64 {
    let mut table = [(0.0, 0.0); BLOCK_TURNS];
    let each = elements.blocks.iter().flat_map(|block| {
        block.rotations(bodies, &mut table);
        block
            .links
            .iter()
            .map(move |link| link.energy(bodies, &table))
    });
    each.sum()
}
