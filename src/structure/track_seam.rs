//! The rail over the deck behind the structure seam (`Structure::Track`):
//! the contacts see the rail as a free Hermite mesh from the approach's
//! start to the run-off's end, while the state is the interleaved rail and
//! deck DOFs of `track_on_deck` with its wide-band mass, damping and
//! stiffness; the deck's sensors read the deck.
//!
//! The system's abscissa starts at the rail's start: the deck's x = 0 is
//! the system's `deck_start` (the approach), so the rail mesh, whose nodes
//! start at 0 like every mesh, needs no negative abscissae.

use nalgebra::{DMatrix, DVector};

use crate::beam::{EffectiveFactor, Foundation, HermiteBeam, Modes, Rayleigh};
use crate::mesh::Mesh;
use crate::structure::beam::{BeamSpec, EndSupport, SpringSpec, SupportsSpec};
use crate::structure::kinds::ChosenKind;
use crate::structure::ops::StructureOps;
use crate::structure::rail_on_deck::RailOnDeck;
use crate::structure::seam::TRACK_NOT_MODAL;
use crate::structure::track_on_deck::{TrackAssembly, TrackOnDeck};
use crate::structure::track_sleepers::Sleepers;
use crate::structure::track_spec::{OnDeckSpec, TrackSpec};
use crate::wide_band::{RecallingLdlt, WideBand, WideLdlt};

/// The rail over the deck's spans, as the seam sees it.
pub struct TrackBeam {
    /// The rail: geometry and shapes for the contacts (no supports, no
    /// dynamics of its own: its DOFs are mapped into the assembly's).
    pub(in crate::structure) mesh: HermiteBeam,
    assembly: TrackAssembly,
    /// The assembly's index of each free DOF of the rail mesh.
    rail_dofs: Vec<usize>,
    mass_factor: WideLdlt,
    stiffness_factor: WideLdlt,
    /// The system's abscissa of the deck's x = 0 (m): the approach.
    deck_start: f64,
    /// An upper bound of the highest natural circular frequency (rad/s).
    highest_frequency: f64,
}

impl TrackBeam {
    /// The rail of `on_deck` over the deck of `deck` (validated: spans and
    /// joints in elements of one length, Rayleigh damping) between an
    /// approach and a run-off on the ground; the rail's elements are the
    /// deck's.
    pub fn new(
        deck: &BeamSpec,
        on_deck: &OnDeckSpec,
        (approach, run_off): (f64, f64),
    ) -> Result<TrackBeam, String> {
        let deck_damping: Rayleigh = HermiteBeam::new(deck)?.damping();
        let element_length = deck_element_length(deck)?;
        let track = TrackOnDeck {
            layout: RailOnDeck {
                deck_length: deck.length,
                deck_bending_stiffness: deck.bending_stiffness,
                rail_bending_stiffness: on_deck.rail_bending_stiffness,
                track_stiffness: on_deck.stiffness(),
                ground_stiffness: on_deck.ground_stiffness(),
                approach,
                run_off,
                element_length,
                sleepers: on_deck.sleepers.map(|s| s.resolve()),
            },
            rail_mass_per_length: on_deck.rail_mass_per_length,
            deck_mass_per_length: deck.mass_per_length,
            track_damping: on_deck.damping(),
            ground_damping: on_deck.ground_damping(),
            deck_damping,
        };
        let assembly = track.assemble_over(deck)?;
        let lengths = &assembly.layout.element_length;
        let rail = rail_spec(deck, on_deck, &assembly.node_x, lengths);
        let mesh = HermiteBeam::new(&rail)?;
        let rail_dofs = rail_dofs(&mesh, &assembly)?;
        let not_definite =
            |what: &str| format!("the rail-over-deck {what} is not positive definite");
        let mass_factor = assembly.mass.ldlt().ok_or_else(|| not_definite("mass"))?;
        let stiffness_factor =
            (assembly.stiffness.ldlt()).ok_or_else(|| not_definite("stiffness"))?;
        let highest_frequency = assembly.element_frequency_bound()?;
        Ok(TrackBeam {
            mesh,
            assembly,
            rail_dofs,
            mass_factor,
            stiffness_factor,
            deck_start: approach,
            highest_frequency,
        })
    }

    /// The system's abscissa of the deck's x = 0 (m).
    pub fn deck_start(&self) -> f64 {
        self.deck_start
    }

    /// The assembled rail over the deck.
    pub fn assembly(&self) -> &TrackAssembly {
        &self.assembly
    }

