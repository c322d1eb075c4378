//! Running a scene and reporting on it: the recorded outputs (`Trace`), the
//! figures of merit (`RunSummary`), CSV and PNG writers. Shared by the
//! command line, the tests and the FMU cross-check.

pub mod csv;
pub mod curve_groups;
mod deck_acceleration;
pub mod exits;
pub mod nodes;
pub mod output_file;
pub mod plot;
pub mod plot_style;
mod run;
mod shortest;
mod stream;
mod summary;
mod trace;

pub use crate::numbers::fmt_number;
pub use crate::outputs::non_finite_output;
pub use run::{drive, run_scene, Run, RunError, Steppable};
pub use stream::{
    check_run_length, drive_into, progress_column, stop_time, RowSink, StepProgress, StreamError,
    Streamed, DEFAULT_END_TIME_FACTOR, DEFAULT_MAX_STEPS,
};
pub use summary::{RunSummary, SummaryBuilder, SummaryEvent};
pub use trace::{Decimated, Trace};

/// Which recorded output the report reads for the travel (the others it
/// names by `outputs::output_name`).
pub mod output_names {
    use crate::outputs::{output_name, QuantityKind};

    /// Index of the output that best tells how far along the beam the body
    /// is: the abscissa of the contact named `contact`, else the body's x.
    pub fn travel_position(names: &[String], body: &str) -> Option<usize> {
        let contact = output_name(QuantityKind::ContactPosition, "contact");
        let body_x = output_name(QuantityKind::X, body);
        [contact, body_x]
            .iter()
            .find_map(|wanted| names.iter().position(|n| n == wanted))
    }
}

#[cfg(test)]
mod tests;
