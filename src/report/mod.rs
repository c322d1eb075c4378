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
mod stream;
mod summary;
mod trace;

pub use crate::numbers::fmt_number;
pub use crate::outputs::non_finite_output;
pub use run::{drive, run_scene, Run, RunError, Steppable};
pub use stream::{
    check_run_length, drive_into, stop_time, RowSink, StepProgress, StreamError, Streamed,
    DEFAULT_END_TIME_FACTOR, DEFAULT_MAX_STEPS,
};
pub use summary::{RunSummary, SummaryBuilder, SummaryEvent};
pub use trace::{Decimated, Trace};

/// Names of the simulation outputs the report reads.
pub mod output_names {
    /// Nominal speed V (eq. 24) of the body.
    pub fn nominal_speed(body: &str) -> String {
        format!("{body}.nominal_speed")
    }

    /// Deflection of a sensor.
    pub fn sensor_deflection(sensor: &str) -> String {
        format!("sensor.{sensor}.deflection")
    }

    /// Energy balance: constant for the exact solution, equal to the initial
    /// total energy at t = 0.
    pub const ENERGY_BALANCE: &str = "energy.balance";

    /// Contact-force iterations of the last step.
    pub const ITERATIONS: &str = "solver.iterations";

    /// Index of the output that best tells how far along the beam the body
    /// is: the contact abscissa, else the body's x.
    pub fn travel_position(names: &[String], body: &str) -> Option<usize> {
        let body_x = format!("{body}.x");
        ["contact.position", body_x.as_str()]
            .iter()
            .find_map(|wanted| names.iter().position(|n| n == wanted))
    }
}

#[cfg(test)]
mod tests;