    /// Deck deflection of `u` at the deck's abscissa `x` (NaN off it).
    pub fn deck_deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        let on = x >= 0.0 && x <= self.assembly.track.layout.deck_length;
        let value = self.assembly.deck_deflection(x, u.as_slice());
        value.ok().filter(|_| on).unwrap_or(f64::NAN)
    }

    /// The state entries `deck_deflection` reads at the deck's abscissa
    /// `x` (none off the deck).
    pub fn deck_deflection_coordinates(&self, x: f64) -> Vec<usize> {
        let on = x >= 0.0 && x <= self.assembly.track.layout.deck_length;
        let dofs = self.assembly.deck_deflection_dofs(x).ok().filter(|_| on);
        dofs.unwrap_or_default()
    }

    /// Rail deflection of `u` at the deck's abscissa `x` (NaN off the rail).
    pub fn rail_deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        (self.assembly.rail_deflection(x, u.as_slice())).unwrap_or(f64::NAN)
    }
}

/// The products on the interleaved DOFs.
impl TrackBeam {
    /// `out = band x`.
    fn times(band: &WideBand, x: &DVector<f64>, out: &mut DVector<f64>) {
        band.mul_to(x.as_slice(), out.as_mut_slice());
    }

    fn quadratic(band: &WideBand, x: &DVector<f64>) -> f64 {
        let mut product = DVector::zeros(x.len());
        Self::times(band, x, &mut product);
        x.dot(&product)
    }

    /// Whether the rail rests on sleepers (else on a continuous layer).
    pub fn has_sleepers(&self) -> bool {
        self.assembly.track.layout.sleepers.is_some()
    }

    /// The rail-seat (pad) force of the sleeper nearest the deck's
    /// abscissa `x` (N, compression positive; NaN without sleepers).
    pub fn rail_seat_force(&self, u: &DVector<f64>, v: &DVector<f64>, x: f64) -> f64 {
        (self.assembly.rail_seat_force(x, u.as_slice(), v.as_slice())).unwrap_or(f64::NAN)
    }
}

/// Chosen by a track with a layer over the deck (`track.on_deck`).
impl ChosenKind for TrackBeam {
    fn chosen(spec: &BeamSpec, track: &TrackSpec) -> Option<Result<TrackBeam, String>> {
        let on_deck = track.on_deck.as_ref()?;
        Some(TrackBeam::new(spec, on_deck, (track.approach, track.run_off)))
    }
}

/// The rail over the deck behind the seam: the state is the interleaved
/// rail and deck DOFs of the wide-band assembly.
impl StructureOps for TrackBeam {
    fn mesh(&self) -> &HermiteBeam {
        &self.mesh
    }

    /// The deck's deflection at the deck's abscissa `x`: the sensors read
    /// the deck, the contacts the rail.
    fn deflection(&self, u: &DVector<f64>, x: f64) -> f64 {
        self.deck_deflection(u, x)
    }

    /// None: the track's and the ground's layers are the assembly's.
    fn foundation(&self) -> Option<Foundation> {
        None
    }

    /// The coupled rail and deck's (dense, `track_on_deck::MAX_DENSE_DOFS`).
    fn modes(&self, count: usize) -> Result<Modes, String> {
        let (omega, shapes) = self.assembly().modes(count)?;
        Ok(Modes { omega, shapes })
    }

    fn frequencies(&self, count: usize) -> Result<Vec<f64>, String> {
        self.modes(count).map(|m| m.omega)
    }

    fn into_mesh(self) -> Result<HermiteBeam, String> {
        Err(TRACK_NOT_MODAL.into())
    }

    /// Entries of a state vector: every free DOF of rail and deck.
    fn coordinates(&self) -> usize {
        self.assembly.free_dofs()
    }

    /// The wide-band factor of M + `damping_weight` C + `stiffness_weight` K.
    fn effective_factor(
        &self,
        damping_weight: f64,
        stiffness_weight: f64,
    ) -> Result<EffectiveFactor, String> {
        let band = self
            .assembly
            .combination([1.0, damping_weight, stiffness_weight])?;
        band.ldlt().map(|factor| EffectiveFactor::Wide(RecallingLdlt::new(factor))).ok_or_else(|| {
            "the implicit scheme's effective matrix of the rail over the deck is not positive \
             definite"
                .into()
        })
    }

    /// No support dampers: the track's and the ground's are distributed.
    fn damper_rate_bound(&self) -> f64 {
        0.0
    }

    /// The element-by-element bound of the highest circular frequency.
    fn highest_frequency(&self) -> f64 {
        self.highest_frequency
    }

    fn dof_value(&self, dof: usize, u: &DVector<f64>) -> f64 {
        u[self.rail_dofs[dof]]
    }

