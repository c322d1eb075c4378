//! The outputs of a run, one row per internal step, kept in memory.

use crate::simulation::{OutputInfo, OutputKind};

/// Time series of every output of a run: `time[i]` and `columns[j][i]` are
/// the time and the value of output `names[j]` after step `i` (row 0 is the
/// initial state).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    pub names: Vec<String>,
    pub units: Vec<String>,
    pub kinds: Vec<OutputKind>,
    pub time: Vec<f64>,
    pub columns: Vec<Vec<f64>>,
}

impl Trace {
    /// An empty trace for a simulation's outputs.
    pub fn for_outputs(outputs: &[OutputInfo]) -> Trace {
        Trace {
            names: outputs.iter().map(|o| o.name.clone()).collect(),
            units: outputs.iter().map(|o| o.unit.to_string()).collect(),
            kinds: outputs.iter().map(|o| o.kind).collect(),
            time: Vec::new(),
            columns: vec![Vec::new(); outputs.len()],
        }
    }

    /// An empty trace of real-valued, unit-less outputs (for tests and
    /// synthetic data).
    pub fn with_names<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Trace {
        let names: Vec<String> = names.into_iter().map(Into::into).collect();
        Trace {
            units: vec![String::new(); names.len()],
            kinds: vec![OutputKind::Real; names.len()],
            columns: vec![Vec::new(); names.len()],
            time: Vec::new(),
            names,
        }
    }

    /// Append one row; `values` are in the order of `names`.
    pub fn push(&mut self, time: f64, values: &[f64]) {
        assert_eq!(
            values.len(),
            self.columns.len(),
            "one value per output expected"
        );
        self.time.push(time);
        for (column, &value) in self.columns.iter_mut().zip(values) {
            column.push(value);
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The values of the output of that name, one per row.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let index = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[index])
    }
}

/// A trace of bounded length for a run of any length: every row while the
/// run is short, then every 2nd, 4th, ... row (the stride doubles whenever
/// the kept rows reach twice `rows`), and always the last row. Enough for a
/// plot, whose width is a few thousand pixels.
#[derive(Debug, Clone)]
pub struct Decimated {
    trace: Trace,
    rows: usize,
    stride: u64,
    seen: u64,
    last: Option<(f64, Vec<f64>)>,
}

impl Decimated {
    /// Keeps between `rows` and `2 × rows` rows (at least 2).
    pub fn new(trace: Trace, rows: usize) -> Decimated {
        Decimated {
            trace,
            rows: rows.max(2),
            stride: 1,
            seen: 0,
            last: None,
        }
    }

    pub fn push(&mut self, time: f64, values: &[f64]) {
        if self.seen.is_multiple_of(self.stride) {
            self.trace.push(time, values);
            self.last = None;
            if self.trace.len() >= 2 * self.rows {
                self.halve();
            }
        } else {
            self.last = Some((time, values.to_vec()));
        }
        self.seen += 1;
    }

    /// Drop every other kept row (row 0 stays).
    fn halve(&mut self) {
        let keep = |i: usize| i.is_multiple_of(2);
        let thin = |v: &mut Vec<f64>| {
            let mut i = 0;
            v.retain(|_| {
                i += 1;
                keep(i - 1)
            });
        };
        thin(&mut self.trace.time);
        self.trace.columns.iter_mut().for_each(thin);
        self.stride *= 2;
    }

    /// The kept rows, ending with the last row pushed.
    pub fn finish(mut self) -> Trace {
        if let Some((time, values)) = self.last.take() {
            self.trace.push(time, &values);
        }
        self.trace
    }
}
