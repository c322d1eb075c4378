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

/// A measured element's places and a loaded one's (`Condensed::places`).
type PlacesPair = ([Option<usize>; 4], [Option<usize>; 4]);
use nalgebra::Matrix4;

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
    /// Per build element (`elements`), its DOFs' places in `dofs`.
    places: Vec<(usize, [Option<usize>; 4])>,
    /// The response weights (w_u, w_v) of the build.
    weights: (f64, f64),
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
        if !matches!(&self.inverse, Some((_, kept)) if *kept == factor.serial()) {
            self.inverse = Some((InverseBand::new(factor), factor.serial()));
            self.walks.clear();
            self.work.bands += 1;
        }
        self.weights = (w_u, w_v);
        self.places.clear();
        self.places.extend(elements.map(|e| (e, [None; 4])));
        self.places.sort_unstable_by_key(|p| p.0);
        self.places.dedup_by_key(|p| p.0);
        self.dofs.clear();
        for &(e, _) in &self.places {
            self.dofs.extend(beam.element_dofs(e).iter().flatten());
        }
        self.dofs.sort_unstable();
        self.dofs.dedup();
        for (e, places) in &mut self.places {
            for (place, dof) in places.iter_mut().zip(beam.element_dofs(*e)) {
                *place = dof.map(|d| self.dofs.binary_search(&d).expect("listed above"));
            }
        }
        let m = self.dofs.len();
        self.entries.resize(m * m, 0.0);
        let (inverse, _) = self.inverse.as_ref().expect("computed above");
        let walked = inverse.entries(&self.dofs, &mut self.walks, &mut self.entries);
        self.work.builds += 1;
        self.work.rows_walked += walked as u64;
    }

    /// The places in the build's DOFs of element `e`'s (one of
    /// `prepare`'s elements): looked up once per contact, not per pair.
    pub fn places(&self, e: usize) -> [Option<usize>; 4] {
        let at = self.places.binary_search_by_key(&e, |p| p.0);
        self.places[at.expect("an element of the build")].1
    }

    /// The response block of a measured element to unit loads on the DOFs
    /// of a loaded one (their `places`), of `part` only: displacements for
    /// the gap operator, velocities for the velocity operator.
    #[inline]
    pub fn block(&self, (measured, loaded): PlacesPair, part: Part) -> Matrix4<f64> {
        let m = self.dofs.len();
        let weight = match part {
            Part::Gap => self.weights.0,
            Part::Velocity => self.weights.1,
        };
        let mut z = Matrix4::zeros();
        for (l, column) in loaded.iter().enumerate() {
            let Some(column) = column else { continue };
            let entries = &self.entries[column * m..(column + 1) * m];
            for (k, row) in measured.iter().enumerate() {
                if let Some(row) = row {
                    z[(k, l)] = weight * entries[*row];
                }
            }
        }
        z
    }
}
