//! The static rail-over-deck assembly (issue 24 item 1): a rail continuous
//! from the approach over every span and joint of the deck to the run-off,
//! on a Winkler ground off the deck (approach, run-off, gaps between
//! spans) and on the deck through the track's stiffness, the rail's and
//! the deck's DOFs interleaved node by node so that the coupled stiffness
//! is a narrow band (`wide_band`; half-bandwidth 7 on one span, 8 where two
//! spans meet at a node); on sleepers the deck's elements apart from the
//! rail's, numbered by abscissa (`sleeper_layout`). Static loads only;
//! `track_on_deck` adds the masses and dampers for the dynamics.

use crate::beam::{element_mass, element_stiffness};
use crate::mesh::Mesh;
use crate::structure::beam::BeamSpec;
use crate::structure::sleeper_layout::{deck_at, layout_apart, rail_at_sleepers};
use crate::structure::track_sleepers::Sleepers;
use crate::wide_band::WideBand;
use nalgebra::Matrix4;

/// A deck [0, L] under a rail that runs on from x = −`approach` to L +
/// `run_off`; every length a whole number of `element_length`. The deck is
/// one simply supported span unless its spans, supports and joints are
/// given as a beam (`static_solution_over`, `TrackOnDeck::assemble_over`).
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
    /// Discrete supports in place of the continuous layer and ground
    /// (`track_stiffness` and `ground_stiffness` then unused).
    pub sleepers: Option<Sleepers>,
}

/// Deflections at the nodes and the forces that hold the assembly.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    pub node_x: Vec<f64>,
    /// Rail w at every node (m, up positive).
    pub rail: Vec<f64>,
    /// Deck w at every node (0 off the deck).
    pub deck: Vec<f64>,
    /// Upward reactions of the deck's supports (N), each at its abscissa
    /// (m), from left to right (the two bearings of a joint summed).
    pub reactions: Vec<(f64, f64)>,
    /// Upward force of the ground on the rail off the deck (N).
    pub ground_force: f64,
}

