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

    /// Z(a, b) where |a − b| ≤ 3 (within the band), else None.
    pub fn entry(&self, a: usize, b: usize) -> Option<f64> {
        (a.abs_diff(b) <= 3 && a.max(b) < self.size()).then(|| entry_within(&self.band, a, b))
    }

    /// Z(rows[p], rows[q]) into `out` (column-major, m × m for the m
    /// `rows`, increasing and distinct); returns the rows the column
    /// recurrences walked: Σ over the columns of their distance to the
    /// first row, whatever the matrix's size, less what `walks` kept of
    /// them from the last call. Each entry is a function of its row and
    /// column alone, so a kept one has the bits of one walked again.
    pub fn entries(&self, rows: &[usize], walks: &mut Walks, out: &mut [f64]) -> usize {
        let m = rows.len();
        assert!(out.len() == m * m && rows.windows(2).all(|w| w[0] < w[1]));
        assert!(rows.last().is_none_or(|&r| r < self.size()));
        let Some(&first) = rows.first() else {
            walks.columns.clear();
            return 0;
        };
        // The columns asked for again keep their walks (both lists are
        // increasing); the others' storage is reused.
        let mut kept = std::mem::take(&mut walks.columns).into_iter().peekable();
        let mut columns = Vec::with_capacity(m);
        let mut walked = 0;
        for &b in rows {
            while let Some((_, walk)) = kept.next_if(|(old, _)| *old < b) {
                walks.spare.push(walk);
            }
            let mut walk = match kept.next_if(|(old, _)| *old == b) {
                Some((_, walk)) => walk,
                None => {
                    let mut walk = walks.spare.pop().unwrap_or_default();
                    walk.clear();
                    walk
                }
            };
            walked += self.walk_down(b, first, &mut walk);
            columns.push((b, walk));
        }
        walks.spare.extend(kept.map(|(_, walk)| walk));
        for (q, (b, walk)) in columns.iter().enumerate() {
            out[q * m + q] = self.band[*b][0];
            for (p, &a) in rows[..q].iter().enumerate() {
                let z = walk[b - 1 - a];
                (out[q * m + p], out[p * m + q]) = (z, z);
            }
        }
        walks.columns = columns;
        walked
    }

    /// Continues column b's recurrence upwards (`walk` holds Z(b − 1 − d,
    /// b) for d = 0, 1, …) down to row `first`; returns the rows added.
    /// One column's multiply-adds wait on each other, but a build walks
    /// only the columns that are new to it (a contact entering an
    /// element): walking all of them side by side at every build was a
    /// twentieth of the long viaduct's run.
    fn walk_down(&self, b: usize, first: usize, walk: &mut Vec<f64>) -> usize {
        let (done, wanted) = (walk.len(), b - first);
        if done >= wanted {
            return 0;
        }
        // Z(k, b) for the rows k just above the next one.
        let above = |walk: &[f64], k: usize| {
            if k >= b {
                entry_within(&self.band, k, b)
            } else {
                walk[b - 1 - k]
            }
        };
        let next_row = b - 1 - done;
        let (mut z0, mut z1, mut z2) = (
            above(walk, next_row + 1),
            above(walk, next_row + 2),
            above(walk, next_row + 3),
        );
        walk.reserve(wanted - done);
        for l in self.below[first..=next_row].iter().rev() {
            let next = -(l[0] * z0 + l[1] * z1 + l[2] * z2);
            walk.push(next);
            (z2, z1, z0) = (z1, z0, next);
        }
        wanted - done
    }
}

/// The column recurrences of `InverseBand::entries` kept for its next
/// call on the same band: a train's operator asks for nearly the same
/// columns at every step.
#[derive(Debug, Clone, Default)]
pub struct Walks {
    /// Per column b asked for (increasing): Z(b − 1 − d, b), d = 0, 1, ….
    columns: Vec<(usize, Vec<f64>)>,
    /// Storage of columns no longer asked for.
    spare: Vec<Vec<f64>>,
}

impl Walks {
    /// Forget every walk (the band they were taken from is gone).
    pub fn clear(&mut self) {
        let columns = self.columns.drain(..).map(|(_, walk)| walk);
        self.spare.extend(columns);
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
                let walked = band.entries(&rows, &mut Walks::default(), &mut out);
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
            let walked = band.entries(&rows, &mut Walks::default(), &mut out);
            assert_eq!(walked, 1 + 2 + 30 + 31, "n = {n}");
        }
    }

    #[test]
    fn kept_walks_give_the_bits_of_fresh_ones_and_walk_only_what_is_new() {
        // A cluster of rows moving up a long matrix build by build, as a
        // train's contacts do: each build's entries are those of a build
        // from nothing, bit for bit, and only the new columns (and rows
        // below where the kept ones stopped) are walked.
        let n = 2_000;
        let band = InverseBand::new(&sample(n).ldlt().expect("SPD"));
        let mut walks = Walks::default();
        let builds: [&[usize]; 5] = [
            &[100, 101, 102, 103, 160, 161, 162, 163],
            &[100, 101, 102, 103, 160, 161, 162, 163],
            &[102, 103, 104, 105, 160, 161, 162, 163],
            &[102, 103, 104, 105, 162, 163, 164, 165],
            &[90, 91, 92, 93, 162, 163, 164, 165],
        ];
        let mut walked_kept = Vec::new();
        for rows in builds {
            let m = rows.len();
            let (mut kept, mut fresh) = (vec![0.0; m * m], vec![0.0; m * m]);
            walked_kept.push(band.entries(rows, &mut walks, &mut kept));
            let walked_fresh = band.entries(rows, &mut Walks::default(), &mut fresh);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&kept), bits(&fresh), "{rows:?}");
            assert_eq!(
                walked_fresh,
                rows.iter().map(|r| r - rows[0]).sum::<usize>()
            );
        }
        // The first build walks everything, the same rows again nothing;
        // then the two new columns 104, 105 (2 + 3 rows), the two new
        // 164, 165 (62 + 63); then the new 90..=93 (0 + 1 + 2 + 3) and the
        // kept 162, 163 (walked to 100) and 164, 165 (to 102) on down to 90.
        let from_nothing = |rows: &[usize]| rows.iter().map(|r| r - rows[0]).sum::<usize>();
        let last = 6 + 2 * 10 + 2 * 12;
        assert_eq!(walked_kept, vec![from_nothing(builds[0]), 0, 5, 125, last]);
        // Cleared (another band), everything is walked again.
        walks.clear();
        let mut again = vec![0.0; 64];
        let walked = band.entries(builds[4], &mut walks, &mut again);
        assert_eq!(walked, from_nothing(builds[4]));
    }
}
