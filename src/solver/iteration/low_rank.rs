//! The velocity operator of rolling contacts on a beam without a surface
//! offset, in its low-rank form (issue 29).
//!
//! Without a surface offset both rows a rolling contact j applies to the
//! beam are its shape functions N_j times (sin φ_j, cos φ_j)
//! (`ContactFrame::beam_rows`): the beam sees one force a contact. So the
//! operator is W = D + P Vᵀ, with D the bodies' blocks (a wheelset's 2 × 2),
//! P the measured rows' responses to each applied contact's N_j (k columns,
//! k the contacts applied on the beam) and V the k columns of (sin φ_j,
//! cos φ_j) at contact j's rows. Woodbury's identity,
//!   W⁻¹ = D⁻¹ − D⁻¹ P S⁻¹ Vᵀ D⁻¹,   S = I + Vᵀ D⁻¹ P,
//! factors S of k rows instead of W's 2k on the beam: an eighth of the
//! flops, half the responses to take (condensed on HHT-α's nominal step,
//! a beam solve each on a shortened one) and a quarter of the entries to
//! write. The rounding is not the dense operator's, so a rolling train's
//! iterates move within the iteration's tolerance; operators inverted
//! whole (the paper's scenes, `EXPLICIT_INVERSE_ROWS`) keep the dense form.

use nalgebra::{DMatrix, DVector, Dyn, Vector4, LU};

use super::operator::{Inverted, EXPLICIT_INVERSE_ROWS};
use super::{ContactIteration, Part};
use crate::contact::ContactFrame;
use crate::system::System;

/// W⁻¹ by Woodbury's identity, its storage kept from build to build.
#[derive(Default)]
pub(super) struct LowRank {
    /// The bodies with contacts, each a block of D over its contacts' rows
    /// (in order), laid out once for the operator's rows (`lay_out`).
    blocks: Vec<Block>,
    block_rows: Vec<usize>,
    /// D, then D⁻¹, block by block (each column-major).
    inverses: Vec<f64>,
    /// Per row: its block and its place there.
    place_of_row: Vec<(usize, usize)>,
    /// The contacts applied on the beam, closed: V's columns; and the
    /// contacts measured there, closed (`fill_integrated`).
    columns: Vec<Column>,
    applied: Vec<usize>,
    measured: Vec<usize>,
    /// The measured contacts' beam rows, turned (`fill_integrated`).
    measured_rows: Vec<[Vector4<f64>; 2]>,
    /// The rows of the blocks the beam's responses reach (those of the
    /// bodies of closed contacts measured on it), block by block, and each
    /// row's index among them (`UNREACHED` elsewhere).
    reached: Vec<usize>,
    compact: Vec<usize>,
    /// Q = D⁻¹ P over the reached rows, column-major, each column with a
    /// zero last (where an unreached row of V reads it: no branch).
    q: Vec<f64>,
    /// S = I + Vᵀ Q, factored (None when k = 0).
    s: Option<LU<f64, Dyn, Dyn>>,
    /// Vᵀ D⁻¹ b, then S⁻¹ of it; Q S⁻¹ Vᵀ D⁻¹ b over the reached rows
    /// (`apply`).
    z: DVector<f64>,
    correction: Vec<f64>,
    /// A block's entries gathered (and solved), for blocks of more than
    /// two rows.
    gathered: Vec<f64>,
}

/// One body's block of D: its rows at `rows..rows + size` of
/// `LowRank::block_rows`, its entries from `entries` of
/// `LowRank::inverses`.
#[derive(Debug, Clone, Copy)]
struct Block {
    rows: usize,
    size: usize,
    entries: usize,
}

/// A row no response reaches.
const UNREACHED: usize = usize::MAX;

/// An applied contact's column of V: its rows (1 or 2), their
/// coefficients (0 past its rows) and their places in a column of Q (the
/// column's zero where not reached).
#[derive(Debug, Clone, Copy)]
struct Column {
    first: usize,
    count: usize,
    coefficients: [f64; 2],
    reached: [usize; 2],
}

impl Column {
    /// vᵀ x over the column's rows.
    fn dot(&self, x: &[f64]) -> f64 {
        let c = &self.coefficients;
        match self.count {
            1 => c[0] * x[self.first],
            _ => c[0] * x[self.first] + c[1] * x[self.first + 1],
        }
    }

