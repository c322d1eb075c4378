//! Entries of the inverse of a factored band matrix at chosen rows and
//! columns, without solving for whole columns (issue 29): the contact
//! iteration's Delassus operator needs the effective matrix's inverse only
//! at the contacts' DOFs.
//!
//! Selected inversion (Takahashi, Fagan and Chen, 1973): from A = L D Lᵀ,
//! Z = A⁻¹ satisfies Z = D⁻¹ L⁻¹ + (I − Lᵀ) Z, so that for i < j
//! Z(i, j) = −Σ_{k=i+1..i+3} L(k, i) Z(k, j), and
//! Z(i, i) = 1/D(i) − Σ_{k=i+1..i+3} L(k, i) Z(k, i).
//! One sweep from the last row up gives Z within the band (O(n), once per
//! factor). An entry farther from the diagonal continues its column's
//! recurrence upwards from the band: the back substitution of a solve,
//! started at the column instead of at the matrix's last row, O(distance)
//! instead of O(n). Written here: no crate offers selected inversion of a
//! band LDLᵀ factor.

use crate::band::BandLdlt;

/// The entries of A⁻¹ within A's band, with the factor's columns they
/// recur on.
#[derive(Debug, Clone)]
pub struct InverseBand {
    /// Row i: Z(i, i), Z(i+1, i), Z(i+2, i), Z(i+3, i) (0 past the last).
    band: Vec<[f64; 4]>,
    /// Row i: L(i+1, i), L(i+2, i), L(i+3, i) (0 past the last).
    below: Vec<[f64; 3]>,
}

impl InverseBand {
    /// The band of the inverse of the factored matrix, in one sweep.
    pub fn new(factor: &BandLdlt) -> InverseBand {
        let (below, inverse_pivot) = factor.columns_below_and_inverse_pivots();
        let n = below.len();
        let mut band = vec![[0.0f64; 4]; n];
        for i in (0..n).rev() {
            let l = below[i];
            // Z(k, j) for k, j in i+1..=i+3: at most 2 apart, in the band.
            let z = |k: usize, j: usize| entry_within(&band, k, j);
            let mut row = [0.0f64; 4];
            for (d, entry) in row.iter_mut().enumerate().skip(1) {
                let j = i + d;
                if j < n {
                    *entry = -(l[0] * z(i + 1, j) + l[1] * z(i + 2, j) + l[2] * z(i + 3, j));
                }
            }
            row[0] = inverse_pivot[i] - (l[0] * row[1] + l[1] * row[2] + l[2] * row[3]);
            band[i] = row;
        }
        InverseBand {
            band,
            below: below.to_vec(),
        }
    }

    pub fn size(&self) -> usize {
        self.band.len()
    }

    /// Z(rows[p], rows[q]) into `out` (column-major, m × m for the m
    /// `rows`, increasing and distinct); returns the rows the column
    /// recurrences walked: Σ over the columns of their distance to the
    /// first row, whatever the matrix's size.
    pub fn entries(&self, rows: &[usize], out: &mut [f64]) -> usize {
        let m = rows.len();
        assert!(out.len() == m * m && rows.windows(2).all(|w| w[0] < w[1]));
        assert!(rows.last().is_none_or(|&r| r < self.size()));
        let Some(&first) = rows.first() else {
            return 0;
        };
        for (q, &b) in rows.iter().enumerate() {
            out[q * m + q] = self.band[b][0];
        }
        // Every column's recurrence upwards at once, row by row: the
        // columns whose own row lies below row i (a suffix of `rows`) each
        // take Z(i, b) from their Z(i+1..=i+3, b). Side by side, the
        // columns' multiply-adds are independent (they vectorise), where
        // one column's each waits on the last.
        let mut z = [vec![0.0; m], vec![0.0; m], vec![0.0; m]];
        let (mut walked, mut started, mut p) = (0, m, m - 1);
        for i in (first..rows[m - 1]).rev() {
            // Columns whose own row is i + 1 start: Z(i+1..=i+3, b).
            while started > 0 && rows[started - 1] == i + 1 {
                started -= 1;
                let b = rows[started];
                z[0][started] = self.band[b][0];
                z[1][started] = entry_within(&self.band, b + 1, b);
                z[2][started] = entry_within(&self.band, b + 2, b);
            }
            let l = &self.below[i];
            let [z0, z1, z2] = &mut z;
            for c in started..m {
                let next = -(l[0] * z0[c] + l[1] * z1[c] + l[2] * z2[c]);
                (z2[c], z1[c], z0[c]) = (z1[c], z0[c], next);
            }
            walked += m - started;
            while rows[p] > i {
                p -= 1;
            }
            if rows[p] == i {
                for q in started..m {
                    (out[q * m + p], out[p * m + q]) = (z0[q], z0[q]);
                }
            }
        }
        walked
    }
}

/// Z(a, b) for |a − b| ≤ 3 from the stored band (0 past the last row).
fn entry_within(band: &[[f64; 4]], a: usize, b: usize) -> f64 {
    let (low, high) = (a.min(b), a.max(b));
    if high >= band.len() {
        return 0.0;
    }
    band[low][high - low]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::band::tests::sample;
    use nalgebra::DMatrix;

    #[test]
    fn chosen_entries_are_those_of_the_dense_inverse() {
        for n in [1usize, 2, 3, 5, 8, 9, 40, 120] {
            let a = sample(n);
            let dense = DMatrix::from_fn(n, n, |i, j| a.get(i, j));
            let inverse = dense.clone().try_inverse().expect("SPD");
            let band = InverseBand::new(&a.ldlt().expect("SPD"));
            // Every row, then a scattered few (the first, far pairs).
            let every: Vec<usize> = (0..n).collect();
            let few: Vec<usize> = [0, 1, n / 3, n / 3 + 2, n - 1]
                .into_iter()
                .filter(|&r| r < n)
                .collect::<std::collections::BTreeSet<_>>()
                .into_iter()
                .collect();
            for rows in [every, few] {
                let m = rows.len();
                let mut out = vec![f64::NAN; m * m];
                let walked = band.entries(&rows, &mut out);
                assert!(walked <= m * n, "n = {n}");
                for (q, &j) in rows.iter().enumerate() {
                    for (p, &i) in rows.iter().enumerate() {
                        let want = inverse[(i, j)];
                        let got = out[q * m + p];
                        assert!(
                            (got - want).abs() <= 1e-13 * inverse.amax(),
                            "n = {n}: Z({i}, {j}) = {got} against {want}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_walk_spans_the_rows_asked_for_not_the_matrix() {
        // Two clusters of rows 30 apart near the end of a long matrix: the
        // recurrences walk back to the first row asked for, never to row 0
        // or from the last row.
        for n in [200usize, 20_000] {
            let band = InverseBand::new(&sample(n).ldlt().expect("SPD"));
            let rows = [n - 60, n - 59, n - 58, n - 30, n - 29];
            let mut out = vec![0.0; 25];
            let walked = band.entries(&rows, &mut out);
            assert_eq!(walked, 1 + 2 + 30 + 31, "n = {n}");
        }
    }
}
