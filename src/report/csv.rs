//! The run as CSV: `time` then one column per output, one row per step.

use super::shortest::push_debug;
use super::trace::Trace;
use crate::simulation::OutputKind;
use std::io::{self, Write};

/// Writes the header at creation and then one row per call, so that a run
/// streams its results to the file as they are computed.
pub struct CsvWriter<W: Write> {
    out: io::BufWriter<W>,
    kinds: Vec<OutputKind>,
    /// A row's text, made in memory and written at once.
    line: Vec<u8>,
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
            line: Vec::new(),
        })
    }

    /// One row. Reals are written in the shortest form that reads back to
    /// the same `f64` (`0.1`, `1e-7`: `{:?}`'s text, `shortest`),
    /// integers without a decimal point (`{}`'s).
    pub fn row(&mut self, time: f64, values: &[f64]) -> io::Result<()> {
        let line = &mut self.line;
        line.clear();
        push_debug(line, time);
        for (&value, kind) in values.iter().zip(&self.kinds) {
            line.push(b',');
            match kind {
                OutputKind::Integer if is_whole(value) => push_whole(line, value),
                _ => push_debug(line, value),
            }
        }
        line.push(b'\n');
        self.out.write_all(line)
    }

    /// Flush and hand back the underlying writer.
    pub fn finish(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

/// Whether `value` is a finite whole number (`fract() == 0`, without
/// its call to libm's `trunc` for each integer column of each row).
fn is_whole(value: f64) -> bool {
    // From 2⁵² on every finite f64 is whole; below, the cast truncates.
    match value.abs() < 4_503_599_627_370_496.0 {
        true => (value as i64) as f64 == value,
        false => value.is_finite(),
    }
}

/// Append the whole number `value` as `{value}` writes it (`3`, `-0`).
fn push_whole(line: &mut Vec<u8>, value: f64) {
    // Below 2⁵³ every whole f64 is an i64 written with the same digits.
    if value.abs() < 9_007_199_254_740_992.0 && !(value == 0.0 && value.is_sign_negative()) {
        line.extend_from_slice(itoa::Buffer::new().format(value as i64).as_bytes());
    } else {
        line.extend_from_slice(value.to_string().as_bytes());
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A whole number is `{}`'s text (std's formatter is the reference),
    /// the signed zero and the largest magnitudes included.
    #[test]
    fn whole_numbers_are_written_as_display_writes_them() {
        let big = 9_007_199_254_740_992.0;
        let values = [
            0.0,
            -0.0,
            1.0,
            -7.0,
            4201.0,
            big - 1.0,
            big,
            -big,
            1e300,
            f64::MAX,
        ];
        for value in values {
            let mut line = Vec::new();
            push_whole(&mut line, value);
            assert_eq!(String::from_utf8(line).expect("ASCII"), format!("{value}"));
        }
    }

    /// `is_whole` is `fract() == 0` of a finite value (std the reference).
    #[test]
    fn whole_is_a_finite_value_without_a_fraction() {
        let values = [
            0.0,
            -0.0,
            2.0,
            -3.0,
            0.5,
            -2.5,
            1e-300,
            4503599627370495.5,
            4503599627370496.0,
            1e300,
            f64::MAX,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for value in values {
            let expected = value.is_finite() && value.fract() == 0.0;
            assert_eq!(is_whole(value), expected, "{value:?}");
        }
    }

    /// A row is the time and each value, reals as `{:?}` and integers as
    /// `{}` write them, a non-whole integer column as a real.
    #[test]
    fn a_row_is_debugs_and_displays_text() {
        let names = ["a".to_string(), "n".to_string(), "m".to_string()];
        let kinds = [OutputKind::Real, OutputKind::Integer, OutputKind::Integer];
        let mut writer = CsvWriter::new(Vec::new(), &names, &kinds).expect("header");
        writer.row(0.25, &[-1.5e-7, 3.0, 2.5]).expect("row");
        writer
            .row(1e16, &[f64::NAN, -0.0, f64::INFINITY])
            .expect("row");
        let text = String::from_utf8(writer.finish().expect("flushed")).expect("ASCII");
        assert_eq!(text, "time,a,n,m\n0.25,-1.5e-7,3,2.5\n1e16,NaN,-0,inf\n");
    }
}
