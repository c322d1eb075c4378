//! The beam's element response blocks on HHT-α's nominal steps from the
//! effective matrix's inverse at the contacts' DOFs alone (issue 29): the
//! Delassus operator of all contacts in one pass, no beam solve per
//! contact.
//!
//! From rest, one step of HHT-α under a load f held over it moves the beam
//! by u = w_u A⁻¹ f with velocity v = w_v A⁻¹ f (A the nominal step's
//! effective matrix, `Hht::nominal_band_response`). The operator needs
//! these only at the DOFs of the elements the contacts are on, that is
//! A⁻¹ at those DOFs: its band once per factor, then the entries between
//! the contacts by short recurrences (`band_inverse`), whose length is the
//! distance between the contacts, not the beam's. The whole-beam solves
//! (four per loaded element, `responses`) cost O(elements) each, and made
//! a train's operator on a long viaduct most of its step.

use crate::band::BandLdlt;
use crate::linalg::band_inverse::{InverseBand, Walks};
use crate::system::System;

use super::Part;

use nalgebra::Vector4;

/// A⁻¹'s band for the factor it was taken from, and its entries at the
/// DOFs of one build's elements.
#[derive(Default)]
pub(super) struct Condensed {
    /// The band, and the serial of the factor it was computed from
    /// (compared at each build: a band of another factor is never used;
    /// comparing the factor's pivots instead cost O(n) a build).
    inverse: Option<(InverseBand, u64)>,
    /// The column recurrences of the last build, for the next (`Walks`).
    walks: Walks,
    /// The build's DOFs, increasing, and A⁻¹ among them (column-major).
    dofs: Vec<usize>,
    entries: Vec<f64>,
    /// The next build's DOFs while they are compared with the last's.
    next_dofs: Vec<usize>,
    /// One loaded row's responses at every DOF of the build and, last, at
    /// a DOF the beam holds (`respond`).
    column: Vec<f64>,
    /// Per build element (`elements`), its DOFs' places in `dofs`; a
    /// DOF the beam holds has the held place, `dofs.len()`.
    places: Vec<(usize, [usize; 4])>,
    /// A held DOF's column of A⁻¹ (zeros, `dofs.len()` of them).
    held_column: Vec<f64>,
    /// The response weights (w_u, w_v) of the build.
    weights: (f64, f64),
    /// The elements `prepare` was given, in their order, this build's and
    /// the last's: the same ones of the same band keep `places`, `dofs`
    /// and `entries` without sorting them again.
    given: Vec<usize>,
    last_given: Vec<usize>,
    work: Work,
}

/// What the condensed builds did, for the tests that keep them linear.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    /// Bands of A⁻¹ computed (one sweep over the beam each).
    pub bands: u64,
    /// Operator builds.
    pub builds: u64,
    /// Rows the recurrences between the contacts walked, in all builds
    /// (a column kept from the build before walks only its new rows).
    pub rows_walked: u64,
}

impl Condensed {
    pub fn work(&self) -> Work {
        self.work
    }

    /// Takes A⁻¹ at the DOFs of `elements` (with repeats) for responses of
    /// weights `weights` from `factor`.
    pub fn prepare(
        &mut self,
        (factor, w_u, w_v): (&BandLdlt, f64, f64),
        system: &System,
        elements: impl Iterator<Item = usize>,
    ) {
        let beam = &system.beam;
        let new_band = !matches!(&self.inverse, Some((_, kept)) if *kept == factor.serial());
        if new_band {
            self.inverse = Some((InverseBand::new(factor), factor.serial()));
            self.walks.clear();
            self.work.bands += 1;
        }
        self.weights = (w_u, w_v);
        self.work.builds += 1;
        self.given.clear();
        self.given.extend(elements);
        if !new_band && self.given == self.last_given {
            return;
        }
        std::mem::swap(&mut self.given, &mut self.last_given);
        self.places.clear();
        self.places
            .extend(self.last_given.iter().map(|&e| (e, [0; 4])));
        self.places.sort_unstable_by_key(|p| p.0);
        self.places.dedup_by_key(|p| p.0);
        let mut dofs = std::mem::take(&mut self.next_dofs);
        dofs.clear();
        for &(e, _) in &self.places {
            dofs.extend(beam.element_dofs(e).iter().flatten());
        }
        dofs.sort_unstable();
        dofs.dedup();
        // The same DOFs of the same band: the same entries, already here
        // (the contacts stay on their elements for many steps).
        let kept = !new_band && dofs == self.dofs;
        self.next_dofs = std::mem::replace(&mut self.dofs, dofs);
        let m = self.dofs.len();
        for (e, places) in &mut self.places {
            for (place, dof) in places.iter_mut().zip(beam.element_dofs(*e)) {
                let at = |d| self.dofs.binary_search(&d).expect("listed above");
                *place = dof.map_or(m, at);
            }
        }
        self.held_column.resize(m, 0.0);
        if kept {
            return;
        }
        self.entries.resize(m * m, 0.0);
        let (inverse, _) = self.inverse.as_ref().expect("computed above");
        let walked = inverse.entries(&self.dofs, &mut self.walks, &mut self.entries);
        self.work.rows_walked += walked as u64;
    }