/// An element's 8×8 mass, damping and stiffness (`place` order).
pub(super) type ElementMatrices = [[[f64; 8]; 8]; 3];

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
    /// at `at` (m) over one simply supported span, and the bearings' and
    /// the ground's forces.
    pub fn static_solution(&self, at: f64, load: f64) -> Result<StaticSolution, String> {
        self.static_solution_over(&self.single_span()?, at, load)
    }

    /// As `static_solution`, over the deck `deck` (spans, supports and
    /// joints as the beam's; `deck_length` and `element_length` must be
    /// its own).
    pub fn static_solution_over(
        &self,
        deck: &BeamSpec,
        at: f64,
        load: f64,
    ) -> Result<StaticSolution, String> {
        let layout = self.layout(deck)?;
        let zero = [[0.0; 8]; 8];
        let springs =
            (self.sleepers).map_or([0.0; 3], |s| [s.pad_stiffness, s.ballast_stiffness, 0.0]);
        let stiffness = layout.assemble(
            &|on_deck, h| [zero, zero, self.element(on_deck, h)],
            [0.0, 0.0, 1.0],
            springs,
        )?;
        let mut u = vec![0.0; layout.free];
        let (e, s) = layout.locate(at)?;
        let local = layout.element_dofs[e];
        for (k, n) in [0, 1, 4, 5]
            .into_iter()
            .zip(hermite(s, layout.element_length[e]))
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
        let mut residual = vec![0.0; layout.free];
        stiffness.mul_to(&u, &mut residual);
        residual.iter_mut().zip(&rhs).for_each(|(r, f)| *r = f - *r);
        factor.solve_in_place(&mut residual);
        u.iter_mut().zip(&residual).for_each(|(u, d)| *u += d);
        Ok(self.forces(&layout, &u))
    }

    /// Nodal deflections, support reactions (K q at the held deck
    /// deflections) and the ground's force (−k_g ∫ w dx) of the solved `u`.
    fn forces(&self, layout: &TrackLayout, u: &[f64]) -> StaticSolution {
        let value = |dof: Option<usize>| dof.map_or(0.0, |i| u[i]);
        let (mut reactions, mut ground_force) = (Vec::<(f64, f64)>::new(), 0.0);
        let x = &layout.node_x;
        // On sleepers the rail's elements carry nothing to the deck or
        // the ground: the sleepers do (`seat_forces`).
        let rail_only = layout.deck_apart();
        for (e, local) in layout.element_dofs.iter().enumerate() {
            let (q, h) = (local.map(value), layout.element_length[e]);
            if rail_only {
                continue;
            }
            if !layout.on_deck[e] {
                let integral = [h / 2.0, h * h / 12.0, h / 2.0, -h * h / 12.0];
                let w: f64 = [0, 1, 4, 5]
                    .iter()
                    .zip(integral)
                    .map(|(&k, n)| q[k] * n)
                    .sum();
                ground_force -= self.ground_stiffness * w;
                continue;
            }
            let k = self.element(true, h);
            for (p, node) in [(2, e), (6, e + 1)] {
                if local[p].is_none() {
                    let force: f64 = k[p].iter().zip(&q).map(|(a, b)| a * b).sum();
                    add_reaction(&mut reactions, x[node], force, 1e-9 * h);
                }
            }
        }
        if rail_only {
            ground_force += self.seat_forces(layout, u, &mut reactions);
        }
        reactions.sort_by(|a, b| a.0.total_cmp(&b.0));
        let deck_at = |n: usize| {
            if rail_only {
                return layout.deck_field(x[n], u);
            }
            let right =
                (n < layout.on_deck.len() && layout.on_deck[n]).then(|| layout.element_dofs[n][2]);
            let left = (n > 0 && layout.on_deck[n - 1]).then(|| layout.element_dofs[n - 1][6]);
            value(right.or(left).flatten())
        };
        StaticSolution {
            rail: layout.rail_dofs.iter().map(|d| u[d[0]]).collect(),
            deck: (0..x.len()).map(deck_at).collect(),
            node_x: layout.node_x.clone(),
            reactions,
            ground_force,
        }
    }

    /// On sleepers, the deck's reactions into `reactions` (K q of each
    /// deck element at its held w, and the part of each ballast force the
    /// shape functions put on a held w) and the ground's force on the
    /// sleepers off the deck (returned).
    fn seat_forces(&self, layout: &TrackLayout, u: &[f64], reactions: &mut Vec<(f64, f64)>) -> f64 {
        let value = |dof: Option<usize>| dof.map_or(0.0, |i| u[i]);
        let tolerance = 1e-9 * self.element_length;
        for element in &layout.deck {
            let q = element.dofs.map(value);
            let k = self.element(true, element.length);
            for (p, at) in [(0, element.start), (2, element.end)] {
                if element.dofs[p].is_none() {
                    let row = [2, 3, 6, 7].map(|c| k[[2, 3, 6, 7][p]][c]);
                    let force: f64 = row.iter().zip(&q).map(|(a, b)| a * b).sum();
                    add_reaction(reactions, at, force, tolerance);
                }
            }
        }
        // A sleeper's ballast pushes on the ground, or on the deck element
        // under it: on its held w a bearing's reaction, on its free DOFs
        // carried by the deck to its bearings.
        let ballast = self.sleepers.map_or(0.0, |s| s.ballast_stiffness);
        let mut ground_force = 0.0;
        for seat in &layout.seats {
            let base: f64 = layout.seat_base(seat).map(|(i, n)| n * u[i]).sum();
            let force = -ballast * (u[seat.dof] - base);
            let Some((k, shape)) = seat.deck else {
                ground_force += force;
                continue;
            };
            let element = &layout.deck[k];
            for (p, at) in [(0, element.start), (2, element.end)] {
                if element.dofs[p].is_none() && shape[p] != 0.0 {
                    add_reaction(reactions, at, shape[p] * force, tolerance);
                }
            }
        }
        ground_force
    }

    /// The deck of one simply supported span of `deck_length` in elements
    /// of `element_length`.
    pub(super) fn single_span(&self) -> Result<BeamSpec, String> {
        let elements = whole_elements("deck_length", self.deck_length, self.element_length)?;
        Ok(BeamSpec {
            length: self.deck_length,
            mass_per_length: 1.0,
            bending_stiffness: self.deck_bending_stiffness,
            surface_offset: 0.0,
            elements,
            ..BeamSpec::default()
        })
    }

    /// The rail's nodes from −approach to L + run-off and each element's
    /// DOFs, the deck's (its spans, supports and joints, from `deck`'s
    /// mesh) numbered beside the rail's node by node; refused where the
    /// deck's elements are not the rail's.
    pub(super) fn layout(&self, deck: &BeamSpec) -> Result<TrackLayout, String> {
        let h = self.element_length;
        if (deck.length - self.deck_length).abs() > 1e-9 * self.deck_length {
            return Err(format!(
                "deck_length = {} m is not the deck's length {} m",
                self.deck_length, deck.length
            ));
        }
        let mesh = Mesh::new(deck)?;
        if let Some(sleepers) = self.sleepers {
            return self.layout_on_sleepers(&sleepers, &mesh);
        }
        let (node_x, element_length) = self.rail_nodes(&mesh)?;
        let tolerance = 1e-9 * h;
        let (on_deck, deck_elements) = deck_under_rail(&node_x, &mesh, tolerance)?;
        let (numbering, rail_dofs, free) = number_dofs(&node_x, &mesh, tolerance)?;
        let element_dofs: Vec<[Option<usize>; 8]> = (0..node_x.len() - 1)
            .map(|e| {
                let deck =
                    deck_elements[e].map_or([None; 4], |d| d.map(|i| i.map(|i| numbering[i])));
                let (a, b) = (rail_dofs[e], rail_dofs[e + 1]);
                [
                    Some(a[0]),
                    Some(a[1]),
                    deck[0],
                    deck[1],
                    Some(b[0]),
                    Some(b[1]),
                    deck[2],
                    deck[3],
                ]
            })
            .collect();
        let half_bandwidth = half_bandwidth(&element_dofs);
        Ok(TrackLayout {
            node_x,
            element_length,
            element_dofs,
            on_deck,
            rail_dofs,
            seats: Vec::new(),
            deck: Vec::new(),
            free,
            half_bandwidth,
        })
    }

    /// The layout on `sleepers`: the rail meshed at the deck's nodes (the
    /// sleepers sitting there) or, with `rail_elements_per_bay`, at the
    /// sleepers; the deck on its own elements under it.
    fn layout_on_sleepers(&self, sleepers: &Sleepers, mesh: &Mesh) -> Result<TrackLayout, String> {
        let (rail, sleeper_at) = match sleepers.rail_elements_per_bay {
            Some(per_bay) => {
                let ends = (-self.approach, self.deck_length + self.run_off);
                let (x, lengths, at) = rail_at_sleepers(ends, sleepers.spacing, per_bay)?;
                ((x, lengths), at)
            }
            None => {
                let (x, lengths) = self.rail_nodes(mesh)?;
                let at = self.sleeper_nodes(&x).map_err(|rule| {
                    format!(
                        "track.on_deck.sleepers.spacing = {:?} m {rule}",
                        sleepers.spacing
                    )
                })?;
                ((x, lengths), at)
            }
        };
        // The deck's element matrices take its elements' lengths as the
        // rail's did where the rail's nodes were the deck's.
        let h = self.element_length;
        let uniform = (mesh.element_length.iter()).all(|l| (l - h).abs() <= 1e-9 * h);
        let deck_lengths: Vec<f64> = (0..mesh.element_length.len())
            .map(|k| match uniform {
                true => h,
                false => mesh.element_end[k] - mesh.element_start[k],
            })
            .collect();
        Ok(layout_apart(rail, &sleeper_at, mesh, &deck_lengths))
    }

    /// Whether a sleeper sits at each node: every `spacing` from the
    /// rail's start, each at a node of the rail (none without sleepers);
    /// else the rule, naming the abscissa without a node.
    fn sleeper_nodes(&self, node_x: &[f64]) -> Result<Vec<bool>, String> {
        let mut at = vec![false; node_x.len()];
        let Some(sleepers) = self.sleepers else {
            return Ok(at);
        };
        let (first, last) = (node_x[0], node_x[node_x.len() - 1]);
        let spacing = sleepers.spacing;
        let count = ((last - first) / spacing * (1.0 + 1e-12)).floor() as usize;
        let shortest = (node_x.windows(2).map(|w| w[1] - w[0])).fold(f64::INFINITY, f64::min);
        let tolerance = 1e-9 * shortest;
        for j in 0..=count {
            let x = first + j as f64 * spacing;
            let node = node_x.partition_point(|&n| n < x - tolerance);
            if node >= node_x.len() || (node_x[node] - x).abs() > tolerance {
                return Err(format!(
                    "puts a sleeper at x = {x:?} m, where the rail has no node: sleepers sit \
                     at the rail's nodes, so the spacing must be a whole number of the rail's \
                     elements (the shortest {shortest:?} m), or give \
                     track.on_deck.sleepers.rail_elements_per_bay to mesh the rail at the \
                     sleepers on its own"
                ));
            }
            at[node] = true;
        }
        Ok(at)
    }

    /// The rail's nodes and element lengths over the deck's `mesh`: every
    /// `element_length` from the approach's start where the deck's
    /// elements are all of that length and the approach, the run-off and
    /// the gaps whole numbers of them; else the deck's own nodes, and the
    /// approach, the run-off and each gap in equal elements of at most
    /// `element_length`.
    fn rail_nodes(&self, mesh: &Mesh) -> Result<(Vec<f64>, Vec<f64>), String> {
        let h = self.element_length;
        let uniform = (mesh.element_length.iter()).all(|l| (l - h).abs() <= 1e-9 * h);
        if let Some(nodes) = self.nodes().ok().filter(|_| uniform) {
            let lengths = vec![h; nodes.len() - 1];
            return Ok((nodes, lengths));
        }
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!("element_length = {h} m must be finite and > 0"));
        }
        // Up to `to` in equal elements of at most h, `from` already placed.
        let fill = |x: &mut Vec<f64>, from: f64, to: f64| {
            let count = ((to - from) / h - 1e-9).ceil().max(1.0) as usize;
            x.extend((1..=count).map(|i| from + (to - from) * i as f64 / count as f64));
        };
        let mut x = vec![-self.approach];
        for (&start, &end) in mesh.element_start.iter().zip(&mesh.element_end) {
            let last = x[x.len() - 1];
            if start - last > 1e-9 * h {
                fill(&mut x, last, start);
            }
            x.push(end);
        }
        if self.run_off > 0.0 {
            fill(&mut x, self.deck_length, self.deck_length + self.run_off);
        }
        let lengths = x.windows(2).map(|w| w[1] - w[0]).collect();
        Ok((x, lengths))
    }

    /// Whether the sleepers of `sleepers` meet a node of the rail over
    /// `deck` at every spacing: the rule and the abscissa where one does
    /// not.
    pub fn sleeper_problem(&self, deck: &BeamSpec) -> Option<String> {
        let mesh = Mesh::new(deck).ok()?;
        let (node_x, _) = self.rail_nodes(&mesh).ok()?;
        self.sleeper_nodes(&node_x).err()
    }

    /// Node abscissae, refusing lengths that are not whole elements.
    pub(super) fn nodes(&self) -> Result<Vec<f64>, String> {
        let h = self.element_length;
        let before = whole_elements("approach", self.approach, h)?;
        let span = whole_elements("deck_length", self.deck_length, h)?;
        let after = whole_elements("run_off", self.run_off, h)?;
        if span == 0 {
            return Err("deck_length must hold at least one element".into());
        }
        let count = before + span + after + 1;
        Ok((0..count).map(|i| (i as f64 - before as f64) * h).collect())
    }

    /// The element's 8×8 stiffness on (rail w, ψ at both ends, deck w, ψ at
    /// both ends) in node order: rail bending, deck bending and the track
    /// on the span, rail bending and the ground off it.
    pub(super) fn element(&self, on_deck: bool, h: f64) -> [[f64; 8]; 8] {
        let rail = element_stiffness(h, self.rail_bending_stiffness);
        let mut k = [[0.0; 8]; 8];
        place(&mut k, &rail, (0, 0));
        // On sleepers the rail rests on them only (`TrackLayout::add_seats`).
        let (track, ground) = match self.sleepers {
            Some(_) => (0.0, 0.0),
            None => (self.track_stiffness, self.ground_stiffness),
        };
        if on_deck {
            let layer = element_mass(h, track);
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
            place(&mut k, &element_mass(h, ground), (0, 0));
        }
        k
    }
}

