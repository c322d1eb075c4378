//! The mesh of the structure: elements, their degrees of freedom and the
//! elastic supports, for one beam or several beams in a row.
//!
//! Several beams (separate spans, spans joined by a hinge) share one set of
//! free DOFs and so one band matrix, not a `Vec` of beams: the integrators,
//! the Delassus operator's unit-load responses and the energy sums then see
//! one `Beam` whatever the track, and a track of n separate spans costs the
//! same per step as one beam of as many elements. The band stays of
//! half-bandwidth 3 because the DOFs are numbered node by node along the
//! track: separate beams share no element, and a hinge node numbers its
//! DOFs (ψ_left, w, ψ_right), so each element's four DOFs are consecutive.

use std::ops::Range;

use super::{BeamSpec, EndSupport, JointKind, SpringSpec};

/// One smooth piece of the track's surface: a beam, or the part of a beam
/// between its ends and hinges; its abscissae and its elements.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub start: f64,
    pub end: f64,
    pub elements: Range<usize>,
}

/// A spring and damper from one free DOF to the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundSpring {
    pub dof: usize,
    pub stiffness: f64,
    pub damping: f64,
}

pub struct Mesh {
    /// Start abscissa and length of each element, along the track.
    pub element_start: Vec<f64>,
    pub element_end: Vec<f64>,
    pub element_length: Vec<f64>,
    /// Free-DOF index of each element's (w_i, ψ_i, w_j, ψ_j), `None` where held.
    pub element_dofs: Vec<[Option<usize>; 4]>,
    /// The pieces of the surface, split at separate joints and hinges.
    pub segments: Vec<Segment>,
    pub free_dofs: usize,
    /// Free rotation DOFs.
    pub rotation_dofs: Vec<usize>,
    pub springs: Vec<GroundSpring>,
}

/// A node: its global DOFs (w, ψ seen by the element on its left, ψ seen
/// by the element on its right; the two ψ differ only at a hinge).
#[derive(Debug, Clone, Copy)]
struct Node {
    w: usize,
    psi_left: usize,
    psi_right: usize,
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

/// The beams' [start, end] along the track, split at the separate joints.
fn segment_bounds(spec: &BeamSpec) -> Vec<(f64, f64)> {
    let mut bounds = Vec::new();
    let mut start = 0.0;
    for joint in spec.joints.iter().filter(|j| j.kind == JointKind::Separate) {
        bounds.push((start, joint.at));
        start = joint.at + joint.gap;
    }
    bounds.push((start, spec.length));
    bounds
}

/// Abscissae where a node must lie strictly inside a beam: intermediate
/// supports, springs, continuous joints and hinges.
fn interior_breaks(spec: &BeamSpec, (start, end): (f64, f64)) -> Vec<f64> {
    let joints = spec
        .joints
        .iter()
        .filter(|j| j.kind != JointKind::Separate)
        .map(|j| j.at);
    let springs = spec.supports.springs.iter().map(|s| s.at);
    let mut breaks: Vec<f64> = spec
        .supports
        .intermediate
        .iter()
        .copied()
        .chain(joints)
        .chain(springs)
        .filter(|&x| x > start && x < end)
        .collect();
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    breaks
}

impl Mesh {
    /// The abscissa of each free DOF's node, along the track.
    pub fn free_dof_x(&self) -> Vec<f64> {
        let mut x = vec![f64::NAN; self.free_dofs];
        for (k, local) in self.element_dofs.iter().enumerate() {
            let ends = [self.element_start[k], self.element_end[k]];
            for (p, dof) in local.iter().enumerate() {
                if let Some(d) = dof {
                    x[*d] = ends[p / 2];
                }
            }
        }
        x
    }

