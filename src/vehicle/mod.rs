//! What moves on the structure: the rigid bodies and the force elements
//! (spring–dampers) that join them into vehicles, the presets that
//! build vehicles of each kind, and the standard trains (HSLM) a moving
//! force may be.

pub mod body;
mod element_sweep;
pub mod force_element;
pub mod hslm;
pub mod presets;
pub mod speed;
