//! The static rail-over-deck assembly (issue 24 item 1, step 2): a rail
//! continuous from the approach to the run-off, on a Winkler ground off the
//! deck and on the deck through the track's stiffness on the span, the
//! rail's and the deck's DOFs interleaved node by node so that the coupled
//! stiffness is a band of half-bandwidth 7 (`wide_band`). Static loads
//! only; `track_on_deck` adds the masses and dampers for the dynamics.

use crate::beam::{element_mass, element_stiffness};
use crate::wide_band::WideBand;
use nalgebra::Matrix4;

/// A single simply supported span [0, L] under a rail that runs on from
/// x = −`approach` to L + `run_off`; every length a whole number of
/// `element_length`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailOnDeck {
    pub deck_length: f64,
    /// Deck EI (N m²).
    pub deck_bending_stiffness: f64,
    /// Rail EI (N m²).
    pub rail_bending_stiffness: f64,
    /// Rail to deck, per metre (N/m²).
    pub track_stiffness: f64,
    /// Rail to ground on the approach and run-off, per metre (N/m²).
    pub ground_stiffness: f64,
    pub approach: f64,
    pub run_off: f64,
    pub element_length: f64,
}

/// Deflections at the nodes and the forces that hold the assembly.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    pub node_x: Vec<f64>,
    /// Rail w at every node (m, up positive).
    pub rail: Vec<f64>,
    /// Deck w at every node (0 off the deck).
    pub deck: Vec<f64>,
    /// Upward reactions of the deck's two bearings (N).
    pub reactions: [f64; 2],
    /// Upward force of the ground on the rail off the deck (N).
    pub ground_force: f64,
}

/// Free-DOF index of (rail w, rail ψ, deck w, deck ψ) at each node.
pub(super) type NodeDofs = [Option<usize>; 4];

