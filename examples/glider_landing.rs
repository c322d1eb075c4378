//! A glider released 0.2 m above midspan of the paper's beam, which the
//! wheel at 100 m/s sets vibrating, undamped: its landings and lift-offs
//! against the mesh and the step.
//! `cargo run --release --example glider_landing -- ELEMENTS STEP [damped]`
//! (`VERBOSE=1`: every event of the glider; `JUMPS=1`: every grid step in
//! which the energy balance moves by more than 1 J, with its events).

use guideway::scene::{BodyKind, DampingSpec, IntegratorKind, Scene};
use guideway::simulation::EventKind;
use guideway::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let elements: usize = args.get(1).map_or(16, |s| s.parse().expect("elements"));
    let step: f64 = args.get(2).map_or(1e-4, |s| s.parse().expect("step"));
    let damped = args.get(3).is_some_and(|s| s == "damped");
    let scene = scene(elements, step, damped);
    let mut sim = Simulation::new(&scene).expect("builds");
    let grid = (0.2 / step).round() as u64;
    let record = run(&mut sim, step, grid);
    report(&sim, (elements, step, grid), &record);
}

/// The wheel at 100 m/s on `elements` elements, and the glider 0.2 m
/// above midspan, to t = 0.2 s.
fn scene(elements: usize, step: f64, damped: bool) -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Wheel, 100.0, step);
    scene.beam.elements = elements;
    scene.solver.integrator = IntegratorKind::Auto;
    if damped {
        scene.beam.damping = Some(DampingSpec::Modes {
            ratio: 0.05,
            modes: [1, 2],
        });
    }
    scene.solver.end_time = Some(0.2);
    let mut glider = Scene::lee1994(BodyKind::Glider, 0.0, step).vehicles[0].clone();
    glider.name = "glider".into();
    glider.initial_position = 12.0;
    glider.initial_height = 0.2;
    scene.vehicles.push(glider);
    scene.validate().expect("valid");
    scene
}

/// What the run recorded of the glider (contact 1).
struct GliderRecord {
    /// (time, normal impulse) of each landing.
    impulses: Vec<(f64, f64)>,
    min_gap: f64,
    /// Its last event's time, and the shortest time between two.
    last_time: f64,
    shortest: f64,
}

/// Run `grid` steps, recording the glider's events and gaps.
fn run(sim: &mut Simulation, step: f64, grid: u64) -> GliderRecord {
    let mut seen = 0;
    let mut impulses = Vec::new();
    let mut min_gap: f64 = 0.0;
    let mut last_time = sim.time();
    let mut shortest = f64::INFINITY;
    let mut balance = sim.energy_balance();
    for k in 1..=grid {
        sim.advance_to(k as f64 * step).expect("runs");
        let jump = sim.energy_balance() - balance;
        balance = sim.energy_balance();
        if std::env::var("JUMPS").is_ok() && jump.abs() > 1.0 {
            let events: Vec<String> = sim.events()[seen..]
                .iter()
                .map(|e| format!("{}:{:?}@{:.7}", e.contact, e.kind, e.time))
                .collect();
            let open: Vec<bool> = sim.contact_statuses().iter().map(|c| c.open).collect();
            println!(
                "t {:.5} jump {jump:+.2} J open {open:?} {}",
                sim.time(),
                events.join(" ")
            );
        }
        min_gap = min_gap.min(sim.contact_statuses()[1].gap);
        let new: Vec<_> = sim.events()[seen..].to_vec();
        seen = sim.events().len();
        for e in new.iter().filter(|e| e.contact == 1) {
            if e.time > last_time {
                shortest = shortest.min(e.time - last_time);
            }
            last_time = e.time;
            if e.kind == EventKind::Landing {
                impulses.push((e.time, sim.contact_statuses()[1].impulse[1]));
            }
            if std::env::var("VERBOSE").is_ok() {
                println!("  {:?} at {:.7}", e.kind, e.time);
            }
        }
    }
    GliderRecord {
        impulses,
        min_gap,
        last_time,
        shortest,
    }
}

/// One line: the glider's landings, lift-offs and impulses, the steps and
/// the energy books.
fn report(sim: &Simulation, (elements, step, grid): (usize, f64, u64), record: &GliderRecord) {
    let GliderRecord {
        impulses,
        min_gap,
        last_time,
        shortest,
    } = record;
    let of = |kind| {
        sim.events()
            .iter()
            .filter(|e| e.contact == 1 && e.kind == kind)
            .count()
    };
    let wheel_lift_offs = sim
        .events()
        .iter()
        .filter(|e| e.contact == 0 && e.kind == EventKind::LiftOff)
        .count();
    let first = impulses.first().copied().unwrap_or((f64::NAN, f64::NAN));
    let later: f64 = impulses.iter().skip(1).map(|p| p.1).fold(0.0, f64::max);
    let smallest = impulses
        .iter()
        .skip(1)
        .map(|p| p.1)
        .fold(f64::INFINITY, f64::min);
    println!(
        "{elements} elements, {step:e} s ({}): glider landings {}, lift-offs {}, \
         last event {:.4} s, first landing {:.6} s P {:.1} N s, later P {smallest:.2} to {later:.2} N s, \
         open at end {}, steps {} of {grid}, wheel lift-offs {wheel_lift_offs}, \
         impact loss {:.0} J, numerical dissipation {:.0} J, drift {:.1} J, \
         lowest gap {min_gap:.1e} m, shortest time between its events {shortest:.1e} s",
        sim.integrator_choice().split(' ').next().unwrap_or(""),
        of(EventKind::Landing),
        of(EventKind::LiftOff),
        last_time,
        first.0,
        first.1,
        sim.contact_statuses()[1].open,
        sim.counters().0,
        sim.impact_loss(),
        sim.state().dynamic.numerical_dissipation,
        sim.energy_balance() - sim.initial_energy(),
    );
}
