//! The figures of merit of one run, as JSON and as a short human summary.

use super::output_names;
use super::trace::Trace;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// What `guideway run --summary` writes. `None` becomes JSON `null`: the
/// body did not exit, or the simulation has no such output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// Time (s) at which the contact point reached the end of the beam.
    pub exit_time: Option<f64>,
    /// Nominal speed V (eq. 24, m/s) at the exit.
    pub exit_nominal_speed: Option<f64>,
    /// Largest nominal speed V (m/s) over the run.
    pub peak_nominal_speed: Option<f64>,
    /// Per sensor, the most negative (downward) deflection (m), sign kept.
    pub peak_sensor_deflection: BTreeMap<String, f64>,
    /// max |E(t) − E(0)| / |E(0)| of `energy.balance`, E(0) being the
    /// initial total energy.
    pub max_energy_drift: Option<f64>,
    /// Internal steps taken (rows of the CSV after the initial one).
    pub steps: usize,
    /// Contact-force iterations, summed over the steps.
    pub iterations: Option<u64>,
    /// Wall-clock time (s) of the solve alone.
    pub wall_time_s: f64,
    /// The integrator that ran, and for `auto` why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<String>,
}

impl RunSummary {
    /// Summarise a trace of `scene`'s outputs.
    pub fn from_trace(
        scene: &Scene,
        trace: &Trace,
        exit_time: Option<f64>,
        wall_time_s: f64,
    ) -> RunSummary {
        let speed = trace.column(&output_names::nominal_speed(&scene.body.name));
        let peak_sensor_deflection = scene
            .sensors
            .iter()
            .filter_map(|sensor| {
                let column = trace.column(&output_names::sensor_deflection(&sensor.name))?;
                Some((sensor.name.clone(), finite_extreme(column, f64::min)?))
            })
            .collect();
        RunSummary {
            scene: scene.name.clone(),
            exit_time,
            exit_nominal_speed: exit_time.and(speed.and_then(|v| v.last().copied())),
            peak_nominal_speed: speed.and_then(|v| finite_extreme(v, f64::max)),
            peak_sensor_deflection,
            max_energy_drift: trace
                .column(output_names::ENERGY_BALANCE)
                .and_then(max_relative_drift),
            steps: trace.len().saturating_sub(1),
            iterations: trace
                .column(output_names::ITERATIONS)
                .map(|per_step| per_step.iter().skip(1).map(|&n| n.max(0.0) as u64).sum()),
            wall_time_s,
            integrator: None,
        }
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a summary always serialises to JSON")
    }
}

/// The short summary printed at the end of `guideway run`.
impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let or_none = |x: Option<f64>, unit: &str, precision: usize| match x {
            Some(x) => format!("{x:.precision$} {unit}"),
            None => "-".to_string(),
        };
        writeln!(f, "scene              {}", self.scene)?;
        if let Some(integrator) = &self.integrator {
            writeln!(f, "integrator         {integrator}")?;
        }
        match self.exit_time {
            Some(t) => writeln!(f, "exit time          {t:.6} s")?,
            None => writeln!(f, "exit time          - (the body did not leave the beam)")?,
        }
        writeln!(
            f,
            "exit speed V       {}",
            or_none(self.exit_nominal_speed, "m/s", 4)
        )?;
        writeln!(
            f,
            "peak speed V       {}",
            or_none(self.peak_nominal_speed, "m/s", 4)
        )?;
        for (sensor, deflection) in &self.peak_sensor_deflection {
            writeln!(f, "peak deflection    {deflection:.6} m at sensor {sensor}")?;
        }
        let drift = self
            .max_energy_drift
            .map_or("-".to_string(), |d| format!("{:.3e} %", d * 100.0));
        writeln!(f, "max energy drift   {drift}")?;
        writeln!(f, "steps              {}", self.steps)?;
        let iterations = self.iterations.map_or("-".to_string(), |n| n.to_string());
        writeln!(f, "iterations         {iterations}")?;
        write!(f, "wall time (solve)  {:.3} ms", self.wall_time_s * 1e3)
    }
}

/// The extreme of the finite values by `pick` (`f64::max`, `f64::min`).
fn finite_extreme(values: &[f64], pick: fn(f64, f64) -> f64) -> Option<f64> {
    values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .reduce(pick)
}

/// max |E − E0| / |E0|; `None` without a usable E0. A non-finite energy
/// later in the run is an infinite drift.
fn max_relative_drift(energy: &[f64]) -> Option<f64> {
    let initial = *energy.first()?;
    if !initial.is_finite() || initial == 0.0 {
        return None;
    }
    Some(
        energy
            .iter()
            .map(|&e| {
                if e.is_finite() {
                    ((e - initial) / initial).abs()
                } else {
                    f64::INFINITY
                }
            })
            .fold(0.0, f64::max),
    )
}
