//! Helpers shared by the integration tests: run a scene to its exit and
//! collect the figures the paper reports.
#![allow(dead_code)]

pub mod cli;
pub mod fryba;
pub mod yang_yau;

use guideway::scene::{BodyKind, Scene};
use guideway::{Advance, Simulation};

/// The acceleration of gravity the tests' scenes are written with (m/s²).
pub const GRAVITY: f64 = 9.81;

pub struct RunFigures {
    pub exit_time: f64,
    pub exit_nominal_speed: f64,
    pub exit_vx: f64,
    pub peak_nominal_speed: f64,
    pub max_energy_drift: f64,
    pub peak_midspan_deflection: f64,
    pub steps: u64,
    pub final_values: Vec<f64>,
    pub initial_values: Vec<f64>,
    pub names: Vec<String>,
    pub max_abs_tangential_force: f64,
}

impl RunFigures {
    pub fn value(&self, name: &str) -> f64 {
        self.final_values[self.index(name)]
    }
    pub fn initial(&self, name: &str) -> f64 {
        self.initial_values[self.index(name)]
    }
    fn index(&self, name: &str) -> usize {
        self.names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no output {name}"))
    }
}

pub fn paper_scene(kind: BodyKind, speed: f64, step: f64) -> Scene {
    Scene::lee1994(kind, speed, step)
}

/// Run `scene` to the exit, sampling outputs at every internal step.
pub fn run_to_exit(scene: &Scene) -> RunFigures {
    let mut sim = Simulation::new(scene).expect("scene builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let body = &scene.vehicles[0].name;
    let at = |n: &str| names.iter().position(|x| x == n).unwrap();
    let (speed, balance) = (at(&format!("{body}.nominal_speed")), at("energy.balance"));
    let midspan = names.iter().position(|x| x == "sensor.midspan.deflection");
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    let initial_values = values.clone();
    let e0 = sim.initial_energy();
    let dt = scene.solver.step;
    let mut figures = RunFigures {
        exit_time: f64::NAN,
        exit_nominal_speed: f64::NAN,
        exit_vx: f64::NAN,
        peak_nominal_speed: values[speed],
        max_energy_drift: 0.0,
        peak_midspan_deflection: 0.0,
        steps: 0,
        final_values: vec![],
        initial_values,
        names: names.clone(),
        max_abs_tangential_force: 0.0,
    };
    for k in 1..10_000_000u64 {
        let advance = sim.advance_to(k as f64 * dt).expect("step converges");
        sim.output_values(&mut values);
        figures.peak_nominal_speed = figures.peak_nominal_speed.max(values[speed]);
        figures.max_energy_drift = figures
            .max_energy_drift
            .max(((values[balance] - e0) / e0).abs());
        if let Some(m) = midspan {
            figures.peak_midspan_deflection = figures.peak_midspan_deflection.min(values[m]);
        }
        let force = sim.state().force_history[0][0].tangential.abs();
        figures.max_abs_tangential_force = figures.max_abs_tangential_force.max(force);
        if let Advance::Exited { time } = advance {
            figures.exit_time = time;
            figures.exit_nominal_speed = values[speed];
            figures.exit_vx = values[at(&format!("{body}.vx"))];
            figures.steps = sim.counters().0;
            figures.final_values = values.clone();
            return figures;
        }
    }
    panic!("the body never left the beam");
}

/// The modelDescription.xml inside an FMU, checked to be well-formed XML.
pub fn model_description(fmu: &std::path::Path) -> String {
    use std::io::Read;
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    guideway::fmu::check_well_formed(&xml).expect("modelDescription.xml is well-formed");
    xml
}

/// The stress case's scene: a coach on rolling wheelsets (e = 0.9) at
/// 300 km/h on an ISO 8608 random profile of `class` (wavelengths 1–50 m,
/// `seed`), from the approach over Yang & Yau's 25 m bridge (20 elements)
/// onto the run-off, to 0.75 s at `step` with `integrator`.
pub fn rough_coach_scene(name: &str, class: &str, seed: u64, step: f64, integrator: &str) -> Scene {
    let bogie = coach_bogie(2.0e3, 4.5e3);
    Scene::from_toml_str(&format!(
        r#"
name = "{name}"
gravity = 9.81
[beam]
length = 25.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 20
[track]
approach = 30.0
run_off = 40.0
[[track.irregularities]]
type = "random"
spectrum = "iso8608"
class = "{class}"
seed = {seed}
shortest_wavelength = 1.0
longest_wavelength = 50.0
[body]
kind = "bogie_vehicle"
name = "coach"
mass = 38884.0
initial_position = -15.0
initial_speed = 83.33333333333333
restitution = 0.9
{bogie}
[solver]
step = {step:?}
integrator = "{integrator}"
end_time = 0.75
"#
    ))
    .expect("valid")
}

/// The `[body.bogie]` table of the coach of `train-3-coaches` on rolling
/// wheelsets, with its primary and secondary dampers (N s/m).
pub fn coach_bogie(primary_damping: f64, secondary_damping: f64) -> String {
    let gliders = coach_bogie_on_gliders("body", primary_damping, secondary_damping);
    format!("{gliders}\nwheel_radius = 0.45\nwheelset_inertia = 700.0")
}

/// The `[{vehicle}.bogie]` table (`vehicle`: `body` or `vehicles`) of the
/// coach of `train-3-coaches` on glider wheelsets, with its primary and
/// secondary dampers (N s/m).
pub fn coach_bogie_on_gliders(
    vehicle: &str,
    primary_damping: f64,
    secondary_damping: f64,
) -> String {
    format!(
        r#"[{vehicle}.bogie]
car_inertia = 1.95e6
bogie_mass = 2400.0
bogie_inertia = 3200.0
wheelset_mass = 1400.0
bogie_half_distance = 8.75
axle_half_distance = 1.25
primary_stiffness = 1.18e6
primary_damping = {primary_damping:?}
secondary_stiffness = 5.3e5
secondary_damping = {secondary_damping:?}"#
    )
}

/// The static load on one wheelset of `scene`'s first (bogie) vehicle: the
/// coach over its four wheelsets plus its bogie's share and the
/// wheelset's own weight, under the scene's gravity.
pub fn static_wheelset_load(scene: &Scene) -> f64 {
    let bogie = scene.vehicles[0].bogie.as_ref().expect("a bogie vehicle");
    scene.gravity * (scene.vehicles[0].mass / 4.0 + bogie.bogie_mass / 2.0 + bogie.wheelset_mass)
}

/// The largest |a − b| over two series, pair by pair.
pub fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The largest |a| over a series.
pub fn peak(a: &[f64]) -> f64 {
    a.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// The largest component of any body's (ẍ, ÿ, θ̈), in units of g.
pub fn largest_acceleration(sim: &Simulation) -> f64 {
    sim.body_accelerations()
        .iter()
        .flat_map(|a| a.iter().map(|x| x.abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max)
        / GRAVITY
}