    /// vᵀ q over one column `q` of Q.
    #[inline(always)]
    fn dot_reached(&self, q: &[f64]) -> f64 {
        self.coefficients[0] * q[self.reached[0]] + self.coefficients[1] * q[self.reached[1]]
    }
}

/// `out` = A `x` for a g × g block `a` (column-major), g = `x.len()`.
#[inline(always)]
fn block_times(a: &[f64], x: &[f64], out: &mut [f64]) {
    let g = x.len();
    for (r, out) in out[..g].iter_mut().enumerate() {
        *out = (0..g).map(|c| a[c * g + r] * x[c]).sum();
    }
}

/// Inverts a g × g column-major block in place; false if singular or not
/// finite.
fn invert_block(block: &mut [f64]) -> bool {
    let inverted = match block.len() {
        1 => {
            let d = block[0];
            block[0] = 1.0 / d;
            d != 0.0
        }
        4 => {
            let [a, b, c, d] = [block[0], block[1], block[2], block[3]];
            let det = a * d - b * c;
            block.copy_from_slice(&[d / det, -b / det, -c / det, a / det]);
            det != 0.0
        }
        len => {
            let g = (len as f64).sqrt().round() as usize;
            let mut m = DMatrix::from_column_slice(g, g, block);
            let ok = m.try_inverse_mut();
            block.copy_from_slice(m.as_slice());
            ok
        }
    };
    inverted && block.iter().all(|x| x.is_finite())
}

impl LowRank {
    /// `out` = W⁻¹ `b`.
    pub(super) fn apply(&mut self, b: &DVector<f64>, out: &mut DVector<f64>) {
        let (b, x) = (b.as_slice(), out.as_mut_slice());
        for block in &self.blocks {
            let rows = &self.block_rows[block.rows..block.rows + block.size];
            let inverse = &self.inverses[block.entries..];
            if let [r0, r1] = *rows {
                let (u, v) = (b[r0], b[r1]);
                x[r0] = inverse[0] * u + inverse[2] * v;
                x[r1] = inverse[1] * u + inverse[3] * v;
                continue;
            }
            let g = block.size;
            self.gathered.clear();
            self.gathered.extend(rows.iter().map(|&r| b[r]));
            self.gathered.resize(2 * g, 0.0);
            let (gathered, solved) = self.gathered.split_at_mut(g);
            block_times(&inverse[..g * g], gathered, solved);
            for (&r, &value) in rows.iter().zip(solved.iter()) {
                x[r] = value;
            }
        }
        let Some(s) = &self.s else {
            return;
        };
        for (z, column) in self.z.iter_mut().zip(&self.columns) {
            *z = column.dot(x);
        }
        s.solve_mut(&mut self.z);
        let reached = self.reached.len();
        let correction = &mut self.correction[..reached];
        correction.fill(0.0);
        for (q, &y) in self.q.chunks_exact(reached + 1).zip(self.z.iter()) {
            for (t, &qr) in correction.iter_mut().zip(&q[..reached]) {
                *t += qr * y;
            }
        }
        for (&r, &t) in self.reached.iter().zip(correction.iter()) {
            x[r] -= t;
        }
    }

    /// Lays out the bodies' blocks over the operator's `n` rows (each
    /// body's contacts' rows, `rows`) where not laid out yet (the bodies'
    /// contacts and their rows stay for a run), and zeroes D.
    fn lay_out(
        &mut self,
        n: usize,
        contacts_of_body: &[Vec<usize>],
        rows: impl Fn(usize) -> (usize, usize),
    ) {
        if self.place_of_row.len() == n {
            self.inverses.fill(0.0);
            return;
        }
        self.blocks.clear();
        self.block_rows.clear();
        self.place_of_row.clear();
        self.place_of_row.resize(n, (usize::MAX, 0));
        let mut entries = 0;
        for contacts in contacts_of_body.iter().filter(|c| !c.is_empty()) {
            let start = self.block_rows.len();
            for &c in contacts {
                let (first, count) = rows(c);
                self.block_rows.extend(first..first + count);
            }
            let size = self.block_rows.len() - start;
            for (place, &r) in self.block_rows[start..].iter().enumerate() {
                self.place_of_row[r] = (self.blocks.len(), place);
            }
            self.blocks.push(Block {
                rows: start,
                size,
                entries,
            });
            entries += size * size;
        }
        self.inverses.clear();
        self.inverses.resize(entries, 0.0);
    }

