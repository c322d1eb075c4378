//! How the system is advanced in time: the integrators (RK4, HHT-α), the
//! contact-force iteration of Lee (1994) over them, the stepper that
//! advances a state with them (`stepper`) and the events it locates inside
//! a step (`events`), the impacts at a landing, the static start, and the
//! scene's `[solver]` table (`spec`).

pub mod deadline;
pub(crate) mod events;
pub mod impact;
pub mod integrate;
pub mod iteration;
pub mod parameters;
pub mod spec;
pub mod static_start;
pub mod stepper;
