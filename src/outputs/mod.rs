//! The catalogue of outputs: one named, typed, unit-carrying entry per
//! reported quantity, generated from the system. CSV headers, plots, the
//! summary and the FMU variable table are all read from it. Each kind of
//! output is one entry of the `quantities!` list (its name, unit, type,
//! description and needs), one line of `Catalogue` (where a system has it)
//! and one arm of `Now::value` (its value).

use crate::energy;
use crate::state::SimState;
use crate::structure::beam::Beam;
use crate::system::System;
use derived::{beam_dynamics_at, body_accelerations_at, frames_now};
use std::borrow::Cow;
use std::cell::OnceCell;
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

/// An index into the system's bodies.
pub type BodyIndex = usize;
/// An index into the system's contacts.
pub type ContactIndex = usize;
/// An index into the scene's sensors (`Probes::sensors`).
pub type SensorIndex = usize;
/// An index into the scene's sections (`Probes::sections`).
pub type SectionIndex = usize;
/// A node of the beam's mesh (a support's).
pub type NodeIndex = usize;

/// The list of quantities, one entry per kind of output:
///
/// `Variant(IndexType) => Group "suffix", "unit", Real|Integer, "description" [, needs A | B];`
///
/// its variant of `Quantity` (with whose it is), its name (`names`: the
/// group and suffix of `<owner>.<suffix>`, `<group>.<owner>.<suffix>` or
/// `<group>.<suffix>`), its unit, its type when exported, the description
/// every output of it carries, and what it reads beyond the state
/// (`Needs`, none where left out). From it come `Quantity` (each variant
/// documented by its description), `QuantityKind` (strum: the variant
/// without its index) and one `const fn` per column. Its value is an arm
/// of `Now::value` (exhaustive, so the compiler asks) and where it
/// appears a line of `Catalogue`.
macro_rules! quantities {
    ($(
        $variant:ident $(($index:ty))? => $group:ident $(($group_name:literal))? $suffix:literal,
        $unit:literal, $type:ident, $description:literal
        $(, needs $($need:ident)|+)?;
    )*) => {
        /// Which quantity an output reports, and whose (its index). Its
        /// variants without their indices are `QuantityKind` (derived:
        /// what an output reports, without whose), named in `names`.
        #[derive(Debug, Clone, Copy, PartialEq, EnumDiscriminants)]
        #[strum_discriminants(name(QuantityKind), derive(Hash, EnumIter))]
        pub enum Quantity {
            $(#[doc = $description] $variant $(($index))?,)*
        }

        impl QuantityKind {
            /// Its group and suffix: the naming rule's row (`names`).
            const fn naming(self) -> (names::Group, &'static str) {
                match self {
                    $(QuantityKind::$variant => (names::Group::$group $(($group_name))?, $suffix),)*
                }
            }
            /// The unit of its outputs.
            pub const fn unit(self) -> &'static str {
                match self { $(QuantityKind::$variant => $unit,)* }
            }
            /// The description of its outputs.
            pub const fn description(self) -> &'static str {
                match self { $(QuantityKind::$variant => $description,)* }
            }
            /// How its outputs are typed when exported.
            pub const fn output_kind(self) -> OutputKind {
                match self { $(QuantityKind::$variant => OutputKind::$type,)* }
            }
            /// What its outputs read beyond the state's own numbers.
            pub const fn needs(self) -> Needs {
                match self {
                    $(QuantityKind::$variant => Needs::NONE $($(.and(Needs::$need))+)?,)*
                }
            }
        }
    };
}

