//! A block Delassus operator assembled over the entries its contacts can
//! couple, and inverted block by block (issue 29).
//!
//! An entry (row of contact i, column of contact j) can be nonzero only
//! where i and j load each other: both on the beam (measured and applied
//! there) or on one body. The operator's matrix is kept zero between
//! builds; a build lists those entries (`Assembly::list`), the caller
//! writes them, and masking the open contacts, checking, finding the
//! blocks and cleaning up walk that list alone: a train's contacts on rigid
//! ground no longer cost a pass over all rows² (zeroing, masking, the
//! pattern's scan were a fifth of a run). The blocks are the connected
//! components of the nonzero entries, exactly as a scan of the whole matrix
//! finds them, so each block is inverted on the same entries in the same
//! row order as before: the same bits.

use nalgebra::{DMatrix, DVector, Dyn, LU};

/// Operators up to this many rows are inverted explicitly, larger ones
/// by their blocks.
pub(super) const EXPLICIT_INVERSE_ROWS: usize = 16;

/// Groups above this many rows are factored, smaller ones inverted (closed
/// forms up to 4 rows). An operator is applied about 3 times a build: a
/// train's 12-row group cost 15k instructions to invert and 4k to factor,
/// while an application costs 0.3k more.
const FACTORED_GROUP_ROWS: usize = 4;

/// A Delassus operator ready to apply: its inverse when small (one product
/// per application, and what the paper's scenes have always computed), its
/// LU factors (a group of a larger one: a third of the flops of
/// inverting), or its blocks.
pub(super) enum Inverted {
    Inverse(DMatrix<f64>),
    Factors(LU<f64, Dyn, Dyn>),
    /// A large operator that falls apart into blocks no entry couples
    /// (contacts on rigid ground, open contacts, spans that do not load
    /// each other), each inverted on its own: of a train's 32 contacts a
    /// dozen are on the bridge, and factoring 32 rows was a tenth of its run.
    Blocks(Layout),
    /// Rolling contacts' operator by Woodbury's identity (`low_rank`).
    LowRank(Box<super::low_rank::LowRank>),
}

/// How an operator falls apart: single rows, and groups of rows inverted
/// together (with room to gather and scatter them). Kept from one build to
/// the next with its storage, and found again only when the operator's
/// nonzero pattern changes (a vehicle enters or leaves a span, a contact
/// opens).
pub(super) struct Layout {
    /// A row no entry couples to another, and its diagonal entry.
    singles: Vec<(usize, f64)>,
    groups: Vec<Group>,
    /// The nonzero pattern the blocks were found for (`Pattern`).
    pattern: Pattern,
}

/// Which entries of a listing are nonzero: the listing's serial
/// (`Assembly::list`), and a flag per listed entry, in their order.
#[derive(Clone, PartialEq, Eq)]
struct Pattern {
    listing: u64,
    nonzero: Vec<bool>,
}

/// Listed entries of one column: its rows `first..first + count`.
#[derive(Debug, Clone, Copy)]
struct Run {
    column: u32,
    first: u32,
    count: u32,
}

impl Run {
    fn rows(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    /// Its entries' places in an n × n column-major matrix.
    fn places(&self, n: usize) -> std::ops::Range<usize> {
        let start = self.column as usize * n + self.first as usize;
        start..start + self.count as usize
    }
}

/// Rows an operator's entries couple, inverted together.
struct Group {
    rows: Vec<usize>,
    inverted: Inverted,
    gathered: DVector<f64>,
    solved: DVector<f64>,
}

/// One contact's place in a build's operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ContactRows {
    /// Its first row and its rows' count.
    pub first: usize,
    pub count: usize,
    pub body: usize,
    /// Measured on the beam (its rows load-coupled there), and its force
    /// applied on the beam.
    pub measured_on_beam: bool,
    pub applied_on_beam: bool,
    /// An open contact: identity rows and columns.
    pub open: bool,
}

