//! What moves on the structure: the rigid bodies and the force elements
//! (spring–dampers) that join them into vehicles.

pub mod body;
pub mod force_element;
