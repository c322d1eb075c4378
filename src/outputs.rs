//! The catalogue of outputs: one named, typed, unit-carrying entry per
//! reported quantity, generated from the system. CSV headers, plots, the
//! summary and the FMU variable table are all read from it.

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

/// Which quantity an output reports; indices are into the system's bodies,
/// contacts and the scene's sensors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quantity {
    X(usize),
    Y(usize),
    Vx(usize),
    Vy(usize),
    Ax(usize),
    Ay(usize),
    AngularAcceleration(usize),
    Angle(usize),
    AngularVelocity(usize),
    NominalSpeed(usize),
    ContactPosition(usize),
    TangentialForce(usize),
    NormalForce(usize),
    OnBeam(usize),
    Sensor(usize),
    BodyKinetic,
    BeamKinetic,
    BeamStrain,
    SpringEnergy,
    Dissipated,
    BeamDamping,
    GravityWork,
    ExternalWork,
    Balance,
    VelocityError,
    GapError,
    Iterations,
    PositionIterations,
}

struct Catalogue {
    entries: Vec<(OutputInfo, Quantity)>,
}

impl Catalogue {
    fn real(&mut self, name: String, unit: &'static str, description: &str, q: Quantity) {
        self.push(name, unit, description, q, OutputKind::Real);
    }
    fn push(
        &mut self,
        name: String,
        unit: &'static str,
        description: &str,
        q: Quantity,
        kind: OutputKind,
    ) {
        let info = OutputInfo {
            name,
            unit,
            description: description.to_string(),
            kind,
        };
        self.entries.push((info, q));
    }

    fn body(&mut self, system: &System, b: usize) {
        let body = &system.bodies[b];
        let n = &body.name;
        let is_contact_body = system.contacts.iter().any(|c| c.body == b);
        self.real(
            format!("{n}.x"),
            "m",
            "horizontal position of the body's centre",
            Quantity::X(b),
        );
        self.real(
            format!("{n}.y"),
            "m",
            "vertical position of the body's centre",
            Quantity::Y(b),
        );
        self.real(
            format!("{n}.vx"),
            "m/s",
            "horizontal velocity of the body's centre",
            Quantity::Vx(b),
        );
        self.real(
            format!("{n}.vy"),
            "m/s",
            "vertical velocity of the body's centre",
            Quantity::Vy(b),
        );
        let coupled = system.couplings.contains(&b);
        if coupled {
            self.real(
                format!("{n}.ax"),
                "m/s2",
                "horizontal acceleration of the body's centre",
                Quantity::Ax(b),
            );
        }
        if !system.force_elements.is_empty() || coupled {
            self.real(
                format!("{n}.ay"),
                "m/s2",
                "vertical acceleration of the body's centre",
                Quantity::Ay(b),
            );
        }
        if body.turns() && (!is_contact_body || coupled) {
            self.real(
                format!("{n}.pitch"),
                "rad",
                "pitch angle, counter-clockwise positive",
                Quantity::Angle(b),
            );
        }
        if body.turns() {
            self.real(
                format!("{n}.angular_velocity"),
                "rad/s",
                "angular velocity, counter-clockwise positive",
                Quantity::AngularVelocity(b),
            );
        }
        if body.turns() && coupled {
            self.real(
                format!("{n}.angular_acceleration"),
                "rad/s2",
                "angular acceleration, counter-clockwise positive",
                Quantity::AngularAcceleration(b),
            );
        }
        for (c, contact) in system.contacts.iter().enumerate() {
            if contact.body == b {
                self.real(
                    format!("{n}.nominal_speed"),
                    "m/s",
                    "nominal travel speed V = vx + (r + h) dphi/dt (eq. 24)",
                    Quantity::NominalSpeed(c),
                );
            }
        }
    }

    fn contact(&mut self, system: &System, c: usize) {
        let contact = &system.contacts[c];
        let n = &contact.name;
        self.real(
            format!("{n}.position"),
            "m",
            "abscissa of the contact point along the track",
            Quantity::ContactPosition(c),
        );
        if contact.rolls() {
            self.real(
                format!("{n}.tangential_force"),
                "N",
                "tangential contact force on the body",
                Quantity::TangentialForce(c),
            );
        }
        self.real(
            format!("{n}.normal_force"),
            "N",
            "normal contact force on the body (positive pushes it off the track)",
            Quantity::NormalForce(c),
        );
        let track = &system.track;
        if track.approach > 0.0 || track.run_off > 0.0 || track.open_ends {
            self.push(
                format!("{n}.on_beam"),
                "",
                "1 while the contact point is on the beam (the structure), 0 on rigid ground or \
                 beyond the track",
                Quantity::OnBeam(c),
                OutputKind::Integer,
            );
        }
    }

    fn energy(&mut self, system: &System) {
        let e = |s: &str| format!("energy.{s}");
        self.real(
            e("body_kinetic"),
            "J",
            "kinetic energy of the bodies",
            Quantity::BodyKinetic,
        );
        self.real(
            e("beam_kinetic"),
            "J",
            "kinetic energy of the beam",
            Quantity::BeamKinetic,
        );
        self.real(
            e("beam_strain"),
            "J",
            "strain energy of the beam",
            Quantity::BeamStrain,
        );
        if !system.force_elements.is_empty() {
            self.real(
                e("spring"),
                "J",
                "potential energy of the force elements' springs",
                Quantity::SpringEnergy,
            );
            self.real(
                e("dissipated"),
                "J",
                "energy dissipated by the force elements' dampers",
                Quantity::Dissipated,
            );
        }
        if !system.beam.damping().is_zero() {
            self.real(
                e("beam_damping"),
                "J",
                "energy dissipated by the beam's Rayleigh structural damping",
                Quantity::BeamDamping,
            );
        }
        if system.gravity != 0.0 {
            self.real(
                e("gravity_work"),
                "J",
                "work done by gravity on the bodies",
                Quantity::GravityWork,
            );
        }
        self.real(
            e("external_work"),
            "J",
            "work done by the applied force",
            Quantity::ExternalWork,
        );
        self.real(
            e("balance"),
            "J",
            "kinetic + strain + spring energy + dissipated (dampers, beam damping) - work of \
             gravity and applied force: \
             constant for the exact solution",
            Quantity::Balance,
        );
    }

