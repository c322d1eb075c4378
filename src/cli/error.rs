//! `guideway run --error [time|mesh]` and `--rtol`: the companion runs
//! beside the base run, and the ± of every summary figure on the terminal
//! and in the summary JSON (`error_estimate`).

use super::Failure;
use guideway::report::RunSummary;
use guideway::study::refine::{
    companions, cores, level_of, study, CompanionRuns, Refinement, StepChoice, Study,
};
use guideway::Scene;
use serde_json::{json, Value};
use std::thread::JoinHandle;

type Companions = Result<CompanionRuns, String>;

/// What the base run waits for: companion runs under way, or the study the
/// tolerance loop made already (its base the run at the chosen step).
pub(super) enum Pending {
    Companions(Refinement, JoinHandle<Companions>),
    Chosen(Box<StepChoice>),
}

/// Start the companion runs of `scene` on their own threads, beside the
/// base run (which chose `integrator_choice`).
pub(super) fn start(
    scene: &Scene,
    refinement: Refinement,
    integrator_choice: &str,
    max_steps: u64,
) -> Pending {
    let (scene, choice) = (scene.clone(), integrator_choice.to_string());
    let handle =
        std::thread::spawn(move || companions(&scene, refinement, &choice, max_steps, cores()));
    Pending::Companions(refinement, handle)
}

/// Choose the step (or with `Refinement::Mesh` the elements) for `rtol`
/// before the base run (printing the choice).
pub(super) fn choose(
    scene: &Scene,
    refinement: Refinement,
    rtol: f64,
    max_steps: u64,
    quiet: bool,
) -> Result<StepChoice, Failure> {
    let what = match refinement {
        Refinement::Time => "step",
        Refinement::Mesh => "mesh",
    };
    let choice = guideway::study::refine::choose(scene, refinement, rtol, max_steps, cores())
        .map_err(|e| Failure::Run(format!("cannot choose the {what} for rtol = {rtol:e}: {e}")))?;
    if !quiet {
        let chosen = match refinement {
            Refinement::Time => format!(
                "step {:e} s chosen (scene: {:e} s",
                choice.step, scene.solver.step
            ),
            Refinement::Mesh => format!(
                "{} elements chosen (scene: {}",
                choice.elements, scene.beam.elements
            ),
        };
        println!(
            "tolerance          rtol = {rtol:e}: {chosen}; {} runs, {:.3} s of solve)",
            choice.runs, choice.cost_s
        );
        if let Some(why) = &choice.stopped {
            println!("tolerance          stopped: {why}");
        }
    }
    Ok(choice)
}

/// The study of the finished base run (`summary` of `scene`).
pub(super) fn finish(
    pending: Pending,
    scene: &Scene,
    summary: &RunSummary,
) -> Result<(Study, Option<StepChoice>), Failure> {
    match pending {
        Pending::Chosen(choice) => Ok((choice.study.clone(), Some(*choice))),
        Pending::Companions(refinement, handle) => {
            let result = handle
                .join()
                .map_err(|_| Failure::Run("a companion run panicked".into()))?;
            let (runs, note, wall) = result.map_err(|e| {
                Failure::Run(format!(
                    "cannot estimate the error ({}): {e}",
                    refinement_name(refinement)
                ))
            })?;
            let base = level_of(scene, summary);
            Ok((study(refinement, base, runs, note, wall), None))
        }
    }
}

fn refinement_name(refinement: Refinement) -> &'static str {
    match refinement {
        Refinement::Time => "time",
        Refinement::Mesh => "mesh",
    }
}

/// (base + companions) over base solve time.
fn cost_ratio(study: &Study) -> f64 {
    let total: f64 = study.levels.iter().map(|l| l.cost_s).sum();
    total / study.levels[study.base].cost_s
}

/// The `error_estimate` entry of the summary JSON.
pub(super) fn to_json(study: &Study, choice: Option<&StepChoice>) -> Value {
    let runs: Vec<Value> = study
        .levels
        .iter()
        .enumerate()
        .map(|(k, l)| json!({"step": l.step, "elements": l.elements, "solve_time_s": l.cost_s, "base": k == study.base}))
        .collect();
    let figures: serde_json::Map<String, Value> = study
        .estimates
        .iter()
        .map(|e| {
            (
                e.name.clone(),
                serde_json::to_value(e).expect("serialisable"),
            )
        })
        .collect();
    let flagged: Vec<&str> = study
        .estimates
        .iter()
        .filter(|e| e.not_converged.is_some())
        .map(|e| e.name.as_str())
        .collect();
    let mut out = json!({
        "refinement": refinement_name(study.refinement),
        "runs": runs,
        "cost_ratio": cost_ratio(study),
        "companions_wall_s": study.companions_wall_s,
        "note": study.note,
        "not_converged": flagged,
        "figures": figures,
    });
    if let Some(choice) = choice {
        let unmet: Vec<Value> = choice
            .unmet
            .iter()
            .map(|(f, why)| json!({"figure": f, "why": why}))
            .collect();
        out["tolerance"] = json!({
            "rtol": choice.rtol, "chosen_step": choice.step,
            "chosen_elements": choice.elements, "unmet": unmet,
            "stopped": choice.stopped, "solve_time_s": choice.cost_s,
        });
    }
    out
}

/// The figures with their ± on the terminal.
pub(super) fn print(study: &Study, choice: Option<&StepChoice>) {
    let steps: Vec<String> = study
        .levels
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let this = if k == study.base { " (this run)" } else { "" };
            match study.refinement {
                Refinement::Time => format!("{:e} s{this}", l.step),
                Refinement::Mesh => format!("{}{this}", l.elements),
            }
        })
        .collect();
    let what = match study.refinement {
        Refinement::Time => "Δt",
        Refinement::Mesh => "elements",
    };
    println!("error estimate     {what} = {}", steps.join(", "));
    let companions: f64 =
        study.levels.iter().map(|l| l.cost_s).sum::<f64>() - study.levels[study.base].cost_s;
    println!(
        "error cost         companions' solve {:.3} s, {:.2}x this run's with it",
        companions,
        cost_ratio(study)
    );
    if let Some(note) = &study.note {
        println!("error note         {note}");
    }
    for e in &study.estimates {
        println!("{}", estimate_line(e));
    }
    let flagged = study
        .estimates
        .iter()
        .filter(|e| e.not_converged.is_some())
        .count();
    if flagged > 0 {
        println!(
            "NOT CONVERGED      {flagged} of {} figures (docs/error-estimates.md says what to do)",
            study.estimates.len()
        );
    }
    if let Some(choice) = choice {
        for (figure, why) in &choice.unmet {
            println!("ABOVE rtol         {figure}: {why}");
        }
    }
}

/// `  exit_nominal_speed   9.965068e0 ± 1.6e-3 (order 2.03)`.
fn estimate_line(e: &guideway::study::convergence::Estimate) -> String {
    let error = e.error.map_or("?".to_string(), |x| format!("{x:.2e}"));
    let order = e
        .order
        .map_or(String::new(), |p| format!(" (order {p:.2})"));
    let flag = e
        .not_converged
        .as_ref()
        .map_or(String::new(), |why| format!("  NOT CONVERGED: {why}"));
    let value = if e.count {
        format!("{}", e.value)
    } else {
        format!("{:.6e}", e.value)
    };
    format!("  {:<44} {value} ± {error}{order}{flag}", e.name)
}
