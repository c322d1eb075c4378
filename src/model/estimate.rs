//! The FMU's running error estimate (scene `error_estimate = true`): per
//! sensor, outputs `sensor.<name>.deflection_error` and
//! `.acceleration_error`, the discretisation error in time of the last
//! communication step, by step doubling.
//!
//! After each completed step a companion run of the same scene, restored
//! to the step's start state, is advanced over the same step at twice the
//! internal step; the estimate is |y(Δt) − y(2Δt)| / (2^p − 1), p the
//! scheme's order for deflections and 1 for accelerations. Where the step is shorter than 2Δt, its start is off
//! the 2Δt grid, or 2Δt is not stable (RK4's limit), the companion runs at
//! Δt/2 instead: |y(Δt) − y(Δt/2)| · 2^p / (2^p − 1). The companion is
//! rebuilt from the main state each step, so nothing goes into the saved
//! or serialized FMU state (after a restore the estimates read 0 until the
//! next step).

use super::advance::{advance_within, Stop};
use super::Dynamics;
use crate::outputs::{classify, output_name, OutputInfo, OutputKind, QuantityKind};
use crate::scene::Scene;
use crate::simulation::Advance;

/// The companions' step ratios: doubled first, halved as the fallback.
const DOUBLED: f64 = 2.0;
const HALVED: f64 = 0.5;

/// The estimator of one model: its companions (built once per scene, at
/// the first step that needs them) and the current estimates.
pub struct Estimator<D: Dynamics> {
    /// The scene the companions were built from.
    built_for: Option<Scene>,
    /// The companions at 2Δt and Δt/2; `None` where they cannot be built or
    /// run another scheme.
    companions: [Option<D>; 2],
    /// Per sensor, the columns of its deflection and acceleration.
    columns: Vec<[usize; 2]>,
    /// Per sensor, the deflection's and the acceleration's estimate.
    values: Vec<f64>,
}

/// The error outputs of `outputs` (those of a scene with sensors): one
/// deflection and one acceleration error per sensor, and their columns.
fn error_outputs(outputs: &[OutputInfo]) -> (Vec<OutputInfo>, Vec<[usize; 2]>) {
    let column = |name: &str| outputs.iter().position(|o| o.name == name);
    let mut infos = Vec::new();
    let mut columns = Vec::new();
    for o in outputs {
        let Some(sensor) = classify(&o.name)
            .filter(|n| n.kind == QuantityKind::Sensor)
            .map(|n| n.owner)
        else {
            continue;
        };
        let acceleration = output_name(QuantityKind::SensorAcceleration, sensor);
        let Some(acceleration) = column(&acceleration) else {
            continue;
        };
        let deflection = column(&o.name).expect("o is among the outputs");
        columns.push([deflection, acceleration]);
        for (what, unit) in [("deflection", "m"), ("acceleration", "m/s2")] {
            infos.push(OutputInfo {
                name: format!("sensor.{sensor}.{what}_error"),
                unit,
                description: format!(
                    "estimated discretisation error in time of sensor.{sensor}.{what} over the \
                     last communication step (step doubling, docs/error-estimates.md)"
                ),
                kind: OutputKind::Real,
            });
        }
    }
    (infos, columns)
}

impl<D: Dynamics> Estimator<D> {
    /// The estimator of a model whose dynamics have `outputs`, and the
    /// outputs it adds (after the dynamics' own).
    pub fn new(outputs: &[OutputInfo]) -> (Estimator<D>, Vec<OutputInfo>) {
        let (infos, columns) = error_outputs(outputs);
        let estimator = Estimator {
            built_for: None,
            companions: [None, None],
            values: vec![0.0; infos.len()],
            columns,
        };
        (estimator, infos)
    }

