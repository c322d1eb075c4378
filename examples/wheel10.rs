//! The default scene end to end, for profiling: `cargo run --release --example wheel10`.
use guideway::scene::{BodyKind, Scene};
use guideway::{Advance, Simulation};
fn main() {
    let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    let mut sim = Simulation::new(&scene).unwrap();
    let start = std::time::Instant::now();
    let time = match sim.advance_to(10.0).unwrap() {
        Advance::Exited { time } => time,
        Advance::Reached => f64::NAN,
    };
    println!(
        "exit at {time} s after {:?} in {:?}",
        sim.counters(),
        start.elapsed()
    );
}
