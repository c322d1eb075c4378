//! The dynamic rail-over-deck assembly (issue 24 item 1): the static
//! layout of `rail_on_deck` with the rail's and the deck's masses, the
//! track's and the ground's dampers and the deck's Rayleigh damping, as
//! mass, damping and stiffness bands of half-bandwidth 7 (`wide_band`) on
//! the interleaved DOFs; its natural frequencies (dense, for checks) and an
//! HHT-α stepper for forces on the rail and for wheels of mass on it
//! through Hertz contacts (`HertzWheel`). Library only: scenes do not build
//! it yet (the seam's geometry is one beam's).

use crate::beam::{element_mass, element_stiffness, Rayleigh};
use crate::structure::beam::BeamSpec;
use crate::structure::rail_on_deck::{
    hermite, place, ElementMatrices, RailOnDeck, Seat, TrackLayout,
};
use crate::wide_band::{WideBand, WideLdlt};
use nalgebra::DMatrix;

/// Most free DOFs for which `frequencies` solves the dense eigenproblem
/// (O(n³) time, n² memory).
pub const MAX_DENSE_DOFS: usize = 3000;

/// A rail over a deck, with its masses and dampers: one simply supported
/// span (`assemble`) or the spans, supports and joints of a beam
/// (`assemble_over`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackOnDeck {
    /// Lengths, bending stiffnesses, track and ground moduli.
    pub layout: RailOnDeck,
    /// Rail mass per metre (kg/m).
    pub rail_mass_per_length: f64,
    /// Deck mass per metre (kg/m).
    pub deck_mass_per_length: f64,
    /// Rail to deck damping per metre (N s/m²).
    pub track_damping: f64,
    /// Rail to ground damping per metre off the deck (N s/m²).
    pub ground_damping: f64,
    /// The deck's own damping, α M_deck + β K_deck.
    pub deck_damping: Rayleigh,
}

/// M, C and K of a `TrackOnDeck` on its free DOFs, rail and deck
/// interleaved node by node.
#[derive(Debug, Clone)]
pub struct TrackAssembly {
    pub track: TrackOnDeck,
    /// Node abscissae from −approach to L + run-off (m).
    pub node_x: Vec<f64>,
    pub(super) layout: TrackLayout,
    pub mass: WideBand,
    pub damping: WideBand,
    pub stiffness: WideBand,
}

impl TrackOnDeck {
    /// The element matrices of an element on the deck or off it.
    pub(super) fn element(&self, on_deck: bool, h: f64) -> ElementMatrices {
        let (mut m, mut c) = ([[0.0; 8]; 8], [[0.0; 8]; 8]);
        let k = self.layout.element(on_deck, h);
        place(&mut m, &element_mass(h, self.rail_mass_per_length), (0, 0));
        if on_deck {
            let deck_mass = element_mass(h, self.deck_mass_per_length);
            let deck_stiffness = element_stiffness(h, self.layout.deck_bending_stiffness);
            place(&mut m, &deck_mass, (2, 2));
            let own =
                deck_mass * self.deck_damping.mass + deck_stiffness * self.deck_damping.stiffness;
            place(&mut c, &own, (2, 2));
            let layer = element_mass(h, self.layer_damping()[0]);
            place(&mut c, &layer, (0, 0));
            place(&mut c, &layer, (2, 2));
            place(&mut c, &(-layer), (0, 2));
            place(&mut c, &(-layer), (2, 0));
        } else {
            place(&mut c, &element_mass(h, self.layer_damping()[1]), (0, 0));
        }
        [m, c, k]
    }

    /// The continuous layer's dampers on the deck and on the ground: none
    /// on sleepers (theirs are the pads' and the ballast's).
    fn layer_damping(&self) -> [f64; 2] {
        match self.layout.sleepers {
            Some(_) => [0.0, 0.0],
            None => [self.track_damping, self.ground_damping],
        }
    }

    /// Assemble M, C and K over one simply supported span, refusing
    /// non-positive masses or moduli and lengths that are not whole
    /// elements.
    pub fn assemble(&self) -> Result<TrackAssembly, String> {
        self.assemble_over(&self.layout.single_span()?)
    }