    /// Adds `x` at (row, column) of D (both on one body).
    fn add_to_d(&mut self, row: usize, column: usize, x: f64) {
        let ((block, r), (same, c)) = (self.place_of_row[row], self.place_of_row[column]);
        debug_assert_eq!(block, same, "a body part couples one body's rows");
        let block = self.blocks[block];
        self.inverses[block.entries + c * block.size + r] += x;
    }

    /// Identity rows and columns at the `open` rows, then D⁻¹ block by
    /// block; false if a block is singular or not finite.
    fn mask_and_invert(&mut self, open: impl Iterator<Item = usize>) -> bool {
        for row in open {
            let (block, place) = self.place_of_row[row];
            let Block { size, entries, .. } = self.blocks[block];
            let entries = &mut self.inverses[entries..entries + size * size];
            for k in 0..size {
                entries[k * size + place] = 0.0;
                entries[place * size + k] = 0.0;
            }
            entries[place * size + place] = 1.0;
        }
        (self.blocks.iter())
            .all(|b| invert_block(&mut self.inverses[b.entries..b.entries + b.size * b.size]))
    }

    /// The reached rows: those of the blocks of the measured contacts'
    /// first rows `firsts`.
    fn reach(&mut self, n: usize, firsts: impl IntoIterator<Item = usize>) {
        self.reached.clear();
        self.compact.clear();
        self.compact.resize(n, UNREACHED);
        for first in firsts {
            let (block, _) = self.place_of_row[first];
            let Block { rows, size, .. } = self.blocks[block];
            let rows = &self.block_rows[rows..rows + size];
            if self.compact[rows[0]] != UNREACHED {
                continue;
            }
            for &r in rows {
                self.compact[r] = self.reached.len();
                self.reached.push(r);
            }
        }
    }

    /// Q ← D⁻¹ Q (Q holding P), block by reached block; then S = I + Vᵀ Q,
    /// factored. False if S is singular or not finite.
    fn condense(&mut self) -> bool {
        let (reached, k) = (self.reached.len(), self.columns.len());
        let mut at = 0;
        while at < reached {
            let (block, _) = self.place_of_row[self.reached[at]];
            let Block { size, entries, .. } = self.blocks[block];
            let inverse = &self.inverses[entries..entries + size * size];
            let columns = self.q.chunks_exact_mut(reached + 1);
            match size {
                2 => {
                    let a: &[f64; 4] = inverse.try_into().expect("a 2 × 2 block");
                    for q in columns {
                        let (u, v) = (q[at], q[at + 1]);
                        q[at] = a[0] * u + a[2] * v;
                        q[at + 1] = a[1] * u + a[3] * v;
                    }
                }
                _ => {
                    for q in columns {
                        self.gathered.clear();
                        self.gathered.extend_from_slice(&q[at..at + size]);
                        block_times(inverse, &self.gathered, &mut q[at..at + size]);
                    }
                }
            }
            at += size;
        }
        if self.z.len() != k {
            self.z = DVector::zeros(k);
        }
        self.correction.resize(reached, 0.0);
        if k == 0 {
            self.s = None;
            return true;
        }
        let mut s = Vec::with_capacity(k * k);
        for (j, q) in self.q.chunks_exact(reached + 1).enumerate() {
            s.extend(self.columns.iter().map(|column| column.dot_reached(q)));
            s[j * k + j] += 1.0;
        }
        if !s.iter().chain(&self.q).all(|x| x.is_finite()) {
            return false;
        }
        let lu = DMatrix::from_vec(k, k, s).lu();
        let invertible = lu.is_invertible();
        self.s = Some(lu);
        invertible
    }
}

