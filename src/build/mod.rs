//! From a scene to the mechanical system and its initial state: the bodies,
//! force elements and contacts, where they start and the contact forces the
//! first step's iteration starts from.

use crate::beam::Beam;
use crate::body::BodyState;
use crate::contact::ContactForce;
use crate::scene::{BodySpec, DampingSpec, Scene};
use crate::solver::iteration::IterationSettings;
use crate::solver::parameters::SolverParameters;
use crate::system::{System, Track};

mod compliant;
mod followers;

pub use crate::vehicle::presets::{
    Vehicle, BOGIE_HEIGHTS, GUIDE_STIFFNESS_RATIO, MAGLEV_HEIGHT, MOVING_FORCE_REFUSAL,
    SPRUNG_HEIGHT,
};

/// The system a scene asks for, where everything starts, the static
/// contact forces (the first guesses) and the applied force on each body.
pub struct Assembly {
    pub system: System,
    pub bodies: Vec<BodyState>,
    pub forces: Vec<ContactForce>,
    /// The first body of each vehicle: where its applied force acts.
    pub vehicle_first_bodies: Vec<usize>,
    /// Each vehicle's applied force (fx, fy) at the start, from its spec
    /// (the run's state holds it after: `SimState::vehicle_forces`).
    pub vehicle_forces: Vec<[f64; 2]>,
    /// Per contact: its vehicle's coefficient of restitution, and whether
    /// it starts open (its vehicle starts above the track).
    pub restitution: Vec<f64>,
    pub open: Vec<bool>,
}

/// The system, start and first contact forces of a (validated) scene.
pub fn assemble(scene: &Scene) -> Result<Assembly, String> {
    let mut assembly = Assembly {
        system: System {
            beam: structure(scene)?,
            track: Track {
                approach: scene.track.approach,
                run_off: scene.track.run_off,
                open_ends: false,
            },
            bodies: Vec::new(),
            force_elements: Default::default(),
            contacts: Vec::new(),
            gravity: scene.gravity,
            profile: crate::profile::Profile::new(&scene.track.irregularities)?,
            couplings: Vec::new(),
        },
        bodies: Vec::new(),
        forces: Vec::new(),
        vehicle_first_bodies: Vec::new(),
        vehicle_forces: Vec::new(),
        restitution: Vec::new(),
        open: Vec::new(),
    };
    for (v, spec) in scene.vehicles.iter().enumerate() {
        let vehicle = vehicle(spec, &assembly.system.beam, scene.gravity)?;
        assembly.add_vehicle(v, spec, vehicle);
    }
    if let Some(rail) = assembly.system.beam.track() {
        // The rail is the whole track: the system's abscissa starts at the
        // approach's start (`structure::track_seam`), so move the bodies.
        assembly.system.track.approach = 0.0;
        assembly.system.track.run_off = 0.0;
        let shift = rail.deck_start();
        (assembly.bodies.iter_mut()).for_each(|b| b.position.x += shift);
    }
    for name in &scene.couplings {
        let Some(b) = assembly.system.bodies.iter().position(|b| &b.name == name) else {
            return Err(format!("couplings: no body named {name:?}"));
        };
        assembly.system.couplings.push(b);
    }
    Ok(assembly)
}

/// The scene's structure: reduced to its modes where the solver asks for
/// them, or where one damping ratio is given for every mode.
fn structure(scene: &Scene) -> Result<Beam, String> {
    let beam = Beam::of_scene(&scene.beam, &scene.track)?;
    if let Some(selection) = scene.solver.mode_selection() {
        return beam.reduce_to_modes(selection);
    }
    if matches!(scene.beam.damping, Some(DampingSpec::Modal { .. })) {
        // One ratio for every mode on the full mesh: the mesh in all its
        // modes (a complete basis), where each mode takes its 2 ζ ω.
        let every = crate::modal::ModeSelection::Count(beam.free_dofs());
        return beam.reduce_to_modes(every);
    }
    Ok(beam)
}