    /// Assemble M, C and K over the deck `deck` (its spans, supports and
    /// joints; its length `layout.deck_length`, its elements all of
    /// `layout.element_length`), the rail on the ground in its gaps.
    pub fn assemble_over(&self, deck: &BeamSpec) -> Result<TrackAssembly, String> {
        // On sleepers the continuous layer and ground are not built.
        let layer = match self.layout.sleepers {
            Some(_) => None,
            None => Some([
                ("track_stiffness", self.layout.track_stiffness),
                ("ground_stiffness", self.layout.ground_stiffness),
            ]),
        };
        let positive = [
            ("rail_mass_per_length", self.rail_mass_per_length),
            ("deck_mass_per_length", self.deck_mass_per_length),
            ("rail_bending_stiffness", self.layout.rail_bending_stiffness),
            ("deck_bending_stiffness", self.layout.deck_bending_stiffness),
        ];
        for (name, value) in positive.into_iter().chain(layer.into_iter().flatten()) {
            if !(value > 0.0 && value.is_finite()) {
                return Err(format!("{name} = {value} must be finite and > 0"));
            }
        }
        for (name, value) in [
            ("track_damping", self.track_damping),
            ("ground_damping", self.ground_damping),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(format!("{name} = {value} must be finite and >= 0"));
            }
        }
        if let Some((name, value, rule)) = self
            .layout
            .sleepers
            .and_then(|s| s.problems().first().copied())
        {
            return Err(format!("sleepers.{name} = {value} {rule}"));
        }
        if !(deck.supports.springs.is_empty() && deck.foundation.is_none()) {
            return Err("a deck under a rail has no springs or foundation of its own".into());
        }
        let layout = self.layout.layout(deck)?;
        let mut assembly = TrackAssembly {
            track: *self,
            node_x: layout.node_x.clone(),
            layout,
            mass: WideBand::zeros(0, 0),
            damping: WideBand::zeros(0, 0),
            stiffness: WideBand::zeros(0, 0),
        };
        assembly.mass = assembly.combination([1.0, 0.0, 0.0])?;
        assembly.damping = assembly.combination([0.0, 1.0, 0.0])?;
        assembly.stiffness = assembly.combination([0.0, 0.0, 1.0])?;
        Ok(assembly)
    }
}

impl TrackAssembly {
    /// Free DOFs (rail w, ψ everywhere; deck w, ψ on the spans, w held at
    /// the supports).
    pub fn free_dofs(&self) -> usize {
        self.layout.free
    }

    /// The half-bandwidth of M, C and K.
    pub fn half_bandwidth(&self) -> usize {
        self.layout.half_bandwidth
    }

    /// The rail's (w, ψ) DOFs at each node.
    pub(super) fn rail_node_dofs(&self) -> &[[usize; 2]] {
        &self.layout.rail_dofs
    }

    /// `weights[0]` M + `weights[1]` C + `weights[2]` K, assembled.
    pub fn combination(&self, weights: [f64; 3]) -> Result<WideBand, String> {
        let seats = self.track.layout.sleepers.map_or([0.0; 3], |s| {
            let [m, c, k] = weights;
            let pad = c * s.pad_damping + k * s.pad_stiffness;
            let ballast = c * s.ballast_damping + k * s.ballast_stiffness;
            [pad, ballast, m * s.sleeper_mass]
        });
        self.layout
            .assemble(&|deck, h| self.track.element(deck, h), weights, seats)
    }

    /// The sleepers' DOFs, from the rail's start (none on a continuous
    /// layer).
    pub fn sleeper_dofs(&self) -> Vec<usize> {
        self.layout.seats.iter().map(|seat| seat.dof).collect()
    }

    /// The sleepers' abscissae (m; none on a continuous layer).
    pub fn sleeper_x(&self) -> Vec<f64> {
        (self.layout.seats.iter())
            .map(|seat| self.node_x[seat.node])
            .collect()
    }

    /// The rail-seat (pad) force of the sleeper nearest `x` (N, compression
    /// positive): −(k_p (w_r − w_s) + c_p (ẇ_r − ẇ_s)) from displacements
    /// `u` and velocities `v`; refused on a continuous layer.
    pub fn rail_seat_force(&self, x: f64, u: &[f64], v: &[f64]) -> Result<f64, String> {
        let sleepers = (self.track.layout.sleepers)
            .ok_or("the track has no sleepers: its rail-seat load is per metre")?;
        let distance = |seat: &Seat| (self.node_x[seat.node] - x).abs();
        let seat = (self.layout.seats.iter())
            .min_by(|a, b| distance(a).total_cmp(&distance(b)))
            .ok_or("the track has no sleepers")?;
        let relative = |state: &[f64]| state[seat.rail] - state[seat.dof];
        Ok(-(sleepers.pad_stiffness * relative(u) + sleepers.pad_damping * relative(v)))
    }