impl ContactIteration {
    /// Whether the step's velocity operator is built in its low-rank form:
    /// no surface offset, an operator above those inverted whole, a closed
    /// rolling contact applied on the beam (gliders have a row a contact
    /// already), and responses either condensed (HHT-α's nominal step on
    /// the band factor) or integrated (a shortened step); a nominal step
    /// of another solve reads its cached element responses in the dense
    /// form.
    pub(super) fn low_rank_applies(
        &self,
        system: &System,
        applied: &[ContactFrame],
        dt: f64,
    ) -> bool {
        // The operators inverted whole (the paper's scenes) first: one
        // comparison a build.
        if self.rows <= EXPLICIT_INVERSE_ROWS || system.beam.surface_offset != 0.0 {
            return false;
        }
        let nominal = crate::solver::parameters::is_nominal_step(dt, self.nominal_step);
        let condensed = self.integrator.nominal_band_response().is_some();
        let rolling_on_beam = (system.contacts.iter().zip(applied).zip(&self.open))
            .any(|((c, f), &open)| c.rolls() && f.on_beam && !open);
        (condensed || !nominal) && rolling_on_beam
    }

    /// The velocity operator in the frames `(measured, applied)` in its
    /// low-rank form (`low_rank_applies`), reusing `previous`'s storage;
    /// None if D or S is singular or not finite, or the step's deadline
    /// passed (the caller builds the dense form instead, or refuses).
    pub(super) fn build_low_rank(
        &mut self,
        system: &System,
        (measured_frames, applied_frames): (&[ContactFrame], &[ContactFrame]),
        dt: f64,
        previous: Inverted,
    ) -> Option<Inverted> {
        let mut w = match previous {
            Inverted::LowRank(w) => w,
            _ => Box::default(),
        };
        let n = self.rows;
        let rows = |c: usize| (self.offsets[c], system.contacts[c].rows());
        w.lay_out(n, &self.contacts_of_body, rows);
        let frames = (measured_frames, applied_frames);
        self.body_entries(system, frames, (dt, Part::Velocity), |r, c, x| {
            w.add_to_d(r, c, x)
        });
        let open = (0..system.contacts.len()).filter(|&c| self.open[c]);
        if !w.mask_and_invert(open.flat_map(|c| {
            let (first, count) = rows(c);
            first..first + count
        })) {
            return None;
        }
        match crate::solver::parameters::is_nominal_step(dt, self.nominal_step) {
            true => self.fill_condensed(system, frames, &mut w),
            false if self.fill_integrated(system, frames, dt, &mut w) => {}
            false => return None,
        }
        w.condense().then_some(Inverted::LowRank(w))
    }

    /// V's columns (the closed contacts applied on the beam, with their
    /// coefficients and their rows' places among the reached ones), and
    /// Q zeroed for P.
    fn lay_columns(&self, system: &System, applied_frames: &[ContactFrame], w: &mut LowRank) {
        w.columns.clear();
        let zero = w.reached.len();
        w.applied.clear();
        let closed = (0..system.contacts.len()).filter(|&c| self.closed_on_beam(c, applied_frames));
        w.applied.extend(closed);
        for &c in &w.applied {
            let frame = &applied_frames[c];
            let coefficients = match system.contacts[c].rolls() {
                true => [frame.sin, frame.cos],
                false => [frame.cos, 0.0],
            };
            let (first, count) = (self.offsets[c], system.contacts[c].rows());
            let reached = [0, 1].map(|a| match a < count {
                true => Some(w.compact[first + a]).filter(|&r| r != UNREACHED),
                false => None,
            });
            w.columns.push(Column {
                first,
                count,
                coefficients,
                reached: reached.map(|r| r.unwrap_or(zero)),
            });
        }
        w.q.clear();
        w.q.resize((zero + 1) * w.columns.len(), 0.0);
    }

    /// Whether contact c is closed and on the beam in `frames`.
    fn closed_on_beam(&self, c: usize, frames: &[ContactFrame]) -> bool {
        !self.open[c] && frames[c].on_beam
    }

    /// P's entries over the reached rows into `w.q`, and V's columns: the
    /// responses of the closed contacts measured on the beam to each closed
    /// contact's N applied there, from the condensed blocks.
    fn fill_condensed(
        &mut self,
        system: &System,
        (measured_frames, applied_frames): (&[ContactFrame], &[ContactFrame]),
        w: &mut LowRank,
    ) {
        let frames = (measured_frames, applied_frames);
        let mut measured = self.prepare_condensed(system, frames, Part::Velocity);
        measured.retain(|m| !self.open[m.contact]);
        w.reach(self.rows, measured.iter().map(|m| m.first));
        self.lay_columns(system, applied_frames, w);
        let reached = w.reached.len();
        for (j, &c) in w.applied.iter().enumerate() {
            let shape = &applied_frames[c].shape;
            let loaded = self.condensed.places(shape.element);
            self.condensed
                .respond(loaded, &Vector4::from(shape.n), Part::Velocity);
            let column = &mut w.q[j * (reached + 1)..(j + 1) * (reached + 1)];
            for m in &measured {
                let response = self.condensed.response_at(m.places);
                for (a, &ki) in m.kinds.iter().enumerate() {
                    column[w.compact[m.first + a]] = m.rows[ki].dot(&response);
                }
            }
        }
        self.measured_on_beam = measured;
    }