    fn solver(&mut self) {
        self.real(
            "solver.velocity_error".into(),
            "m/s",
            "largest contact |e| at the end of the last step",
            Quantity::VelocityError,
        );
        self.real(
            "solver.gap_error".into(),
            "m",
            "gap error g of largest magnitude at the end of the last step",
            Quantity::GapError,
        );
        self.push(
            "solver.iterations".into(),
            "",
            "contact-force iterations in the last step",
            Quantity::Iterations,
            OutputKind::Integer,
        );
    }
}

/// The outputs of `system` with the named sensors, in their fixed order.
pub fn catalogue(system: &System, sensors: &[String]) -> Vec<(OutputInfo, Quantity)> {
    let mut c = Catalogue {
        entries: Vec::new(),
    };
    for b in 0..system.bodies.len() {
        c.body(system, b);
    }
    for k in 0..system.contacts.len() {
        c.contact(system, k);
    }
    for (i, name) in sensors.iter().enumerate() {
        c.real(
            format!("sensor.{name}.deflection"),
            "m",
            "beam deflection at the sensor (up positive)",
            Quantity::Sensor(i),
        );
    }
    c.energy(system);
    c.solver();
    if system.contacts.len() > 1 {
        c.push(
            "solver.position_iterations".into(),
            "",
            "iterations of the position (gap) stage in the last step",
            Quantity::PositionIterations,
            OutputKind::Integer,
        );
    }
    c.entries
}

/// The current value of each quantity of `quantities` into `values`.
pub fn values(sim: &crate::Simulation, quantities: &[Quantity], values: &mut [f64]) {
    let system = sim.system();
    let state = sim.current();
    let d = &state.dynamic;
    let beam = &system.beam;
    let needs_frames = quantities
        .iter()
        .any(|q| matches!(q, Quantity::NominalSpeed(_)));
    let frames = needs_frames.then(|| {
        let mut frames = Vec::new();
        crate::integrate::contact_frames(
            system,
            &d.beam_displacement,
            &d.bodies,
            (&d.contact_x, &state.parts),
            &mut frames,
        )
        .map(|_| frames)
        .ok()
    });
    let needs_accelerations = quantities.iter().any(|q| {
        matches!(
            q,
            Quantity::Ax(_) | Quantity::Ay(_) | Quantity::AngularAcceleration(_)
        )
    });
    let accelerations = needs_accelerations.then(|| sim.body_accelerations());
    for (value, quantity) in values.iter_mut().zip(quantities) {
        *value = match *quantity {
            Quantity::X(b) => d.bodies[b].position.x,
            Quantity::Y(b) => d.bodies[b].position.y,
            Quantity::Vx(b) => d.bodies[b].velocity.x,
            Quantity::Vy(b) => d.bodies[b].velocity.y,
            Quantity::Ax(b) => accelerations.as_ref().map_or(f64::NAN, |a| a[b].x),
            Quantity::Ay(b) => accelerations.as_ref().map_or(f64::NAN, |a| a[b].y),
            Quantity::AngularAcceleration(b) => accelerations.as_ref().map_or(f64::NAN, |a| a[b].z),
            Quantity::Angle(b) => d.bodies[b].angle,
            Quantity::AngularVelocity(b) => d.bodies[b].angular_velocity,
            Quantity::NominalSpeed(c) => match frames.as_ref().and_then(|f| f.as_ref()) {
                Some(frames) => {
                    let contact = &system.contacts[c];
                    let body = &d.bodies[contact.body];
                    frames[c].nominal_speed(beam, contact.radius(), body, &d.beam_velocity)
                }
                None => f64::NAN,
            },
            Quantity::ContactPosition(c) => d.contact_x[c],
            Quantity::TangentialForce(c) => state.force_history[c][0].tangential,
            Quantity::NormalForce(c) => state.force_history[c][0].normal,
            Quantity::OnBeam(c) => {
                f64::from(u8::from(state.parts[c] == crate::system::TrackPart::Beam))
            }
            Quantity::Sensor(i) => beam.deflection(&d.beam_displacement, sim.sensor_positions()[i]),
            Quantity::BodyKinetic => sim.body_kinetic_energy(),
            Quantity::BeamKinetic => beam.kinetic_energy(&d.beam_velocity),
            Quantity::BeamStrain => beam.strain_energy(&d.beam_displacement),
            Quantity::SpringEnergy => system.spring_energy(&d.bodies),
            Quantity::Dissipated => d.dissipated,
            Quantity::BeamDamping => d.beam_dissipated,
            Quantity::GravityWork => state.gravity_work,
            Quantity::ExternalWork => state.external_work,
            Quantity::Balance => sim.energy_balance(),
            Quantity::VelocityError => state.last_velocity_error,
            Quantity::GapError => state.last_gap_error,
            Quantity::Iterations => state.last_iterations as f64,
            Quantity::PositionIterations => state.last_position_iterations as f64,
        };
    }
}
