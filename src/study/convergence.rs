//! The discretisation error of every summary figure of a run, from companion
//! runs refined by halving the step (or doubling the elements): Richardson
//! extrapolation with the observed order per figure, and a "not converged"
//! flag with its reason where the runs do not bear an extrapolation out.
//!
//! The estimator works on a generic list of named figures (`figures` reads
//! every number of a `RunSummary`), so a figure the summary gains later is
//! estimated without a change here.

use crate::report::RunSummary;
use serde::Serialize;
use std::collections::BTreeMap;

/// One named figure of a run. A `count` (of events) must not change
/// between runs; it is not extrapolated.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub name: String,
    pub value: f64,
    pub count: bool,
}

/// Summary entries that are not figures of the physics: bookkeeping of the
/// run itself, and the filter's cut-off (a property of the beam).
const NOT_FIGURES: [&str; 7] = [
    "acceleration_cut_off_hz",
    "scene",
    "steps",
    "iterations",
    "wall_time_s",
    "integrator",
    "events",
];

/// Every number of `summary` as a named figure (`peak_design.sensor.midspan.acceleration`,
/// `exit_time`, ...), and per event kind the count (`events.lift_off`).
pub fn figures(summary: &RunSummary) -> Vec<Figure> {
    let json = serde_json::to_value(summary).expect("a summary always serialises to JSON");
    let mut out = Vec::new();
    if let serde_json::Value::Object(entries) = json {
        for (key, value) in entries {
            if !NOT_FIGURES.contains(&key.as_str()) {
                flatten(&key, &value, &mut out);
            }
        }
    }
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for event in &summary.events {
        *counts.entry(event.kind.as_str()).or_default() += 1;
    }
    // Kinds absent from this run still count (0) once any run has them:
    // `estimate` treats a figure missing from a run as a count of zero.
    out.extend(counts.into_iter().map(|(kind, n)| Figure {
        name: format!("events.{kind}"),
        value: n as f64,
        count: true,
    }));
    out
}

/// The numeric leaves under `value`, named by their path.
fn flatten(path: &str, value: &serde_json::Value, out: &mut Vec<Figure>) {
    match value {
        serde_json::Value::Number(n) => {
            if let Some(value) = n.as_f64() {
                let count = !n.is_f64();
                let name = path.to_string();
                out.push(Figure { name, value, count });
            }
        }
        serde_json::Value::Object(entries) => {
            for (key, inner) in entries {
                flatten(&format!("{path}.{key}"), inner, out);
            }
        }
        serde_json::Value::Array(items) => {
            for (k, inner) in items.iter().enumerate() {
                flatten(&format!("{path}.{k}"), inner, out);
            }
        }
        _ => {}
    }
}

/// One run of a refinement study: its step (s) and elements, its figures
/// and the CPU time it took (s).
#[derive(Debug, Clone)]
pub struct Level {
    pub step: f64,
    pub elements: usize,
    pub figures: Vec<Figure>,
    pub cost_s: f64,
}

impl Level {
    fn value(&self, name: &str) -> Option<f64> {
        self.figures
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.value)
    }

    /// `Δt = 2.5e-3 s, 2 elements`.
    pub fn label(&self) -> String {
        format!("Δt = {:e} s, {} elements", self.step, self.elements)
    }
}

/// The estimated error of one figure of the base run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    pub name: String,
    /// The figure in the base run (the one the user asked for).
    pub value: f64,
    /// Estimated |value − converged value|; `None` when the runs do not
    /// give one (a missing figure).
    pub error: Option<f64>,
    /// The Richardson-extrapolated value, where the order allows one.
    pub extrapolated: Option<f64>,
    /// Observed order of convergence (per halving of the step, or doubling
    /// of the elements).
    pub order: Option<f64>,
    /// The figure in each run, coarse to fine (`None`: not in that run).
    pub values: Vec<Option<f64>>,
    /// Why the figure is not converged, if it is not.
    pub not_converged: Option<String>,
    #[serde(skip)]
    pub count: bool,
}

/// Observed orders outside this range are erratic: below it the figure is
/// not settling, above it the finer difference is most likely a chance
/// near-cancellation (no scheme of the project is beyond fifth order).
pub const ORDER_RANGE: (f64, f64) = (0.5, 6.0);

/// Differences below this fraction of the figure are rounding, not
/// discretisation error.
const ROUNDING: f64 = 1e-13;

/// The estimate of every figure of `levels[base]` from three runs, coarse
/// to fine, each refined by a factor of two.
pub fn estimate(levels: &[Level], base: usize) -> Vec<Estimate> {
    assert!(
        levels.len() == 3 && base < 3,
        "three levels, base among them"
    );
    let mut names: Vec<(String, bool)> = Vec::new();
    for figure in levels.iter().flat_map(|l| &l.figures) {
        if !names.iter().any(|(n, _)| *n == figure.name) {
            names.push((figure.name.clone(), figure.count));
        }
    }
    names
        .into_iter()
        .filter_map(|(name, count)| {
            let values: Vec<Option<f64>> = levels.iter().map(|l| l.value(&name)).collect();
            let values = if count {
                values.iter().map(|v| Some(v.unwrap_or(0.0))).collect()
            } else {
                values
            };
            let value = values[base]?;
            let mut estimate = Estimate {
                name,
                value,
                error: None,
                extrapolated: None,
                order: None,
                values: values.clone(),
                not_converged: None,
                count,
            };
            match values.iter().copied().collect::<Option<Vec<f64>>>() {
                None => estimate.not_converged = Some(missing_reason(&values, levels)),
                Some(v) if count => counts(&mut estimate, &v),
                Some(v) => richardson(&mut estimate, &v, base),
            }
            Some(estimate)
        })
        .collect()
}

