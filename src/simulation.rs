//! Simulation: state of beam and body, fixed-step advance, exit, outputs and
//! energy bookkeeping.

use nalgebra::{DVector, Vector2};
use serde::{Deserialize, Serialize};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{foot_point, ContactForce, ContactFrame};
use crate::integrate::DynamicState;
use crate::integrate::{contact_loads, Hht, Integrator, Rk4};
use crate::iteration::{ContactIteration, IterationSettings};
use crate::scene::{BodyKind, IntegratorKind, Scene, SolverSpec};
use crate::system::System;

/// How an output is typed when exported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    Real,
    Integer,
}

/// One named output of the simulation, in the order of `output_values`.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputInfo {
    pub name: String,
    pub unit: &'static str,
    pub description: String,
    pub kind: OutputKind,
}

/// Result of `advance_to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    /// The requested time was reached.
    Reached,
    /// The contact point reached the end of the beam at `time`; the state is
    /// the exit state.
    Exited { time: f64 },
}

/// A failure inside a step. The simulation is left at the start of the
/// failing internal step.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverError {
    pub time: f64,
    pub message: String,
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "at t = {} s: {}", self.time, self.message)
    }
}
impl std::error::Error for SolverError {}

/// What a driver needs of a simulation: `Simulation` itself, or anything that
/// steps like it (a test double). The CLI's run loop needs only this; the FMI
/// model layer extends it (`model::Dynamics`).
pub trait Steppable {
    fn time(&self) -> f64;
    /// The outputs, in a fixed order.
    fn outputs(&self) -> &[OutputInfo];
    /// Current output values, in the order of `outputs()`.
    fn output_values(&self, values: &mut [f64]);
    /// Advance to `t`; on error the state is that at the start of the
    /// failing internal step.
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError>;
}

impl Steppable for Simulation {
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn outputs(&self) -> &[OutputInfo] {
        Simulation::outputs(self)
    }
    fn output_values(&self, values: &mut [f64]) {
        Simulation::output_values(self, values)
    }
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        Simulation::advance_to(self, t)
    }
}

/// Everything needed to continue a run bit-identically.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimState {
    pub time: f64,
    /// Index of the last grid point k·Δt reached (the grid of `solver.step`).
    pub grid_step: u64,
    pub dynamic: DynamicState,
    /// Converged contact force of the last steps, newest first, and the
    /// lengths of the steps between them: the history the next step's
    /// initial guess is extrapolated from.
    pub force_history: [ContactForce; 3],
    pub step_history: [f64; 2],
    pub body_force: [f64; 2],
    pub external_work: f64,
    pub initial_energy: f64,
    pub last_iterations: u32,
    pub last_velocity_error: f64,
    pub last_gap_error: f64,
    pub steps: u64,
    pub total_iterations: u64,
    pub exit_time: Option<f64>,
}

/// Initial guess of the next step's contact force (procedure step 1):
/// quadratic extrapolation of the last three converged forces, at times
/// 0, −h₀, −h₀−h₁, to time `dt`.
fn extrapolate(history: &[ContactForce; 3], steps: &[f64; 2], dt: f64) -> ContactForce {
    let nodes = [0.0, -steps[0], -steps[0] - steps[1]];
    let mut guess = Vector2::zeros();
    for (i, force) in history.iter().enumerate() {
        let mut weight = 1.0;
        for (j, node) in nodes.iter().enumerate() {
            if i != j {
                weight *= (dt - node) / (nodes[i] - node);
            }
        }
        guess += weight * force.as_vector();
    }
    ContactForce::from_vector(guess)
}

/// The largest step explicit RK4 is stable at for this beam (s): its
/// stability region reaches 2√2 on the imaginary axis.
pub fn rk4_step_limit(system: &System) -> f64 {
    2.0 * std::f64::consts::SQRT_2 / system.beam.highest_frequency()
}

/// The least numerical damping `auto` runs HHT-α with.
pub const AUTO_MIN_DAMPING: f64 = 0.1;

