//! Two of the issue scenes' bogie coaches at 300 km/h over a 20 m span
//! from the approach, HHT-α at 0.25 ms, and a run that keeps every output
//! at every step: what the tests of the contact iteration's paths
//! (`prediction_tests`, `secant_tests`) compare.

use super::{Advance, Simulation};
use crate::scene::Scene;

/// The two coaches on wheelsets of `wheelset_mass` (0: massless, their
/// primary suspensions the contact laws) with the contact law preset
/// `contact_law` (none: the scene's default), the `[track]` tables
/// `track` and the `[solver]` lines `solver` besides the step, HHT-α and
/// the static start.
pub(super) fn two_coaches(
    (wheelset_mass, contact_law): (f64, Option<&str>),
    track: &str,
    solver: &str,
) -> Scene {
    let coach = |name: &str, (header, table): (&str, &str), position: f64| {
        let law = contact_law
            .map(|preset| format!("[{table}.contact_law]\npreset = \"{preset}\""))
            .unwrap_or_default();
        format!(
            r#"
{header}
name = "{name}"
kind = "bogie_vehicle"
mass = 38884.0
initial_position = {position:?}
initial_speed = 83.3333
{law}
[{table}.bogie]
car_inertia = 1.95e6
bogie_mass = 2400.0
bogie_inertia = 3200.0
wheelset_mass = {wheelset_mass:?}
bogie_half_distance = 8.75
axle_half_distance = 1.25
primary_stiffness = 1.18e6
primary_damping = 20000.0
secondary_stiffness = 5.3e5
secondary_damping = 45000.0
"#
        )
    };
    let text = format!(
        r#"
name = "two-coaches"
gravity = 9.81
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 2.3539e10
surface_offset = 0.0
elements = 20
[beam.damping]
ratio = 0.015
modes = [1, 3]
{track}
{}
{}
[solver]
step = 0.00025
integrator = "hht"
numerical_damping = 0.1
start = "static"
{solver}
"#,
        coach("coach1", ("[body]", "body"), -11.0),
        coach("coach2", ("[[vehicles]]", "vehicles"), -35.0)
    );
    Scene::from_toml_str(&text).expect("a valid scene")
}

/// Every output after every grid step of `sim` up to `end` (s), and the
/// integrations spent.
pub(super) fn every_step(mut sim: Simulation, dt: f64, end: f64) -> (Vec<Vec<f64>>, u64) {
    let mut values = vec![0.0; sim.outputs().len()];
    let mut rows = Vec::new();
    for k in 1..=(end / dt).round() as u64 {
        match sim.advance_to(k as f64 * dt) {
            Ok(Advance::Reached) => {}
            other => panic!("step {k}: {other:?}"),
        }
        sim.output_values(&mut values);
        rows.push(values.clone());
    }
    (rows, sim.counters().1)
}