fn missing_reason(values: &[Option<f64>], levels: &[Level]) -> String {
    let missing: Vec<String> = values
        .iter()
        .zip(levels)
        .filter(|(v, _)| v.is_none())
        .map(|(_, l)| l.label())
        .collect();
    format!("absent from the run at {}", missing.join(" and "))
}

/// Event counts: converged when equal in every run.
fn counts(estimate: &mut Estimate, v: &[f64]) {
    let spread = spread(v);
    estimate.error = Some(spread);
    if spread > 0.0 {
        let list: Vec<String> = v.iter().map(|n| format!("{n}")).collect();
        estimate.not_converged = Some(format!(
            "the event count changes between the runs: {}",
            list.join(" → ")
        ));
    }
}

/// The base run's error were the figure converging at first order from the
/// base on: twice its largest distance from the finer runs. The coarser run
/// is left out: an erratic order most often means it is outside the range
/// where the error follows a power of the step.
fn first_order_bound(v: &[f64], base: usize) -> f64 {
    let farthest = v[base + 1..]
        .iter()
        .fold(0.0_f64, |m, x| m.max((x - v[base]).abs()));
    2.0 * farthest
}

impl Estimate {
    /// How far a flagged figure's runs disagree, for ordering the flags:
    /// an event count that changes above all, then the spread of the runs
    /// relative to the figure's largest magnitude.
    pub fn disagreement(&self) -> f64 {
        let runs: Option<Vec<f64>> = self.values.iter().copied().collect();
        match runs {
            Some(v) if !self.count => relative_spread(&v),
            _ => f64::INFINITY,
        }
    }
}

