//! The catalogue of outputs: one named, typed, unit-carrying entry per
//! reported quantity, generated from the system. CSV headers, plots, the
//! summary and the FMU variable table are all read from it.

use crate::energy;
use crate::state::SimState;
use crate::structure::beam::Beam;
use crate::system::System;
use derived::{beam_dynamics, body_accelerations, frames_now};
use strum::{EnumDiscriminants, EnumIter};

pub mod derived;
mod finite;
pub mod mask;
pub mod names;

pub use derived::Probes;
pub use finite::non_finite_output;
pub use names::{classify, output_name, reports, OutputName};

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
/// contacts and the scene's sensors. Its variants without their indices
/// are `QuantityKind` (derived: what an output reports, without whose),
/// named in `names`.
#[derive(Debug, Clone, Copy, PartialEq, EnumDiscriminants)]
#[strum_discriminants(name(QuantityKind), derive(Hash, EnumIter))]
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
    ContactClosed(usize),
    Gap(usize),
    /// An EMS magnet's air gap s₀ − g (m) and relative current i/i₀.
    MagnetAirGap(usize),
    MagnetCurrent(usize),
    ImpulseTangential(usize),
    ImpulseNormal(usize),
    Irregularity(usize),
    Sensor(usize),
    SensorVelocity(usize),
    /// Load per metre on the Winkler foundation at sensor i.
    SensorFoundationLoad(usize),
    /// The rail's deflection at sensor i, under a rail over the deck.
    SensorRailDeflection(usize),
    /// The pad force of the sleeper nearest sensor i, on sleepers.
    SensorRailSeatForce(usize),
    SensorAcceleration(usize),
    SectionMoment(usize),
    SectionShear(usize),
    /// The vertical reaction at the support on this node.
    Reaction(usize),
    /// The moment of the clamp on this node.
    ReactionMoment(usize),
    BodyKinetic,
    BeamKinetic,
    BeamStrain,
    SpringEnergy,
    Dissipated,
    BeamDamping,
    GravityWork,
    ExternalWork,
    TractiveWork,
    ImpactLoss,
    NumericalDissipation,
    Balance,
    VelocityError,
    GapError,
    Iterations,
    PositionIterations,
}

impl Quantity {
    /// What this quantity reports, without its index.
    pub fn kind(&self) -> QuantityKind {
        QuantityKind::from(self)
    }
}

struct Catalogue {
    entries: Vec<(OutputInfo, Quantity)>,
}

impl Catalogue {
    /// A Real output reporting `q` of `owner` (`names::output_name`).
    fn real(&mut self, owner: &str, unit: &'static str, description: &str, q: Quantity) {
        self.push(owner, unit, description, q, OutputKind::Real);
    }
    fn push(
        &mut self,
        owner: &str,
        unit: &'static str,
        description: &str,
        q: Quantity,
        kind: OutputKind,
    ) {
        let info = OutputInfo {
            name: output_name(q.kind(), owner),
            unit,
            description: description.to_string(),
            kind,
        };
        self.entries.push((info, q));
    }

    fn body(&mut self, system: &System, b: usize) {
        let n = &system.bodies[b].name;
        self.real(
            n,
            "m",
            "horizontal position of the body's centre",
            Quantity::X(b),
        );
        self.real(
            n,
            "m",
            "vertical position of the body's centre",
            Quantity::Y(b),
        );
        self.real(
            n,
            "m/s",
            "horizontal velocity of the body's centre",
            Quantity::Vx(b),
        );
        self.real(
            n,
            "m/s",
            "vertical velocity of the body's centre",
            Quantity::Vy(b),
        );
        self.body_accelerations(system, b);
        self.body_rotation(system, b);
        self.nominal_speeds(system, b);
    }