    /// `StructureOps::gather` on the slices (the foot-point searches and
    /// the followers' gaps gather about 400,000 times on the rail scene):
    /// the same entries, without nalgebra's index and a check by level.
    fn gather(&self, dofs: &[Option<usize>; 4], u: &DVector<f64>) -> [f64; 4] {
        let (map, u) = (self.rail_dofs.as_slice(), u.as_slice());
        let mut local = [0.0; 4];
        for (value, dof) in local.iter_mut().zip(dofs) {
            if let Some(i) = *dof {
                *value = u[map[i]];
            }
        }
        local
    }

    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>) {
        out[self.rail_dofs[dof]] += scale;
    }

    fn load_coordinate(&self, dof: usize) -> Option<usize> {
        Some(self.rail_dofs[dof])
    }

    fn stiffness_times(&self, u: &DVector<f64>, out: &mut DVector<f64>) {
        Self::times(&self.assembly.stiffness, u, out);
    }

    fn mass_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        Self::times(&self.assembly.mass, v, out);
    }

    fn solve_mass(&self, rhs: &mut DVector<f64>) {
        self.mass_factor.solve_in_place(rhs.as_mut_slice());
    }

    /// K u = `load`, with one step of iterative refinement (the deck's
    /// EI/h³ against the ground's k h, as in `rail_on_deck`).
    fn static_deflection(&self, load: &DVector<f64>) -> Result<DVector<f64>, String> {
        let mut u = load.clone();
        self.stiffness_factor.solve_in_place(u.as_mut_slice());
        let mut residual = DVector::zeros(u.len());
        self.stiffness_times(&u, &mut residual);
        residual = load - residual;
        self.stiffness_factor
            .solve_in_place(residual.as_mut_slice());
        Ok(u + residual)
    }

    /// `out = K u + C v`, using `scratch`.
    fn internal_forces(
        &self,
        u: &DVector<f64>,
        v: &DVector<f64>,
        scratch: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.stiffness_times(u, out);
        Self::times(&self.assembly.damping, v, scratch);
        *out += &*scratch;
    }

    fn damping_times(&self, v: &DVector<f64>, out: &mut DVector<f64>) {
        Self::times(&self.assembly.damping, v, out);
    }

    /// `internal_forces`, its C v kept in `damping`.
    fn internal_and_damping_forces(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        damping: &mut DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.internal_forces(u, v, damping, out);
    }

    fn accelerations_read_internal_forces(&self) -> bool {
        true
    }

    /// `strain_energy` is ½ u·(K u) of the wide band's product.
    fn energies_are_products(&self) -> bool {
        true
    }

    /// K u and C v as `internal_forces` takes them, and their sum.
    fn stiffness_and_damping_forces(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        (stiffness, damping): (&mut DVector<f64>, &mut DVector<f64>),
        out: &mut DVector<f64>,
    ) {
        self.stiffness_times(u, stiffness);
        Self::times(&self.assembly.damping, v, damping);
        out.copy_from(stiffness);
        *out += &*damping;
    }

    /// `accelerations` is M⁻¹ (load − (K u + C v)) with the internal
    /// forces of `internal_forces`.
    fn accelerations_from_internal(
        &self,
        load: &DVector<f64>,
        internal: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> bool {
        out.copy_from(load);
        *out -= internal;
        self.solve_mass(out);
        true
    }

    /// `M⁻¹ (load − K u − C v)`.
    fn accelerations(
        &self,
        (u, v): (&DVector<f64>, &DVector<f64>),
        load: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let mut scratch = DVector::zeros(u.len());
        let mut internal = DVector::zeros(u.len());
        self.internal_forces(u, v, &mut scratch, &mut internal);
        self.accelerations_from_internal(load, &internal, out);
    }

    /// The mass's quadratic form, not ½ vᵀ (M v): no product vector, and
    /// no kept product to agree with (the strain energy's ½ uᵀ (K u) is
    /// the step end's kept K u, bit for bit, and stays a product).
    fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        0.5 * self.assembly.mass.quadratic_form(v.as_slice())
    }

    fn strain_energy(&self, u: &DVector<f64>) -> f64 {
        0.5 * Self::quadratic(&self.assembly.stiffness, u)
    }

    fn damping_power(&self, v: &DVector<f64>) -> f64 {
        Self::quadratic(&self.assembly.damping, v)
    }

    /// Whether any damper acts (the deck's, the track's, the ground's).
    fn is_damped(&self) -> bool {
        let track = &self.assembly.track;
        let sleepers =
            (track.layout.sleepers).is_some_and(|s| s.pad_damping > 0.0 || s.ballast_damping > 0.0);
        let layer = track.layout.sleepers.is_none()
            && (track.track_damping > 0.0 || track.ground_damping > 0.0);
        !track.deck_damping.is_zero() || layer || sleepers
    }
}

