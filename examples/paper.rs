use guideway::scene::{BodyKind, Scene};
use guideway::{Advance, Simulation};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kind = if args[1] == "glider" {
        BodyKind::Glider
    } else {
        BodyKind::Wheel
    };
    let v0: f64 = args[2].parse().unwrap();
    let dt: f64 = args[3].parse().unwrap();
    let elements: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(2);
    let mut scene = Scene::lee1994(kind, v0, dt);
    scene.beam.elements = elements;
    if let Some(t) = args.get(5) {
        scene.solver.velocity_tolerance = t.parse().unwrap();
    }
    let mut sim = Simulation::new(&scene).unwrap();
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let idx = |n: &str| names.iter().position(|x| x == n).unwrap();
    let mut vals = vec![0.0; names.len()];
    let e0 = sim.initial_energy();
    let (mut peak_v, mut drift, mut peak_defl, mut maxit, mut maxg) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let start = std::time::Instant::now();
    let mut k = 0u64;
    loop {
        k += 1;
        let r = sim.advance_to(k as f64 * dt).unwrap();
        sim.output_values(&mut vals);
        let b = if kind == BodyKind::Wheel {
            "wheel"
        } else {
            "glider"
        };
        peak_v = peak_v.max(vals[idx(&format!("{b}.nominal_speed"))]);
        drift = drift.max(((vals[idx("energy.balance")] - e0) / e0).abs());
        peak_defl = peak_defl.min(vals[idx("sensor.midspan.deflection")]);
        maxit = maxit.max(vals[idx("solver.iterations")]);
        maxg = maxg.max(vals[idx("solver.gap_error")].abs());
        if let Advance::Exited { time } = r {
            let wall = start.elapsed().as_secs_f64();
            let (steps, its) = sim.counters();
            println!("exit t={time:.6} V={:.6} vx={:.6} peakV={peak_v:.6} drift={drift:.3e} peak_defl/0.1728={:.5} steps={steps} its={its} maxit={maxit} maxgap={maxg:.2e} wall={wall:.4}s ke_body={:.1} ft={:.1} fn={:.1}",
              vals[idx(&format!("{b}.nominal_speed"))], vals[idx(&format!("{b}.vx"))], -peak_defl/0.1728, vals[idx("energy.body_kinetic")], 0.0, vals[idx("contact.normal_force")]);
            break;
        }
        if k > 10_000_000 {
            break;
        }
    }
}
