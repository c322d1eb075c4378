//! The unit-load responses the contact iteration builds its Delassus
//! operator from on steps of the nominal length, kept in memory linear in
//! the elements (issue 29).
//!
//! A loaded element's four responses (the structure after one step from
//! rest under a unit load held on each of its DOFs) are integrated once
//! while a contact is on it and kept whole, so that a contact entering
//! another element reads its entries instead of integrating again; the
//! elements no contact loads now are kept within a constant budget, the
//! least recently loaded dropped first. The entries at a measured element
//! are read into a small per-pair block, kept while that pair is in use.
//! Up to 256 elements a block used to be kept for every pair of elements
//! (65,536 blocks, 57 MiB at 256 elements), and beyond it every loaded
//! element was integrated again each time a contact entered a new element:
//! a cost and memory cliff between neighbouring meshes. The responses depend only on the elements and the
//! nominal step, never on the history, so what is kept changes no bit of
//! the operator.

use std::collections::HashMap;
use std::hash::BuildHasherDefault;

use nalgebra::{DVector, Matrix4};

use crate::integrate::Integrator;
use crate::system::System;

/// Hashes an element key as itself: keys are small distinct integers.
#[derive(Default)]
struct ElementHasher(u64);

impl std::hash::Hasher for ElementHasher {
    fn finish(&self) -> u64 {
        // Mixed so that the low bits (the table's bucket) and the top bits
        // (its tag) depend on both elements of a pair: unmixed, every pair
        // with the same loaded element fell on one bucket and one tag, and
        // with 64 contacts the probing dominated the step.
        let x = self.0.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        x ^ (x >> 32)
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(*b);
        }
    }
    fn write_usize(&mut self, n: usize) {
        self.0 = self.0.rotate_left(32) ^ n as u64;
    }
}

type Hasher = BuildHasherDefault<ElementHasher>;

/// Displacements and velocities at one element's four DOFs after one step
/// under a unit load held on each DOF of another (or the same) element
/// (column = loaded DOF).
#[derive(Debug, Clone, Copy)]
pub(super) struct ElementResponse {
    pub displacement: Matrix4<f64>,
    pub velocity: Matrix4<f64>,
}

/// A pair's block and the build that last read it.
struct KeptPair {
    response: ElementResponse,
    used: u64,
}

/// One loaded element's whole responses and the build that last read them.
struct Loaded {
    /// Per loaded DOF (zero where it is held): displacement, velocity.
    displacement: [DVector<f64>; 4],
    velocity: [DVector<f64>; 4],
    used: u64,
}

impl Loaded {
    /// Its eight vectors' bytes.
    fn bytes(&self) -> usize {
        8 * self.displacement[0].len() * std::mem::size_of::<f64>()
    }
}

/// Operator builds a pair's block stays kept without being read: read
/// again from its loaded element's responses when those are kept.
const KEPT_BUILDS: u64 = 16;

/// Bytes of whole responses kept for elements no contact loads now, the
/// most recently loaded first: a train's next wheelset finds them on a
/// short bridge (all 75 elements of three 25 m spans at 9.6 kB each, 128
/// of the 250 of ten spans at 32 kB) and a single wheel on a long one
/// keeps a few. Constant, so the cache stays linear in the elements.
const MAX_IDLE_BYTES: usize = 4 << 20;

/// The whole responses kept at most, in bytes: 200 contacts on 100,000
/// elements would otherwise keep 2.5 GB. Beyond it a loaded element's
/// responses are read at the elements measured in this build and dropped
/// (integrated again when a contact enters another element).
const MAX_KEPT_BYTES: usize = 64 << 20;

