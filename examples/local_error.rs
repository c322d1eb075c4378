//! Where the error of a coarse step comes from on the paper's 10 m/s case:
//! the local error of each step of Δt along the run, each step taken from
//! the fine reference's state (its force history the reference's own step
//! means), against the reference at the step's end.
//!
//! `cargo run --release --example local_error [Δt] [held|linear|quadratic] [elements]`
//!
//! Prints per step: time, contact abscissa, the local errors of the nominal
//! speed V and of the energy balance (per initial energy), then the steps
//! with the largest errors and the sums over the run.

use guideway::scene::{builtin, ForceProfile, IntegratorKind, Scene};
use guideway::{Advance, Simulation};

/// Fine steps per coarse step in the reference.
const FINE: usize = 64;

fn column(sim: &Simulation, name: &str) -> usize {
    sim.outputs()
        .iter()
        .position(|o| o.name == name)
        .unwrap_or_else(|| panic!("no output {name}"))
}

fn value(sim: &Simulation, index: usize) -> f64 {
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    values[index]
}

fn profile(name: &str) -> ForceProfile {
    match name {
        "held" => ForceProfile::Held,
        "linear" => ForceProfile::Linear,
        _ => ForceProfile::Quadratic,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dt: f64 = args.get(1).map_or(0.0025, |a| a.parse().expect("a step"));
    let shape = profile(args.get(2).map_or("quadratic", String::as_str));
    let elements: usize = args.get(3).map_or(2, |a| a.parse().expect("a count"));
    let mut base: Scene = builtin("lee1994-wheel-10").expect("built in");
    base.beam.elements = elements;
    base.solver.integrator = IntegratorKind::Rk4;
    base.solver.velocity_tolerance = 1e-12;
    let mut fine_scene = base.clone();
    fine_scene.solver.force_profile = ForceProfile::Quadratic;
    fine_scene.solver.step = dt / FINE as f64;
    let mut coarse_scene = base;
    coarse_scene.solver.force_profile = shape;
    coarse_scene.solver.step = dt;
    let mut fine = Simulation::new(&fine_scene).expect("the reference builds");
    let mut coarse = Simulation::new(&coarse_scene).expect("the coarse run builds");
    let (v, energy, x) = (
        column(&fine, "wheel.nominal_speed"),
        column(&fine, "energy.balance"),
        column(&fine, "contact.position"),
    );
    let e0 = fine.initial_energy();
    // The reference's means over the last coarse steps, newest first.
    let mut means = vec![[guideway::contact::ContactForce::default(); 3]; 1];
    let mut rows = Vec::new();
    for k in 0.. {
        let start = fine.state();
        if k >= 2 {
            let mut from = start.clone();
            from.grid_step = k as u64;
            from.steps = k as u64;
            from.step_history = [dt, dt];
            from.force_history = means.clone();
            from.last_position_iterations = 0;
            coarse.restore(&from).expect("same shape");
        }
        // The reference over the coarse step, its step means summed.
        let mut sum = nalgebra::Vector2::zeros();
        let mut exited = false;
        for j in 1..=FINE {
            let t = (k * FINE + j) as f64 * fine_scene.solver.step;
            if let Advance::Exited { .. } = fine.advance_to(t).expect("reference") {
                exited = true;
                break;
            }
            sum += fine.state().force_history[0][0].as_vector();
        }
        if exited {
            break;
        }
        if k >= 2 {
            let t = (k + 1) as f64 * dt;
            if let Advance::Reached = coarse.advance_to(t).expect("coarse step") {
                rows.push((
                    fine.time(),
                    value(&fine, x),
                    value(&coarse, v) - value(&fine, v),
                    (value(&coarse, energy) - value(&fine, energy)) / e0,
                ));
            }
        }
        let mean = guideway::contact::ContactForce::from_vector(sum / FINE as f64);
        let history = &mut means[0];
        *history = [mean, history[0], history[1]];
    }
    println!("# Δt = {dt} s, {shape:?}, {elements} elements; reference Δt/{FINE}");
    println!("# t (s), x (m), local V error (m/s), local energy error / E0");
    for (t, x, ev, ee) in &rows {
        println!("{t:.5} {x:.4} {ev:+.3e} {ee:+.3e}");
    }
    let mut by_v = rows.clone();
    by_v.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    println!("# largest |local V error|:");
    for (t, x, ev, ee) in by_v.iter().take(8) {
        println!("#   t {t:.5} x {x:.4}: {ev:+.3e} m/s, energy {ee:+.3e}");
    }
    let sum_abs = |f: fn(&(f64, f64, f64, f64)) -> f64| rows.iter().map(|r| f(r).abs()).sum::<f64>();
    let rms = |f: fn(&(f64, f64, f64, f64)) -> f64| {
        (rows.iter().map(|r| f(r).powi(2)).sum::<f64>() / rows.len() as f64).sqrt()
    };
    println!(
        "# steps {}: Σ|V err| {:.3e}, rms {:.3e}; Σ energy err {:.3e}, Σ|energy err| {:.3e}",
        rows.len(),
        sum_abs(|r| r.2),
        rms(|r| r.2),
        rows.iter().map(|r| r.3).sum::<f64>(),
        sum_abs(|r| r.3)
    );
}