/// The vehicle of `spec` on `beam`: its preset's bodies, force elements
/// and contacts, its contact bodies folded where they are massless,
/// driven where its speed is prescribed, and its compliant contact law.
fn vehicle(spec: &BodySpec, beam: &Beam, gravity: f64) -> Result<Vehicle, String> {
    let mut vehicle = spec.kind.build(spec, beam, gravity)?;
    if spec.massless_contacts() {
        followers::fold_contact_bodies(&mut vehicle);
    }
    if spec.prescribed_speed.is_some() {
        // Every body of the vehicle is driven from the first step on
        // (`Simulation` sets each step's ẍ from the speed table): it
        // moves as one, its spacing kept.
        for body in &mut vehicle.bodies {
            body.drive = Some(0.0);
        }
    }
    if let Some(law) = &spec.contact_law {
        let law = law
            .resolve()
            .map_err(|(field, value, rule)| format!("contact_law.{field} = {value}: {rule}"))?;
        let weight: f64 = vehicle.bodies.iter().map(|b| b.mass * gravity).sum();
        let share = (weight - spec.force_y) / vehicle.contacts.len() as f64;
        compliant::apply(&mut vehicle, law, share)?;
    }
    Ok(vehicle)
}

impl Assembly {
    /// Add vehicle number `v` (of `spec`) to the system: its indices
    /// offset past the bodies already there, its contacts named, their
    /// first forces its static shares (none while it starts above the
    /// track), and its applied force.
    fn add_vehicle(&mut self, v: usize, spec: &BodySpec, mut vehicle: Vehicle) {
        let gravity = self.system.gravity;
        // The first vehicle's contact keeps the name `contact` of the
        // single-body scenes; the others' are named after their vehicle.
        let offset = self.system.bodies.len();
        for contact in &mut vehicle.contacts {
            contact.body += offset;
            if v > 0 && !spec.kind.names_its_contacts() {
                contact.name = format!("{}_contact", spec.name);
            }
        }
        for element in &mut vehicle.force_elements {
            element.body_a += offset;
            element.body_b += offset;
        }
        // The normal forces share the vehicle's weight and balance its
        // applied force (a symmetric vehicle loads its contacts equally).
        let weight: f64 = vehicle.bodies.iter().map(|b| b.mass * gravity).sum();
        let mut share = (weight - spec.force_y) / vehicle.contacts.len() as f64;
        if spec.initial_height > 0.0 {
            // Above the track: no contact force until it lands.
            share = 0.0;
            for state in &mut vehicle.states {
                state.position.y += spec.initial_height;
            }
        }
        (self.restitution).extend(vehicle.contacts.iter().map(|_| spec.restitution));
        for contact in &vehicle.contacts {
            // A follower above the track carries what its suspension
            // still transmits; it is open (slack) if that is nothing.
            let normal = contact
                .follower
                .map_or(share, |f| f.force(f.rest + spec.initial_height, 0.0));
            let flying = contact.follower.is_none() && spec.initial_height > 0.0;
            self.open.push(flying || normal == 0.0);
            self.forces.push(ContactForce {
                tangential: 0.0,
                normal,
            });
        }
        self.vehicle_first_bodies.push(offset);
        (self.vehicle_forces).push([spec.force_x, spec.force_y]);
        self.system.bodies.extend(vehicle.bodies);
        self.system.contacts.extend(vehicle.contacts);
        self.system.force_elements.extend(vehicle.force_elements);
        self.bodies.extend(vehicle.states);
    }
}

pub use crate::system::constant_forces;

/// The static envelope's loads of an assembled scene, before its static
/// start: (abscissa, downward force) of each contact's static share.
pub fn static_shares(assembly: &Assembly) -> Vec<(f64, f64)> {
    assembly
        .system
        .contacts
        .iter()
        .zip(&assembly.forces)
        .map(|(c, f)| (assembly.bodies[c.body].position.x, f.normal))
        .collect()
}

/// The solver parameters of a scene: its step and iteration settings, the
/// fixed tolerances and caps at their defaults.
pub fn solver_parameters(solver: &crate::scene::SolverSpec) -> SolverParameters {
    let iteration = IterationSettings {
        velocity_tolerance: solver.velocity_tolerance,
        gap_tolerance: solver.gap_tolerance,
        max_iterations: solver.max_iterations,
    };
    SolverParameters::with_step(solver.step, iteration)
}