quantities! {
    // A body's: `<body>.<suffix>`.
    X(BodyIndex) => Owner "x", "m", Real,
        "horizontal position of the body's centre";
    Y(BodyIndex) => Owner "y", "m", Real,
        "vertical position of the body's centre";
    Vx(BodyIndex) => Owner "vx", "m/s", Real,
        "horizontal velocity of the body's centre";
    Vy(BodyIndex) => Owner "vy", "m/s", Real,
        "vertical velocity of the body's centre";
    Ax(BodyIndex) => Owner "ax", "m/s2", Real,
        "horizontal acceleration of the body's centre",
        needs BODY_ACCELERATIONS;
    Ay(BodyIndex) => Owner "ay", "m/s2", Real,
        "vertical acceleration of the body's centre",
        needs BODY_ACCELERATIONS;
    AngularAcceleration(BodyIndex) => Owner "angular_acceleration", "rad/s2", Real,
        "angular acceleration, counter-clockwise positive",
        needs BODY_ACCELERATIONS;
    Angle(BodyIndex) => Owner "pitch", "rad", Real,
        "pitch angle, counter-clockwise positive";
    AngularVelocity(BodyIndex) => Owner "angular_velocity", "rad/s", Real,
        "angular velocity, counter-clockwise positive";
    // A contact's: `<contact>.<suffix>` (the nominal speed: its body's
    // name, or the contact's where it is attached to a shared body).
    NominalSpeed(ContactIndex) => Owner "nominal_speed", "m/s", Real,
        "nominal travel speed V = vx + (r + h) dphi/dt (eq. 24)",
        needs FRAMES;
    ContactPosition(ContactIndex) => Owner "position", "m", Real,
        "abscissa of the contact point along the track";
    TangentialForce(ContactIndex) => Owner "tangential_force", "N", Real,
        "tangential contact force on the body";
    NormalForce(ContactIndex) => Owner "normal_force", "N", Real,
        "normal contact force on the body (positive pushes it off the track)";
    OnBeam(ContactIndex) => Owner "on_beam", "", Integer,
        "1 while the contact point is on the beam (the structure), 0 on rigid ground or \
         beyond the track";
    ContactClosed(ContactIndex) => Owner "state", "", Integer,
        "1 while the contact is closed, 0 while it is open (in flight)";
    Gap(ContactIndex) => Owner "gap", "m", Real,
        "gap g between the body and the track (zero to the gap tolerance while closed)";
    MagnetAirGap(ContactIndex) => Owner "air_gap", "m", Real,
        "EMS magnet's air gap s = s0 - gap (nominal_gap s0 where the law carries its static load)";
    MagnetCurrent(ContactIndex) => Owner "current", "1", Real,
        "EMS magnet's current over its operating current, i/i0 = 1 + (F - F0)/2F0 + (s - s0)/s0 \
         (the linearised force law; the controller's command below saturation)";
    ImpulseTangential(ContactIndex) => Owner "impact_impulse_tangential", "N.s", Real,
        "tangential impulse on the body at the last impact it took part in (a landing or a rail-gap impact)";
    ImpulseNormal(ContactIndex) => Owner "impact_impulse", "N.s", Real,
        "normal impulse on the body at the last impact it took part in (a landing or a rail-gap impact)";
    Irregularity(ContactIndex) => Owner "irregularity", "m", Real,
        "track irregularity r(x) at the contact point (up positive)";
    // The structure's: at a sensor, a section, a support (its node).
    Sensor(SensorIndex) => Owned("sensor") "deflection", "m", Real,
        "beam deflection at the sensor (up positive)";
    SensorVelocity(SensorIndex) => Owned("sensor") "velocity", "m/s", Real,
        "beam vertical velocity at the sensor (up positive)";
    SensorFoundationLoad(SensorIndex) => Owned("sensor") "foundation_load", "N/m", Real,
        "load per metre of beam on its Winkler foundation at the sensor, -(k w + c v), \
         compression positive: the rail-seat load per metre of a rail";
    SensorRailDeflection(SensorIndex) => Owned("sensor") "rail_deflection", "m", Real,
        "deflection of the rail over the deck at the sensor (up positive); the \
         sensor's deflection is the deck's";
    SensorRailSeatForce(SensorIndex) => Owned("sensor") "rail_seat_force", "N", Real,
        "rail-seat (pad) force of the sleeper nearest the sensor, compression \
         positive: -(k_pad (w_rail - w_sleeper) + c_pad (v_rail - v_sleeper))";
    SensorAcceleration(SensorIndex) => Owned("sensor") "acceleration", "m/s2", Real,
        "beam vertical acceleration at the sensor (up positive), from the current state \
         and the contact forces of the last step: M^-1 (r - K u - C v)",
        needs BEAM_DYNAMICS;
    SectionMoment(SectionIndex) => Owned("section") "moment", "N.m", Real,
        "bending moment at the section, sagging positive (from the element equations)",
        needs BEAM_DYNAMICS;
    SectionShear(SectionIndex) => Owned("section") "shear", "N", Real,
        "shear force at the section: upward force of the beam left of it on the \
         beam right of it (dM/dx)",
        needs BEAM_DYNAMICS;
    Reaction(NodeIndex) => Owned("support") "reaction", "N", Real,
        "vertical force of the support on the beam, up positive",
        needs BEAM_DYNAMICS;
    ReactionMoment(NodeIndex) => Owned("support") "moment", "N.m", Real,
        "moment of the support (clamp or rotational spring) on the beam, counter-clockwise positive",
        needs BEAM_DYNAMICS;
    // The run's own: the energies, the solver's counts.
    BodyKinetic => Run("energy") "body_kinetic", "J", Real,
        "kinetic energy of the bodies";
    BeamKinetic => Run("energy") "beam_kinetic", "J", Real,
        "kinetic energy of the beam";
    BeamStrain => Run("energy") "beam_strain", "J", Real,
        "strain energy of the beam";
    SpringEnergy => Run("energy") "spring", "J", Real,
        "potential energy of the force elements' and followers' springs",
        needs SPRING_ENERGY;
    Dissipated => Run("energy") "dissipated", "J", Real,
        "energy dissipated by the force elements' dampers",
        needs ENERGY_BOOKS;
    BeamDamping => Run("energy") "beam_damping", "J", Real,
        "energy dissipated by the beam's Rayleigh structural damping and support dampers",
        needs ENERGY_BOOKS;
    GravityWork => Run("energy") "gravity_work", "J", Real,
        "work done by gravity on the bodies";
    ExternalWork => Run("energy") "external_work", "J", Real,
        "work done by the applied force";
    TractiveWork => Run("energy") "tractive_work", "J", Real,
        "work done by the tractive forces that hold the prescribed speeds";
    ImpactLoss => Run("energy") "impact_loss", "J", Real,
        "kinetic energy lost in the landings' impacts";
    NumericalDissipation => Run("energy") "numerical_dissipation", "J", Real,
        "energy removed by the integrator's numerical damping: HHT-alpha's \
         from its discrete energy identity, RK4's from the beam's energy",
        needs ENERGY_BOOKS;
    Balance => Run("energy") "balance", "J", Real,
        "kinetic + strain + spring energy + dissipated (dampers, beam damping, impacts, \
         numerical damping) \
         - work of gravity, applied and tractive forces: \
         constant for the exact solution",
        needs SPRING_ENERGY | ENERGY_BOOKS;
    VelocityError => Run("solver") "velocity_error", "m/s", Real,
        "largest contact |e| at the end of the last step";
    GapError => Run("solver") "gap_error", "m", Real,
        "gap error g of largest magnitude at the end of the last step";
    Iterations => Run("solver") "iterations", "", Integer,
        "contact-force iterations in the last step";
    PositionIterations => Run("solver") "position_iterations", "", Integer,
        "iterations of the position (gap) stage in the last step";
}

