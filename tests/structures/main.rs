//! Structures and track: supports and spans, rail joints, the rail layer
//! on a foundation, over the deck and on sleepers, and the trains on them.
//! One test binary of many modules (see tests/physics/main.rs for why).

// The helpers every group shares, one folder up.
#[path = "../common/mod.rs"]
mod common;

mod compliant_secant;
mod rail_gap;
mod rail_over_spans;
mod sleepers_off_nodes;
mod supports_spans;
mod templates_converge;
mod track_layer;
mod track_on_deck;
mod track_sleepers;
mod train_on_sleepers;
