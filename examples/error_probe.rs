use guideway::study::convergence::figures;
use guideway::study::refine::{error_study, summarise, Refinement};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = guideway::Scene::load(&args[1]).unwrap();
    let t = std::time::Instant::now();
    let study = error_study(&scene, Refinement::Time, 100_000_000, 2).unwrap();
    eprintln!("study {:?}", t.elapsed());
    let mut fine = scene.clone();
    fine.solver.step /= 64.0;
    let reff = figures(&summarise(&fine, u64::MAX).unwrap());
    for e in &study.estimates {
        let r = reff.iter().find(|f| f.name == e.name).map(|f| f.value);
        let truth = r.map(|r| (e.value - r).abs());
        println!(
            "{:50} {:>12.6e} est {:>10.3e} true {:>10.3e} ratio {:>8.3} order {:?} {:?}",
            e.name,
            e.value,
            e.error.unwrap_or(f64::NAN),
            truth.unwrap_or(f64::NAN),
            e.error.unwrap_or(f64::NAN) / truth.unwrap_or(f64::NAN),
            e.order.map(|o| (o * 100.0).round() / 100.0),
            e.not_converged
        );
    }
}