    /// `fill_condensed` on a step of another length: the beam's response
    /// to each applied contact's N integrated (one beam solve a contact,
    /// kept while the same load on a step of the same length recurs, as
    /// the dense form's are a row), read at the measured rows. False if
    /// the step's deadline passed (or cannot be met) before the solves.
    fn fill_integrated(
        &mut self,
        system: &System,
        (measured_frames, applied_frames): (&[ContactFrame], &[ContactFrame]),
        dt: f64,
        w: &mut LowRank,
    ) -> bool {
        if !self.within_deadline(system, applied_frames, false) {
            return false;
        }
        let beam = &system.beam;
        w.measured.clear();
        let measured =
            (0..system.contacts.len()).filter(|&c| self.closed_on_beam(c, measured_frames));
        w.measured.extend(measured);
        // Each measured contact's rows once, not once per applied contact.
        w.measured_rows.clear();
        let h = beam.surface_offset;
        let rows = |&i: &usize| self.measured_beam_rows(i, &measured_frames[i], h, Part::Velocity);
        w.measured_rows.extend(w.measured.iter().map(rows));
        let firsts: Vec<usize> = w.measured.iter().map(|&c| self.offsets[c]).collect();
        w.reach(self.rows, firsts);
        self.lay_columns(system, applied_frames, w);
        self.reserve_responses(self.rows);
        let reached = w.reached.len();
        for (j, &c) in w.applied.iter().enumerate() {
            let shape = &applied_frames[c].shape;
            let slot = self.offsets[c];
            let key = super::ResponseKey::new(dt, &shape.dofs, &shape.n);
            if self.response_keys[slot] != Some(key) {
                self.response_keys[slot] = Some(key);
                self.load.fill(0.0);
                beam.scatter(shape, &shape.n, 1.0, &mut self.load);
                let (u, v) = (&mut self.response_u[slot], &mut self.response_v[slot]);
                self.integrator.beam_response(system, &self.load, dt, u, v);
                self.delassus_beam_solves += 1;
            }
            let column = &mut w.q[j * (reached + 1)..(j + 1) * (reached + 1)];
            for (&i, rows) in w.measured.iter().zip(&w.measured_rows) {
                let frame = &measured_frames[i];
                let kinds = super::row_kinds(system.contacts[i].rolls());
                for (a, &ki) in kinds.iter().enumerate() {
                    let row: [f64; 4] = rows[ki].into();
                    let entry = beam.dot(&frame.shape, &row, &self.response_v[slot]);
                    column[w.compact[self.offsets[i] + a]] = entry;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn woodburys_form_solves_the_dense_operator() {
        // Three bodies: two of one contact of two rows, one of two contacts
        // (three rows: a wheel and a glider); the second body's contact
        // open. D + P Vᵀ against its dense LU.
        let n = 7;
        let contacts_of_body = vec![vec![0], vec![1], vec![2, 3]];
        let rows = [(0, 2), (2, 2), (4, 2), (6, 1)];
        let mut w = LowRank::default();
        w.lay_out(n, &contacts_of_body, |c| rows[c]);
        let mut dense = DMatrix::<f64>::zeros(n, n);
        let blocks: [&[usize]; 3] = [&[0, 1], &[2, 3], &[4, 5, 6]];
        for rows in blocks {
            for (a, &r) in rows.iter().enumerate() {
                for (b, &c) in rows.iter().enumerate() {
                    let x = if r == c {
                        2.0 + 0.1 * r as f64
                    } else {
                        0.3 / (1.0 + (a + 2 * b) as f64)
                    };
                    w.add_to_d(r, c, x);
                    dense[(r, c)] += x;
                }
            }
        }
        assert!(w.mask_and_invert([2, 3].into_iter()));
        // Contacts 0, 2 and 3 closed on the beam, measured and applied.
        let measured_rows = [0usize, 4, 6];
        w.reach(n, measured_rows);
        assert_eq!(w.reached, vec![0, 1, 4, 5, 6]);
        w.columns = [
            (0, 2, [0.1, 0.99]),
            (4, 2, [-0.05, 0.998]),
            (6, 1, [0.97, 0.0]),
        ]
        .map(|(first, count, coefficients)| Column {
            first,
            count,
            coefficients,
            reached: [0, 1].map(|a| if a < count { w.compact[first + a] } else { 5 }),
        })
        .to_vec();
        let k = w.columns.len();
        let p = DMatrix::<f64>::from_fn(n, k, |r, j| {
            if [0, 1, 4, 5, 6].contains(&r) {
                0.4 / (1.0 + (r as f64 - 2.5 * j as f64).abs())
            } else {
                0.0
            }
        });
        // Each column of Q with its zero last.
        let rows_and_zero: Vec<Option<usize>> =
            w.reached.iter().map(|&r| Some(r)).chain([None]).collect();
        let p_at = |r: Option<usize>, j: usize| r.map_or(0.0, |r| p[(r, j)]);
        w.q = (0..k)
            .flat_map(|j| rows_and_zero.iter().map(move |&r| p_at(r, j)))
            .collect();
        let mut v = DMatrix::<f64>::zeros(n, k);
        for (j, column) in w.columns.iter().enumerate() {
            for a in 0..column.count {
                v[(column.first + a, j)] = column.coefficients[a];
            }
        }
        assert!(w.condense());
        let mut expected = dense + &p * v.transpose();
        for r in [2, 3] {
            expected.row_mut(r).fill(0.0);
            expected.column_mut(r).fill(0.0);
            expected[(r, r)] = 1.0;
        }
        let b = DVector::from_fn(n, |i, _| 1.0 - 0.37 * i as f64);
        let direct = expected.lu().solve(&b).unwrap();
        let mut out = DVector::zeros(n);
        w.apply(&b, &mut out);
        assert!((&out - &direct).amax() < 1e-14, "{out} vs {direct}");
        assert_eq!((out[2], out[3]), (b[2], b[3]), "open rows pass their error");
    }

    #[test]
    fn a_singular_or_non_finite_part_is_refused_for_the_dense_form() {
        // One body of one rolling contact: D singular (a massless body's
        // zero block), then D regular but S singular (P Vᵀ cancelling D's
        // coupling to the beam exactly), then a non-finite response.
        let contacts_of_body = vec![vec![0]];
        let rows = [(0, 2)];
        let laid_out = |d: [f64; 4]| {
            let mut w = LowRank::default();
            w.lay_out(2, &contacts_of_body, |c| rows[c]);
            for (k, x) in d.into_iter().enumerate() {
                w.add_to_d(k % 2, k / 2, x);
            }
            w
        };
        assert!(!laid_out([0.0; 4]).mask_and_invert(std::iter::empty()));
        let with_column = |p: [f64; 2]| {
            let mut w = laid_out([1.0, 0.0, 0.0, 1.0]);
            assert!(w.mask_and_invert(std::iter::empty()));
            w.reach(2, [0]);
            w.columns = vec![Column {
                first: 0,
                count: 2,
                coefficients: [0.6, 0.8],
                reached: [0, 1],
            }];
            w.q = vec![p[0], p[1], 0.0];
            w.condense()
        };
        assert!(with_column([0.3, 0.4]));
        // S = 1 + 0.6 p₀ + 0.8 p₁ = 0.
        assert!(!with_column([-0.6, -0.8]));
        assert!(!with_column([f64::NAN, 0.4]));
    }

    /// `count` paper wheels spread over a 40-element beam without a
    /// surface offset, rolling at 83 m/s under HHT-α of nominal step `dt`.
    fn rolling_wheels_on_hht(
        dt: f64,
        count: usize,
    ) -> (System, crate::integrate::DynamicState, ContactIteration) {
        let mut scene = crate::integrate::fixtures::two_paper_wheels();
        scene.beam.elements = 40;
        // The low-rank form needs the rows applied without an offset.
        scene.beam.surface_offset = 0.0;
        let wheel = scene.vehicles[0].clone();
        scene.vehicles = (0..count)
            .map(|i| {
                let mut v = wheel.clone();
                v.name = format!("wheel{i}");
                v.initial_position = 1.5 + 2.5 * i as f64;
                v
            })
            .collect();
        super::super::tests::moving_on_hht(&scene, 83.0, dt)
    }

    #[test]
    fn a_rolling_trains_low_rank_operator_is_the_dense_one_and_the_steps_jacobian() {
        // Nine wheels (18 rows, above those inverted whole), on the nominal
        // step (condensed responses) and a shortened one (integrated): the
        // operator in its low-rank form against the dense operator of the
        // same frames (to rounding), and against finite differences of
        // whole integrations, W⁻¹ J = I.
        let nominal = 1e-3;
        for dt in [nominal, 0.37 * nominal] {
            low_rank_against_dense_and_jacobian(nominal, dt);
        }
    }

    fn low_rank_against_dense_and_jacobian(nominal: f64, dt: f64) {
        use crate::contact::ContactForce;
        use crate::system::TrackPart;
        use nalgebra::Vector3;
        let (system, start, mut iteration) = rolling_wheels_on_hht(nominal, 9);
        let rows = iteration.rows;
        assert_eq!(rows, 18);
        let parts = vec![TrackPart::Beam; 9];
        let applied = vec![Vector3::zeros(); system.bodies.len()];
        let loose = super::super::IterationSettings {
            velocity_tolerance: f64::INFINITY,
            gap_tolerance: f64::INFINITY,
            max_iterations: 1,
        };
        let base = vec![
            ContactForce {
                tangential: 50.0,
                normal: 2e4,
            };
            9
        ];
        let mut end = start.clone();
        let mut errors = |iteration: &mut ContactIteration, forces: &[ContactForce]| {
            iteration
                .solve(
                    &system, &start, &parts, forces, &applied, dt, &loose, &mut end,
                )
                .unwrap();
            iteration.velocity_errors(&system, &end);
            iteration.error.clone()
        };
        // Central differences of 1 N: the frames' own motion under the
        // push (second order) cancels.
        let mut jacobian = DMatrix::zeros(rows, rows);
        for column in 0..rows {
            let mut pushed = [base.clone(), base.clone()];
            for (forces, push) in pushed.iter_mut().zip([1.0, -1.0]) {
                let force = &mut forces[column / 2];
                match column % 2 {
                    0 => force.tangential += push,
                    _ => force.normal += push,
                }
            }
            let difference =
                errors(&mut iteration, &pushed[0]) - errors(&mut iteration, &pushed[1]);
            jacobian.set_column(column, &(0.5 * difference));
        }
        errors(&mut iteration, &base);
        iteration.delassus.built = false;
        let frames = iteration.start_frames.clone();
        iteration
            .build_delassus(&system, (&frames, &end), dt, Part::Velocity)
            .unwrap();
        assert!(matches!(iteration.delassus.velocity, Inverted::LowRank(_)));
        let measured = iteration.delassus.frames.clone();
        let mut assembly = super::super::Assembly::default();
        let at = (measured.as_slice(), measured.as_slice());
        iteration
            .assemble(&system, at, (dt, Part::Velocity), &mut assembly)
            .unwrap();
        let mut dense = assembly.invert(Inverted::unbuilt(0)).unwrap();
        assert!(!matches!(dense, Inverted::LowRank(_)));
        let (mut low, mut full) = (DVector::zeros(rows), DVector::zeros(rows));
        let mut product = DMatrix::<f64>::zeros(rows, rows);
        for j in 0..rows {
            let column: DVector<f64> = jacobian.column(j).into();
            iteration.delassus.velocity.apply(&column, &mut low);
            dense.apply(&column, &mut full);
            let scale = full.amax();
            assert!(
                (&low - &full).amax() <= 1e-12 * scale,
                "column {j}: {low} vs {full}"
            );
            product.set_column(j, &low);
        }
        // The dense operator is this step's Jacobian to 2.7e-7 here (a
        // wheel's normal row under its own tangential force; the gliders'
        // test holds 1e-7): the low-rank form is held to the same measure,
        // far below the 0.3 % the first correction needs.
        let deviation = (product - DMatrix::<f64>::identity(rows, rows)).amax();
        assert!(deviation < 1e-6, "{deviation:e}");
    }
}
