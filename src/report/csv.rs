//! The run as CSV: `time` then one column per output, one row per step.

use super::trace::Trace;
use crate::simulation::OutputKind;
use std::io::{self, Write};

/// Writes the header at creation and then one row per call, so that a run
/// streams its results to the file as they are computed.
pub struct CsvWriter<W: Write> {
    out: io::BufWriter<W>,
    kinds: Vec<OutputKind>,
}

impl<W: Write> CsvWriter<W> {
    /// Write the header `time,<names...>`.
    pub fn new(out: W, names: &[String], kinds: &[OutputKind]) -> io::Result<CsvWriter<W>> {
        let mut out = io::BufWriter::new(out);
        write!(out, "time")?;
        for name in names {
            write!(out, ",{name}")?;
        }
        writeln!(out)?;
        Ok(CsvWriter {
            out,
            kinds: kinds.to_vec(),
        })
    }

    /// One row. Reals are written in the shortest form that reads back to
    /// the same `f64` (`0.1`, `1e-7`), integers without a decimal point.
    pub fn row(&mut self, time: f64, values: &[f64]) -> io::Result<()> {
        write!(self.out, "{time:?}")?;
        for (&value, kind) in values.iter().zip(&self.kinds) {
            match kind {
                OutputKind::Integer if value.is_finite() && value.fract() == 0.0 => {
                    write!(self.out, ",{value}")?
                }
                _ => write!(self.out, ",{value:?}")?,
            }
        }
        writeln!(self.out)
    }

    /// Flush and hand back the underlying writer.
    pub fn finish(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

/// Write a whole trace: the header and one row per trace row.
pub fn write_csv(trace: &Trace, out: impl Write) -> io::Result<()> {
    let mut writer = CsvWriter::new(out, &trace.names, &trace.kinds)?;
    let mut values = vec![0.0; trace.columns.len()];
    for (row, &time) in trace.time.iter().enumerate() {
        for (value, column) in values.iter_mut().zip(&trace.columns) {
            *value = column[row];
        }
        writer.row(time, &values)?;
    }
    writer.finish().map(drop)
}