    /// A body's accelerations: where it is coupled (the FMU's inputs), or
    /// its vertical one where anything but a contact acts on it.
    fn body_accelerations(&mut self, system: &System, b: usize) {
        let n = &system.bodies[b].name;
        let coupled = system.couplings.contains(&b);
        if coupled {
            self.real(
                n,
                "m/s2",
                "horizontal acceleration of the body's centre",
                Quantity::Ax(b),
            );
        }
        let on_follower = system
            .contacts
            .iter()
            .any(|c| c.body == b && c.follower.is_some());
        if !system.force_elements.is_empty() || coupled || on_follower {
            self.real(
                n,
                "m/s2",
                "vertical acceleration of the body's centre",
                Quantity::Ay(b),
            );
        }
    }

    /// A turning body's pitch, angular velocity and acceleration.
    fn body_rotation(&mut self, system: &System, b: usize) {
        let body = &system.bodies[b];
        let n = &body.name;
        let coupled = system.couplings.contains(&b);
        // A body over massless followers pitches like a car body: its
        // angle is not a wheel's rolling angle.
        let is_contact_body = system
            .contacts
            .iter()
            .any(|c| c.body == b && c.follower.is_none());
        if body.turns() && (!is_contact_body || coupled) {
            self.real(
                n,
                "rad",
                "pitch angle, counter-clockwise positive",
                Quantity::Angle(b),
            );
        }
        if body.turns() {
            self.real(
                n,
                "rad/s",
                "angular velocity, counter-clockwise positive",
                Quantity::AngularVelocity(b),
            );
        }
        if body.turns() && coupled {
            self.real(
                n,
                "rad/s2",
                "angular acceleration, counter-clockwise positive",
                Quantity::AngularAcceleration(b),
            );
        }
    }