/// An operator's matrix, zero outside a build, and the entries a build
/// writes.
pub(super) struct Assembly {
    /// n × n; between builds every entry is zero.
    pub matrix: DMatrix<f64>,
    /// The build's contacts, filled by the caller before `list`.
    pub contacts: Vec<ContactRows>,
    /// Those `entries` were listed for.
    listed_for: Vec<ContactRows>,
    /// The entries the build may write, column by column, each column's
    /// rows increasing and run together where they follow each other (the
    /// contacts on the beam are mostly neighbours: a run is a slice of
    /// the matrix, no index an entry); empty on an operator inverted whole
    /// (`EXPLICIT_INVERSE_ROWS`).
    runs: Vec<Run>,
    /// The entries the runs hold.
    listed_entries: usize,
    /// Whether a contact is open.
    any_open: bool,
    /// Per row: its contact is open (read only when `any_open`).
    open_rows: Vec<bool>,
    /// Scratch: the contacts measured on the beam, increasing; a column's
    /// rows' contacts.
    measured: Vec<usize>,
    rows_of: Vec<usize>,
    /// The serial of `entries` (a new one each time they are listed again).
    listing: u64,
    /// The nonzero entries after masking.
    pattern: Pattern,
}

impl Default for Assembly {
    fn default() -> Assembly {
        Assembly {
            matrix: DMatrix::zeros(0, 0),
            contacts: Vec::new(),
            listed_for: Vec::new(),
            runs: Vec::new(),
            listed_entries: 0,
            any_open: false,
            open_rows: Vec::new(),
            measured: Vec::new(),
            rows_of: Vec::new(),
            listing: 0,
            pattern: Pattern {
                listing: 0,
                nonzero: Vec::new(),
            },
        }
    }
}

/// Lists `rows` of column `column` after the runs of `runs`: in the last
/// run where they follow it.
fn push_rows(runs: &mut Vec<Run>, column: usize, rows: std::ops::Range<usize>) {
    let (column, first, count) = (column as u32, rows.start as u32, rows.len() as u32);
    match runs.last_mut() {
        Some(last) if last.column == column && last.first + last.count == first => {
            last.count += count;
        }
        _ => runs.push(Run {
            column,
            first,
            count,
        }),
    }
}

/// The union of two increasing lists, increasing, into `out`.
fn merge_sorted(a: &[usize], b: &[usize], out: &mut Vec<usize>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (x, y) = (a[i], b[j]);
        out.push(x.min(y));
        i += usize::from(x <= y);
        j += usize::from(y <= x);
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
}

impl Assembly {
    /// Whether an operator of n rows is inverted whole: written, masked,
    /// checked and zeroed whole, with no listing (`whole`), as the
    /// paper's scenes' operators were before the listing.
    fn inverted_whole(n: usize) -> bool {
        n <= EXPLICIT_INVERSE_ROWS
    }

    /// Readies an operator of n rows inverted whole (`inverted_whole`) for
    /// a build: its open contacts' rows alone, no listing.
    fn whole(&mut self, n: usize) {
        if self.matrix.nrows() != n {
            self.matrix = DMatrix::zeros(n, n);
            self.listed_for.clear();
            self.runs.clear();
        }
        // `open_rows` is read only when a contact is open: the paper's
        // scenes, all closed, skip it.
        self.any_open = false;
        let open = self.contacts.iter().filter(|c| c.open);
        for &ContactRows { first, count, .. } in open {
            if !self.any_open {
                self.open_rows.clear();
                self.open_rows.resize(n, false);
                self.any_open = true;
            }
            self.open_rows[first..first + count].fill(true);
        }
    }

    /// Lists the entries of an n × n operator over `self.contacts` (their
    /// bodies' contacts in `contacts_of_body`, increasing): the pairs both
    /// on the beam, and the pairs on one body. The list of the build
    /// before is kept while the contacts' places are the same.
    pub fn list(&mut self, n: usize, contacts_of_body: &[Vec<usize>]) {
        if Self::inverted_whole(n) {
            return self.whole(n);
        }
        if self.matrix.nrows() != n {
            self.matrix = DMatrix::zeros(n, n);
            self.listed_for.clear();
        }
        if self.contacts == self.listed_for {
            return;
        }
        self.listed_for.clone_from(&self.contacts);
        self.listing += 1;
        self.any_open = self.contacts.iter().any(|c| c.open);
        self.open_rows.clear();
        self.open_rows.resize(n, false);
        for c in self.contacts.iter().filter(|c| c.open) {
            self.open_rows[c.first..c.first + c.count].fill(true);
        }
        self.runs.clear();
        let contacts = &self.contacts;
        self.measured.clear();
        let on_beam = (0..contacts.len()).filter(|&c| contacts[c].measured_on_beam);
        self.measured.extend(on_beam);
        for column in contacts {
            let body = contacts_of_body[column.body].as_slice();
            let rows_of = if column.applied_on_beam {
                merge_sorted(&self.measured, body, &mut self.rows_of);
                self.rows_of.as_slice()
            } else {
                body
            };
            for b in column.first..column.first + column.count {
                for row in rows_of.iter().map(|&i| &contacts[i]) {
                    push_rows(&mut self.runs, b, row.first..row.first + row.count);
                }
            }
        }
        self.listed_entries = self.runs.iter().map(|run| run.count as usize).sum();
    }