    /// The element holding `x` and the abscissa s ∈ [0, 1] in it; `x` off
    /// the rail is refused.
    fn locate(&self, x: f64) -> Result<(usize, f64), String> {
        self.layout.locate(x)
    }

    /// Add a force `force` (N, up positive) on the rail at `x` into the
    /// load vector `out` (consistent nodal loads).
    pub fn add_rail_force(&self, x: f64, force: f64, out: &mut [f64]) -> Result<(), String> {
        let (e, s) = self.locate(x)?;
        let local = self.layout.element_dofs[e];
        let shape = hermite(s, self.layout.element_length[e]);
        for (k, n) in [0, 1, 4, 5].into_iter().zip(shape) {
            if let Some(i) = local[k] {
                out[i] += force * n;
            }
        }
        Ok(())
    }

    /// w at `x` of the rail (`part` 0) or the deck (`part` 2) in `u`.
    fn field(&self, part: usize, x: f64, u: &[f64]) -> Result<f64, String> {
        let (e, s) = self.locate(x)?;
        if part == 2 && self.layout.deck_apart() {
            return Ok(self.layout.deck_field(x, u));
        }
        if part == 2 && !self.layout.on_deck[e] {
            return Ok(0.0);
        }
        let local = self.layout.element_dofs[e];
        let shape = hermite(s, self.layout.element_length[e]);
        Ok([0, 1, 4, 5]
            .into_iter()
            .zip(shape)
            .map(|(k, n)| local[k + part].map_or(0.0, |i| n * u[i]))
            .sum())
    }

    /// The free DOFs `deck_deflection` reads at `x`: the state entries
    /// its value is a combination of.
    pub fn deck_deflection_dofs(&self, x: f64) -> Result<Vec<usize>, String> {
        let (e, _) = self.locate(x)?;
        if self.layout.deck_apart() {
            return Ok(self.layout.deck_field_dofs(x));
        }
        if !self.layout.on_deck[e] {
            return Ok(Vec::new());
        }
        let local = self.layout.element_dofs[e];
        Ok([0, 1, 4, 5]
            .into_iter()
            .filter_map(|k| local[k + 2])
            .collect())
    }

    /// Rail deflection at `x` (m, up positive).
    pub fn rail_deflection(&self, x: f64, u: &[f64]) -> Result<f64, String> {
        self.field(0, x, u)
    }

    /// Deck deflection at `x` (m; 0 off the deck).
    pub fn deck_deflection(&self, x: f64, u: &[f64]) -> Result<f64, String> {
        self.field(2, x, u)
    }

    /// The free-DOF vector of the fields `rail(x)` and `deck(x)`, each
    /// [w, w'] at a node (the deck's read on the span only; held DOFs
    /// dropped): initial states and mode shapes to compare.
    pub fn nodal_field(
        &self,
        rail: &dyn Fn(f64) -> [f64; 2],
        deck: &dyn Fn(f64) -> [f64; 2],
    ) -> Vec<f64> {
        let mut out = vec![0.0; self.free_dofs()];
        for (e, local) in self.layout.element_dofs.iter().enumerate() {
            for (k, dof) in local.iter().enumerate() {
                let x = self.node_x[e + k / 4];
                let values = if k % 4 < 2 { rail(x) } else { deck(x) };
                if let Some(i) = *dof {
                    out[i] = values[k % 2];
                }
            }
        }
        for element in &self.layout.deck {
            for (k, dof) in element.dofs.iter().enumerate() {
                let x = if k < 2 { element.start } else { element.end };
                if let Some(i) = *dof {
                    out[i] = deck(x)[k % 2];
                }
            }
        }
        out
    }

    /// The rail-seat load per metre at `x` (N/m, compression positive):
    /// −(k_t (w_r − w_d) + c_t (ẇ_r − ẇ_d)) on the deck, −(k_g w_r + c_g
    /// ẇ_r) on the ground, from displacements `u` and velocities `v`.
    pub fn rail_seat_load(&self, x: f64, u: &[f64], v: &[f64]) -> Result<f64, String> {
        if self.track.layout.sleepers.is_some() {
            return Err("on sleepers the rail-seat load is each sleeper's: rail_seat_force".into());
        }
        let (e, _) = self.locate(x)?;
        let relative = |state: &[f64]| -> Result<f64, String> {
            Ok(self.field(0, x, state)? - self.field(2, x, state)?)
        };
        let (stiffness, damping) = if self.layout.on_deck[e] {
            (self.track.layout.track_stiffness, self.track.track_damping)
        } else {
            (
                self.track.layout.ground_stiffness,
                self.track.ground_damping,
            )
        };
        Ok(-(stiffness * relative(u)? + damping * relative(v)?))
    }