    /// The nominal speed of each contact of body `b`.
    fn nominal_speeds(&mut self, system: &System, b: usize) {
        let n = &system.bodies[b].name;
        for (c, contact) in system.contacts.iter().enumerate() {
            if contact.body == b {
                // Several followers share their body: each its own speed.
                let owner = if contact.is_attached() {
                    &contact.name
                } else {
                    n
                };
                self.real(
                    owner,
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
            n,
            "m",
            "abscissa of the contact point along the track",
            Quantity::ContactPosition(c),
        );
        if contact.rolls() {
            self.real(
                n,
                "N",
                "tangential contact force on the body",
                Quantity::TangentialForce(c),
            );
        }
        self.real(
            n,
            "N",
            "normal contact force on the body (positive pushes it off the track)",
            Quantity::NormalForce(c),
        );
        if system.profile.is_some() {
            self.real(
                n,
                "m",
                "track irregularity r(x) at the contact point (up positive)",
                Quantity::Irregularity(c),
            );
        }
        let track = &system.track;
        if track.approach > 0.0 || track.run_off > 0.0 || track.open_ends {
            self.push(
                n,
                "",
                "1 while the contact point is on the beam (the structure), 0 on rigid ground or \
                 beyond the track",
                Quantity::OnBeam(c),
                OutputKind::Integer,
            );
        }
        self.flight(contact, c);
        self.magnet(system, c);
    }

    /// An EMS magnet's air gap and current (`contact_law = "ems"`).
    fn magnet(&mut self, system: &System, c: usize) {
        if magnet(system, c).is_none() {
            return;
        }
        let n = &system.contacts[c].name;
        self.real(
            n,
            "m",
            "EMS magnet's air gap s = s0 - gap (nominal_gap s0 where the law carries its static load)",
            Quantity::MagnetAirGap(c),
        );
        self.real(
            n,
            "1",
            "EMS magnet's current over its operating current, i/i0 = 1 + (F - F0)/2F0 + (s - s0)/s0 \
             (the linearised force law; the controller's command below saturation)",
            Quantity::MagnetCurrent(c),
        );
    }

    /// Lift-off and landing: the contact's state, gap and last impact.
    fn flight(&mut self, contact: &crate::contact::Contact, c: usize) {
        let n = &contact.name;
        self.push(
            n,
            "",
            "1 while the contact is closed, 0 while it is open (in flight)",
            Quantity::ContactClosed(c),
            OutputKind::Integer,
        );
        self.real(
            n,
            "m",
            "gap g between the body and the track (zero to the gap tolerance while closed)",
            Quantity::Gap(c),
        );
        if contact.rolls() {
            self.real(
                n,
                "N.s",
                "tangential impulse on the body at the last impact it took part in (a landing or a rail-gap impact)",
                Quantity::ImpulseTangential(c),
            );
        }
        self.real(
            n,
            "N.s",
            "normal impulse on the body at the last impact it took part in (a landing or a rail-gap impact)",
            Quantity::ImpulseNormal(c),
        );
    }

    fn beam_energy(&mut self) {
        self.real("", "J", "kinetic energy of the beam", Quantity::BeamKinetic);
        self.real("", "J", "strain energy of the beam", Quantity::BeamStrain);
    }

    fn energy(&mut self, system: &System) {
        self.real(
            "",
            "J",
            "kinetic energy of the bodies",
            Quantity::BodyKinetic,
        );
        self.beam_energy();
        let followers = system.contacts.iter().any(|c| c.follower.is_some());
        if !system.force_elements.is_empty() || followers {
            self.real(
                "",
                "J",
                "potential energy of the force elements' and followers' springs",
                Quantity::SpringEnergy,
            );
            self.real(
                "",
                "J",
                "energy dissipated by the force elements' dampers",
                Quantity::Dissipated,
            );
        }
        if system.beam.is_damped() {
            self.real(
                "",
                "J",
                "energy dissipated by the beam's Rayleigh structural damping and support dampers",
                Quantity::BeamDamping,
            );
        }
        if system.gravity != 0.0 {
            self.real(
                "",
                "J",
                "work done by gravity on the bodies",
                Quantity::GravityWork,
            );
        }
        self.works(system);
    }

    /// The works of the forces on the system, the losses, and the balance.
    fn works(&mut self, system: &System) {
        self.real(
            "",
            "J",
            "work done by the applied force",
            Quantity::ExternalWork,
        );
        if system.bodies.iter().any(|b| b.drive.is_some()) {
            self.real(
                "",
                "J",
                "work done by the tractive forces that hold the prescribed speeds",
                Quantity::TractiveWork,
            );
        }
        self.real(
            "",
            "J",
            "kinetic energy lost in the landings' impacts",
            Quantity::ImpactLoss,
        );
        self.real(
            "",
            "J",
            "energy removed by the integrator's numerical damping: HHT-alpha's \
             from its discrete energy identity, RK4's from the beam's energy",
            Quantity::NumericalDissipation,
        );
        self.real(
            "",
            "J",
            "kinetic + strain + spring energy + dissipated (dampers, beam damping, impacts, \
             numerical damping) \
             - work of gravity, applied and tractive forces: \
             constant for the exact solution",
            Quantity::Balance,
        );
    }

    /// The structure's outputs: each sensor's, then the sections' and
    /// the supports' (design outputs).
    fn structure(&mut self, beam: &Beam, sensors: &[String], sections: &[String], reactions: bool) {
        for (i, name) in sensors.iter().enumerate() {
            self.real(
                name,
                "m",
                "beam deflection at the sensor (up positive)",
                Quantity::Sensor(i),
            );
            self.real(
                name,
                "m/s",
                "beam vertical velocity at the sensor (up positive)",
                Quantity::SensorVelocity(i),
            );
            self.real(
                name,
                "m/s2",
                "beam vertical acceleration at the sensor (up positive), from the current state \
                 and the contact forces of the last step: M^-1 (r - K u - C v)",
                Quantity::SensorAcceleration(i),
            );
            if beam.foundation().is_some() {
                self.real(
                    name,
                    "N/m",
                    "load per metre of beam on its Winkler foundation at the sensor, -(k w + c v), \
                     compression positive: the rail-seat load per metre of a rail",
                    Quantity::SensorFoundationLoad(i),
                );
            }
            if beam.track().is_some() {
                self.real(
                    name,
                    "m",
                    "deflection of the rail over the deck at the sensor (up positive); the \
                     sensor's deflection is the deck's",
                    Quantity::SensorRailDeflection(i),
                );
            }
            if beam.track().is_some_and(|t| t.has_sleepers()) {
                self.real(
                    name,
                    "N",
                    "rail-seat (pad) force of the sleeper nearest the sensor, compression \
                     positive: -(k_pad (w_rail - w_sleeper) + c_pad (v_rail - v_sleeper))",
                    Quantity::SensorRailSeatForce(i),
                );
            }
        }
        self.design(beam, sections, reactions);
    }

    fn design(&mut self, beam: &Beam, sections: &[String], reactions: bool) {
        for (i, name) in sections.iter().enumerate() {
            self.real(
                name,
                "N.m",
                "bending moment at the section, sagging positive (from the element equations)",
                Quantity::SectionMoment(i),
            );
            self.real(
                name,
                "N",
                "shear force at the section: upward force of the beam left of it on the \
                 beam right of it (dM/dx)",
                Quantity::SectionShear(i),
            );
        }
        if !reactions {
            return;
        }
        for support in crate::structure::section_forces::supports(beam) {
            let name = &support.name;
            self.real(
                name,
                "N",
                "vertical force of the support on the beam, up positive",
                Quantity::Reaction(support.node),
            );
            if support.has_moment {
                self.real(
                    name,
                    "N.m",
                    "moment of the support (clamp or rotational spring) on the beam, counter-clockwise positive",
                    Quantity::ReactionMoment(support.node),
                );
            }
        }
    }

    fn solver(&mut self) {
        self.real(
            "",
            "m/s",
            "largest contact |e| at the end of the last step",
            Quantity::VelocityError,
        );
        self.real(
            "",
            "m",
            "gap error g of largest magnitude at the end of the last step",
            Quantity::GapError,
        );
        self.push(
            "",
            "",
            "contact-force iterations in the last step",
            Quantity::Iterations,
            OutputKind::Integer,
        );
    }
}

/// The outputs of `system` with the named sensors, in their fixed order;
/// with `sections` (names) and `reactions` where the scene asks for them.
pub fn catalogue(
    system: &System,
    sensors: &[String],
    sections: &[String],
    reactions: bool,
) -> Vec<(OutputInfo, Quantity)> {
    let mut c = Catalogue {
        entries: Vec::new(),
    };
    for b in 0..system.bodies.len() {
        c.body(system, b);
    }
    for k in 0..system.contacts.len() {
        c.contact(system, k);
    }
    c.structure(&system.beam, sensors, sections, reactions);
    c.energy(system);
    c.solver();
    if system.contacts.len() > 1 {
        c.push(
            "",
            "",
            "iterations of the position (gap) stage in the last step",
            Quantity::PositionIterations,
            OutputKind::Integer,
        );
    }
    c.entries
}

/// The structure's outputs alone (sensors, sections, supports), as in
/// `catalogue`, and its kinetic and strain energy: the outputs of moving
/// forces, which have no bodies or contacts.
pub fn structure_catalogue(
    beam: &Beam,
    sensors: &[String],
    sections: &[String],
    reactions: bool,
) -> Vec<(OutputInfo, Quantity)> {
    let mut c = Catalogue {
        entries: Vec::new(),
    };
    c.structure(beam, sensors, sections, reactions);
    c.beam_energy();
    c.entries
}

/// The beam's state that the structure's outputs read: displacement,
/// velocity and, where known, its dynamics (acceleration, loads).
pub struct BeamNow<'a> {
    pub displacement: &'a nalgebra::DVector<f64>,
    pub velocity: &'a nalgebra::DVector<f64>,
    pub dynamics: Option<&'a crate::structure::section_forces::BeamDynamics>,
}

/// The value of a structure's `quantity` (sensors, sections, supports,
/// beam energies) for the beam `now` with `probes`' abscissae; `None` for
/// the other quantities.
pub fn structure_value(
    beam: &Beam,
    now: &BeamNow,
    probes: (&[f64], &[f64]),
    quantity: Quantity,
) -> Option<f64> {
    let (sensors, sections) = probes;
    let (u, v, dynamics) = (now.displacement, now.velocity, now.dynamics);
    Some(match quantity {
        Quantity::Sensor(i) => beam.deflection(u, sensors[i]),
        Quantity::SensorVelocity(i) => beam.deflection(v, sensors[i]),
        Quantity::SensorFoundationLoad(i) => beam.foundation().map_or(f64::NAN, |f| {
            let x = sensors[i];
            -(f.stiffness * beam.deflection(u, x) + f.damping * beam.deflection(v, x))
        }),
        Quantity::SensorRailDeflection(i) => beam
            .track()
            .map_or(f64::NAN, |t| t.rail_deflection(u, sensors[i])),
        Quantity::SensorRailSeatForce(i) => beam
            .track()
            .map_or(f64::NAN, |t| t.rail_seat_force(u, v, sensors[i])),
        Quantity::SensorAcceleration(i) => {
            dynamics.map_or(f64::NAN, |b| b.acceleration_at(beam, sensors[i]))
        }
        Quantity::SectionMoment(i) => {
            dynamics.map_or(f64::NAN, |b| b.section_forces(beam, sections[i]).moment)
        }
        Quantity::SectionShear(i) => {
            dynamics.map_or(f64::NAN, |b| b.section_forces(beam, sections[i]).shear)
        }
        Quantity::Reaction(node) => dynamics.map_or(f64::NAN, |b| b.reaction(beam, node)[0]),
        Quantity::ReactionMoment(node) => dynamics.map_or(f64::NAN, |b| b.reaction(beam, node)[1]),
        Quantity::BeamKinetic => beam.kinetic_energy(v),
        Quantity::BeamStrain => beam.strain_energy(u),
        _ => return None,
    })
}

/// The elements whose accelerations `quantities` read (with `probes`'
/// sensor and section abscissae): a sensor's or a section's element, a
/// support's elements either side of its node.
pub fn acceleration_elements(
    beam: &Beam,
    (sensors, sections): (&[f64], &[f64]),
    quantities: &[Quantity],
) -> Vec<usize> {
    let mut elements = Vec::new();
    for quantity in quantities {
        match *quantity {
            Quantity::SensorAcceleration(i) => elements.push(beam.element_at(sensors[i])),
            Quantity::SectionMoment(i) | Quantity::SectionShear(i) => {
                elements.push(beam.element_at(sections[i]))
            }
            Quantity::Reaction(node) | Quantity::ReactionMoment(node) => {
                elements.extend(node.checked_sub(1));
                elements.push(node);
            }
            _ => {}
        }
    }
    elements
}

/// What an output reads beyond the numbers the state holds: each a
/// derived quantity computed once per evaluation where an output needs it
/// (an output whose need is not computed would read NaN).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Needs {
    /// The contact frames now (`derived::frames_now`).
    pub frames: bool,
    /// The bodies' accelerations under the last forces
    /// (`derived::body_accelerations`).
    pub body_accelerations: bool,
    /// The beam's accelerations and loads under the last contact forces
    /// (`derived::beam_dynamics`: a mass solve per row, or the few dots of
    /// the design outputs' rows, `AccelerationRows`).
    pub beam_dynamics: bool,
    /// The springs' potential energy (`energy::spring`).
    pub spring_energy: bool,
    /// The energy the steps remove, booked by the integrator step by step
    /// (not computable at the end: see `Simulation::read_only`).
    pub energy_books: bool,
}

