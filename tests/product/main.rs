//! The product as a user meets it: the `guideway` command line (run, sweep,
//! check, release), the exported FMUs, hostile inputs and the fuzzers. One
//! test binary of many modules (see tests/physics/main.rs for why).

// The helpers every group shares, one folder up.
#[path = "../common/mod.rs"]
mod common;

mod bridge_check;
mod bridge_templates;
mod cli;
mod cli_robustness;
mod csv_headers;
mod fmu_error_outputs;
mod fmu_import;
mod fmu_own_states;
mod hostile_inputs;
mod magnitude_fuzz;
mod nodes_output;
mod output_names;
mod release;
mod scene_fuzz;
mod sweep;
mod sweep_envelope;
mod vehicle_sweep;