    /// Whether `x` lies on an element of the deck.
    pub fn on_deck(&self, x: f64) -> Result<bool, String> {
        let e = self.locate(x)?.0;
        Ok(match self.layout.deck_apart() {
            true => crate::structure::sleeper_layout::deck_at(&self.layout.deck, x).is_some(),
            false => self.layout.on_deck[e],
        })
    }

    /// The static deflections K u = `load`.
    pub fn static_deflection(&self, load: &[f64]) -> Result<Vec<f64>, String> {
        let factor = self
            .stiffness
            .ldlt()
            .ok_or("the rail-over-deck stiffness is not positive definite")?;
        let mut u = load.to_vec();
        factor.solve_in_place(&mut u);
        Ok(u)
    }

    /// The lowest `count` natural circular frequencies (rad/s) and their
    /// mass-normalised shapes (columns), by the dense eigenproblem through
    /// M's Cholesky factor; refused beyond `MAX_DENSE_DOFS`.
    pub fn modes(&self, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
        let n = self.free_dofs();
        if n > MAX_DENSE_DOFS {
            return Err(format!(
                "{n} free DOFs: the dense eigenproblem is limited to {MAX_DENSE_DOFS}; \
                 use longer elements"
            ));
        }
        let dense = |a: &WideBand| DMatrix::from_fn(n, n, |i, j| a.get(i, j));
        let (mass, stiffness) = (dense(&self.mass), dense(&self.stiffness));
        crate::dense_modes::lowest_modes(mass, stiffness, count, "the rail-over-deck")
    }

    /// An HHT-α stepper of step `step` (s) and α ∈ [−1/3, 0].
    pub fn hht(&self, step: f64, alpha: f64) -> Result<Hht, String> {
        if !(step > 0.0 && step.is_finite()) {
            return Err(format!("step = {step} s must be finite and > 0"));
        }
        if !(-1.0 / 3.0..=0.0).contains(&alpha) {
            return Err(format!("alpha = {alpha} must lie in [-1/3, 0]"));
        }
        let gamma = 0.5 - alpha;
        let beta = 0.25 * (1.0 - alpha).powi(2);
        let weights = [
            1.0,
            (1.0 + alpha) * gamma * step,
            (1.0 + alpha) * beta * step * step,
        ];
        let factor = self
            .combination(weights)?
            .ldlt()
            .ok_or("the HHT effective matrix is not positive definite")?;
        Ok(Hht {
            step,
            alpha,
            gamma,
            beta,
            factor,
        })
    }
}

/// Displacements, velocities and accelerations on the free DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackState {
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// The HHT-α scheme (Hilber, Hughes and Taylor 1977) on M a + C v + K u =
/// f: the equation of motion is met at t + (1 + α) Δt for C v + K u and f,
/// with Newmark's γ = ½ − α, β = ¼ (1 − α)².
#[derive(Debug, Clone)]
pub struct Hht {
    step: f64,
    alpha: f64,
    gamma: f64,
    beta: f64,
    factor: WideLdlt,
}

impl Hht {
    /// Advance `state` by one step from the load `now` to the load `next`.
    pub fn advance(
        &self,
        assembly: &TrackAssembly,
        state: &mut TrackState,
        (now, next): (&[f64], &[f64]),
    ) {
        let (dt, alpha, gamma, beta) = (self.step, self.alpha, self.gamma, self.beta);
        let n = state.u.len();
        // Predictors: u and v of the new step without its acceleration.
        let u_tilde: Vec<f64> = (0..n)
            .map(|i| state.u[i] + dt * state.v[i] + dt * dt * (0.5 - beta) * state.a[i])
            .collect();
        let v_tilde: Vec<f64> = (0..n)
            .map(|i| state.v[i] + dt * (1.0 - gamma) * state.a[i])
            .collect();
        // u and v where C v + K u is taken: (1 + α) new − α old.
        let mix = |new: &[f64], old: &[f64]| -> Vec<f64> {
            new.iter()
                .zip(old)
                .map(|(a, b)| (1.0 + alpha) * a - alpha * b)
                .collect()
        };
        let (u_mix, v_mix) = (mix(&u_tilde, &state.u), mix(&v_tilde, &state.v));
        let (mut ku, mut cv) = (vec![0.0; n], vec![0.0; n]);
        assembly.stiffness.mul_to(&u_mix, &mut ku);
        assembly.damping.mul_to(&v_mix, &mut cv);
        let mut a_new: Vec<f64> = (0..n)
            .map(|i| (1.0 + alpha) * next[i] - alpha * now[i] - ku[i] - cv[i])
            .collect();
        self.factor.solve_in_place(&mut a_new);
        for i in 0..n {
            state.u[i] = u_tilde[i] + dt * dt * beta * a_new[i];
            state.v[i] = v_tilde[i] + dt * gamma * a_new[i];
        }
        state.a = a_new;
    }
}

