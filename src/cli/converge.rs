//! `guideway converge SCENE`: the summary figures at a ladder of steps (or
//! meshes) as a table, a CSV and a plot (docs/error-estimates.md).

use super::{load_scene, ConvergeArgs, Failure};
use guideway::study::converge::{converge, to_csv};
use guideway::study::converge_plot::write_converge_plot;
use guideway::study::refine::{cores, Refinement};

pub(super) fn run_converge(args: ConvergeArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    let refinement = if args.mesh {
        Refinement::Mesh
    } else {
        Refinement::Time
    };
    let threads = args.threads.unwrap_or_else(cores);
    let ladder = converge(&scene, refinement, args.rungs, args.max_steps, threads)
        .map_err(|e| Failure::Run(format!("scene `{}`: {e}", scene.name)))?;
    println!(
        "{:<48} {:>11} {:>8} {:>15} {:>10} {:>6} {:>10}",
        "figure", "step (s)", "elements", "value", "error", "order", "solve (s)"
    );
    for p in &ladder.points {
        let order = p.order.map_or("-".to_string(), |o| format!("{o:.2}"));
        println!(
            "{:<48} {:>11.4e} {:>8} {:>15.8e} {:>10.2e} {:>6} {:>10.4}",
            p.figure, p.step, p.elements, p.value, p.error, order, p.cost_s
        );
    }
    for (figure, why) in &ladder.not_converged {
        println!("NOT CONVERGED at the finest runs: {figure}: {why}");
    }
    std::fs::write(&args.out, to_csv(&ladder.points))
        .map_err(|e| Failure::Run(format!("cannot write {}: {e}", args.out.display())))?;
    eprintln!("wrote {}", args.out.display());
    if let Some(plot) = &args.plot {
        write_converge_plot(&ladder, args.mesh, plot).map_err(Failure::Run)?;
        eprintln!("wrote {}", plot.display());
    }
    Ok(())
}