/// The kept responses, with the largest footprint they reached.
pub(super) struct ResponseCache {
    loaded: HashMap<usize, Loaded, Hasher>,
    /// Per (measured, loaded) element pair.
    pairs: HashMap<(usize, usize), KeptPair, Hasher>,
    /// The responses of an element that did not fit in `MAX_KEPT_BYTES`,
    /// or one dropped, to integrate the next into.
    spare: Vec<Loaded>,
    /// Operator builds begun.
    build: u64,
    /// Pairs after the last sweep of the unused ones.
    swept_pairs: usize,
    load: DVector<f64>,
    peak: Footprint,
    /// Beam responses integrated.
    integrations: u64,
}

/// What the cache holds (or the most it held).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Footprint {
    /// Loaded elements whose whole responses are kept.
    pub loaded_elements: usize,
    /// Element pairs whose blocks are kept.
    pub pairs: usize,
    /// Bytes of both.
    pub bytes: usize,
}

impl ResponseCache {
    pub fn new() -> ResponseCache {
        ResponseCache {
            loaded: HashMap::default(),
            pairs: HashMap::default(),
            spare: Vec::new(),
            build: 0,
            swept_pairs: 0,
            load: DVector::zeros(0),
            peak: Footprint::default(),
            integrations: 0,
        }
    }

    /// What the cache holds now.
    pub fn footprint(&self) -> Footprint {
        let pair = std::mem::size_of::<((usize, usize), KeptPair)>();
        Footprint {
            loaded_elements: self.loaded.len(),
            pairs: self.pairs.len(),
            // Every loaded element's responses are of the one beam's size.
            bytes: self.loaded.values().next().map_or(0, Loaded::bytes) * self.loaded.len()
                + self.pairs.len() * pair,
        }
    }

    /// The most the cache held at once (at the end of each build).
    pub fn peak(&self) -> Footprint {
        self.peak
    }

    /// Beam responses integrated so far.
    pub fn integrations(&self) -> u64 {
        self.integrations
    }

    /// Whether a build would integrate loaded element `le`.
    pub fn misses(&self, le: usize) -> bool {
        !self.loaded.contains_key(&le)
    }

    /// Starts an operator build: what the last builds did not read ages.
    pub fn begin_build(&mut self) {
        self.build += 1;
    }

    /// Drops the least recently read responses beyond `MAX_IDLE_BYTES` and the
    /// pairs the last `KEPT_BUILDS` builds did not read, and records the
    /// footprint. Each sweep frees a quarter of the budget, and pairs are
    /// swept when they have doubled since the last sweep, so that sweeping
    /// costs O(1) an entry.
    pub fn end_build(&mut self) {
        self.drop_idle();
        let oldest = self.build.saturating_sub(KEPT_BUILDS);
        if self.pairs.len() > 2 * self.swept_pairs + 64 {
            self.pairs.retain(|_, p| p.used >= oldest);
            self.swept_pairs = self.pairs.len();
        }
        let now = self.footprint();
        let peak = &mut self.peak;
        peak.loaded_elements = peak.loaded_elements.max(now.loaded_elements);
        peak.pairs = peak.pairs.max(now.pairs);
        peak.bytes = peak.bytes.max(now.bytes);
    }

    /// Drops the least recently read whole responses of elements this
    /// build did not read until they fit in three quarters of `MAX_IDLE_BYTES`,
    /// when they exceed it.
    fn drop_idle(&mut self) {
        let build = self.build;
        let Some(whole) = self.loaded.values().next().map(Loaded::bytes) else {
            return;
        };
        // Counted before listed: most builds drop nothing, and the list's
        // allocation was most of a small beam's build (the paper's case).
        let idle_count = self.loaded.values().filter(|l| l.used < build).count();
        if idle_count * whole <= MAX_IDLE_BYTES {
            return;
        }
        let mut idle: Vec<(u64, usize)> = (self.loaded.iter())
            .filter(|(_, l)| l.used < build)
            .map(|(&e, l)| (l.used, e))
            .collect();
        // Oldest first; the element breaks ties so that the order is the
        // same whatever the map's.
        idle.sort_unstable();
        let keep = (3 * MAX_IDLE_BYTES / 4) / whole;
        let drop = idle.len() - keep;
        for &(_, e) in &idle[..drop] {
            let loaded = self.loaded.remove(&e).expect("listed above");
            if self.spare.is_empty() {
                self.spare.push(loaded);
            }
        }
    }