fn choose_integrator(system: &System, solver: &SolverSpec) -> Result<(Integrator, String), String> {
    let step = solver.step;
    let damping = solver.numerical_damping;
    let hht = |damping: f64, why: String| -> Result<(Integrator, String), String> {
        let integrator = Hht::new(system, damping, step)?;
        Ok((
            Integrator::Hht(Box::new(integrator)),
            format!("hht (implicit HHT-α, α = {}){why}", 0.0 - damping),
        ))
    };
    match solver.integrator {
        IntegratorKind::Hht => hht(damping, String::new()),
        IntegratorKind::Rk4 | IntegratorKind::Auto => {
            let limit = rk4_step_limit(system);
            let free = system.beam.free_dofs();
            if step <= limit {
                let why = if solver.integrator == IntegratorKind::Auto {
                    format!("; auto: the step is within RK4's stability limit {limit:.3e} s")
                } else {
                    String::new()
                };
                return Ok((
                    Integrator::Rk4(Rk4::new(free)),
                    format!("rk4 (explicit){why}"),
                ));
            }
            if solver.integrator == IntegratorKind::Auto {
                // Undamped HHT lets the contact force oscillate from step to
                // step at high speed (a spurious early lift-off at 150 m/s on
                // 8 elements, report/stress.md): auto damps at least a little.
                return hht(
                    damping.max(AUTO_MIN_DAMPING),
                    format!("; auto: RK4 would need a step of at most {limit:.3e} s for this mesh"),
                );
            }
            Err(format!(
                "solver.step = {step} s is beyond the stability limit of explicit RK4 \
                 for this mesh: elements of {:.4} m give the beam a highest frequency of \
                 {:.1} rad/s, so the step must not exceed {limit:.3e} s; shorten solver.step, \
                 use fewer elements, or set solver.integrator = \"hht\" or \"auto\"",
                system.beam.min_element_length(),
                2.0 * std::f64::consts::SQRT_2 / limit
            ))
        }
    }
}

/// Which quantity an output reports.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Quantity {
    X,
    Y,
    Vx,
    Vy,
    AngularVelocity,
    NominalSpeed,
    ContactPosition,
    TangentialForce,
    NormalForce,
    Sensor(usize),
    BodyKinetic,
    BeamKinetic,
    BeamStrain,
    ExternalWork,
    Balance,
    VelocityError,
    GapError,
    Iterations,
}

pub struct Simulation {
    system: System,
    /// Which integrator runs, and why (for `auto`).
    integrator_choice: String,
    sensors: Vec<f64>,
    step: f64,
    settings: IterationSettings,
    iteration: ContactIteration,
    state: SimState,
    scratch: DynamicState,
    outputs: Vec<OutputInfo>,
    quantities: Vec<Quantity>,
}

fn output_table(scene: &Scene) -> Vec<(OutputInfo, Quantity)> {
    let b = &scene.body.name;
    let rolls = scene.body.kind == BodyKind::Wheel;
    let real = |name: String, unit: &'static str, description: &str| OutputInfo {
        name,
        unit,
        description: description.to_string(),
        kind: OutputKind::Real,
    };
    let mut table = vec![
        (
            real(
                format!("{b}.x"),
                "m",
                "horizontal position of the body's centre",
            ),
            Quantity::X,
        ),
        (
            real(
                format!("{b}.y"),
                "m",
                "vertical position of the body's centre",
            ),
            Quantity::Y,
        ),
        (
            real(
                format!("{b}.vx"),
                "m/s",
                "horizontal velocity of the body's centre",
            ),
            Quantity::Vx,
        ),
        (
            real(
                format!("{b}.vy"),
                "m/s",
                "vertical velocity of the body's centre",
            ),
            Quantity::Vy,
        ),
    ];
    if rolls {
        table.push((
            real(
                format!("{b}.angular_velocity"),
                "rad/s",
                "angular velocity, counter-clockwise positive",
            ),
            Quantity::AngularVelocity,
        ));
    }
    table.push((
        real(
            format!("{b}.nominal_speed"),
            "m/s",
            "nominal travel speed V = vx + (r + h) dphi/dt (eq. 24)",
        ),
        Quantity::NominalSpeed,
    ));
    table.push((
        real(
            "contact.position".into(),
            "m",
            "abscissa of the contact point along the beam",
        ),
        Quantity::ContactPosition,
    ));
    if rolls {
        table.push((
            real(
                "contact.tangential_force".into(),
                "N",
                "tangential contact force on the body",
            ),
            Quantity::TangentialForce,
        ));
    }
    table.push((
        real(
            "contact.normal_force".into(),
            "N",
            "normal contact force on the body (positive pushes it off the beam)",
        ),
        Quantity::NormalForce,
    ));
    for (i, sensor) in scene.sensors.iter().enumerate() {
        table.push((
            real(
                format!("sensor.{}.deflection", sensor.name),
                "m",
                "beam deflection at the sensor (up positive)",
            ),
            Quantity::Sensor(i),
        ));
    }
    table.extend([
        (
            real(
                "energy.body_kinetic".into(),
                "J",
                "kinetic energy of the body",
            ),
            Quantity::BodyKinetic,
        ),
        (
            real(
                "energy.beam_kinetic".into(),
                "J",
                "kinetic energy of the beam",
            ),
            Quantity::BeamKinetic,
        ),
        (
            real(
                "energy.beam_strain".into(),
                "J",
                "strain energy of the beam",
            ),
            Quantity::BeamStrain,
        ),
        (
            real(
                "energy.external_work".into(),
                "J",
                "work done by the force on the body's centre",
            ),
            Quantity::ExternalWork,
        ),
        (
            real(
                "energy.balance".into(),
                "J",
                "kinetic + strain energy - external work: constant for the exact solution",
            ),
            Quantity::Balance,
        ),
        (
            real(
                "solver.velocity_error".into(),
                "m/s",
                "|e| at the end of the last step",
            ),
            Quantity::VelocityError,
        ),
        (
            real(
                "solver.gap_error".into(),
                "m",
                "gap error g at the end of the last step",
            ),
            Quantity::GapError,
        ),
    ]);
    table.push((
        OutputInfo {
            name: "solver.iterations".into(),
            unit: "",
            description: "contact-force iterations in the last step".into(),
            kind: OutputKind::Integer,
        },
        Quantity::Iterations,
    ));
    table
}