/// Add `force` to the reaction at `x` (a new one where none is within
/// `tolerance`).
fn add_reaction(reactions: &mut Vec<(f64, f64)>, x: f64, force: f64, tolerance: f64) {
    match reactions.iter_mut().find(|r| (r.0 - x).abs() < tolerance) {
        Some(r) => r.1 += force,
        None => reactions.push((x, force)),
    }
}

/// The count of elements of `h` in `length`, refused unless whole.
fn whole_elements(name: &str, length: f64, h: f64) -> Result<usize, String> {
    let count = length / h;
    if h > 0.0 && (count - count.round()).abs() < 1e-9 * count.max(1.0) && count >= 0.0 {
        Ok(count.round() as usize)
    } else {
        Err(format!(
            "{name} = {length} m must be a whole number of elements of {h} m"
        ))
    }
}

/// Per rail element, whether it lies on the deck, and the deck element's
/// DOFs (in the deck mesh's numbering) under it.
type DeckUnderRail = (Vec<bool>, Vec<Option<[Option<usize>; 4]>>);

/// Which rail elements lie on the deck and the deck element's DOFs (in
/// the deck mesh's numbering) under each; refused where a deck element is
/// not one of the rail's.
fn deck_under_rail(node_x: &[f64], mesh: &Mesh, tolerance: f64) -> Result<DeckUnderRail, String> {
    let mut on_deck = vec![false; node_x.len() - 1];
    let mut deck_elements = vec![None; node_x.len() - 1];
    for (k, (&start, &end)) in (mesh.element_start.iter().zip(&mesh.element_end)).enumerate() {
        let e = node_x.partition_point(|&x| x < start - tolerance);
        let aligned = e + 1 < node_x.len()
            && (node_x[e] - start).abs() < tolerance
            && (node_x[e + 1] - end).abs() < tolerance;
        if !aligned {
            return Err(format!(
                "the deck's element from x = {start} m to {end} m is not one of the \
                 rail's elements"
            ));
        }
        on_deck[e] = true;
        deck_elements[e] = Some(mesh.element_dofs[k]);
    }
    Ok((on_deck, deck_elements))
}