    /// Marks loaded element `le`'s whole responses (if kept) as read in
    /// this build: once per contact, not once per pair.
    pub fn touch(&mut self, le: usize) {
        if let Some(loaded) = self.loaded.get_mut(&le) {
            loaded.used = self.build;
        }
    }

    /// The block of (measured element `key.0`, loaded element `key.1`),
    /// integrating the loaded element's responses if they are not kept
    /// (`measured`: every element measured in this build, at which they
    /// are read when they cannot be kept), handed to `with`: one look-up
    /// a pair, and no copy.
    #[inline]
    pub fn pair(
        &mut self,
        (integrator, system, step): (&mut Integrator, &System, f64),
        key: (usize, usize),
        measured: &[usize],
        with: impl FnOnce(&ElementResponse),
    ) {
        let build = self.build;
        if let Some(kept) = self.pairs.get_mut(&key) {
            kept.used = build;
            return with(&kept.response);
        }
        let (me, le) = key;
        if self.misses(le) {
            self.integrate(integrator, system, step, le);
            let spare = self.spare.last();
            let loaded = self.loaded.get(&le).or(spare).expect("integrated above");
            for &m in measured.iter().chain([&me]) {
                let response = read_pair(system, loaded, (m, le));
                let used = build;
                self.pairs.insert((m, le), KeptPair { response, used });
            }
        } else {
            let response = read_pair(system, &self.loaded[&le], key);
            let used = build;
            self.pairs.insert(key, KeptPair { response, used });
        }
        with(&self.pairs[&key].response);
    }

    /// Integrates loaded element `le`'s four responses, into a kept entry
    /// when `MAX_KEPT_BYTES` allows, else into the spare one.
    fn integrate(&mut self, integrator: &mut Integrator, system: &System, step: f64, le: usize) {
        let beam = &system.beam;
        let n = beam.coordinates();
        if self.load.len() != n {
            self.load = DVector::zeros(n);
        }
        let mut entry = self.spare.pop().unwrap_or_else(|| Loaded {
            displacement: std::array::from_fn(|_| DVector::zeros(n)),
            velocity: std::array::from_fn(|_| DVector::zeros(n)),
            used: self.build,
        });
        entry.used = self.build;
        for (l, dof) in beam.element_dofs(le).iter().enumerate() {
            let (u, v) = (&mut entry.displacement[l], &mut entry.velocity[l]);
            // A response overwrites its vectors: only a held DOF's are cleared.
            let Some(dof) = *dof else {
                u.fill(0.0);
                v.fill(0.0);
                continue;
            };
            self.load.fill(0.0);
            beam.add_dof_load(dof, 1.0, &mut self.load);
            integrator.beam_response(system, &self.load, step, u, v);
            self.integrations += 1;
        }
        if self.footprint().bytes + entry.bytes() <= MAX_KEPT_BYTES {
            self.loaded.insert(le, entry);
        } else {
            self.spare.push(entry);
        }
    }
}

/// The block of `loaded`'s responses at measured element `me`'s DOFs.
fn read_pair(system: &System, loaded: &Loaded, (me, le): (usize, usize)) -> ElementResponse {
    let beam = &system.beam;
    let (dofs, mdofs) = (beam.element_dofs(le), beam.element_dofs(me));
    let mut response = ElementResponse {
        displacement: Matrix4::zeros(),
        velocity: Matrix4::zeros(),
    };
    for (l, dof) in dofs.iter().enumerate() {
        if dof.is_none() {
            continue;
        }
        for (k, m) in mdofs.iter().enumerate() {
            if let Some(m) = *m {
                response.displacement[(k, l)] = beam.dof_value(m, &loaded.displacement[l]);
                response.velocity[(k, l)] = beam.dof_value(m, &loaded.velocity[l]);
            }
        }
    }
    response
}