/// The rail as a free mesh over the whole track at the assembly's nodes
/// `node_x` with its element `lengths` (from the approach's start): the rail's mass and bending
/// stiffness, the deck's surface offset (the running surface's height in
/// the bodies' frame). Where the elements differ in length, a spring of
/// zero stiffness at each inner node places the node there (the rail mesh
/// is geometry only: its matrices are never used).
fn rail_spec(deck: &BeamSpec, on_deck: &OnDeckSpec, node_x: &[f64], lengths: &[f64]) -> BeamSpec {
    let elements = node_x.len() - 1;
    let element_length = lengths[0];
    let uniform = lengths.iter().all(|&l| l == element_length);
    let springs = (node_x[1..elements].iter())
        .filter(|_| !uniform)
        .map(|x| SpringSpec {
            at: x - node_x[0],
            ..SpringSpec::default()
        })
        .collect();
    BeamSpec {
        length: if uniform {
            element_length * elements as f64
        } else {
            node_x[elements] - node_x[0]
        },
        mass_per_length: on_deck.rail_mass_per_length,
        bending_stiffness: on_deck.rail_bending_stiffness,
        surface_offset: deck.surface_offset,
        elements,
        supports: SupportsSpec {
            left: EndSupport::Free,
            right: EndSupport::Free,
            intermediate: Vec::new(),
            springs,
        },
        ..BeamSpec::default()
    }
}

/// The length of the deck's elements where they are all one (the first's),
/// else of its longest: the rail's elements on the approach, the run-off
/// and the gaps are at most this long.
pub fn deck_element_length(deck: &BeamSpec) -> Result<f64, String> {
    let mesh = Mesh::new(deck)?;
    let first = (mesh.element_length.first().copied()).ok_or("the deck has no elements")?;
    let longest = mesh.element_length.iter().copied().fold(first, f64::max);
    Ok(if longest - first > 1e-9 * first {
        longest
    } else {
        first
    })
}

/// The assembly's index of every free DOF of the rail mesh: node by node,
/// its w and ψ.
fn rail_dofs(mesh: &HermiteBeam, assembly: &TrackAssembly) -> Result<Vec<usize>, String> {
    let nodes = assembly.rail_node_dofs();
    if mesh.elements() + 1 != nodes.len() {
        return Err("the rail mesh and the rail-over-deck assembly differ in nodes".into());
    }
    let mut map = vec![usize::MAX; mesh.free_dofs()];
    for e in 0..mesh.elements() {
        let local = [nodes[e][0], nodes[e][1], nodes[e + 1][0], nodes[e + 1][1]];
        for (dof, rail) in mesh.element_dofs(e).iter().zip(local) {
            if let Some(i) = *dof {
                map[i] = rail;
            }
        }
    }
    if map.contains(&usize::MAX) {
        return Err("a rail DOF has no place in the rail-over-deck assembly".into());
    }
    Ok(map)
}

impl TrackAssembly {
    /// Irons' bound: the highest generalized eigenvalue of the assembly is
    /// at most the highest of its elements' (each element's mass being
    /// positive definite), here from the dense 8×8 (4×4 off the deck)
    /// element eigenproblems; on sleepers, of the groups of
    /// `group_frequency_bound`.
    fn element_frequency_bound(&self) -> Result<f64, String> {
        if self.layout.deck_apart() {
            return self.group_frequency_bound();
        }
        let mut highest = 0.0f64;
        let mut lengths = self.layout.element_length.clone();
        lengths.sort_by(f64::total_cmp);
        lengths.dedup();
        for (deck, h) in lengths.into_iter().flat_map(|h| [(false, h), (true, h)]) {
            let [m, _, k] = self.track.element(deck, h);
            let n = if deck { 8 } else { 4 };
            // Off the deck the element has the rail's four DOFs: 0, 1, 4, 5.
            let pick = |p: usize| if deck { p } else { [0, 1, 4, 5][p] };
            let dense = |a: &[[f64; 8]; 8]| DMatrix::from_fn(n, n, |i, j| a[pick(i)][pick(j)]);
            let (omega, _) =
                crate::dense_modes::lowest_modes(dense(&m), dense(&k), n, "a rail element")?;
            highest = highest.max(omega.last().copied().unwrap_or(0.0));
        }
        Ok(highest)
    }