impl Needs {
    const NONE: Needs = Needs {
        frames: false,
        body_accelerations: false,
        beam_dynamics: false,
        spring_energy: false,
        energy_books: false,
    };
    const FRAMES: Needs = Needs {
        frames: true,
        ..Needs::NONE
    };
    const BODY_ACCELERATIONS: Needs = Needs {
        body_accelerations: true,
        ..Needs::NONE
    };
    const BEAM_DYNAMICS: Needs = Needs {
        beam_dynamics: true,
        ..Needs::NONE
    };
    const SPRING_ENERGY: Needs = Needs {
        spring_energy: true,
        ..Needs::NONE
    };
    const ENERGY_BOOKS: Needs = Needs {
        energy_books: true,
        ..Needs::NONE
    };

    /// What any of `quantities` needs.
    pub fn of(quantities: &[Quantity]) -> Needs {
        let either = |a: Needs, b: Needs| Needs {
            frames: a.frames || b.frames,
            body_accelerations: a.body_accelerations || b.body_accelerations,
            beam_dynamics: a.beam_dynamics || b.beam_dynamics,
            spring_energy: a.spring_energy || b.spring_energy,
            energy_books: a.energy_books || b.energy_books,
        };
        quantities
            .iter()
            .map(Quantity::needs)
            .fold(Needs::NONE, either)
    }
}