    /// The mesh of a (validated) spec.
    pub fn new(spec: &BeamSpec) -> Result<Mesh, String> {
        let bounds = segment_bounds(spec);
        let breaks: Vec<Vec<f64>> = bounds
            .iter()
            .map(|&(a, b)| {
                let mut all = vec![a];
                all.extend(interior_breaks(spec, (a, b)));
                all.push(b);
                all
            })
            .collect();
        let spans: Vec<f64> = breaks
            .iter()
            .flat_map(|b| b.windows(2).map(|w| w[1] - w[0]))
            .collect();
        if spec.elements < spans.len() {
            return Err(format!(
                "beam.elements = {} is fewer than the {} spans between supports, springs and \
                 joints; each span needs at least one element",
                spec.elements,
                spans.len()
            ));
        }
        let mut counts = elements_per_span(&spans, spec.elements).into_iter();
        let hinges: Vec<f64> = spec
            .joints
            .iter()
            .filter(|j| j.kind == JointKind::Hinge)
            .map(|j| j.at)
            .collect();
        let mut layout = Layout::default();
        for segment_breaks in &breaks {
            layout.start_segment();
            for (k, pair) in segment_breaks.windows(2).enumerate() {
                if k == 0 {
                    layout.node(pair[0], false);
                }
                let count = counts.next().unwrap_or(1);
                let span = pair[1] - pair[0];
                for i in 1..=count {
                    let x = pair[0] + span * i as f64 / count as f64;
                    let at_break = i == count;
                    let hinge = at_break && hinges.contains(&pair[1]);
                    layout.node(x, hinge);
                    if at_break {
                        layout.mark_break(pair[1]);
                    }
                }
            }
            layout.end_segment();
        }
        layout.hold_supports(spec)?;
        layout.finish(spec)
    }
}

/// The mesh under construction: nodes along the track, global DOFs.
#[derive(Default)]
struct Layout {
    nodes: Vec<Node>,
    node_x: Vec<f64>,
    /// Index of the node at each interior break abscissa, and of each
    /// beam's first and last node.
    break_nodes: Vec<(f64, usize)>,
    ends: Vec<(usize, usize)>,
    elements: Vec<(usize, usize)>,
    /// The first element of each smooth piece (a beam, or after a hinge).
    piece_starts: Vec<usize>,
    global_dofs: usize,
    held: Vec<bool>,
    segment_first: usize,
}

impl Layout {
    fn start_segment(&mut self) {
        self.segment_first = self.nodes.len();
        self.piece_starts.push(self.elements.len());
    }

    fn new_dof(&mut self) -> usize {
        self.global_dofs += 1;
        self.held.push(false);
        self.global_dofs - 1
    }

    /// Add a node (a hinge numbers ψ_left, w, ψ_right) and the element
    /// from the previous node of the same beam to it.
    fn node(&mut self, x: f64, hinge: bool) {
        let node = if hinge {
            let psi_left = self.new_dof();
            let w = self.new_dof();
            let psi_right = self.new_dof();
            Node {
                w,
                psi_left,
                psi_right,
            }
        } else {
            let w = self.new_dof();
            let psi = self.new_dof();
            Node {
                w,
                psi_left: psi,
                psi_right: psi,
            }
        };
        if self.nodes.len() > self.segment_first {
            self.elements.push((self.nodes.len() - 1, self.nodes.len()));
        }
        self.nodes.push(node);
        self.node_x.push(x);
        if hinge {
            self.piece_starts.push(self.elements.len());
        }
    }

    fn mark_break(&mut self, x: f64) {
        self.break_nodes.push((x, self.nodes.len() - 1));
    }

    fn end_segment(&mut self) {
        let last = self.nodes.len() - 1;
        // The last break of a beam is its end, not an interior node.
        self.break_nodes.pop();
        self.ends.push((self.segment_first, last));
    }

    /// The smooth pieces of the surface, from `piece_starts`.
    fn pieces(&self) -> Vec<Segment> {
        let mut bounds = self.piece_starts.clone();
        bounds.push(self.elements.len());
        bounds
            .windows(2)
            .map(|w| Segment {
                start: self.node_x[self.elements[w[0]].0],
                end: self.node_x[self.elements[w[1] - 1].1],
                elements: w[0]..w[1],
            })
            .collect()
    }

    fn interior_node(&self, x: f64) -> Option<usize> {
        self.break_nodes
            .iter()
            .find(|&&(bx, _)| bx == x)
            .map(|&(_, n)| n)
    }

    /// Hold the DOFs the end supports, intermediate supports, continuous
    /// joints and separate joints' pinned ends hold.
    fn hold_supports(&mut self, spec: &BeamSpec) -> Result<(), String> {
        let (first, _) = self.ends[0];
        let (_, last) = self.ends[self.ends.len() - 1];
        for (node, support, psi) in [
            (first, spec.supports.left, self.nodes[first].psi_right),
            (last, spec.supports.right, self.nodes[last].psi_left),
        ] {
            let w = self.nodes[node].w;
            match support {
                EndSupport::Pinned => self.held[w] = true,
                EndSupport::Clamped => {
                    self.held[w] = true;
                    self.held[psi] = true;
                }
                EndSupport::Free => {}
            }
        }
        for b in 1..self.ends.len() {
            let (before, after) = (self.ends[b - 1].1, self.ends[b].0);
            self.held[self.nodes[before].w] = true;
            self.held[self.nodes[after].w] = true;
        }
        let continuous = spec
            .joints
            .iter()
            .filter(|j| j.kind == JointKind::Continuous)
            .map(|j| j.at);
        let pinned: Vec<f64> = spec
            .supports
            .intermediate
            .iter()
            .copied()
            .chain(continuous)
            .collect();
        for x in pinned {
            let node = self.interior_node(x).ok_or_else(|| {
                format!("the support at x = {x} m lies on no beam (in a gap or at a beam's end)")
            })?;
            let w = self.nodes[node].w;
            self.held[w] = true;
        }
        Ok(())
    }