impl Quantity {
    /// What this quantity reports, without its index.
    pub fn kind(&self) -> QuantityKind {
        QuantityKind::from(self)
    }

    /// What this quantity reads beyond the state's own numbers.
    pub fn needs(&self) -> Needs {
        self.kind().needs()
    }
}

struct Catalogue {
    entries: Vec<(OutputInfo, Quantity)>,
}

impl Catalogue {
    /// The output reporting `q` of `owner` (`names::output_name`), with
    /// its kind's unit, description and type.
    fn add(&mut self, owner: &str, q: Quantity) {
        let kind = q.kind();
        let info = OutputInfo {
            name: output_name(kind, owner),
            unit: kind.unit(),
            description: kind.description().to_string(),
            kind: kind.output_kind(),
        };
        self.entries.push((info, q));
    }

    fn body(&mut self, system: &System, b: usize) {
        let n = &system.bodies[b].name;
        self.add(n, Quantity::X(b));
        self.add(n, Quantity::Y(b));
        self.add(n, Quantity::Vx(b));
        self.add(n, Quantity::Vy(b));
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
            self.add(n, Quantity::Ax(b));
        }
        let on_follower = system
            .contacts
            .iter()
            .any(|c| c.body == b && c.follower.is_some());
        if !system.force_elements.is_empty() || coupled || on_follower {
            self.add(n, Quantity::Ay(b));
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
            self.add(n, Quantity::Angle(b));
        }
        if body.turns() {
            self.add(n, Quantity::AngularVelocity(b));
        }
        if body.turns() && coupled {
            self.add(n, Quantity::AngularAcceleration(b));
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
                self.add(owner, Quantity::NominalSpeed(c));
            }
        }
    }

    fn contact(&mut self, system: &System, c: usize) {
        let contact = &system.contacts[c];
        let n = &contact.name;
        self.add(n, Quantity::ContactPosition(c));
        if contact.rolls() {
            self.add(n, Quantity::TangentialForce(c));
        }
        self.add(n, Quantity::NormalForce(c));
        if system.profile.is_some() {
            self.add(n, Quantity::Irregularity(c));
        }
        let track = &system.track;
        if track.approach > 0.0 || track.run_off > 0.0 || track.open_ends {
            self.add(n, Quantity::OnBeam(c));
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
        self.add(n, Quantity::MagnetAirGap(c));
        self.add(n, Quantity::MagnetCurrent(c));
    }

    /// Lift-off and landing: the contact's state, gap and last impact.
    fn flight(&mut self, contact: &crate::contact::Contact, c: usize) {
        let n = &contact.name;
        self.add(n, Quantity::ContactClosed(c));
        self.add(n, Quantity::Gap(c));
        if contact.rolls() {
            self.add(n, Quantity::ImpulseTangential(c));
        }
        self.add(n, Quantity::ImpulseNormal(c));
    }

    fn beam_energy(&mut self) {
        self.add("", Quantity::BeamKinetic);
        self.add("", Quantity::BeamStrain);
    }

    fn energy(&mut self, system: &System) {
        self.add("", Quantity::BodyKinetic);
        self.beam_energy();
        let followers = system.contacts.iter().any(|c| c.follower.is_some());
        if !system.force_elements.is_empty() || followers {
            self.add("", Quantity::SpringEnergy);
            self.add("", Quantity::Dissipated);
        }
        if system.beam.is_damped() {
            self.add("", Quantity::BeamDamping);
        }
        if system.gravity != 0.0 {
            self.add("", Quantity::GravityWork);
        }
        self.works(system);
    }

    /// The works of the forces on the system, the losses, and the balance.
    fn works(&mut self, system: &System) {
        self.add("", Quantity::ExternalWork);
        if system.bodies.iter().any(|b| b.drive.is_some()) {
            self.add("", Quantity::TractiveWork);
        }
        self.add("", Quantity::ImpactLoss);
        self.add("", Quantity::NumericalDissipation);
        self.add("", Quantity::Balance);
    }

    /// The structure's outputs: each sensor's, then the sections' and
    /// the supports' (design outputs).
    fn structure(&mut self, beam: &Beam, sensors: &[String], sections: &[String], reactions: bool) {
        for (i, name) in sensors.iter().enumerate() {
            self.add(name, Quantity::Sensor(i));
            self.add(name, Quantity::SensorVelocity(i));
            self.add(name, Quantity::SensorAcceleration(i));
            if beam.foundation().is_some() {
                self.add(name, Quantity::SensorFoundationLoad(i));
            }
            if beam.track().is_some() {
                self.add(name, Quantity::SensorRailDeflection(i));
            }
            if beam.track().is_some_and(|t| t.has_sleepers()) {
                self.add(name, Quantity::SensorRailSeatForce(i));
            }
        }
        self.design(beam, sections, reactions);
    }

    fn design(&mut self, beam: &Beam, sections: &[String], reactions: bool) {
        for (i, name) in sections.iter().enumerate() {
            self.add(name, Quantity::SectionMoment(i));
            self.add(name, Quantity::SectionShear(i));
        }
        if !reactions {
            return;
        }
        for support in crate::structure::section_forces::supports(beam) {
            let name = &support.name;
            self.add(name, Quantity::Reaction(support.node));
            if support.has_moment {
                self.add(name, Quantity::ReactionMoment(support.node));
            }
        }
    }

    fn solver(&mut self) {
        self.add("", Quantity::VelocityError);
        self.add("", Quantity::GapError);
        self.add("", Quantity::Iterations);
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
        c.add("", Quantity::PositionIterations);
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
    pub dynamics: Option<&'a crate::structure::section_forces::BeamDynamics<'a>>,
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

/// The sensors whose accelerations `quantities` read, or `None` where a
/// section's or a support's outputs read accelerations too (the rail over
/// the deck's rows are the sensors' only).
pub fn acceleration_sensors(quantities: &[Quantity]) -> Option<Vec<usize>> {
    let mut read = Vec::new();
    for quantity in quantities {
        match *quantity {
            Quantity::SensorAcceleration(i) => read.push(i),
            Quantity::SectionMoment(_)
            | Quantity::SectionShear(_)
            | Quantity::Reaction(_)
            | Quantity::ReactionMoment(_) => return None,
            _ => {}
        }
    }
    Some(read)
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

    /// What either needs.
    const fn and(self, other: Needs) -> Needs {
        Needs {
            frames: self.frames || other.frames,
            body_accelerations: self.body_accelerations || other.body_accelerations,
            beam_dynamics: self.beam_dynamics || other.beam_dynamics,
            spring_energy: self.spring_energy || other.spring_energy,
            energy_books: self.energy_books || other.energy_books,
        }
    }

    /// What any of `quantities` needs.
    pub fn of(quantities: &[Quantity]) -> Needs {
        quantities
            .iter()
            .map(Quantity::needs)
            .fold(Needs::NONE, Needs::and)
    }
}

/// The value in `state` of each quantity of `quantities` into `values`,
/// with `needs` what they need (`Needs::of(quantities)`, found once per
/// run: a row's outputs are the run's).
pub fn evaluate(
    system: &System,
    state: &SimState,
    probes: &Probes,
    (quantities, needs): (&[Quantity], Needs),
    values: &mut [f64],
) {
    debug_assert_eq!(needs, Needs::of(quantities));
    let now = Now::new(system, state, probes, needs);
    for (value, quantity) in values.iter_mut().zip(quantities) {
        *value = now.value(*quantity);
    }
}

/// A state and what its outputs need derived from it (`Needs`), computed
/// once for all the outputs of one evaluation: the frames once for the
/// outputs that read them, the beam's and bodies' energies once for their
/// own outputs and the balance.
struct Now<'a> {
    system: &'a System,
    state: &'a SimState,
    probes: &'a Probes<'a>,
    /// The frames now, lent by the last step where they are its end's.
    frames: Option<Cow<'a, [crate::contact::ContactFrame]>>,
    accelerations: Option<Vec<nalgebra::Vector3<f64>>>,
    beam_dynamics: Option<crate::structure::section_forces::BeamDynamics<'a>>,
    spring_energy: f64,
    /// The state's energies, each taken once where an output reads it.
    energies: [OnceCell<f64>; 3],
    /// Under a rail over the deck the system's abscissa starts at the
    /// approach; the outputs keep the scene's (the deck's x = 0).
    origin: Option<f64>,
}

/// The slots of `Now::energies`.
const BODY_KINETIC: usize = 0;
const BEAM_KINETIC: usize = 1;
const BEAM_STRAIN: usize = 2;

impl<'a> Now<'a> {
    fn new(system: &'a System, state: &'a SimState, probes: &'a Probes, needs: Needs) -> Self {
        let located = needs.frames || needs.beam_dynamics || needs.body_accelerations;
        let frames = located
            .then(|| frames_now(system, state, probes.frames).ok())
            .flatten();
        let beam_dynamics = needs.beam_dynamics.then(|| {
            Some(beam_dynamics_at(
                system,
                state,
                frames.as_deref()?,
                probes.route(),
            ))
        });
        let accelerations = needs
            .body_accelerations
            .then(|| body_accelerations_at(system, state, probes, frames.as_deref()));
        let spring_energy = if needs.spring_energy {
            energy::spring_with(system, state, probes.end_forces)
        } else {
            f64::NAN
        };
        Now {
            system,
            state,
            probes,
            frames,
            accelerations,
            beam_dynamics: beam_dynamics.flatten(),
            spring_energy,
            energies: Default::default(),
            origin: system.beam.track().map(|t| t.deck_start()),
        }
    }

    /// The state's energy in slot `which` of `energies`, taken once.
    fn energy(&self, which: usize) -> f64 {
        let (system, state) = (self.system, self.state);
        *self.energies[which].get_or_init(|| match which {
            BODY_KINETIC => energy::body_kinetic(system, state),
            BEAM_KINETIC => system.beam.kinetic_energy(&state.dynamic.beam_velocity),
            _ => energy::structure_strain(system, state, self.probes.end_forces),
        })
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
            | Quantity::ReactionMoment(_) => self.structure_value(quantity),
            Quantity::BeamKinetic => self.energy(BEAM_KINETIC),
            Quantity::BeamStrain => self.energy(BEAM_STRAIN),
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
        let (state, probes) = (self.state, self.probes);
        let d = &state.dynamic;
        match quantity {
            Quantity::BodyKinetic => self.energy(BODY_KINETIC),
            Quantity::SpringEnergy => self.spring_energy,
            Quantity::Dissipated => probes.booked(d.dissipated),
            Quantity::BeamDamping => probes.booked(d.beam_dissipated),
            Quantity::GravityWork => state.gravity_work,
            Quantity::ExternalWork => state.external_work,
            Quantity::TractiveWork => d.tractive_work,
            Quantity::ImpactLoss => state.impact_loss,
            Quantity::NumericalDissipation => probes.booked(d.numerical_dissipation),
            Quantity::Balance => probes.booked(energy::balance_of(
                state,
                energy::StateEnergies {
                    body_kinetic: self.energy(BODY_KINETIC),
                    beam_kinetic: self.energy(BEAM_KINETIC),
                    strain: self.energy(BEAM_STRAIN),
                    spring: self.spring_energy,
                },
            )),
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

#[cfg(test)]
mod tests {
    use super::QuantityKind;
    use strum::IntoEnumIterator;

    /// Each description is one line of words, as the FMU and the CSV
    /// header carry it: no stray whitespace from a continued literal.
    #[test]
    fn every_kind_is_described_in_one_clean_line() {
        for kind in QuantityKind::iter() {
            let text = kind.description();
            assert!(
                !text.is_empty() && text.trim() == text,
                "{kind:?}: {text:?}"
            );
            assert!(
                !text.contains("  ") && !text.contains('\n'),
                "{kind:?}: {text:?}"
            );
            assert!(!kind.unit().contains(char::is_whitespace), "{kind:?}");
        }
    }
}