    /// Masks the open rows and columns (identity), checks the entries and
    /// finds the nonzero ones; whether every entry is finite.
    fn mask_and_check(&mut self) -> bool {
        let n = self.matrix.nrows();
        let matrix = self.matrix.as_mut_slice();
        if n <= EXPLICIT_INVERSE_ROWS {
            let open = self.open_rows.iter().enumerate().filter(|(_, &open)| open);
            if self.any_open {
                for (r, _) in open {
                    matrix[r * n..(r + 1) * n].fill(0.0);
                    matrix.iter_mut().skip(r).step_by(n).for_each(|x| *x = 0.0);
                    matrix[r * n + r] = 1.0;
                }
            }
            return matrix.iter().all(|x| x.is_finite());
        }
        if self.any_open {
            for run in &self.runs {
                let c = run.column as usize;
                for r in run.rows() {
                    if self.open_rows[r] || self.open_rows[c] {
                        matrix[c * n + r] = if r == c { 1.0 } else { 0.0 };
                    }
                }
            }
        }
        // Branch-free, a flag an entry, a run's slice at a time: pushing
        // the nonzero entries and comparing them with the last build's was
        // most of this pass.
        let mut finite = true;
        self.pattern.listing = self.listing;
        self.pattern.nonzero.resize(self.listed_entries, false);
        let mut flags = self.pattern.nonzero.as_mut_slice();
        for run in &self.runs {
            let (these, rest) = flags.split_at_mut(run.count as usize);
            for (nonzero, &x) in these.iter_mut().zip(&matrix[run.places(n)]) {
                finite &= x.is_finite();
                *nonzero = x != 0.0;
            }
            flags = rest;
        }
        finite
    }

    /// The nonzero entries (row, column) of the build.
    fn nonzero(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.entries()
            .zip(&self.pattern.nonzero)
            .filter(|(_, &nonzero)| nonzero)
            .map(|(entry, _)| entry)
    }

    /// The listed entries (row, column), in their order.
    fn entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.runs.iter()).flat_map(|run| run.rows().map(|r| (r, run.column as usize)))
    }

    /// Zeroes the entries the build wrote.
    pub fn clean(&mut self) {
        let n = self.matrix.nrows();
        let matrix = self.matrix.as_mut_slice();
        if n <= EXPLICIT_INVERSE_ROWS {
            matrix.fill(0.0);
            return;
        }
        for run in &self.runs {
            matrix[run.places(n)].fill(0.0);
        }
    }

    /// The written operator, masked, inverted (reusing `previous`'s storage,
    /// and its blocks while the nonzero pattern is the same); None if an
    /// entry is not finite or it is singular. Leaves the matrix zero.
    pub fn invert(&mut self, previous: Inverted) -> Option<Inverted> {
        let finite = self.mask_and_check();
        let inverted = finite.then(|| self.inverted(previous)).flatten();
        // A blocked operator's gathering left the matrix zero.
        if !matches!(inverted, Some(Inverted::Blocks(_))) {
            self.clean();
        }
        inverted
    }

    fn inverted(&mut self, previous: Inverted) -> Option<Inverted> {
        let n = self.matrix.nrows();
        if n <= EXPLICIT_INVERSE_ROWS {
            // Inverted in place; the last inverse's storage, zeroed by
            // `clean`, holds the next build.
            let mut inverse = match previous {
                Inverted::Inverse(m) if m.nrows() == n => m,
                _ => DMatrix::zeros(n, n),
            };
            std::mem::swap(&mut inverse, &mut self.matrix);
            return inverse
                .try_inverse_mut()
                .then_some(Inverted::Inverse(inverse));
        }
        let mut layout = match previous {
            Inverted::Blocks(layout) if layout.pattern == self.pattern => layout,
            _ => {
                let (singles, groups) = decoupled_blocks(n, self.nonzero());
                Layout::new(singles, groups, self.pattern.clone())
            }
        };
        layout.invert(&mut self.matrix)?;
        Some(Inverted::Blocks(layout))
    }
}

