//! How the system is advanced in time: the integrators (RK4, HHT-α), the
//! contact-force iteration of Lee (1994) over them, and the static start.

pub mod deadline;
pub mod integrate;
pub mod iteration;
pub mod parameters;
pub mod static_start;
