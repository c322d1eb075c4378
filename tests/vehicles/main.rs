//! Vehicles and their contacts: the presets, followers, trains, lift-off
//! and impacts, contact laws, irregularities and prescribed speed. One test
//! binary of many modules (see tests/physics/main.rs for why).

// The helpers every group shares, one folder up.
#[path = "../common/mod.rs"]
mod common;

mod approach_run_off;
mod bogie_vehicle;
mod contact_laws;
mod follower;
mod impacts;
mod irregularity;
mod lift_off;
mod maglev_vehicle;
mod magnet_outputs;
mod no_tension;
mod open_ends;
mod prescribed_speed;
mod preset_followers;
mod summary_vehicles;
mod trains;
mod vehicles;