/// The widest reach of any element's DOFs: the assembly's half-bandwidth.
fn half_bandwidth(element_dofs: &[[Option<usize>; 8]]) -> usize {
    element_dofs
        .iter()
        .map(|local| {
            let present = local.iter().flatten();
            present.clone().max().unwrap_or(&0) - present.min().unwrap_or(&0)
        })
        .max()
        .unwrap_or(0)
}

/// The rail's nodes, each element's eight DOFs (`place` order; `None`
/// where held or off the deck) and the band they span. On sleepers the
/// deck's elements are apart from the rail's (`deck`; the rail elements'
/// deck DOFs all `None`); on a continuous layer each rail element over
/// the deck holds the deck element under it (`deck` empty).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TrackLayout {
    /// Node abscissae from −approach to L + run-off (m).
    pub node_x: Vec<f64>,
    /// Each element's length (m).
    pub element_length: Vec<f64>,
    pub element_dofs: Vec<[Option<usize>; 8]>,
    /// Whether each element lies on a span of the deck (else on the ground).
    pub on_deck: Vec<bool>,
    /// The rail's (w, ψ) at each node.
    pub rail_dofs: Vec<[usize; 2]>,
    /// The sleepers, from the rail's start (none on a continuous layer).
    pub seats: Vec<Seat>,
    /// The deck's elements on their own (on sleepers only).
    pub deck: Vec<DeckElement>,
    pub free: usize,
    pub half_bandwidth: usize,
}

