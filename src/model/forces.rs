//! Moving forces as FMU dynamics: the crossing of `moving_load::ForceRun`
//! stepped on its fixed grid to each communication point, open-ended (the
//! free vibration goes on to the stop time), its state the beam's and the
//! steps taken.

use super::Dynamics;
use crate::moving_load::{ForceRun, ForceState};
use crate::scene::Scene;
use crate::simulation::{Advance, OutputInfo, SolverError, Steppable};

/// How far (in steps) a communication point may lie from the grid of
/// `solver.step` and still be taken as its grid point (masters that count
/// time in integers pass points off by ulps).
const GRID_SLACK: f64 = 1e-6;

/// The moving-force run behind an FMU.
pub struct ForceDynamics {
    run: ForceRun,
}

impl ForceDynamics {
    /// The run's fixed step (s).
    fn step(&self) -> f64 {
        self.run.steps().0
    }

    /// The steps from 0 to `t`, a point of the grid: Newmark's factor is
    /// that of the fixed step, so a step is never shortened.
    fn grid_index(&self, t: f64) -> Result<f64, String> {
        let step = self.step();
        let k = (t / step).round();
        if (t / step - k).abs() <= GRID_SLACK {
            return Ok(k);
        }
        Err(format!(
            "moving forces are stepped on the fixed grid of solver.step = {step} s: a \
             communication point (t = {t} s) must be a multiple of it"
        ))
    }
}

impl Steppable for ForceDynamics {
    /// The grid time of the steps taken (the crossing's own time is their
    /// sum, off by rounding): communication points are compared with it.
    fn time(&self) -> f64 {
        let (step, steps) = self.run.steps();
        steps as f64 * step
    }

    fn outputs(&self) -> &[OutputInfo] {
        self.run.outputs()
    }

    fn output_values(&self, values: &mut [f64]) {
        self.run.output_values(values)
    }

    /// Whole steps to `t`, which must be a point of the grid.
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        let k = self.grid_index(t).map_err(|message| SolverError {
            time: self.time(),
            message,
        })?;
        self.run.advance_to(k * self.step())
    }
}

impl Dynamics for ForceDynamics {
    type State = ForceState;

    fn build(scene: &Scene) -> Result<Self, String> {
        if scene.error_estimate {
            return Err("error_estimate is not available for moving forces: halve \
                        solver.step and compare the runs"
                .into());
        }
        Ok(ForceDynamics {
            run: ForceRun::open_ended(scene)?,
        })
    }
    /// The forces are prescribed: a moving-force FMU has no force inputs.
    fn set_vehicle_force(&mut self, _vehicle: usize, _force: [f64; 2]) {}
    /// Open-ended: the run never ends at an exit.
    fn exit_time(&self) -> Option<f64> {
        None
    }
    fn check_target(&self, t: f64) -> Result<(), String> {
        self.grid_index(t).map(|_| ())
    }
    fn events_since(&self, from: usize) -> Vec<String> {
        let events = self.run.events();
        events
            .get(from..)
            .unwrap_or_default()
            .iter()
            .map(|e| format!("t = {} s: {} of {}", e.time, e.kind, e.axle))
            .collect()
    }
    fn event_count(&self) -> usize {
        self.run.events().len()
    }
    fn state(&self) -> ForceState {
        self.run.state()
    }
    fn restore(&mut self, state: &ForceState) -> Result<(), String> {
        self.run.restore(state)
    }
    fn check_state(&self, state: &ForceState) -> Result<(), String> {
        self.run.check_state(state)
    }
}