    /// Irons' bound on sleepers, the deck on its own elements: the
    /// assembly's mass and stiffness are the sums of groups' (a rail
    /// element, a deck element, each sleeper with the rail element that
    /// starts at its node (the last node's: the one that ends there) and
    /// the deck element under it, groups sharing an element joined), each
    /// group's mass positive definite on its DOFs; the highest eigenvalue
    /// of any group bounds the assembly's. Alike groups are solved once.
    fn group_frequency_bound(&self) -> Result<f64, String> {
        let Some(s) = self.track.layout.sleepers else {
            return Ok(0.0);
        };
        let layout = &self.layout;
        let (rails, decks) = (layout.element_dofs.len(), layout.deck.len());
        let mut parent: Vec<usize> = (0..rails + decks + layout.seats.len()).collect();
        let root = |parent: &mut Vec<usize>, mut i: usize| {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        };
        for (g, seat) in layout.seats.iter().enumerate() {
            let sleeper = rails + decks + g;
            let mut join = |piece: usize| {
                let (a, b) = (root(&mut parent, sleeper), root(&mut parent, piece));
                parent[a] = b;
            };
            join(seat.node.min(rails - 1));
            if let Some((k, _)) = seat.deck {
                join(rails + k);
            }
        }
        let mut groups: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for piece in 0..parent.len() {
            let r = root(&mut parent, piece);
            groups.entry(r).or_default().push(piece);
        }
        let mut seen = std::collections::HashSet::new();
        let mut highest = 0.0f64;
        for pieces in groups.values() {
            let (mass, stiffness) = self.group_matrices(&s, pieces, (rails, decks));
            let key: Vec<u64> = (mass.iter().chain(stiffness.iter()))
                .map(|v| v.to_bits())
                .collect();
            if !seen.insert((mass.nrows(), key)) {
                continue;
            }
            let n = mass.nrows();
            let (omega, _) = crate::dense_modes::lowest_modes(mass, stiffness, n, "a sleeper")?;
            highest = highest.max(omega.last().copied().unwrap_or(0.0));
        }
        Ok(highest)
    }

    /// The dense mass and stiffness of a group of `pieces` (rail elements
    /// below `rails`, then `decks` deck elements, then sleepers) on the
    /// free DOFs they touch, in the order they are met.
    fn group_matrices(
        &self,
        s: &Sleepers,
        pieces: &[usize],
        (rails, decks): (usize, usize),
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        let layout = &self.layout;
        let mut entries: Vec<(usize, usize, f64, f64)> = Vec::new();
        let element = |entries: &mut Vec<_>, dofs: [Option<usize>; 8], on_deck: bool, h: f64| {
            let [m, _, k] = self.track.element(on_deck, h);
            for (p, i) in dofs.iter().enumerate() {
                for (q, j) in dofs.iter().enumerate() {
                    if let (Some(i), Some(j)) = (i, j) {
                        entries.push((*i, *j, m[p][q], k[p][q]));
                    }
                }
            }
        };
        for &piece in pieces {
            if piece < rails {
                let h = layout.element_length[piece];
                element(&mut entries, layout.element_dofs[piece], false, h);
            } else if piece < rails + decks {
                let deck = &layout.deck[piece - rails];
                let [a, b, c, d] = deck.dofs;
                let dofs = [None, None, a, b, None, None, c, d];
                element(&mut entries, dofs, true, deck.length);
            } else {
                let seat = &layout.seats[piece - rails - decks];
                let (pad, ballast) = (s.pad_stiffness, s.ballast_stiffness);
                entries.extend([
                    (seat.rail, seat.rail, 0.0, pad),
                    (seat.dof, seat.dof, s.sleeper_mass, pad + ballast),
                    (seat.rail, seat.dof, 0.0, -pad),
                    (seat.dof, seat.rail, 0.0, -pad),
                ]);
                for (i, n) in layout.seat_base(seat) {
                    for (j, n_j) in layout.seat_base(seat) {
                        entries.push((i, j, 0.0, ballast * n * n_j));
                    }
                    entries.push((seat.dof, i, 0.0, -ballast * n));
                    entries.push((i, seat.dof, 0.0, -ballast * n));
                }
            }
        }
        let mut dofs: Vec<usize> = entries.iter().map(|e| e.0).collect();
        dofs.sort_unstable();
        dofs.dedup();
        let n = dofs.len();
        let (mut mass, mut stiffness) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        for (i, j, m, k) in entries {
            let (p, q) = (dofs.binary_search(&i), dofs.binary_search(&j));
            if let (Ok(p), Ok(q)) = (p, q) {
                mass[(p, q)] += m;
                stiffness[(p, q)] += k;
            }
        }
        (mass, stiffness)
    }
}
