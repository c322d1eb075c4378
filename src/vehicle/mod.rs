//! What moves on the structure: the rigid bodies and the force elements
//! (spring–dampers) that join them into vehicles, and the presets that
//! build vehicles of each kind.

pub mod body;
pub mod force_element;
pub mod presets;
pub mod speed;
