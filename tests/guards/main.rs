//! The project's guards: the layout guards (G1, G2, recordings in
//! `recordings/`), the layering of `src/`, the limits table and the user
//! guide kept in step with the code. One test binary of many modules (see
//! tests/physics/main.rs for why).

// The helpers every group shares, one folder up.
#[path = "../common/mod.rs"]
mod common;

mod docs;
mod layers;
mod layout_guards;
mod limits_doc;
