//! EMS magnet outputs (issue 24 item 5): each magnet's air gap and current
//! against the force balance of the levitated car in closed form.

use guideway::{Scene, Simulation};

use crate::common::GRAVITY;
const CAR: f64 = 30000.0;
const MAGNET: f64 = 600.0;
/// The `ems` preset's nominal air gap s₀ (m).
const NOMINAL_GAP: f64 = 0.01;

/// The car of `tests/vehicles/contact_laws.rs` standing on rigid ground (the
/// approach) on eight magnets on the `ems` preset, started at rest where
/// each magnet carries its share of the weight.
fn levitated() -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "maglev-levitating"
gravity = {GRAVITY:?}
[beam]
length = 24.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 4
[track]
approach = 60.0
[body]
name = "car"
kind = "maglev_vehicle"
mass = {CAR:?}
initial_position = -30.0
initial_speed = 0.0
[body.contact_law]
preset = "ems"
[body.maglev]
car_inertia = 1.5e6
magnets = 8
magnet_spacing = 3.0
magnet_mass = {MAGNET:?}
stiffness = 8.0e5
[solver]
integrator = "hht"
step = 1.0e-3
end_time = 4.0
start = "rest"
"#
    ))
    .expect("valid scene")
}

/// Each magnet's (normal force, air gap, current) at the end of the run.
fn settled(scene: &Scene) -> Vec<[f64; 3]> {
    let mut sim = Simulation::new(scene).expect("builds");
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: String| names.iter().position(|x| *x == n).expect(&n);
    sim.advance_to(scene.solver.end_time.unwrap())
        .expect("no solver error");
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    (1..=8)
        .map(|i| {
            let m = format!("car_magnet{i}");
            [
                values[at(format!("{m}.normal_force"))],
                values[at(format!("{m}.air_gap"))],
                values[at(format!("{m}.current"))],
            ]
        })
        .collect()
}

/// Levitating under its weight alone every magnet carries its share
/// F₀ = (M/8 + m) g (the force balance) at the nominal air gap s₀ and so,
/// by the linearised law ΔF = 2F₀ Δi/i₀ − 2F₀ Δs/s₀, at its operating
/// current, i/i₀ = 1.
#[test]
fn a_levitating_magnet_reports_the_gap_and_current_of_its_force_balance() {
    let share = (CAR / 8.0 + MAGNET) * GRAVITY;
    for &[force, gap, current] in &settled(&levitated()) {
        assert!((force / share - 1.0).abs() < 1e-6, "{force} {share}");
        assert!((gap / NOMINAL_GAP - 1.0).abs() < 1e-6, "{gap}");
        assert!((current - 1.0).abs() < 1e-6, "{current}");
    }
}