/// A wheel of mass on the rail through a Hertz contact, P = C_H δ^(3/2)
/// for a compression δ > 0 and nothing in tension, carrying a constant
/// downward load (its weight and its share of the vehicle's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzWheel {
    /// Mass (kg).
    pub mass: f64,
    /// Constant downward load W (N).
    pub load: f64,
    /// C_H (N/m^1.5).
    pub coefficient: f64,
    /// Contact abscissa (m) and speed (m/s).
    pub x: f64,
    pub speed: f64,
    /// Height of the wheel's contact point (m, up positive), its velocity
    /// and acceleration.
    pub z: f64,
    pub z_velocity: f64,
    pub z_acceleration: f64,
    /// Contact force of the last step (N, compression positive).
    pub force: f64,
}

impl TrackAssembly {
    /// The unit upward force on the rail at `x` as (DOF, load) entries
    /// (four at most): also the row that reads the rail's deflection.
    fn rail_row(&self, x: f64) -> Result<SparseRow, String> {
        let (e, s) = self.locate(x)?;
        let local = self.layout.element_dofs[e];
        let shape = hermite(s, self.layout.element_length[e]);
        Ok([0, 1, 4, 5]
            .into_iter()
            .zip(shape)
            .filter_map(|(k, n)| local[k].map(|i| (i, n)))
            .collect())
    }

    /// The wheels at rest in static equilibrium on the rail: the
    /// structure's state (returned) and the wheels' (set), each contact
    /// carrying its wheel's load.
    pub fn wheels_at_rest(&self, wheels: &mut [HertzWheel]) -> Result<TrackState, String> {
        let mut load = vec![0.0; self.free_dofs()];
        for wheel in wheels.iter() {
            self.add_rail_force(wheel.x, -wheel.load, &mut load)?;
        }
        let u = self.static_deflection(&load)?;
        for wheel in wheels.iter_mut() {
            let rail = self.rail_deflection(wheel.x, &u)?;
            wheel.force = wheel.load;
            wheel.z = rail - libm::pow(wheel.load / wheel.coefficient, 2.0 / 3.0);
            wheel.z_velocity = 0.0;
            wheel.z_acceleration = 0.0;
        }
        let n = u.len();
        Ok(TrackState {
            u,
            v: vec![0.0; n],
            a: vec![0.0; n],
        })
    }
}

/// A load vector's non-zero entries, (DOF, value).
type SparseRow = Vec<(usize, f64)>;

/// `row` · `vector`.
fn dot(row: &SparseRow, vector: &[f64]) -> f64 {
    row.iter().map(|&(i, value)| value * vector[i]).sum()
}