impl Layout {
    fn new(singles: Vec<usize>, groups: Vec<Vec<usize>>, pattern: Pattern) -> Layout {
        let groups = groups
            .into_iter()
            .map(|rows| {
                let n = rows.len();
                Group {
                    rows,
                    inverted: Inverted::Inverse(DMatrix::zeros(n, n)),
                    gathered: DVector::zeros(n),
                    solved: DVector::zeros(n),
                }
            })
            .collect();
        Layout {
            singles: singles.into_iter().map(|i| (i, 0.0)).collect(),
            groups,
            pattern,
        }
    }

    /// Takes the single rows' diagonals and inverts the groups of
    /// `matrix` (of this layout's pattern); None if any is singular.
    /// Zeroes what it takes: every nonzero entry is a single's diagonal
    /// or within a group, so a success leaves `matrix` zero (no pass of
    /// `Assembly::clean` over the listing); a failure leaves it to clean.
    fn invert(&mut self, matrix: &mut DMatrix<f64>) -> Option<()> {
        let n = matrix.nrows();
        let entries = matrix.as_mut_slice();
        for (i, d) in &mut self.singles {
            let x = std::mem::take(&mut entries[*i * n + *i]);
            if x == 0.0 || !x.is_finite() {
                return None;
            }
            *d = x;
        }
        for group in &mut self.groups {
            let k = group.rows.len();
            let taken =
                std::mem::replace(&mut group.inverted, Inverted::Inverse(DMatrix::zeros(0, 0)));
            let mut storage: Vec<f64> = match taken {
                Inverted::Inverse(m) => m.data.into(),
                _ => Vec::with_capacity(k * k),
            };
            storage.clear();
            take_block(entries, n, &group.rows, &mut storage);
            let mut sub = DMatrix::from_vec(k, k, storage);
            group.inverted = if k > FACTORED_GROUP_ROWS {
                let lu = sub.lu();
                lu.is_invertible().then_some(Inverted::Factors(lu))?
            } else {
                sub.try_inverse_mut().then_some(Inverted::Inverse(sub))?
            };
        }
        Some(())
    }
}

/// Takes the entries of `rows` × `rows` (increasing, two or more) out of
/// the n × n column-major `entries` into `block`, column by column, and
/// leaves zeros there; a column's slice at a time where the rows follow
/// each other (a group of contacts on the beam), not an index an entry.
fn take_block(entries: &mut [f64], n: usize, rows: &[usize], block: &mut Vec<f64>) {
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let contiguous = last - first + 1 == rows.len();
    for &j in rows {
        let column = &mut entries[j * n..(j + 1) * n];
        if contiguous {
            let taken = &mut column[first..=last];
            block.extend_from_slice(taken);
            taken.fill(0.0);
        } else {
            block.extend(rows.iter().map(|&i| std::mem::take(&mut column[i])));
        }
    }
}

/// The n rows grouped by the blocks the nonzero entries `couplings` (row,
/// column) tie together (connected components, each in increasing row
/// order, in the order of their first rows): the rows alone in theirs,
/// then the groups of two or more.
fn decoupled_blocks(
    n: usize,
    couplings: impl Iterator<Item = (usize, usize)>,
) -> (Vec<usize>, Vec<Vec<usize>>) {
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for (i, j) in couplings {
        if i != j && root[i] != root[j] {
            let (a, b) = (find(&mut root, i), find(&mut root, j));
            root[a.max(b)] = a.min(b);
        }
    }
    for i in 0..n {
        root[i] = find(&mut root, i);
    }
    let mut sizes = vec![0usize; n];
    for &r in &root {
        sizes[r] += 1;
    }
    let singles: Vec<usize> = (0..n).filter(|&i| sizes[root[i]] == 1).collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    // Each group's index, at its root (the component's first row).
    let mut group_of = vec![usize::MAX; n];
    for (i, &r) in root.iter().enumerate() {
        if sizes[r] < 2 {
            continue;
        }
        if group_of[r] == usize::MAX {
            group_of[r] = groups.len();
            groups.push(Vec::with_capacity(sizes[r]));
        }
        groups[group_of[r]].push(i);
    }
    (singles, groups)
}