impl Simulation {
    /// Build the model a scene asks for. The scene must be valid.
    pub fn new(scene: &Scene) -> Result<Simulation, String> {
        let beam = Beam::new(&scene.beam)?;
        let body = RigidBody::from_spec(&scene.body);
        let step = scene.solver.step;
        let system = System { beam, body };
        let (integrator, integrator_choice) = choose_integrator(&system, &scene.solver)?;
        let (beam, body) = (&system.beam, &system.body);
        let x0 = scene.body.initial_position;
        let v0 = scene.body.initial_speed;
        let body_state = BodyState {
            position: Vector2::new(x0, body.radius + beam.surface_offset),
            velocity: Vector2::new(v0, 0.0),
            angle: 0.0,
            angular_velocity: if body.rolls && body.radius > 0.0 {
                -v0 / body.radius
            } else {
                0.0
            },
        };
        let n = beam.free_dofs();
        let body_force = [scene.body.force_x, scene.body.force_y];
        // Initial guess: the normal force balances the applied force.
        let force = ContactForce {
            tangential: 0.0,
            normal: -body_force[1],
        };
        // Loads and accelerations consistent with that force (the implicit
        // scheme starts from them).
        let undeformed = DVector::zeros(n);
        let frame = foot_point(beam, &undeformed, &body_state.position, x0)
            .map_err(|e| format!("no contact point at the start (x = {})", e.last_x))?;
        let external = Vector2::new(body_force[0], body_force[1]);
        let mut beam_load = DVector::zeros(n);
        let body_load = contact_loads(&system, &frame, force, external, &mut beam_load);
        let mut beam_acceleration = DVector::zeros(n);
        beam.accelerations(&undeformed, &beam_load, &mut beam_acceleration);
        let body_acceleration = body.acceleration(&body_load);
        let dynamic = DynamicState {
            beam_displacement: undeformed,
            beam_velocity: DVector::zeros(n),
            beam_acceleration,
            body_acceleration,
            beam_load,
            body_load,
            body: body_state,
            contact_x: x0,
        };
        let (outputs, quantities) = output_table(scene).into_iter().unzip();
        let mut simulation = Simulation {
            sensors: scene.sensors.iter().map(|s| s.position).collect(),
            step,
            settings: IterationSettings {
                velocity_tolerance: scene.solver.velocity_tolerance,
                gap_tolerance: scene.solver.gap_tolerance,
                max_iterations: scene.solver.max_iterations,
            },
            iteration: ContactIteration::new(integrator, n, beam.elements(), step),
            integrator_choice,
            scratch: dynamic.clone(),
            state: SimState {
                time: 0.0,
                grid_step: 0,
                dynamic,
                force_history: [force; 3],
                step_history: [step; 2],
                body_force,
                external_work: 0.0,
                initial_energy: 0.0,
                last_iterations: 0,
                last_velocity_error: 0.0,
                last_gap_error: 0.0,
                steps: 0,
                total_iterations: 0,
                exit_time: None,
            },
            system,
            outputs,
            quantities,
        };
        simulation.state.initial_energy = simulation.energy_balance();
        Ok(simulation)
    }

    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The integrator that runs, in words (`auto` says what it picked and why).
    pub fn integrator_choice(&self) -> &str {
        &self.integrator_choice
    }