impl Quantity {
    /// What this quantity reads beyond the state's own numbers. One
    /// exhaustive match (no `_` arm): a new quantity must answer here.
    pub fn needs(&self) -> Needs {
        use Quantity::*;
        match self {
            NominalSpeed(_) => Needs::FRAMES,
            Ax(_) | Ay(_) | AngularAcceleration(_) => Needs::BODY_ACCELERATIONS,
            SensorAcceleration(_) | SectionMoment(_) | SectionShear(_) => Needs::BEAM_DYNAMICS,
            Reaction(_) | ReactionMoment(_) => Needs::BEAM_DYNAMICS,
            SpringEnergy => Needs::SPRING_ENERGY,
            Dissipated | BeamDamping | NumericalDissipation => Needs::ENERGY_BOOKS,
            Balance => Needs {
                spring_energy: true,
                ..Needs::ENERGY_BOOKS
            },
            X(_) | Y(_) | Vx(_) | Vy(_) | Angle(_) | AngularVelocity(_) => Needs::NONE,
            ContactPosition(_) | TangentialForce(_) | NormalForce(_) | OnBeam(_) => Needs::NONE,
            ContactClosed(_) | Gap(_) | MagnetAirGap(_) | MagnetCurrent(_) => Needs::NONE,
            ImpulseTangential(_) | ImpulseNormal(_) | Irregularity(_) => Needs::NONE,
            Sensor(_) | SensorVelocity(_) | SensorFoundationLoad(_) => Needs::NONE,
            SensorRailDeflection(_) | SensorRailSeatForce(_) => Needs::NONE,
            BodyKinetic | BeamKinetic | BeamStrain | GravityWork | ExternalWork => Needs::NONE,
            TractiveWork | ImpactLoss | VelocityError | GapError => Needs::NONE,
            Iterations | PositionIterations => Needs::NONE,
        }
    }
}