impl Inverted {
    /// An operator of n rows not built yet.
    pub fn unbuilt(n: usize) -> Inverted {
        Inverted::Inverse(DMatrix::zeros(n, n))
    }

    /// `out` = A⁻¹ `b`.
    pub fn apply(&mut self, b: &DVector<f64>, out: &mut DVector<f64>) {
        match self {
            Inverted::Inverse(m) => out.gemv(1.0, m, b, 0.0),
            Inverted::Factors(lu) => {
                out.copy_from(b);
                // Invertible by construction.
                lu.solve_mut(out);
            }
            Inverted::LowRank(w) => w.apply(b, out),
            Inverted::Blocks(layout) => {
                for &(i, d) in &layout.singles {
                    out[i] = b[i] / d;
                }
                for group in &mut layout.groups {
                    for (k, &i) in group.rows.iter().enumerate() {
                        group.gathered[k] = b[i];
                    }
                    group.inverted.apply(&group.gathered, &mut group.solved);
                    for (k, &i) in group.rows.iter().enumerate() {
                        out[i] = group.solved[k];
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `m`'s operator with every row a contact of its own on the beam
    /// (every entry listed), `open` ones open; inverted from `previous`.
    fn assembled(m: &DMatrix<f64>, open: &[usize], previous: Inverted) -> Option<Inverted> {
        let n = m.nrows();
        let contacts = (0..n)
            .map(|c| ContactRows {
                first: c,
                count: 1,
                body: c,
                measured_on_beam: true,
                applied_on_beam: true,
                open: open.contains(&c),
            })
            .collect();
        let mut assembly = Assembly {
            contacts,
            ..Default::default()
        };
        let bodies: Vec<Vec<usize>> = (0..n).map(|c| vec![c]).collect();
        assembly.list(n, &bodies);
        assembly.matrix.copy_from(m);
        let inverted = assembly.invert(previous);
        assert_eq!(assembly.matrix.amax(), 0.0, "left zero");
        inverted
    }

    fn solved(inverted: &mut Inverted, b: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(b.len());
        inverted.apply(b, &mut out);
        out
    }

    #[test]
    fn an_operator_that_falls_apart_is_solved_block_by_block() {
        // 24 rows: a coupled 5-row block and a 2-row block interleaved with
        // 17 single rows (contacts on the ground), in scattered order.
        let n = 24;
        let big = [1, 4, 9, 15, 22];
        let pair = [3, 17];
        let mut m = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            m[(i, i)] = 2.0 + 0.1 * i as f64;
        }
        for (a, &i) in big.iter().enumerate() {
            for (b, &j) in big.iter().enumerate() {
                if i != j {
                    m[(i, j)] = 0.3 / (1.0 + (a as f64 - 0.5 * b as f64).abs());
                }
            }
        }
        m[(3, 17)] = 0.7;
        m[(17, 3)] = -0.4;
        let nonzero = (0..n * n)
            .map(|k| (k % n, k / n))
            .filter(|&(i, j)| m[(i, j)] != 0.0);
        let (singles, groups) = decoupled_blocks(n, nonzero);
        assert_eq!(singles.len(), n - 7);
        assert!(singles
            .iter()
            .all(|i| !big.contains(i) && !pair.contains(i)));
        assert_eq!(groups, vec![big.to_vec(), pair.to_vec()]);
        let b = DVector::from_fn(n, |i, _| libm::sin(i as f64 * 0.37) + 0.2);
        let expected = m.clone().lu().solve(&b).unwrap();
        let mut inverted = assembled(&m, &[], Inverted::unbuilt(0)).unwrap();
        assert!(matches!(inverted, Inverted::Blocks(..)));
        let out = solved(&mut inverted, &b);
        assert!((&out - &expected).amax() < 1e-14, "{out} vs {expected}");
        // A singular single row is refused, as a singular whole is.
        let mut singular = DMatrix::<f64>::identity(n, n);
        singular[(5, 5)] = 0.0;
        assert!(assembled(&singular, &[], Inverted::unbuilt(0)).is_none());
        // A non-finite entry too.
        let mut infinite = m.clone();
        infinite[(4, 9)] = f64::INFINITY;
        assert!(assembled(&infinite, &[], Inverted::unbuilt(0)).is_none());
    }

    #[test]
    fn open_contacts_are_identity_rows_and_columns() {
        // Row 4 couples the 5-row block to row 20; opened, it leaves the
        // rest of the block and row 20 apart, and its error unchanged.
        let n = 21;
        let mut m = DMatrix::<f64>::from_fn(n, n, |i, j| if i == j { 3.0 } else { 0.0 });
        for &(i, j) in &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 20), (20, 4), (4, 0)] {
            m[(i, j)] = 0.5;
        }
        let mut masked = m.clone();
        masked.row_mut(4).fill(0.0);
        masked.column_mut(4).fill(0.0);
        masked[(4, 4)] = 1.0;
        let b = DVector::from_fn(n, |i, _| 1.0 + 0.25 * i as f64);
        let expected = masked.clone().lu().solve(&b).unwrap();
        let mut inverted = assembled(&m, &[4], Inverted::unbuilt(0)).unwrap();
        let Inverted::Blocks(layout) = &inverted else {
            panic!("blocks expected");
        };
        assert_eq!(layout.groups.len(), 1);
        assert_eq!(layout.groups[0].rows, vec![0, 1, 2, 3]);
        assert!(layout.singles.contains(&(4, 1.0)));
        let out = solved(&mut inverted, &b);
        assert!((&out - &expected).amax() < 1e-14, "{out} vs {expected}");
        assert_eq!(out[4], b[4]);
    }

    #[test]
    fn a_rebuilt_operator_reuses_its_blocks_only_while_its_pattern_holds() {
        let n = 20;
        let operator = |coupled: &[(usize, usize)], scale: f64| {
            let mut m = DMatrix::<f64>::zeros(n, n);
            for i in 0..n {
                m[(i, i)] = scale * (3.0 + 0.1 * i as f64);
            }
            for &(i, j) in coupled {
                m[(i, j)] = 0.5 * scale;
                m[(j, i)] = -0.25 * scale;
            }
            m
        };
        let b = DVector::from_fn(n, |i, _| libm::cos(i as f64 * 0.53) - 0.1);
        let check = |inverted: &mut Inverted, m: &DMatrix<f64>| {
            let expected = m.clone().lu().solve(&b).unwrap();
            let out = solved(inverted, &b);
            assert!((&out - &expected).amax() < 1e-13, "{out} vs {expected}");
        };
        let groups = |inverted: &Inverted| -> Vec<Vec<usize>> {
            match inverted {
                Inverted::Blocks(layout) => layout.groups.iter().map(|g| g.rows.clone()).collect(),
                _ => panic!("blocks expected"),
            }
        };
        // Six rows coupled in a chain (factored), two in a pair.
        let chain = [(2, 5), (5, 7), (7, 11), (11, 12), (12, 18), (0, 9)];
        let first = operator(&chain, 1.0);
        let mut inverted = assembled(&first, &[], Inverted::unbuilt(0)).unwrap();
        check(&mut inverted, &first);
        // The same pattern, other values: the blocks are kept (the same
        // groups' storage).
        let kept = groups(&inverted);
        let Inverted::Blocks(layout) = &inverted else {
            unreachable!()
        };
        let storage = layout.groups[1].gathered.as_ptr();
        let mut inverted = assembled(&operator(&chain, 2.0), &[], inverted).unwrap();
        check(&mut inverted, &operator(&chain, 2.0));
        assert_eq!(groups(&inverted), kept);
        let Inverted::Blocks(layout) = &inverted else {
            unreachable!()
        };
        assert_eq!(layout.groups[1].gathered.as_ptr(), storage);
        // A new coupling joins the pair to the chain: found again.
        let joined = [&chain[..], &[(9, 18)]].concat();
        let mut inverted = assembled(&operator(&joined, 1.5), &[], inverted).unwrap();
        assert_eq!(groups(&inverted), vec![vec![0, 2, 5, 7, 9, 11, 12, 18]]);
        check(&mut inverted, &operator(&joined, 1.5));
        // A group made singular (its first column zero) is refused.
        let mut singular = operator(&joined, 1.0);
        for &i in &[0, 2, 5, 7, 9, 11, 12, 18] {
            singular[(i, 0)] = 0.0;
        }
        assert!(assembled(&singular, &[], inverted).is_none());
    }

    #[test]
    fn a_small_operator_is_masked_whole_without_a_listing() {
        // Six rows: contact 1 (rows 2 and 3) open in the first build, none
        // in the second (the mask of the first is not kept).
        let n = 6;
        let m = DMatrix::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                4.0 + i as f64
            } else {
                0.3 / (1.0 + (i as f64 - 0.7 * j as f64).abs())
            }
        });
        let b = DVector::from_fn(n, |i, _| 1.0 - 0.3 * i as f64);
        let mut masked = m.clone();
        for r in [2, 3] {
            masked.row_mut(r).fill(0.0);
            masked.column_mut(r).fill(0.0);
            masked[(r, r)] = 1.0;
        }
        let mut assembly = Assembly::default();
        let mut previous = Inverted::unbuilt(n);
        let bodies: Vec<Vec<usize>> = (0..3).map(|c| vec![c]).collect();
        for (open, expected) in [(true, &masked), (false, &m)] {
            assert!(Assembly::inverted_whole(n));
            assembly.contacts = (0..3)
                .map(|c| ContactRows {
                    first: 2 * c,
                    count: 2,
                    body: c,
                    measured_on_beam: true,
                    applied_on_beam: true,
                    open: open && c == 1,
                })
                .collect();
            assembly.list(n, &bodies);
            assert!(assembly.runs.is_empty(), "no listing");
            assembly.matrix.copy_from(&m);
            let mut inverted = assembly.invert(previous).unwrap();
            assert_eq!(assembly.matrix.amax(), 0.0, "left zero");
            let out = solved(&mut inverted, &b);
            let direct = expected.clone().lu().solve(&b).unwrap();
            assert!((&out - &direct).amax() < 1e-14, "{out} vs {direct}");
            previous = inverted;
        }
    }

    #[test]
    fn the_listed_entries_are_the_pairs_on_the_beam_and_on_one_body() {
        // Contacts 0 and 1 (two rows each) on body 0, 2 (one row) on body
        // 1, 3 (one row) on body 2; 0 and 2 measured on the beam, 1 and 2
        // applied there.
        let contact = |first, count, body, on: (bool, bool)| ContactRows {
            first,
            count,
            body,
            measured_on_beam: on.0,
            applied_on_beam: on.1,
            open: false,
        };
        let mut assembly = Assembly {
            contacts: vec![
                contact(0, 2, 0, (true, false)),
                contact(2, 2, 0, (false, true)),
                contact(4, 1, 1, (true, true)),
                contact(5, 1, 2, (false, false)),
            ],
            ..Default::default()
        };
        let bodies = vec![vec![0, 1], vec![2], vec![3]];
        // 17 rows: above those inverted whole (the last 11 no contact's).
        assembly.list(17, &bodies);
        let entries: Vec<_> = assembly.entries().collect();
        let mut listed = entries.clone();
        listed.sort_unstable();
        listed.dedup();
        assert_eq!(listed.len(), entries.len(), "each entry once");
        let body_block = |a: usize, b: usize| a < 4 && b < 4;
        let beam = |a: usize, b: usize| [0, 1, 4].contains(&a) && [2, 3, 4].contains(&b);
        let expected: Vec<(usize, usize)> = (0..6)
            .flat_map(|r| (0..6).map(move |c| (r, c)))
            .filter(|&(r, c)| body_block(r, c) || beam(r, c) || r == c)
            .collect();
        assert_eq!(listed, expected);
        // Column-major, rows increasing, the rows that follow each other
        // run together.
        let keys: Vec<_> = entries.iter().map(|&(r, c)| (c, r)).collect();
        assert!(keys.windows(2).all(|w| w[0] < w[1]), "{keys:?}");
        let runs: Vec<_> = (assembly.runs.iter())
            .map(|run| (run.column, run.first, run.count))
            .collect();
        let expected_runs = [
            (0, 0, 4),
            (1, 0, 4),
            (2, 0, 5),
            (3, 0, 5),
            (4, 0, 2),
            (4, 4, 1),
            (5, 5, 1),
        ];
        assert_eq!(runs, expected_runs);
    }
}