/// A deck element on its own: its ends, the length its matrices take and
/// its (w₁, ψ₁, w₂, ψ₂) in the assembly (`None` where held).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct DeckElement {
    pub start: f64,
    pub end: f64,
    pub length: f64,
    pub dofs: [Option<usize>; 4],
}

/// A sleeper: its node, its DOF, the rail's w above it and the deck
/// element under it with the element's Hermite shape values at the
/// sleeper (`None` on the ground).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Seat {
    pub node: usize,
    pub dof: usize,
    /// The rail's w at the sleeper's node.
    pub rail: usize,
    pub deck: Option<(usize, [f64; 4])>,
}

impl TrackLayout {
    /// Whether the deck's elements are apart from the rail's (on sleepers).
    pub fn deck_apart(&self) -> bool {
        !self.deck.is_empty()
    }

    /// The free deck DOFs the sleeper `seat` rests on, each with its shape
    /// value (exact zeros left out: a sleeper over a deck node loads that
    /// node's w alone).
    pub fn seat_base<'a>(&'a self, seat: &Seat) -> impl Iterator<Item = (usize, f64)> + 'a {
        let (dofs, shape) = match seat.deck {
            Some((k, shape)) => (self.deck[k].dofs, shape),
            None => ([None; 4], [0.0; 4]),
        };
        (dofs.into_iter().zip(shape))
            .filter_map(|(dof, n)| dof.filter(|_| n != 0.0).map(|i| (i, n)))
    }

    /// Add every sleeper's `[pad, ballast, mass]` (stiffnesses, dampers or
    /// masses: one of the three matrices, or their combination) into
    /// `band`: the pad between the rail and the sleeper, the ballast
    /// between the sleeper and the deck at the sleeper's abscissa
    /// (through the deck element's shape values N: N Nᵀ on the deck, −N
    /// to the sleeper) or the ground, the mass on the sleeper.
    pub fn add_seats(
        &self,
        band: &mut WideBand,
        [pad, ballast, mass]: [f64; 3],
    ) -> Result<(), String> {
        for seat in &self.seats {
            band.add_symmetric(seat.rail, seat.rail, pad)?;
            band.add_symmetric(seat.dof, seat.dof, pad + ballast + mass)?;
            band.add_symmetric(seat.rail, seat.dof, -pad)?;
            let base: Vec<(usize, f64)> = self.seat_base(seat).collect();
            for (a, &(i, n_i)) in base.iter().enumerate() {
                for &(j, n_j) in &base[..=a] {
                    band.add_symmetric(i, j, ballast * n_i * n_j)?;
                }
                band.add_symmetric(seat.dof, i, -ballast * n_i)?;
            }
        }
        Ok(())
    }

    /// `weights[0]` M + `weights[1]` C + `weights[2]` K of the elements
    /// `element(on_deck, h)` gives (`place` order) and of the sleepers'
    /// `seats` ([pad, ballast, mass] already weighted), assembled: the
    /// rail's elements (with the deck's under them on a continuous
    /// layer), then the deck's on their own, then the sleepers.
    pub fn assemble(
        &self,
        element: &dyn Fn(bool, f64) -> ElementMatrices,
        weights: [f64; 3],
        seats: [f64; 3],
    ) -> Result<WideBand, String> {
        let mut band = WideBand::zeros(self.free, self.half_bandwidth);
        // Each element's matrices, computed anew only where its kind or
        // length changes (every element alike on a uniform mesh).
        let mut last: Option<(bool, f64, ElementMatrices)> = None;
        let mut parts_of = |on_deck: bool, h: f64| match last {
            Some((d, l, parts)) if d == on_deck && l == h => parts,
            _ => {
                let parts = element(on_deck, h);
                last = Some((on_deck, h, parts));
                parts
            }
        };
        let rails = (self.element_dofs.iter().enumerate()).map(|(e, local)| {
            (
                self.on_deck[e] && !self.deck_apart(),
                self.element_length[e],
                *local,
            )
        });
        let decks = self.deck.iter().map(|d| {
            let [a, b, c, e] = d.dofs;
            (true, d.length, [None, None, a, b, None, None, c, e])
        });
        for (on_deck, h, local) in rails.chain(decks) {
            let parts = parts_of(on_deck, h);
            for (p, row) in local.iter().enumerate() {
                for (q, col) in local.iter().enumerate().take(p + 1) {
                    if let (Some(i), Some(j)) = (row, col) {
                        let value: f64 = (0..3).map(|m| weights[m] * parts[m][p][q]).sum();
                        band.add_symmetric(*i, *j, value)?;
                    }
                }
            }
        }
        self.add_seats(&mut band, seats)?;
        Ok(band)
    }

    /// The free DOFs `deck_field` reads at `x` (none off the deck).
    pub fn deck_field_dofs(&self, x: f64) -> Vec<usize> {
        deck_at(&self.deck, x).map_or(Vec::new(), |(k, _)| {
            self.deck[k].dofs.iter().flatten().copied().collect()
        })
    }

    /// The deck's w at `x` in `u` on its own elements (0 off the deck).
    pub fn deck_field(&self, x: f64, u: &[f64]) -> f64 {
        let Some((k, s)) = deck_at(&self.deck, x) else {
            return 0.0;
        };
        let element = &self.deck[k];
        let shape = hermite(s, element.length);
        (element.dofs.iter().zip(shape))
            .map(|(dof, n)| dof.map_or(0.0, |i| n * u[i]))
            .sum()
    }

    /// The element holding `x` and the abscissa s ∈ [0, 1] in it; `x` off
    /// the rail is refused.
    pub fn locate(&self, x: f64) -> Result<(usize, f64), String> {
        let elements = self.node_x.len() - 1;
        let e = self
            .node_x
            .partition_point(|&n| n <= x)
            .saturating_sub(1)
            .min(elements - 1);
        let s = (x - self.node_x[e]) / self.element_length[e];
        if !(0.0..=1.0).contains(&s) {
            return Err(format!(
                "x = {x} m lies off the rail [{}, {}] m",
                self.node_x[0], self.node_x[elements]
            ));
        }
        Ok((e, s))
    }
}

