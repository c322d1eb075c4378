//! `guideway converge`: a scene's summary figures at a ladder of steps
//! (or meshes), each halving (doubling) the last, with the observed orders,
//! the error of each run against the Richardson extrapolation of the three
//! finest, and the cost of each run.

use super::convergence::{estimate, Estimate, Level};
use super::refine::{level_of, refined, summarise, Refinement};
use crate::report::check_run_length;
use crate::scene::Scene;

/// Runs of a ladder at most: the finest costs 2^(rungs − 1) times the first.
pub const MAX_RUNGS: usize = 12;

/// One figure at one rung of the ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub figure: String,
    pub step: f64,
    pub elements: usize,
    pub value: f64,
    /// |value − extrapolated| (the finest runs' Richardson value, or the
    /// finest value where its order is erratic).
    pub error: f64,
    /// Observed order from this rung and the two coarser ones.
    pub order: Option<f64>,
    /// Solve time of the run (s).
    pub cost_s: f64,
}

/// The runs of the ladder (coarse to fine) and every figure's points;
/// the figures flagged at the three finest runs, with why.
pub struct Ladder {
    pub levels: Vec<Level>,
    pub points: Vec<Point>,
    pub not_converged: Vec<(String, String)>,
}

/// Run `scene` at `rungs` refinements (the scene's own first), `threads` at
/// a time, every run refused up front beyond `max_steps`.
pub fn converge(
    scene: &Scene,
    refinement: Refinement,
    rungs: usize,
    max_steps: u64,
    threads: usize,
) -> Result<Ladder, String> {
    if !(3..=MAX_RUNGS).contains(&rungs) {
        return Err(format!(
            "--rungs {rungs}: must be between 3 and {MAX_RUNGS}"
        ));
    }
    let finest = refined(scene, refinement, rungs as i32 - 1)?;
    check_run_length(&finest, max_steps, " (--max-steps N raises it)")
        .map_err(|e| format!("the finest run: {e}"))?;
    let halvings: Vec<i32> = (0..rungs as i32).collect();
    let levels = super::sweep::in_parallel(&halvings, threads, |h| {
        let scene = refined(scene, refinement, h)?;
        let summary = summarise(&scene, max_steps)
            .map_err(|e| format!("the run at {} failed: {e}", describe(&scene)))?;
        Ok(level_of(&scene, &summary))
    })?;
    let finest3 = &levels[rungs - 3..];
    let estimates = estimate(finest3, 2);
    let not_converged = flags_in_order(&estimates);
    let points = estimates
        .iter()
        .flat_map(|e| {
            let reference = e.extrapolated.unwrap_or(e.value);
            points_of(&levels, &e.name, reference)
        })
        .collect();
    Ok(Ladder {
        levels,
        points,
        not_converged,
    })
}

/// The flagged figures and why, those that matter first: changing event
/// counts, then the runs' largest disagreements; a spread at the
/// iteration's tolerance (an exit time's 5.8e-10 s) last.
fn flags_in_order(estimates: &[Estimate]) -> Vec<(String, String)> {
    let mut flagged: Vec<(&Estimate, &String)> = (estimates.iter())
        .filter_map(|e| Some((e, e.not_converged.as_ref()?)))
        .collect();
    flagged.sort_by(|(a, _), (b, _)| b.disagreement().total_cmp(&a.disagreement()));
    (flagged.into_iter())
        .map(|(e, why)| (e.name.clone(), why.clone()))
        .collect()
}

/// `Δt = 1e-3 s, 10 elements`.
fn describe(scene: &Scene) -> String {
    format!(
        "Δt = {:e} s, {} elements",
        scene.solver.step, scene.beam.elements
    )
}

/// The points of figure `name` at every rung where it exists.
fn points_of(levels: &[Level], name: &str, reference: f64) -> Vec<Point> {
    let values: Vec<Option<f64>> = levels
        .iter()
        .map(|l| l.figures.iter().find(|f| f.name == name).map(|f| f.value))
        .collect();
    let order = |k: usize| -> Option<f64> {
        let (a, b, c) = (values[k - 2]?, values[k - 1]?, values[k]?);
        let p = libm::log2((a - b) / (b - c));
        p.is_finite().then_some(p)
    };
    levels
        .iter()
        .enumerate()
        .filter_map(|(k, level)| {
            Some(Point {
                figure: name.to_string(),
                step: level.step,
                elements: level.elements,
                value: values[k]?,
                error: (values[k]? - reference).abs(),
                order: if k >= 2 { order(k) } else { None },
                cost_s: level.cost_s,
            })
        })
        .collect()
}

/// The points as CSV: figure, step, elements, value, error, order, cost.
pub fn to_csv(points: &[Point]) -> String {
    let mut csv = String::from("figure,step_s,elements,value,error,observed_order,solve_time_s\n");
    for p in points {
        let order = p.order.map_or(String::new(), |o| format!("{o}"));
        csv.push_str(&format!(
            "{},{:e},{},{:e},{:e},{order},{:e}\n",
            p.figure, p.step, p.elements, p.value, p.error, p.cost_s
        ));
    }
    csv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::convergence::tests::level;

    /// A changing event count first, then the figure whose runs disagree
    /// most, the exit time at the iteration's tolerance last; the names'
    /// order would put it first.
    #[test]
    fn the_flags_that_matter_come_first() {
        let runs = [
            [1.0, 1.0 + 5.8e-10, 1.0 - 2e-11, 3.0, 2.2e5],
            [1.0, 1.0 - 1e-10, 1.0 + 3e-11, 5.0, 1.9e5],
            [1.0, 1.0 + 4e-10, 1.0 - 1e-11, 5.0, 2.1e5],
        ];
        let levels: Vec<Level> = [1e-3, 5e-4, 2.5e-4]
            .iter()
            .zip(&runs)
            .map(|(&step, v)| {
                level(
                    step,
                    &[
                        ("a_exit_time", v[1], false),
                        ("b_speed", v[2], false),
                        ("events.lift_off", v[3], true),
                        ("peak_contact_force", v[4], false),
                        ("settled", v[0], false),
                    ],
                )
            })
            .collect();
        let flags = flags_in_order(&estimate(&levels, 2));
        let names: Vec<&str> = flags.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "events.lift_off",
                "peak_contact_force",
                "a_exit_time",
                "b_speed"
            ]
        );
        assert!(
            flags[1].1.ends_with("differ by 1.4e-1 of the figure"),
            "{flags:?}"
        );
        assert!(
            flags[2].1.ends_with("differ by 6.8e-10 of the figure"),
            "{flags:?}"
        );
    }
}
