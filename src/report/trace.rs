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