/// The Hertz force P with P = C_H max(δ₀ − c P, 0)^(3/2): the one root of
/// a monotone function of P on [0, δ₀ / c], by bisection to the last bit.
fn hertz_force(coefficient: f64, free_compression: f64, compliance: f64) -> f64 {
    if free_compression <= 0.0 {
        return 0.0;
    }
    let excess =
        |p: f64| p - coefficient * libm::pow((free_compression - compliance * p).max(0.0), 1.5);
    let (mut low, mut high) = (0.0, free_compression / compliance);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if middle <= low || middle >= high {
            break;
        }
        if excess(middle) < 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

impl Hht {
    /// One step of the structure and `wheels` coupled through their Hertz
    /// contacts, each wheel under the same HHT-α scheme. The contact
    /// forces are implicit: solved at the new step from the step
    /// compliances (the structure's between every two contacts, the
    /// wheels' own) by Gauss–Seidel sweeps, each a monotone scalar root.
    pub fn advance_wheels(
        &self,
        assembly: &TrackAssembly,
        state: &mut TrackState,
        wheels: &mut [HertzWheel],
    ) -> Result<(), String> {
        let (dt, alpha, gamma, beta) = (self.step, self.alpha, self.gamma, self.beta);
        let n = state.u.len();
        let mut now = vec![0.0; n];
        for wheel in wheels.iter() {
            assembly.add_rail_force(wheel.x, -wheel.force, &mut now)?;
        }
        // The structure's step without the new contact forces.
        let mut free = state.clone();
        self.advance(assembly, &mut free, (&now, &vec![0.0; n]));
        let weight = (1.0 + alpha) * beta * dt * dt;
        let mut rows = Vec::with_capacity(wheels.len());
        let mut units = Vec::with_capacity(wheels.len());
        let mut predicted = Vec::with_capacity(wheels.len());
        let mut compression = Vec::with_capacity(wheels.len());
        for wheel in wheels.iter() {
            let row = assembly.rail_row(wheel.x + wheel.speed * dt)?;
            let mut unit = vec![0.0; n];
            row.iter().for_each(|&(i, value)| unit[i] = value);
            self.factor.solve_in_place(&mut unit);
            let z = wheel.z + dt * wheel.z_velocity + dt * dt * (0.5 - beta) * wheel.z_acceleration;
            let z_free = z + beta
                * dt
                * dt
                * (-(1.0 + alpha) * wheel.load - alpha * (wheel.force - wheel.load))
                / wheel.mass;
            compression.push(dot(&row, &free.u) - z_free);
            predicted.push(z);
            rows.push(row);
            units.push(unit);
        }
        let forces = contact_forces(wheels, &rows, &units, &compression, weight)?;
        for (unit, force) in units.iter().zip(&forces) {
            for (i, unit) in unit.iter().enumerate() {
                let a = -(1.0 + alpha) * force * unit;
                free.a[i] += a;
                free.u[i] += beta * dt * dt * a;
                free.v[i] += gamma * dt * a;
            }
        }
        *state = free;
        for ((wheel, force), z) in wheels.iter_mut().zip(forces).zip(predicted) {
            let acceleration = ((1.0 + alpha) * (force - wheel.load)
                - alpha * (wheel.force - wheel.load))
                / wheel.mass;
            wheel.z_velocity += dt * ((1.0 - gamma) * wheel.z_acceleration + gamma * acceleration);
            wheel.z = z + beta * dt * dt * acceleration;
            wheel.z_acceleration = acceleration;
            wheel.force = force;
            wheel.x += wheel.speed * dt;
        }
        Ok(())
    }
}

/// Most Gauss–Seidel sweeps for a step's contact forces.
const MAX_SWEEPS: usize = 200;

/// The contact forces P_i = C_H max(δ_i − Σ_j G_ij P_j, 0)^(3/2), G_ij =
/// `weight` (row_i · S⁻¹ row_j) + δ_ij `weight` / m_i, by Gauss–Seidel
/// until no force moves by more than 1e-12 of the largest load.
fn contact_forces(
    wheels: &[HertzWheel],
    rows: &[SparseRow],
    units: &[Vec<f64>],
    compression: &[f64],
    weight: f64,
) -> Result<Vec<f64>, String> {
    let count = wheels.len();
    let coupling: Vec<Vec<f64>> = rows
        .iter()
        .map(|row| units.iter().map(|unit| weight * dot(row, unit)).collect())
        .collect();
    let scale = wheels.iter().map(|w| w.load.abs()).fold(0.0, f64::max);
    let mut forces: Vec<f64> = wheels.iter().map(|w| w.force).collect();
    for _ in 0..MAX_SWEEPS {
        let mut moved = 0.0f64;
        for i in 0..count {
            let others: f64 = (0..count)
                .filter(|&j| j != i)
                .map(|j| coupling[i][j] * forces[j])
                .sum();
            let own = coupling[i][i] + weight / wheels[i].mass;
            let force = hertz_force(wheels[i].coefficient, compression[i] - others, own);
            moved = moved.max((force - forces[i]).abs());
            forces[i] = force;
        }
        if moved <= 1e-12 * scale {
            return Ok(forces);
        }
    }
    Err(format!(
        "the {count} contact forces did not settle in {MAX_SWEEPS} Gauss–Seidel sweeps"
    ))
}