    /// The nodes at `x`: an interior node, or the end of a beam.
    fn nodes_at(&self, x: f64) -> Vec<usize> {
        if let Some(n) = self.interior_node(x) {
            return vec![n];
        }
        self.ends
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .filter(|&n| self.node_x[n] == x)
            .collect()
    }

    /// The mesh of the laid-out nodes: the free DOFs numbered node by
    /// node, each element's DOFs, the rotations and the elastic supports.
    fn finish(self, spec: &BeamSpec) -> Result<Mesh, String> {
        let mut free = vec![None; self.global_dofs];
        let mut free_dofs = 0;
        for (dof, &held) in self.held.iter().enumerate() {
            if !held {
                free[dof] = Some(free_dofs);
                free_dofs += 1;
            }
        }
        if free_dofs == 0 {
            return Err("the supports hold every DOF of the beam".into());
        }
        let mut springs = Vec::new();
        for (i, spring) in spec.supports.springs.iter().enumerate() {
            self.ground_springs(i, spring, &free, &mut springs)?;
        }
        let element_dofs = self
            .elements
            .iter()
            .map(|&(p, q)| {
                let (a, b) = (self.nodes[p], self.nodes[q]);
                [a.w, a.psi_right, b.w, b.psi_left].map(|g| free[g])
            })
            .collect();
        let rotation_dofs = self
            .nodes
            .iter()
            .flat_map(|n| {
                let mut psi = vec![n.psi_left];
                if n.psi_right != n.psi_left {
                    psi.push(n.psi_right);
                }
                psi
            })
            .filter_map(|g| free[g])
            .collect();
        Ok(Mesh {
            element_start: self.elements.iter().map(|&(p, _)| self.node_x[p]).collect(),
            element_end: self.elements.iter().map(|&(_, q)| self.node_x[q]).collect(),
            element_length: self
                .elements
                .iter()
                .map(|&(p, q)| self.node_x[q] - self.node_x[p])
                .collect(),
            element_dofs,
            segments: self.pieces(),
            free_dofs,
            rotation_dofs,
            springs,
        })
    }

    /// The one node at `at` a support spring (`path`) acts on.
    fn spring_node(&self, path: &str, at: f64) -> Result<Node, String> {
        match self.nodes_at(at).as_slice() {
            [node] => Ok(self.nodes[*node]),
            [] => Err(format!(
                "{path}.at = {at} m lies on no beam (in a rail gap)"
            )),
            _ => Err(format!(
                "{path}.at = {at} m is where two separate beams meet; give the joint a gap to \
                 tell their ends apart"
            )),
        }
    }

    /// The ground springs and dampers of support spring `i` (`spec`) on
    /// the free DOFs `free`, pushed onto `springs`; refused where it lies
    /// on no beam, on two, at a hinge's rotation or on a held DOF.
    fn ground_springs(
        &self,
        i: usize,
        spring: &SpringSpec,
        free: &[Option<usize>],
        springs: &mut Vec<GroundSpring>,
    ) -> Result<(), String> {
        let path = format!("beam.supports.springs[{i}]");
        let node = self.spring_node(&path, spring.at)?;
        let vertical = (node.w, spring.vertical, spring.vertical_damping, "vertical");
        let rotational = (
            node.psi_left,
            spring.rotational,
            spring.rotational_damping,
            "rotational",
        );
        if node.psi_left != node.psi_right
            && (spring.rotational != 0.0 || spring.rotational_damping != 0.0)
        {
            return Err(format!(
                "{path}.rotational = {} at a hinge (x = {} m): a hinge has two rotations, \
                 so a rotational spring there is ambiguous; leave it 0",
                spring.rotational, spring.at
            ));
        }
        for (dof, stiffness, damping, what) in [vertical, rotational] {
            if stiffness == 0.0 && damping == 0.0 {
                continue;
            }
            let Some(dof) = free[dof] else {
                return Err(format!(
                    "{path}: its {what} spring or damper acts where a support already holds \
                     the {} (x = {} m); leave {what} and {what}_damping 0 there, or make the \
                     support free",
                    if what == "vertical" {
                        "deflection"
                    } else {
                        "rotation"
                    },
                    spring.at
                ));
            };
            springs.push(GroundSpring {
                dof,
                stiffness,
                damping,
            });
        }
        Ok(())
    }
}