/// The largest magnitude of `v`.
fn magnitude(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// `spread` relative to the largest magnitude (0 where every run is 0).
fn relative_spread(v: &[f64]) -> f64 {
    let scale = magnitude(v);
    if scale > 0.0 {
        spread(v) / scale
    } else {
        0.0
    }
}

/// Largest minus smallest.
fn spread(v: &[f64]) -> f64 {
    let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = v.iter().copied().fold(f64::INFINITY, f64::min);
    max - min
}

/// Observed order from the two successive differences, and the base run's
/// distance from the extrapolated value; a figure whose order is erratic
/// gets the spread of its runs as its error and a reason.
fn richardson(estimate: &mut Estimate, v: &[f64], base: usize) {
    let rounding = ROUNDING * magnitude(v);
    let (coarse, fine) = (v[0] - v[1], v[1] - v[2]);
    if coarse.abs() <= rounding && fine.abs() <= rounding {
        estimate.error = Some(rounding);
        estimate.extrapolated = Some(v[2]);
        return;
    }
    let ratio = coarse / fine;
    let order = libm::log2(ratio);
    let erratic = |why: String| Some(format!("erratic observed order: {why}"));
    estimate.not_converged = if ratio.is_nan() || ratio <= 0.0 {
        erratic(format!(
            "the differences between successive runs change sign ({coarse:.3e}, then {fine:.3e})"
        ))
    } else if order < ORDER_RANGE.0 {
        erratic(format!(
            "{order:.2}, below {}: the figure is not settling under refinement",
            ORDER_RANGE.0
        ))
    } else if order > ORDER_RANGE.1 {
        erratic(format!(
            "{order:.2}, above {}: the finer difference ({fine:.3e}) is likely a chance cancellation",
            ORDER_RANGE.1
        ))
    } else {
        None
    };
    if let Some(why) = &mut estimate.not_converged {
        // How much the flag matters: a spread at the iteration's tolerance
        // (an exit time's 5.8e-10 s) is read otherwise than one of 2e5 N.
        why.push_str(&format!(
            "; the runs differ by {:.1e} of the figure",
            relative_spread(v)
        ));
        estimate.error = Some(first_order_bound(v, base).max(rounding));
        estimate.order = order.is_finite().then_some(order);
        return;
    }
    let extrapolated = v[2] - fine / (ratio - 1.0);
    estimate.order = Some(order);
    estimate.extrapolated = Some(extrapolated);
    estimate.error = Some((v[base] - extrapolated).abs().max(rounding));
}

/// Figures whose value is already an error measure: their tolerance is
/// absolute (a drift of 1e-4 meets `rtol` = 1e-3 whatever the drift's
/// own relative error).
pub fn is_error_measure(name: &str) -> bool {
    name == "max_energy_drift"
}

/// Whether `estimate` meets the relative tolerance `rtol`, and if not, why.
/// A figure of erratic order meets it only when its conservative error
/// (the first-order bound) and the spread of its three runs do: where the
/// runs do not bear an extrapolation out, a small finer difference may be
/// a chance cancellation (a train's raw deck acceleration on 128, 256, 512
/// elements: 0.06036, 0.06246, 0.06245, and 0.06162 on 1,024). A changing
/// event count never meets it.
pub fn check_tolerance(estimate: &Estimate, rtol: f64) -> Result<(), String> {
    let flagged = || {
        let reason = estimate.not_converged.as_deref().unwrap_or_default();
        format!("not converged ({reason})")
    };
    if estimate.count && estimate.not_converged.is_some() {
        return Err(flagged());
    }
    let mut error = estimate.error.ok_or_else(flagged)?;
    if estimate.not_converged.is_some() {
        let runs: Option<Vec<f64>> = estimate.values.iter().copied().collect();
        error = error.max(runs.as_deref().map_or(f64::INFINITY, spread));
    }
    let allowed = tolerance_scale(estimate) * rtol;
    if error <= allowed {
        return Ok(());
    }
    let scale = if is_error_measure(&estimate.name) {
        "1"
    } else {
        "|value|"
    };
    let above = format!("estimated error {error:.3e} above {allowed:.3e} (rtol × {scale})");
    match estimate.not_converged {
        Some(_) => Err(format!("{above}; {}", flagged())),
        None => Err(above),
    }
}

fn tolerance_scale(estimate: &Estimate) -> f64 {
    if is_error_measure(&estimate.name) {
        1.0
    } else {
        estimate.value.abs()
    }
}

/// Halvings of the step that bring `estimate` below `rtol` at its observed
/// order (0 if it meets it); `None` if the order does not tell.
pub fn halvings_needed(estimate: &Estimate, rtol: f64) -> Option<u32> {
    if check_tolerance(estimate, rtol).is_ok() {
        return Some(0);
    }
    if estimate.not_converged.is_some() {
        // An erratic order tells nothing of the step needed: one halving,
        // to see whether the figure settles; a changing count, none.
        return (!estimate.count && estimate.error.is_some()).then_some(1);
    }
    let order = estimate.order?;
    let allowed = tolerance_scale(estimate) * rtol;
    let factor = estimate.error? / allowed;
    let halvings = (libm::log2(factor) / order).ceil();
    (halvings.is_finite() && allowed > 0.0).then_some(halvings.max(1.0) as u32)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A run of the ladder at `step` with `figures` (name, value, count).
    pub(crate) fn level(step: f64, figures: &[(&str, f64, bool)]) -> Level {
        Level {
            step,
            elements: 2,
            cost_s: 0.0,
            figures: figures
                .iter()
                .map(|&(name, value, count)| Figure {
                    name: name.into(),
                    value,
                    count,
                })
                .collect(),
        }
    }

    /// A figure f(h) = 1 + 3 h² is extrapolated to 1 exactly, with order 2.
    #[test]
    fn second_order_figure_is_extrapolated_to_its_limit() {
        let f = |h: f64| 1.0 + 3.0 * h * h;
        let levels: Vec<Level> = [0.2, 0.1, 0.05]
            .iter()
            .map(|&h| level(h, &[("x", f(h), false)]))
            .collect();
        let e = &estimate(&levels, 1)[0];
        assert!((e.order.unwrap() - 2.0).abs() < 1e-9);
        assert!((e.extrapolated.unwrap() - 1.0).abs() < 1e-12);
        assert!((e.error.unwrap() - 0.03).abs() < 1e-12);
        assert!(e.not_converged.is_none());
    }

    #[test]
    fn sign_change_and_changing_counts_are_flagged() {
        let levels = vec![
            level(0.2, &[("x", 1.0, false), ("events.lift_off", 3.0, true)]),
            level(0.1, &[("x", 1.1, false), ("events.lift_off", 5.0, true)]),
            level(0.05, &[("x", 1.05, false)]),
        ];
        let e = estimate(&levels, 1);
        let why = e[0].not_converged.as_ref().unwrap();
        assert!(why.contains("change sign"), "{why}");
        assert!(
            why.ends_with("the runs differ by 9.1e-2 of the figure"),
            "{why}"
        );
        // Twice the distance of the base run from the finer one.
        assert!((e[0].error.unwrap() - 0.1).abs() < 1e-12);
        let lift = e[1].not_converged.as_ref().unwrap();
        assert!(lift.contains("3 → 5 → 0"), "{lift}");
    }

    #[test]
    fn tolerance_and_halvings_follow_the_order() {
        let f = |h: f64| 1.0 + h * h;
        let levels: Vec<Level> = [0.2, 0.1, 0.05]
            .iter()
            .map(|&h| level(h, &[("x", f(h), false)]))
            .collect();
        let e = &estimate(&levels, 1)[0];
        // error 0.01 at order 2: 1e-3 needs a factor 10, two halvings.
        assert_eq!(halvings_needed(e, 1e-3), Some(2));
        assert!(check_tolerance(e, 0.02).is_ok());
    }
}
