//! The run as CSV: `time` then one column per output, one row per step.

use super::trace::Trace;
use crate::simulation::OutputKind;
use std::io::{self, Write};

/// Write the header `time,<names...>` and one row per trace row. Reals are
/// written in the shortest form that reads back to the same `f64` (`0.1`,
/// `1e-7`, `NaN`, `inf`), integers without a decimal point.
pub fn write_csv(trace: &Trace, out: impl Write) -> io::Result<()> {
    let mut out = io::BufWriter::new(out);
    write!(out, "time")?;
    for name in &trace.names {
        write!(out, ",{name}")?;
    }
    writeln!(out)?;
    for (row, time) in trace.time.iter().enumerate() {
        write!(out, "{time:?}")?;
        for (column, kind) in trace.columns.iter().zip(&trace.kinds) {
            let value = column[row];
            match kind {
                OutputKind::Integer if value.is_finite() && value.fract() == 0.0 => {
                    write!(out, ",{value}")?
                }
                _ => write!(out, ",{value:?}")?,
            }
        }
        writeln!(out)?;
    }
    out.flush()
}
