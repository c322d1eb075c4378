//! Order of the contact-force profiles on the paper's 10 m/s case: exit
//! speed error and largest energy drift against Δt, RK4 with each
//! `solver.force_profile`, against a fine quadratic-profile reference.
//!
//! `cargo run --release --example force_profile_order [elements] [hht]`
//!
//! With `hht`: HHT-α (α = 0 and −0.1) at 2.5 ms / 2^k instead, against the
//! same RK4 reference.

use guideway::report::run_scene;
use guideway::scene::{builtin, ForceProfile, IntegratorKind, Scene};

fn run(scene: &Scene) -> (f64, f64, u64) {
    let run = run_scene(scene, |_| {}).expect("the run converges");
    let s = run.summary(scene);
    (
        s.exit_nominal_speed.expect("the wheel leaves the beam"),
        s.max_energy_drift.unwrap_or(f64::NAN),
        s.iterations.unwrap_or(0),
    )
}

fn main() {
    let elements: usize = std::env::args()
        .nth(1)
        .map_or(2, |a| a.parse().expect("a count"));
    let mut base = builtin("lee1994-wheel-10").expect("built in");
    base.beam.elements = elements;
    base.solver.integrator = IntegratorKind::Rk4;
    base.solver.velocity_tolerance = 1e-12;
    let mut largest = 0.0025;
    while guideway::Simulation::new(&Scene {
        solver: guideway::scene::SolverSpec {
            step: largest,
            ..base.solver.clone()
        },
        ..base.clone()
    })
    .is_err()
    {
        largest /= 2.0;
    }
    let mut reference = base.clone();
    reference.solver.force_profile = ForceProfile::Quadratic;
    reference.solver.step = (largest / 4.0).min(0.0025 / 64.0);
    let (v_ref, drift_ref, _) = run(&reference);
    println!(
        "{elements} elements, reference V = {v_ref:.12} m/s (Δt = {:.3e} s, drift {drift_ref:.2e})",
        reference.solver.step
    );
    println!(
        "| profile | Δt (s) | exit V error (m/s) | ratio | max energy drift | ratio | iterations |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|");
    if std::env::args().nth(2).as_deref() == Some("hht") {
        hht_table(&base, v_ref);
        return;
    }
    for profile in [
        ForceProfile::Held,
        ForceProfile::Linear,
        ForceProfile::Quadratic,
    ] {
        let mut last: Option<(f64, f64)> = None;
        for k in 0..5 {
            let mut scene = base.clone();
            scene.solver.force_profile = profile;
            scene.solver.step = largest / f64::from(1u32 << k);
            let (v, drift, iterations) = run(&scene);
            let error = (v - v_ref).abs();
            let ratios = last.map_or((f64::NAN, f64::NAN), |(e, d)| (e / error, d / drift));
            println!(
                "| {profile:?} | {:.4e} | {error:.3e} | {:.1} | {drift:.3e} | {:.1} | {iterations} |",
                scene.solver.step, ratios.0, ratios.1
            );
            last = Some((error, drift));
        }
    }
}

fn hht_table(base: &Scene, v_ref: f64) {
    println!("| HHT-α | Δt (s) | exit V error (m/s) | max energy drift | iterations |");
    println!("|---|---:|---:|---:|---:|");
    for damping in [0.0, 0.1] {
        for k in 0..7 {
            let mut scene = base.clone();
            scene.solver.integrator = IntegratorKind::Hht;
            scene.solver.numerical_damping = damping;
            scene.solver.step = 0.0025 / f64::from(1u32 << k);
            let (v, drift, iterations) = run(&scene);
            println!(
                "| α = {} | {:.4e} | {:.3e} | {drift:.3e} | {iterations} |",
                -damping,
                scene.solver.step,
                v - v_ref
            );
        }
    }
}