    /// The outputs this scene has, in a fixed order.
    pub fn outputs(&self) -> &[OutputInfo] {
        &self.outputs
    }

    fn contact_frame(&self) -> Option<ContactFrame> {
        let d = &self.state.dynamic;
        foot_point(
            &self.system.beam,
            &d.beam_displacement,
            &d.body.position,
            d.contact_x,
        )
        .ok()
    }

    /// Current output values, in the order of `outputs()`.
    pub fn output_values(&self, values: &mut [f64]) {
        let d = &self.state.dynamic;
        let beam = &self.system.beam;
        let body = &self.system.body;
        let frame = self.contact_frame();
        for (value, quantity) in values.iter_mut().zip(&self.quantities) {
            *value = match *quantity {
                Quantity::X => d.body.position.x,
                Quantity::Y => d.body.position.y,
                Quantity::Vx => d.body.velocity.x,
                Quantity::Vy => d.body.velocity.y,
                Quantity::AngularVelocity => d.body.angular_velocity,
                Quantity::NominalSpeed => frame.map_or(f64::NAN, |f| {
                    f.nominal_speed(beam, body, &d.body, &d.beam_velocity)
                }),
                Quantity::ContactPosition => d.contact_x,
                Quantity::TangentialForce => self.state.force_history[0].tangential,
                Quantity::NormalForce => self.state.force_history[0].normal,
                Quantity::Sensor(i) => beam.deflection(&d.beam_displacement, self.sensors[i]),
                Quantity::BodyKinetic => body.kinetic_energy(&d.body),
                Quantity::BeamKinetic => beam.kinetic_energy(&d.beam_velocity),
                Quantity::BeamStrain => beam.strain_energy(&d.beam_displacement),
                Quantity::ExternalWork => self.state.external_work,
                Quantity::Balance => self.energy_balance(),
                Quantity::VelocityError => self.state.last_velocity_error,
                Quantity::GapError => self.state.last_gap_error,
                Quantity::Iterations => self.state.last_iterations as f64,
            };
        }
    }

    /// Kinetic + strain energy − work of external forces (J).
    pub fn energy_balance(&self) -> f64 {
        let d = &self.state.dynamic;
        self.system.body.kinetic_energy(&d.body)
            + self.system.beam.kinetic_energy(&d.beam_velocity)
            + self.system.beam.strain_energy(&d.beam_displacement)
            - self.state.external_work
    }

