//! A stand-in for the physics, for testing the model and FMI layers alone.
//!
//! A point mass sliding along the beam under `force_x`, with fixed internal
//! steps like the real solver, an exit at the end of the beam, and solver
//! failures to exercise roll-back: every step fails when `|force_y|` exceeds
//! `FAIL_FORCE` (no step size cures it), steps longer than `FINE_STEP` fail
//! when it exceeds `FINE_FORCE` (smaller steps cure it).
//! Built only for unit tests and with the `fake-physics` feature (which
//! builds a test FMU); the shipped FMU always uses `Simulation`.

use super::Dynamics;
use crate::scene::{BodyKind, Scene};
use crate::simulation::{Advance, OutputInfo, OutputKind, SolverError, Steppable};
use serde::{Deserialize, Serialize};

/// `|force_y|` above this makes the fake solver fail.
pub const FAIL_FORCE: f64 = 1e9;
/// `|force_y|` above this makes internal steps longer than `FINE_STEP` fail.
pub const FINE_FORCE: f64 = 1e8;
pub const FINE_STEP: f64 = 1e-3;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FakeState {
    pub time: f64,
    pub x: f64,
    pub vx: f64,
    pub steps: u64,
    pub exit_time: Option<f64>,
}

pub struct FakeDynamics {
    outputs: Vec<OutputInfo>,
    mass: f64,
    length: f64,
    step: f64,
    radius: Option<f64>,
    force: (f64, f64),
    sensors: Vec<f64>,
    state: FakeState,
}

fn real(name: String, unit: &'static str, description: &str) -> OutputInfo {
    OutputInfo {
        name,
        unit,
        description: description.to_string(),
        kind: OutputKind::Real,
    }
}

impl Dynamics for FakeDynamics {
    type State = FakeState;

    fn build(scene: &Scene) -> Result<Self, String> {
        let b = &scene.vehicles[0].name;
        let mut outputs = vec![
            real(format!("{b}.x"), "m", "abscissa of the body's centre"),
            real(format!("{b}.vx"), "m/s", "horizontal velocity"),
        ];
        let radius = (scene.vehicles[0].kind == BodyKind::Wheel).then(|| {
            outputs.push(real(
                format!("{b}.angular_velocity"),
                "rad/s",
                "angular velocity",
            ));
            scene.vehicles[0].radius.unwrap_or(1.0)
        });
        for s in &scene.sensors {
            outputs.push(real(
                format!("sensor.{}.deflection", s.name),
                "m",
                "beam deflection at the sensor",
            ));
        }
        outputs.push(OutputInfo {
            name: "solver.iterations".into(),
            unit: "",
            description: "internal steps in the last advance".into(),
            kind: OutputKind::Integer,
        });
        Ok(FakeDynamics {
            outputs,
            mass: scene.vehicles[0].mass,
            length: scene.beam.length,
            step: scene.solver.step,
            radius,
            force: (scene.vehicles[0].force_x, scene.vehicles[0].force_y),
            sensors: scene.sensors.iter().map(|s| s.position).collect(),
            state: FakeState {
                time: 0.0,
                x: scene.vehicles[0].initial_position,
                vx: scene.vehicles[0].initial_speed,
                steps: 0,
                exit_time: None,
            },
        })
    }
    /// The fake has one body: vehicle 0's.
    fn set_vehicle_force(&mut self, vehicle: usize, [fx, fy]: [f64; 2]) {
        if vehicle == 0 {
            self.force = (fx, fy);
        }
    }
    fn exit_time(&self) -> Option<f64> {
        self.state.exit_time
    }
    fn state(&self) -> FakeState {
        self.state.clone()
    }
    fn restore(&mut self, state: &FakeState) -> Result<(), String> {
        self.state = state.clone();
        Ok(())
    }
}

impl Steppable for FakeDynamics {
    fn time(&self) -> f64 {
        self.state.time
    }
    fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }
    fn output_values(&self, values: &mut [f64]) {
        let s = &self.state;
        let mut v = vec![s.x, s.vx];
        if let Some(r) = self.radius {
            v.push(s.vx / r);
        }
        for p in &self.sensors {
            v.push(-1e-3 * libm::exp(-(s.x - p).powi(2)));
        }
        v.push(s.steps as f64);
        values.copy_from_slice(&v);
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        if let Some(time) = self.state.exit_time {
            return Ok(Advance::Exited { time });
        }
        self.state.steps = 0;
        while self.state.time < t {
            if self.force.1.abs() > FAIL_FORCE {
                return Err(SolverError {
                    time: self.state.time,
                    message: format!("fake solver: |force_y| > {FAIL_FORCE} N"),
                });
            }
            let dt = self.step.min(t - self.state.time);
            if self.force.1.abs() > FINE_FORCE && dt > FINE_STEP {
                return Err(SolverError {
                    time: self.state.time,
                    message: format!(
                        "fake solver: |force_y| > {FINE_FORCE} N needs steps <= {FINE_STEP} s"
                    ),
                });
            }
            let s = &mut self.state;
            s.vx += self.force.0 / self.mass * dt;
            let x_new = s.x + s.vx * dt;
            if x_new >= self.length && s.vx > 0.0 {
                let frac = (self.length - s.x) / (x_new - s.x);
                s.time += frac * dt;
                s.x = self.length;
                s.exit_time = Some(s.time);
                return Ok(Advance::Exited { time: s.time });
            }
            s.x = x_new;
            s.time = if t - s.time <= self.step {
                t
            } else {
                s.time + dt
            };
            s.steps += 1;
        }
        Ok(Advance::Reached)
    }
}
