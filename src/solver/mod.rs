//! How the system is advanced in time: the integrators (RK4, HHT-α), the
//! contact-force iteration of Lee (1994) over them, the stepper that
//! advances a state with them (`stepper`) and the events it locates inside
//! a step (`events`), and the static start.

pub mod deadline;
pub(crate) mod events;
pub mod integrate;
pub mod iteration;
pub mod parameters;
pub mod static_start;
pub mod stepper;