    /// Total energy at t = 0 (J), the reference of relative energy drift.
    pub fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }

    /// Set the external force on the body's centre (N), held until changed.
    pub fn set_body_force(&mut self, fx: f64, fy: f64) {
        self.state.body_force = [fx, fy];
    }

    /// The fixed internal step (s).
    pub fn step_size(&self) -> f64 {
        self.step
    }

    /// Steps taken and contact iterations spent so far.
    pub fn counters(&self) -> (u64, u64) {
        (self.state.steps, self.state.total_iterations)
    }

    /// Exit time, once the body has left the beam.
    pub fn exit_time(&self) -> Option<f64> {
        self.state.exit_time
    }

    pub fn state(&self) -> SimState {
        self.state.clone()
    }

    pub fn restore(&mut self, state: &SimState) -> Result<(), String> {
        let n = self.system.beam.free_dofs();
        let d = &state.dynamic;
        if d.beam_displacement.len() != n || d.beam_velocity.len() != n {
            return Err(format!(
                "the state has {} beam DOFs but this model has {n}",
                d.beam_displacement.len()
            ));
        }
        self.state = state.clone();
        Ok(())
    }

    /// Advance to `target` with internal steps on the grid k·`solver.step`,
    /// the last one shortened to land on `target`; stops early at the exit.
    pub fn advance_to(&mut self, target: f64) -> Result<Advance, SolverError> {
        let tolerance = 1e-9 * self.step;
        loop {
            if let Some(time) = self.state.exit_time {
                return Ok(Advance::Exited { time });
            }
            if self.state.time >= target - tolerance {
                return Ok(Advance::Reached);
            }
            let next_grid = (self.state.grid_step + 1) as f64 * self.step;
            if next_grid <= target + tolerance {
                self.step_to(next_grid)?;
                if self.state.exit_time.is_none() {
                    self.state.grid_step += 1;
                }
            } else {
                self.step_to(target)?;
            }
        }
    }

    /// One step from the current time to `to`, or to the exit if the contact
    /// point reaches an end of the beam first.
    fn step_to(&mut self, to: f64) -> Result<(), SolverError> {
        let dt = to - self.state.time;
        let s = &self.state;
        let guess = extrapolate(&s.force_history, &s.step_history, dt);
        let external = Vector2::new(s.body_force[0], s.body_force[1]);
        let solution = self.solve(guess, dt)?;
        if solution.force.normal < 0.0 {
            // The contact is bilateral: a tensile normal force means the body
            // would leave the surface, which this model does not follow.
            return Err(SolverError {
                time: self.state.time,
                message: format!(
                    "lift-off: the normal contact force would become tensile ({:.6e} N) in the \
                     step from t = {} s at x = {:.6} m; the contact is bilateral, so the run \
                     stops at the last step with compression",
                    solution.force.normal, self.state.time, self.scratch.contact_x
                ),
            });
        }
        let length = self.system.beam.length;
        let end_x = self.scratch.contact_x;
        let start_x = self.state.dynamic.contact_x;
        let boundary = if end_x >= length && start_x < length {
            Some(length)
        } else if end_x < 0.0 && start_x >= 0.0 && end_x < start_x {
            Some(0.0)
        } else {
            None
        };
        let (solution, dt) = match boundary {
            None => (solution, dt),
            Some(edge) => self.find_exit(edge, solution.force, dt)?,
        };
        let s = &mut self.state;
        s.external_work += external.dot(&(self.scratch.body.position - s.dynamic.body.position));
        std::mem::swap(&mut s.dynamic, &mut self.scratch);
        s.force_history = [solution.force, s.force_history[0], s.force_history[1]];
        s.step_history = [dt, s.step_history[0]];
        s.time = if boundary.is_some() { s.time + dt } else { to };
        s.last_iterations = solution.iterations;
        s.last_velocity_error = solution.velocity_error;
        s.last_gap_error = solution.gap_error;
        s.steps += 1;
        s.total_iterations += solution.iterations as u64;
        if boundary.is_some() {
            s.exit_time = Some(s.time);
        }
        Ok(())
    }

    fn solve(
        &mut self,
        guess: ContactForce,
        dt: f64,
    ) -> Result<crate::iteration::StepSolution, SolverError> {
        let s = &self.state;
        let external = Vector2::new(s.body_force[0], s.body_force[1]);
        let solution = self
            .iteration
            .solve(
                &self.system,
                &s.dynamic,
                guess,
                external,
                dt,
                &self.settings,
                &mut self.scratch,
            )
            .map_err(|e| SolverError {
                time: s.time,
                message: e.to_string(),
            })?;
        if !self.scratch.beam_displacement.iter().all(|x| x.is_finite()) {
            return Err(SolverError {
                time: s.time,
                message: "the beam state became non-finite".into(),
            });
        }
        Ok(solution)
    }

    /// Shorten the step so that the contact point lands on `edge` (regula
    /// falsi on the step length, Illinois variant). Leaves the exit state in
    /// `scratch`.
    fn find_exit(
        &mut self,
        edge: f64,
        force: ContactForce,
        dt: f64,
    ) -> Result<(crate::iteration::StepSolution, f64), SolverError> {
        let start_x = self.state.dynamic.contact_x;
        let (mut lo, mut f_lo) = (0.0, start_x - edge);
        let (mut hi, mut f_hi) = (dt, self.scratch.contact_x - edge);
        let mut side = 0;
        for _ in 0..60 {
            let tau = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let solution = self.solve(force, tau)?;
            let f = self.scratch.contact_x - edge;
            if f.abs() <= 1e-12 * self.system.beam.length || (hi - lo) <= 1e-15 * dt {
                return Ok((solution, tau));
            }
            if (f > 0.0) == (f_hi > 0.0) {
                hi = tau;
                f_hi = f;
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            } else {
                lo = tau;
                f_lo = f;
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            }
        }
        Err(SolverError {
            time: self.state.time,
            message: format!("the exit instant at x = {edge} m could not be located"),
        })
    }
}