    /// The places in the build's DOFs of element `e`'s (one of
    /// `prepare`'s elements): looked up once per contact, not per pair.
    pub fn places(&self, e: usize) -> [usize; 4] {
        let at = self.places.binary_search_by_key(&e, |p| p.0);
        self.places[at.expect("an element of the build")].1
    }

    /// The responses to a unit load `row` on the DOFs of a loaded element
    /// (its `places`), of `part` only (displacements for the gap operator,
    /// velocities for the velocity operator), at every DOF of the build
    /// and at a held one: once per loaded row, for all the elements
    /// measured (`response_at`). Each is the product of the pair's 4 × 4
    /// block with the row in nalgebra's order (column by column, the
    /// entry w A⁻¹ times the row's, a held DOF's entry 0, summed from the
    /// first column on), so the operator keeps its bits; the four columns
    /// are taken in one pass.
    pub fn respond(&mut self, loaded: [usize; 4], row: &Vector4<f64>, part: Part) {
        let m = self.dofs.len();
        let weight = match part {
            Part::Gap => self.weights.0,
            Part::Velocity => self.weights.1,
        };
        // A held DOF's entry, 0 · 0, is the block's 0.
        let [c0, c1, c2, c3] = loaded.map(|c| match c < m {
            true => (weight, &self.entries[c * m..(c + 1) * m]),
            false => (0.0, self.held_column.as_slice()),
        });
        let [x0, x1, x2, x3] = [row.x, row.y, row.z, row.w];
        self.column.resize(m + 1, 0.0);
        let (free, held) = self.column.split_at_mut(m);
        let loaded_entries = c0.1.iter().zip(c1.1).zip(c2.1).zip(c3.1);
        for (y, (((e0, e1), e2), e3)) in free.iter_mut().zip(loaded_entries) {
            let first = (c1.0 * e1) * x1 + (c0.0 * e0) * x0;
            *y = (c3.0 * e3) * x3 + ((c2.0 * e2) * x2 + first);
        }
        held[0] = 0.0 * x3 + (0.0 * x2 + (0.0 * x1 + 0.0 * x0));
    }

    /// The last `respond`'s responses at a measured element's DOFs (its
    /// `places`).
    #[inline]
    pub fn response_at(&self, measured: [usize; 4]) -> Vector4<f64> {
        Vector4::from(measured.map(|r| self.column[r]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix4;

    /// The pair's 4 × 4 response block as the operator took it before
    /// `respond`: w A⁻¹ at (measured, loaded) places, 0 at a held DOF.
    fn block(c: &Condensed, measured: [usize; 4], loaded: [usize; 4]) -> Matrix4<f64> {
        let m = c.dofs.len();
        Matrix4::from_fn(|k, l| match (measured[k], loaded[l]) {
            (r, col) if r < m && col < m => c.weights.1 * c.entries[col * m + r],
            _ => 0.0,
        })
    }

    #[test]
    fn responses_a_column_at_a_time_are_the_blocks_products_bit_for_bit() {
        let m = 6;
        let mut c = Condensed {
            dofs: (0..m).collect(),
            entries: (0..m * m)
                .map(|i| ((i * 7919 % 101) as f64 - 50.0) * 1.37e-9)
                .collect(),
            weights: (0.3, 1.0 / 3.0),
            held_column: vec![0.0; m],
            ..Default::default()
        };
        c.entries[8] = -0.0;
        let held = m;
        let places = [
            [0, 1, 2, 3],
            [held, held, 4, 5],
            [2, 3, held, held],
            [held, held, held, held],
        ];
        let rows = [
            Vector4::new(0.25, -1.5, 0.75, 1e-3),
            Vector4::new(-0.0, 0.0, -0.0, 0.0),
            Vector4::new(-0.0, -2.0, 0.0, -0.5),
        ];
        for loaded in places {
            for row in &rows {
                c.respond(loaded, row, Part::Velocity);
                for measured in places {
                    let expected = block(&c, measured, loaded) * row;
                    let got = c.response_at(measured);
                    let bits = |v: Vector4<f64>| v.map(f64::to_bits);
                    assert_eq!(bits(got), bits(expected), "{measured:?} {loaded:?} {row}");
                }
            }
        }
    }
}