/// The value in `state` of each quantity of `quantities` into `values`.
pub fn evaluate(
    system: &System,
    state: &SimState,
    probes: &Probes,
    quantities: &[Quantity],
    values: &mut [f64],
) {
    let now = Now::new(system, state, probes, Needs::of(quantities));
    for (value, quantity) in values.iter_mut().zip(quantities) {
        *value = now.value(*quantity);
    }
}

/// A state and what its outputs need derived from it (`Needs`), computed
/// once for all the outputs of one evaluation.
struct Now<'a> {
    system: &'a System,
    state: &'a SimState,
    probes: &'a Probes<'a>,
    frames: Option<Vec<crate::contact::ContactFrame>>,
    accelerations: Option<Vec<nalgebra::Vector3<f64>>>,
    beam_dynamics: Option<crate::structure::section_forces::BeamDynamics>,
    spring_energy: f64,
    /// Under a rail over the deck the system's abscissa starts at the
    /// approach; the outputs keep the scene's (the deck's x = 0).
    origin: Option<f64>,
}

impl<'a> Now<'a> {
    fn new(system: &'a System, state: &'a SimState, probes: &'a Probes, needs: Needs) -> Self {
        let frames = needs
            .frames
            .then(|| frames_now(system, state, probes.frames).ok());
        let beam_dynamics = needs
            .beam_dynamics
            .then(|| beam_dynamics(system, state, probes.frames, probes.route()));
        let accelerations = needs
            .body_accelerations
            .then(|| body_accelerations(system, state, probes));
        let spring_energy = if needs.spring_energy {
            energy::spring(system, state)
        } else {
            f64::NAN
        };
        Now {
            system,
            state,
            probes,
            frames: frames.flatten(),
            accelerations,
            beam_dynamics: beam_dynamics.flatten(),
            spring_energy,
            origin: system.beam.track().map(|t| t.deck_start()),
        }
    }