/// The eight DOFs of element `e`: its two nodes' in turn.
pub(super) fn element_dofs(dofs: &[NodeDofs], e: usize) -> [Option<usize>; 8] {
    let (a, b) = (dofs[e], dofs[e + 1]);
    [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
}

/// Hermite cubics (w₁, ψ₁, w₂, ψ₂) at s ∈ [0, 1] of an element of length h.
pub(super) fn hermite(s: f64, h: f64) -> [f64; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [
        1.0 - 3.0 * s2 + 2.0 * s3,
        h * (s - 2.0 * s2 + s3),
        3.0 * s2 - 2.0 * s3,
        h * (s3 - s2),
    ]
}

impl RailOnDeck {
    /// The static deflections under a downward force `load` (N) on the rail
    /// at `at` (m), and the bearings' and the ground's forces.
    pub fn static_solution(&self, at: f64, load: f64) -> Result<StaticSolution, String> {
        let node_x = self.nodes()?;
        let dofs = self.dofs(&node_x);
        let free = dofs.iter().flatten().flatten().count();
        let elements = node_x.len() - 1;
        let mut stiffness = WideBand::zeros(free, 7);
        for e in 0..elements {
            let k = self.element(self.element_on_deck(&node_x, e));
            let local = element_dofs(&dofs, e);
            for (p, row) in local.iter().enumerate() {
                for (q, col) in local.iter().enumerate().take(p + 1) {
                    if let (Some(i), Some(j)) = (row, col) {
                        stiffness.add_symmetric(*i, *j, k[p][q])?;
                    }
                }
            }
        }
        let mut u = vec![0.0; free];
        let e = node_x
            .partition_point(|&x| x <= at)
            .saturating_sub(1)
            .min(elements - 1);
        let s = (at - node_x[e]) / self.element_length;
        if !(0.0..=1.0).contains(&s) {
            return Err(format!("the load at {at} m lies off the rail"));
        }
        let local = element_dofs(&dofs, e);
        for (k, n) in [0, 1, 4, 5]
            .into_iter()
            .zip(hermite(s, self.element_length))
        {
            if let Some(i) = local[k] {
                u[i] -= load * n;
            }
        }
        let factor = stiffness
            .ldlt()
            .ok_or("the rail-over-deck stiffness is not positive definite")?;
        // One step of iterative refinement: the deck's EI/h³ against the
        // ground's k h leaves the first solve's residual at ~1e-9 of the
        // load, which the bearings' balance would show.
        let rhs = u.clone();
        factor.solve_in_place(&mut u);
        let mut residual = vec![0.0; free];
        stiffness.mul_to(&u, &mut residual);
        residual.iter_mut().zip(&rhs).for_each(|(r, f)| *r = f - *r);
        factor.solve_in_place(&mut residual);
        u.iter_mut().zip(&residual).for_each(|(u, d)| *u += d);
        Ok(self.forces(node_x, &dofs, &u))
    }

    /// Whether element `e` lies on the span.
    pub(super) fn element_on_deck(&self, node_x: &[f64], e: usize) -> bool {
        let tolerance = 1e-9 * self.element_length;
        node_x[e] > -tolerance && node_x[e + 1] < self.deck_length + tolerance
    }

    /// Nodal deflections, bearing reactions (K q at the held deck DOFs)
    /// and the ground's force (−k_g ∫ w dx) of the solved `u`.
    fn forces(&self, node_x: Vec<f64>, dofs: &[NodeDofs], u: &[f64]) -> StaticSolution {
        let value = |dof: Option<usize>| dof.map_or(0.0, |i| u[i]);
        let (mut reactions, mut ground_force) = ([0.0; 2], 0.0);
        let h = self.element_length;
        for e in 0..node_x.len() - 1 {
            let local = element_dofs(dofs, e);
            let q = local.map(value);
            if !self.element_on_deck(&node_x, e) {
                let integral = [h / 2.0, h * h / 12.0, h / 2.0, -h * h / 12.0];
                let w: f64 = [0, 1, 4, 5]
                    .iter()
                    .zip(integral)
                    .map(|(&k, n)| q[k] * n)
                    .sum();
                ground_force -= self.ground_stiffness * w;
                continue;
            }
            let k = self.element(true);
            for (p, node) in [(2, e), (6, e + 1)] {
                if local[p].is_none() {
                    let force: f64 = k[p].iter().zip(&q).map(|(a, b)| a * b).sum();
                    reactions[usize::from(node_x[node] > 0.5 * self.deck_length)] += force;
                }
            }
        }
        StaticSolution {
            rail: dofs.iter().map(|d| value(d[0])).collect(),
            deck: dofs.iter().map(|d| value(d[2])).collect(),
            node_x,
            reactions,
            ground_force,
        }
    }

    /// Node abscissae, refusing lengths that are not whole elements.
    pub(super) fn nodes(&self) -> Result<Vec<f64>, String> {
        let h = self.element_length;
        let whole = |name: &str, length: f64| {
            let count = length / h;
            if h > 0.0 && (count - count.round()).abs() < 1e-9 && count >= 0.0 {
                Ok(count.round() as usize)
            } else {
                Err(format!(
                    "{name} = {length} m must be a whole number of elements of {h} m"
                ))
            }
        };
        let before = whole("approach", self.approach)?;
        let span = whole("deck_length", self.deck_length)?;
        let after = whole("run_off", self.run_off)?;
        if span == 0 {
            return Err("deck_length must hold at least one element".into());
        }
        let count = before + span + after + 1;
        Ok((0..count).map(|i| (i as f64 - before as f64) * h).collect())
    }

    /// DOFs node by node; the deck's w is held at its bearings, the deck
    /// has none off the span.
    pub(super) fn dofs(&self, node_x: &[f64]) -> Vec<NodeDofs> {
        let tolerance = 1e-9 * self.element_length;
        let on_deck = |x: f64| x > -tolerance && x < self.deck_length + tolerance;
        let at_bearing = |x: f64| x.abs() < tolerance || (x - self.deck_length).abs() < tolerance;
        let mut next = 0;
        let mut take = |present: bool| {
            present.then(|| {
                next += 1;
                next - 1
            })
        };
        node_x
            .iter()
            .map(|&x| {
                let deck = on_deck(x);
                [
                    take(true),
                    take(true),
                    take(deck && !at_bearing(x)),
                    take(deck),
                ]
            })
            .collect()
    }

    /// The element's 8×8 stiffness on (rail w, ψ at both ends, deck w, ψ at
    /// both ends) in node order: rail bending, deck bending and the track
    /// on the span, rail bending and the ground off it.
    pub(super) fn element(&self, on_deck: bool) -> [[f64; 8]; 8] {
        let h = self.element_length;
        let rail = element_stiffness(h, self.rail_bending_stiffness);
        let mut k = [[0.0; 8]; 8];
        place(&mut k, &rail, (0, 0));
        if on_deck {
            let layer = element_mass(h, self.track_stiffness);
            place(
                &mut k,
                &element_stiffness(h, self.deck_bending_stiffness),
                (2, 2),
            );
            place(&mut k, &layer, (0, 0));
            place(&mut k, &layer, (2, 2));
            place(&mut k, &(-layer), (0, 2));
            place(&mut k, &(-layer), (2, 0));
        } else {
            place(&mut k, &element_mass(h, self.ground_stiffness), (0, 0));
        }
        k
    }
}

/// Add the 4×4 element matrix `m` into the 8×8 `k` at the blocks of
/// parts (`a`, `b`): 0 the rail, 2 the deck. Local order: rail node 1,
/// deck node 1, rail node 2, deck node 2 (w, ψ each).
pub(super) fn place(k: &mut [[f64; 8]; 8], m: &Matrix4<f64>, (a, b): (usize, usize)) {
    let at = |part: usize, p: usize| 4 * (p / 2) + part + p % 2;
    for p in 0..4 {
        for q in 0..4 {
            k[at(a, p)][at(b, q)] += m[(p, q)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 m deck (EI = 3.8e10 N m²) under a UIC 60 rail on the ballasted
    /// preset's ground, 10 m of approach and run-off.
    fn bridge(track_stiffness: f64) -> RailOnDeck {
        RailOnDeck {
            deck_length: 20.0,
            deck_bending_stiffness: 3.8e10,
            rail_bending_stiffness: 6.4e6,
            track_stiffness,
            ground_stiffness: 3.3e7,
            approach: 10.0,
            run_off: 10.0,
            element_length: 0.25,
        }
    }

    #[test]
    fn the_bearings_and_the_ground_carry_the_load() {
        let load = 100e3;
        for at in [3.3, 10.0, 25.0] {
            let solution = bridge(3.3e7).static_solution(at, load).expect("solves");
            let [left, right] = solution.reactions;
            let total = left + right + solution.ground_force;
            assert!(
                (total - load).abs() < 1e-9 * load,
                "load at {at} m: {left} + {right} + ground {} = {total}",
                solution.ground_force
            );
        }
    }

    #[test]
    fn through_a_very_stiff_track_the_deck_deflects_as_the_bare_beam() {
        let (load, length, ei): (f64, f64, f64) = (100e3, 20.0, 3.8e10);
        let solution = bridge(1e12).static_solution(10.0, load).expect("solves");
        let middle = solution
            .node_x
            .iter()
            .position(|&x| (x - 10.0).abs() < 1e-9)
            .expect("node at midspan");
        let expected = load * length.powi(3) / (48.0 * ei);
        let found = -solution.deck[middle];
        println!(
            "deck midspan {found:e} vs PL³/48EI {expected:e}, ground {}",
            solution.ground_force
        );
        assert!(
            (found - expected).abs() < 5e-3 * expected,
            "{found:e} vs {expected:e}"
        );
        let [left, right] = solution.reactions;
        assert!((left + right + solution.ground_force - load).abs() < 1e-9 * load);
    }
}