/// The deck DOFs' numbers in the assembly, the rail's (w, ψ) at each
/// node and the count of free DOFs.
type Numbering = (Vec<usize>, Vec<[usize; 2]>, usize);

/// Number the rail's DOFs and the deck's node by node: at each rail node
/// its w and ψ, then the deck's free DOFs at that abscissa (two ψ where
/// two spans meet or at a hinge) in the deck mesh's order, which runs
/// along the track. Returns the deck DOFs' new numbers, the rail's and
/// the count.
fn number_dofs(node_x: &[f64], mesh: &Mesh, tolerance: f64) -> Result<Numbering, String> {
    let deck_x = mesh.free_dof_x();
    let mut numbering = vec![usize::MAX; mesh.free_dofs];
    let mut rail = Vec::with_capacity(node_x.len());
    let (mut next, mut d) = (0, 0);
    for &x in node_x {
        rail.push([next, next + 1]);
        next += 2;
        while d < deck_x.len() && (deck_x[d] - x).abs() < tolerance {
            numbering[d] = next;
            next += 1;
            d += 1;
        }
    }
    if d < deck_x.len() {
        return Err(format!(
            "the deck's DOF at x = {} m lies at no node of the rail",
            deck_x[d]
        ));
    }
    Ok((numbering, rail, next))
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
            sleepers: None,
        }
    }

    #[test]
    fn the_bearings_and_the_ground_carry_the_load() {
        let load = 100e3;
        for at in [3.3, 10.0, 25.0] {
            let solution = bridge(3.3e7).static_solution(at, load).expect("solves");
            let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
            let total = bearings + solution.ground_force;
            assert_eq!(solution.reactions.len(), 2);
            assert!(
                (total - load).abs() < 1e-9 * load,
                "load at {at} m: bearings {bearings} + ground {} = {total}",
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
        let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
        assert!((bearings + solution.ground_force - load).abs() < 1e-9 * load);
    }
}