    /// The current estimates, in the order of the outputs `new` added.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Back to "no step estimated yet" (after a restore or a reset).
    pub fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Estimate the error of the step `main` just took from `start` to
    /// `target` (dynamics time) at internal step `step`, within `budget`
    /// seconds of wall time. Err: why no companion could run the step.
    pub fn estimate(
        &mut self,
        scene: &Scene,
        main: &D,
        start: &D::State,
        (target, step, budget): (f64, f64, f64),
        from: f64,
    ) -> Result<(), String> {
        if self.built_for.as_ref() != Some(scene) {
            self.companions = [DOUBLED, HALVED].map(|ratio| companion(scene, main, step * ratio));
            self.built_for = Some(scene.clone());
        }
        let doubled_fits = target - from >= 2.0 * step * (1.0 - 1e-9);
        let ratios = [(0, DOUBLED), (1, HALVED)];
        let mut last_problem = String::from("no companion run can be built for this scene");
        for (slot, ratio) in ratios {
            if slot == 0 && !doubled_fits {
                continue;
            }
            let (Some(companion), Some(state)) =
                (self.companions[slot].as_mut(), D::regridded(start, ratio))
            else {
                continue;
            };
            match run_companion(companion, &state, target, step * ratio, budget) {
                Ok(()) => {
                    self.values = differences(main, companion, &self.columns);
                    let orders = [main.order_in_time(), ACCELERATION_ORDER];
                    for pair in self.values.chunks_mut(2) {
                        for (v, p) in pair.iter_mut().zip(orders) {
                            *v *= richardson_scale(ratio, p);
                        }
                    }
                    return Ok(());
                }
                Err(problem) => last_problem = problem,
            }
        }
        Err(last_problem)
    }
}

/// The order at which the sensors' accelerations converge whatever the
/// scheme: they are read with the last step's mean contact force held over
/// the step. Scaling their difference with the scheme's order instead
/// underestimates by up to 2^p − 1 at fine steps (a third under HHT-α).
const ACCELERATION_ORDER: f64 = 1.0;

/// The factor from |y(Δt) − y(ratio·Δt)| to the error of y(Δt), for a
/// quantity converging at order `p` (Richardson).
fn richardson_scale(ratio: f64, p: f64) -> f64 {
    let gain = libm::pow(2f64, p);
    if ratio > 1.0 {
        1.0 / (gain - 1.0)
    } else {
        gain / (gain - 1.0)
    }
}

/// A companion of `main` at internal step `step`, if it can be built and
/// runs the same scheme (RK4 beyond its stability limit is refused, an
/// `auto` scene could switch to HHT-α).
fn companion<D: Dynamics>(scene: &Scene, main: &D, step: f64) -> Option<D> {
    let mut companion_scene = scene.clone();
    companion_scene.solver.step = step;
    D::build(&companion_scene)
        .ok()
        .filter(|c| main.same_scheme(c))
}

/// Restore `companion` to `state` and advance it to `target` within
/// `budget` seconds.
fn run_companion<D: Dynamics>(
    companion: &mut D,
    state: &D::State,
    target: f64,
    step: f64,
    budget: f64,
) -> Result<(), String> {
    companion.restore(state)?;
    match advance_within(companion, target, step, budget, (false, None)) {
        Ok((Advance::Reached, _)) => Ok(()),
        Ok((Advance::Exited { .. }, _)) => {
            Err("the error estimate's companion run left the structure".into())
        }
        Err(Stop::Solver(e)) => Err(format!("the error estimate's companion run failed {e}")),
        Err(Stop::OverBudget { .. }) => Err(format!(
            "the error estimate's companion run took longer than the rest of \
             solver.wall_time_budget ({budget:.3e} s left)"
        )),
    }
}

/// Per sensor, |main − companion| of its deflection and acceleration.
fn differences<D: Dynamics>(main: &D, companion: &D, columns: &[[usize; 2]]) -> Vec<f64> {
    let values = |d: &D| {
        let mut v = vec![0.0; d.outputs().len()];
        d.output_values(&mut v);
        v
    };
    let (m, c) = (values(main), values(companion));
    columns
        .iter()
        .flat_map(|cols| cols.map(|k| (m[k] - c[k]).abs()))
        .collect()
}