    fn scene_x(&self, x: f64) -> f64 {
        self.origin.map_or(x, |o| x - o)
    }

    fn value(&self, quantity: Quantity) -> f64 {
        let (d, state) = (&self.state.dynamic, self.state);
        let acceleration = |b: usize| self.accelerations.as_ref().map(|a| a[b]);
        let nan = f64::NAN;
        match quantity {
            Quantity::X(b) => self.scene_x(d.bodies[b].position.x),
            Quantity::Y(b) => d.bodies[b].position.y,
            Quantity::Vx(b) => d.bodies[b].velocity.x,
            Quantity::Vy(b) => d.bodies[b].velocity.y,
            Quantity::Ax(b) => acceleration(b).map_or(nan, |a| a.x),
            Quantity::Ay(b) => acceleration(b).map_or(nan, |a| a.y),
            Quantity::AngularAcceleration(b) => acceleration(b).map_or(nan, |a| a.z),
            Quantity::Angle(b) => d.bodies[b].angle,
            Quantity::AngularVelocity(b) => d.bodies[b].angular_velocity,
            Quantity::NominalSpeed(c) => self.nominal_speed(c),
            Quantity::ContactPosition(c) => self.scene_x(d.contact_x[c]),
            Quantity::TangentialForce(c) => state.force_history[c][0].tangential,
            Quantity::NormalForce(c) => state.force_history[c][0].normal,
            Quantity::OnBeam(c) => f64::from(u8::from(state.parts[c].on_structure())),
            Quantity::ContactClosed(c) => f64::from(u8::from(!state.contacts[c].open)),
            Quantity::Gap(c) => state.contacts[c].gap,
            Quantity::MagnetAirGap(_) | Quantity::MagnetCurrent(_) => self.magnet_value(quantity),
            Quantity::ImpulseTangential(c) => state.contacts[c].impulse[0],
            Quantity::ImpulseNormal(c) => state.contacts[c].impulse[1],
            Quantity::Irregularity(c) => {
                (self.system.profile.as_ref()).map_or(0.0, |p| p.at(d.contact_x[c])[0])
            }
            Quantity::Sensor(_)
            | Quantity::SensorVelocity(_)
            | Quantity::SensorFoundationLoad(_)
            | Quantity::SensorRailDeflection(_)
            | Quantity::SensorRailSeatForce(_)
            | Quantity::SensorAcceleration(_)
            | Quantity::SectionMoment(_)
            | Quantity::SectionShear(_)
            | Quantity::Reaction(_)
            | Quantity::ReactionMoment(_)
            | Quantity::BeamKinetic => self.structure_value(quantity),
            Quantity::BeamStrain => {
                energy::structure_strain(self.system, self.state, self.probes.end_forces)
            }
            Quantity::BodyKinetic
            | Quantity::SpringEnergy
            | Quantity::Dissipated
            | Quantity::BeamDamping
            | Quantity::GravityWork
            | Quantity::ExternalWork
            | Quantity::TractiveWork
            | Quantity::ImpactLoss
            | Quantity::NumericalDissipation
            | Quantity::Balance
            | Quantity::VelocityError
            | Quantity::GapError
            | Quantity::Iterations
            | Quantity::PositionIterations => self.run_value(quantity),
        }
    }

