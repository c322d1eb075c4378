//! Where the stress case's energy balance moves: per grid step, the jump of
//! `energy.balance`, summed by the events the step holds.
//! `cargo run --release --example stress_balance -- [step] [restitution] [flat]`

use guideway::simulation::EventKind;
use guideway::{Scene, Simulation};

fn scene(step: f64, e: f64, rough: bool) -> Scene {
    let irregularity = if rough {
        r#"[[track.irregularities]]
type = "random"
spectrum = "iso8608"
class = "C"
seed = 2026
shortest_wavelength = 1.0
longest_wavelength = 50.0"#
    } else {
        ""
    };
    Scene::from_toml_str(&format!(
        r#"
name = "rough-track-300"
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
{irregularity}
[body]
kind = "bogie_vehicle"
name = "coach"
mass = 38884.0
initial_position = -15.0
initial_speed = 83.33333333333333
restitution = {e:?}
[body.bogie]
car_inertia = 1.95e6
bogie_mass = 2400.0
bogie_inertia = 3200.0
wheelset_mass = 1400.0
bogie_half_distance = 8.75
axle_half_distance = 1.25
primary_stiffness = 1.18e6
primary_damping = 2.0e3
secondary_stiffness = 5.3e5
secondary_damping = 4.5e3
wheel_radius = 0.45
wheelset_inertia = 700.0
[solver]
step = {step:?}
integrator = "rk4"
end_time = 0.75
"#
    ))
    .expect("valid")
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let step: f64 = args.get(1).map_or(1.25e-5, |s| s.parse().expect("step"));
    let e: f64 = args.get(2).map_or(0.9, |s| s.parse().expect("e"));
    let rough = args.get(3).is_none_or(|s| s != "flat");
    let verbose = std::env::var("VERBOSE").is_ok();
    let scene = scene(step, e, rough);
    let mut sim = Simulation::new(&scene).expect("builds");
    let grid = (0.75 / step).round() as u64;
    let names = ["none", "landing", "lift-off", "entry/exit", "mixed"];
    let mut sums = [0.0f64; 5];
    let mut counts = [0u64; 5];
    let mut absum = [0.0f64; 5];
    let mut last = sim.energy_balance();
    let mut seen = 0;
    let mut worst: f64 = 0.0;
    for k in 1..=grid {
        sim.advance_to(k as f64 * step).expect("runs");
        let now = sim.energy_balance();
        let jump = now - last;
        worst = worst.max((now - sim.initial_energy()).abs());
        last = now;
        let new = &sim.events()[seen..];
        seen = sim.events().len();
        let kinds: Vec<EventKind> = new.iter().map(|e| e.kind).collect();
        let class = if kinds.is_empty() {
            0
        } else if kinds.iter().all(|&k| k == EventKind::Landing) {
            1
        } else if kinds.iter().all(|&k| k == EventKind::LiftOff) {
            2
        } else if kinds
            .iter()
            .all(|&k| matches!(k, EventKind::Entry | EventKind::Exit))
        {
            3
        } else {
            4
        };
        sums[class] += jump;
        absum[class] += jump.abs();
        counts[class] += 1;
        if verbose && (class != 0 || jump.abs() > 1.0) {
            let desc: Vec<String> = new
                .iter()
                .map(|e| format!("{}:{:?}@{:.9}", e.contact, e.kind, e.time))
                .collect();
            let open: String = sim
                .contact_statuses()
                .iter()
                .map(|c| if c.open { 'o' } else { 'c' })
                .collect();
            let parts = &sim.state().parts;
            println!(
                "t {:.6} jump {jump:+.3} J {open} {parts:?} {}",
                sim.time(),
                desc.join(" ")
            );
        }
    }
    println!(
        "step {step:e} e {e} rough {rough}: drift at the end {:.2} J, largest {worst:.2} J, \
         of {:.4e} J; impact loss {:.1} J, numerical dissipation {:.1} J, steps {}, events {}",
        sim.energy_balance() - sim.initial_energy(),
        sim.initial_energy(),
        sim.impact_loss(),
        sim.state().dynamic.numerical_dissipation,
        sim.counters().0,
        sim.events().len()
    );
    for c in 0..5 {
        println!(
            "  {:10} steps {:6} sum {:+12.3} J  |sum| {:12.3} J",
            names[c], counts[c], sums[c], absum[c]
        );
    }
}