    /// A contact's nominal speed (eq. 24) at its frame now.
    fn nominal_speed(&self, c: usize) -> f64 {
        let Some(frames) = &self.frames else {
            return f64::NAN;
        };
        let d = &self.state.dynamic;
        let contact = &self.system.contacts[c];
        let point = contact.point(&d.bodies[contact.body]);
        let (beam, radius) = (&self.system.beam, contact.radius());
        frames[c].nominal_speed(beam, radius, &point, &d.beam_velocity)
    }

    /// An EMS magnet's air gap or current.
    fn magnet_value(&self, quantity: Quantity) -> f64 {
        let (system, state) = (self.system, self.state);
        match quantity {
            Quantity::MagnetAirGap(c) => {
                magnet(system, c).map_or(f64::NAN, |(_, s0)| s0 - state.contacts[c].gap)
            }
            Quantity::MagnetCurrent(c) => magnet(system, c).map_or(f64::NAN, |(load, s0)| {
                let force = state.force_history[c][0].normal;
                crate::contact_law::magnet_relative_current(load, s0, force, -state.contacts[c].gap)
            }),
            _ => f64::NAN,
        }
    }

    /// A structure's output (see `structure_value`).
    fn structure_value(&self, quantity: Quantity) -> f64 {
        let d = &self.state.dynamic;
        let now = BeamNow {
            displacement: &d.beam_displacement,
            velocity: &d.beam_velocity,
            dynamics: self.beam_dynamics.as_ref(),
        };
        let probes = (self.probes.sensors, self.probes.sections);
        structure_value(&self.system.beam, &now, probes, quantity).unwrap_or(f64::NAN)
    }

    /// The run's energies and the solver's counts.
    fn run_value(&self, quantity: Quantity) -> f64 {
        let (system, state, probes) = (self.system, self.state, self.probes);
        let d = &state.dynamic;
        match quantity {
            Quantity::BodyKinetic => energy::body_kinetic(system, state),
            Quantity::SpringEnergy => self.spring_energy,
            Quantity::Dissipated => probes.booked(d.dissipated),
            Quantity::BeamDamping => probes.booked(d.beam_dissipated),
            Quantity::GravityWork => state.gravity_work,
            Quantity::ExternalWork => state.external_work,
            Quantity::TractiveWork => d.tractive_work,
            Quantity::ImpactLoss => state.impact_loss,
            Quantity::NumericalDissipation => probes.booked(d.numerical_dissipation),
            Quantity::Balance => {
                let energies = (self.spring_energy, probes.end_forces);
                probes.booked(energy::balance_with(system, state, energies))
            }
            Quantity::VelocityError => state.last_velocity_error,
            Quantity::GapError => state.last_gap_error,
            Quantity::Iterations => state.last_iterations as f64,
            Quantity::PositionIterations => state.last_position_iterations as f64,
            _ => f64::NAN,
        }
    }
}

/// Contact `c`'s magnet law, if it has one: its static load F₀ (N) and
/// nominal air gap s₀ (m).
fn magnet(system: &System, c: usize) -> Option<(f64, f64)> {
    let follower = system.contacts[c].follower?;
    match follower.kind {
        crate::contact_law::LawKind::Magnet { nominal_gap, .. } => {
            Some((follower.preload, nominal_gap))
        }
        _ => None,
    }
}
