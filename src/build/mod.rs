//! From a scene to the mechanical system and its initial state: the bodies,
//! force elements and contacts, where they start and the contact forces the
//! first step's iteration starts from.

use nalgebra::{Vector2, Vector3};

use crate::beam::Beam;
use crate::body::{BodyState, RigidBody};
use crate::contact::{Contact, ContactForce, ContactKind, Follower};
use crate::force_element::{Direction, ForceElement};
use crate::scene::{BodyKind, BodySpec, BogieSpec, DampingSpec, MaglevSpec, Scene, SuspensionSpec};
use crate::solver::iteration::IterationSettings;
use crate::solver::parameters::SolverParameters;
use crate::system::{System, Track};

mod compliant;
mod followers;

/// The system a scene asks for, where everything starts, the static
/// contact forces (the first guesses) and the applied force on each body.
pub struct Assembly {
    pub system: System,
    pub bodies: Vec<BodyState>,
    pub forces: Vec<ContactForce>,
    /// The first body of each vehicle and the constant force (fx, fy) on it
    /// (the first is the driven body: the FMU's force inputs act on it).
    pub vehicle_forces: Vec<(usize, [f64; 2])>,
    /// Per contact: its vehicle's coefficient of restitution, and whether
    /// it starts open (its vehicle starts above the track).
    pub restitution: Vec<f64>,
    pub open: Vec<bool>,
}

/// Height of a sprung mass's centre above its unsprung mass at rest (m):
/// only differences of heights enter the model.
pub const SPRUNG_HEIGHT: f64 = 1.0;

/// Longitudinal stiffness of a sprung mass's guide, per unit of its vertical
/// stiffness: it keeps the unsprung glider under the sprung mass (a glider
/// alone drifts with the horizontal part of its normal force).
pub const GUIDE_STIFFNESS_RATIO: f64 = 100.0;

/// A one-body vehicle: a wheel or a glider with one contact.
fn single_body(spec: &BodySpec, beam: &Beam) -> (RigidBody, Contact, BodyState) {
    let (inertia, kind) = match spec.kind {
        BodyKind::Wheel => (
            spec.inertia.unwrap_or(0.0),
            ContactKind::Wheel {
                radius: spec.radius.unwrap_or(0.0),
            },
        ),
        BodyKind::Glider
        | BodyKind::SprungMass
        | BodyKind::BogieVehicle
        | BodyKind::MaglevVehicle
        | BodyKind::MovingForce => (0.0, ContactKind::Glider),
    };
    let body = RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia,
        drive: None,
    };
    let contact = Contact {
        name: "contact".into(),
        body: 0,
        kind,
        follower: None,
    };
    let radius = contact.radius();
    let rolls = contact.rolls();
    let state = BodyState {
        position: Vector2::new(spec.initial_position, radius + beam.surface_offset),
        velocity: Vector2::new(spec.initial_speed, 0.0),
        angle: 0.0,
        angular_velocity: if rolls && radius > 0.0 {
            -spec.initial_speed / radius
        } else {
            0.0
        },
    };
    (body, contact, state)
}

/// The moving oscillator: body 0 the sprung mass (J = 0), body 1 the
/// unsprung glider, a vertical spring–damper preloaded with the sprung
/// weight and a stiff longitudinal guide between them.
fn sprung_mass(spec: &BodySpec, beam: &Beam, gravity: f64) -> Vehicle {
    let suspension = spec.suspension.unwrap_or(SuspensionSpec {
        stiffness: 0.0,
        damping: 0.0,
        unsprung_mass: 0.0,
    });
    if suspension.unsprung_mass == 0.0 {
        return sprung_mass_on_follower(spec, &suspension, beam, gravity);
    }
    let (unsprung, mut contact, contact_state) = single_body(spec, beam);
    let unsprung = RigidBody {
        name: format!("{}_unsprung", spec.name),
        mass: suspension.unsprung_mass,
        ..unsprung
    };
    contact.body = 1;
    let sprung = sprung_body(spec);
    let sprung_state = BodyState {
        position: contact_state.position + Vector2::new(0.0, SPRUNG_HEIGHT),
        ..contact_state
    };
    let element = |name: &str, direction, stiffness, damping, preload, rest| ForceElement {
        name: format!("{}.{name}", spec.name),
        body_a: 0,
        point_a: Vector2::zeros(),
        body_b: 1,
        point_b: Vector2::zeros(),
        direction,
        stiffness,
        damping,
        preload,
        rest,
    };
    let force_elements = vec![
        element(
            "suspension",
            Direction::Vertical,
            suspension.stiffness,
            suspension.damping,
            spec.mass * gravity,
            SPRUNG_HEIGHT,
        ),
        element(
            "guide",
            Direction::Longitudinal,
            GUIDE_STIFFNESS_RATIO * suspension.stiffness,
            0.0,
            0.0,
            0.0,
        ),
    ];
    Vehicle {
        bodies: vec![sprung, unsprung],
        contacts: vec![contact],
        force_elements,
        states: vec![sprung_state, contact_state],
    }
}

/// The sprung mass of a `sprung_mass` vehicle: bounce only (no pitch).
fn sprung_body(spec: &BodySpec) -> RigidBody {
    RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia: 0.0,
        drive: None,
    }
}

/// The moving oscillator over a massless follower (`unsprung_mass = 0`):
/// one body, the sprung mass, whose contact is the follower at
/// `SPRUNG_HEIGHT` below it; the suspension is the follower's force law.
fn sprung_mass_on_follower(
    spec: &BodySpec,
    suspension: &SuspensionSpec,
    beam: &Beam,
    gravity: f64,
) -> Vehicle {
    let (_, contact, contact_state) = single_body(spec, beam);
    let sprung = sprung_body(spec);
    let contact = Contact {
        follower: Some(Follower {
            stiffness: suspension.stiffness,
            damping: suspension.damping,
            preload: spec.mass * gravity,
            rest: SPRUNG_HEIGHT,
            attachment: Vector2::zeros(),
            kind: Default::default(),
        }),
        ..contact
    };
    Vehicle {
        bodies: vec![sprung],
        contacts: vec![contact],
        force_elements: Vec::new(),
        states: vec![BodyState {
            position: contact_state.position + Vector2::new(0.0, SPRUNG_HEIGHT),
            ..contact_state
        }],
    }
}

/// Heights of a bogie's centre above its wheelsets and of the car body's
/// centre above its bogies at rest (m): only differences of heights enter.
pub const BOGIE_HEIGHTS: [f64; 2] = [0.5, 1.5];

/// A vertical spring–damper and a stiff longitudinal guide between point
/// `point_a` of body a (above) and the centre of body b, preloaded with
/// `load`; the rest separations are those of the initial states.
#[allow(clippy::too_many_arguments)]
fn suspension(
    name: &str,
    (a, point_a): (usize, f64),
    b: usize,
    stiffness: f64,
    damping: f64,
    load: f64,
    states: &[BodyState],
    out: &mut Vec<ForceElement>,
) {
    for (suffix, direction, k, c, preload) in [
        ("", Direction::Vertical, stiffness, damping, load),
        (
            "_guide",
            Direction::Longitudinal,
            GUIDE_STIFFNESS_RATIO * stiffness,
            0.0,
            0.0,
        ),
    ] {
        let mut element = ForceElement {
            name: format!("{name}{suffix}"),
            body_a: a,
            point_a: Vector2::new(point_a, 0.0),
            body_b: b,
            point_b: Vector2::zeros(),
            direction,
            stiffness: k,
            damping: c,
            preload,
            rest: 0.0,
        };
        element.rest = element.separation(&states[a], &states[b]);
        out.push(element);
    }
}

/// The 10-DOF half vehicle: body 0 the car body, bodies 1–2 the front and
/// rear bogies, bodies 3–6 the wheelsets (gliders, front to rear), the
/// secondary suspensions (car–bogie) and primary ones (bogie–wheelset)
/// preloaded with the weight each carries.
fn bogie_vehicle(spec: &BodySpec, beam: &Beam, gravity: f64) -> Vehicle {
    let b: BogieSpec = spec.bogie.expect("a validated bogie_vehicle has its bogie");
    let (lc, lt) = (b.bogie_half_distance, b.axle_half_distance);
    // Wheel wheelsets lift everything above them by their radius.
    let lift = b.wheel_radius.unwrap_or(0.0);
    let at = |dx: f64, dy: f64, mass: f64, inertia: f64, name: String| {
        let mut s = spec.clone();
        s.initial_position += dx;
        let (_, _, mut state) = single_body(&s, beam);
        state.position.y += dy + lift;
        (
            RigidBody {
                name,
                mass,
                inertia,
                drive: None,
            },
            state,
        )
    };
    let [bogie_height, car_height] = BOGIE_HEIGHTS;
    let mut parts = vec![at(
        0.0,
        car_height,
        spec.mass,
        b.car_inertia,
        spec.name.clone(),
    )];
    for (i, side) in [1.0, -1.0].into_iter().enumerate() {
        let name = format!("{}_bogie{}", spec.name, i + 1);
        parts.push(at(
            side * lc,
            bogie_height,
            b.bogie_mass,
            b.bogie_inertia,
            name,
        ));
    }
    let mut contacts = Vec::new();
    for (i, (bogie, axle)) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let name = format!("{}_wheelset{}", spec.name, i + 1);
        let (part, contact) = wheelset(spec, &b, bogie * lc + axle * lt, name, beam);
        parts.push(part);
        contacts.push(Contact {
            body: 3 + i,
            ..contact
        });
    }
    let (bodies, states): (Vec<RigidBody>, Vec<BodyState>) = parts.into_iter().unzip();
    let secondary_load = 0.5 * spec.mass * gravity;
    let primary_load = 0.5 * (secondary_load + b.bogie_mass * gravity);
    let mut force_elements = Vec::new();
    // Leaves first: the static start balances horizontal forces from the
    // wheelsets up to the car body in this order.
    for (w, bogie) in [1, 1, 2, 2].into_iter().enumerate() {
        let side = if w % 2 == 0 { lt } else { -lt };
        let name = format!("{}.primary{}", spec.name, w + 1);
        let (k, c) = (b.primary_stiffness, b.primary_damping);
        suspension(
            &name,
            (bogie, side),
            3 + w,
            k,
            c,
            primary_load,
            &states,
            &mut force_elements,
        );
    }
    for (i, side) in [lc, -lc].into_iter().enumerate() {
        let name = format!("{}.secondary{}", spec.name, i + 1);
        let (k, c) = (b.secondary_stiffness, b.secondary_damping);
        suspension(
            &name,
            (0, side),
            1 + i,
            k,
            c,
            secondary_load,
            &states,
            &mut force_elements,
        );
    }
    Vehicle {
        bodies,
        contacts,
        force_elements,
        states,
    }
}

/// A bogie vehicle's wheelset `dx` from the car body's centre: a glider,
/// or a rolling wheel when the bogie spec gives `wheel_radius`.
fn wheelset(
    spec: &BodySpec,
    b: &BogieSpec,
    dx: f64,
    name: String,
    beam: &Beam,
) -> ((RigidBody, BodyState), Contact) {
    let mut s = spec.clone();
    s.initial_position += dx;
    s.mass = b.wheelset_mass;
    if let (Some(radius), Some(inertia)) = (b.wheel_radius, b.wheelset_inertia) {
        s.kind = BodyKind::Wheel;
        s.radius = Some(radius);
        s.inertia = Some(inertia);
    } else {
        s.kind = BodyKind::Glider;
    }
    let (mut body, mut contact, state) = single_body(&s, beam);
    body.name = name.clone();
    contact.name = name;
    ((body, state), contact)
}

/// Height of a maglev car body's centre above its magnets at rest (m).
pub const MAGLEV_HEIGHT: f64 = 1.0;

/// A maglev car body over N magnets: body 0 the car body (M, J), bodies
/// 1..=N the magnets (gliders, front to rear), each on a vertical
/// spring–damper with a longitudinal guide, preloaded with M g / N.
fn maglev_vehicle(spec: &BodySpec, beam: &Beam, gravity: f64) -> Vehicle {
    let m: MaglevSpec = spec
        .maglev
        .expect("a validated maglev_vehicle has its magnets");
    let glider_at = |dx: f64| {
        let mut s = spec.clone();
        s.kind = BodyKind::Glider;
        s.initial_position += dx;
        single_body(&s, beam)
    };
    let (_, _, mut car_state) = glider_at(0.0);
    car_state.position.y += MAGLEV_HEIGHT;
    let mut bodies = vec![RigidBody {
        name: spec.name.clone(),
        mass: spec.mass,
        inertia: m.car_inertia,
        drive: None,
    }];
    let mut states = vec![car_state];
    let mut contacts = Vec::with_capacity(m.magnets);
    for i in 0..m.magnets {
        let (_, contact, state) = glider_at(m.offset(i));
        let name = format!("{}_magnet{}", spec.name, i + 1);
        bodies.push(RigidBody {
            name: name.clone(),
            mass: m.magnet_mass,
            inertia: 0.0,
            drive: None,
        });
        states.push(state);
        contacts.push(Contact {
            name,
            body: 1 + i,
            ..contact
        });
    }
    let load = spec.mass * gravity / m.magnets as f64;
    let mut force_elements = Vec::with_capacity(2 * m.magnets);
    for i in 0..m.magnets {
        let name = format!("{}.magnet{}", spec.name, i + 1);
        suspension(
            &name,
            (0, m.offset(i)),
            1 + i,
            m.stiffness,
            m.damping,
            load,
            &states,
            &mut force_elements,
        );
    }
    Vehicle {
        bodies,
        contacts,
        force_elements,
        states,
    }
}

/// Bodies, contacts and force elements of one vehicle, and where its
/// bodies start; body indices are the vehicle's own.
struct Vehicle {
    bodies: Vec<RigidBody>,
    contacts: Vec<Contact>,
    force_elements: Vec<ForceElement>,
    states: Vec<BodyState>,
}

/// Why a scene of moving forces has no system of bodies and contacts.
pub const MOVING_FORCE_REFUSAL: &str =
    "body.kind = \"moving_force\": a moving force has no body for the contact \
     iteration to move; `guideway run SCENE` and `guideway sweep SCENE` run it as a \
     crossing of prescribed forces (the library's moving_load::ForceRun and Crossing)";

pub fn assemble(scene: &Scene) -> Result<Assembly, String> {
    let mut beam = Beam::of_scene(&scene.beam, &scene.track)?;
    if let Some(selection) = scene.solver.mode_selection() {
        beam = beam.reduce_to_modes(selection)?;
    } else if matches!(scene.beam.damping, Some(DampingSpec::Modal { .. })) {
        // One ratio for every mode on the full mesh: the mesh in all its
        // modes (a complete basis), where each mode takes its 2 ζ ω.
        let every = crate::modal::ModeSelection::Count(beam.free_dofs());
        beam = beam.reduce_to_modes(every)?;
    }
    let spec = &scene.body;
    let gravity = scene.gravity;
    let (mut forces, mut applied) = (Vec::new(), Vec::new());
    let mut system = System {
        beam,
        track: Track {
            approach: scene.track.approach,
            run_off: scene.track.run_off,
            open_ends: false,
        },
        bodies: Vec::new(),
        force_elements: Vec::new(),
        contacts: Vec::new(),
        gravity,
        profile: crate::profile::Profile::new(&scene.track.irregularities)?,
        couplings: Vec::new(),
    };
    let mut bodies = Vec::new();
    let (mut restitution, mut open) = (Vec::new(), Vec::new());
    for (v, spec) in std::iter::once(spec).chain(&scene.vehicles).enumerate() {
        let mut vehicle = match spec.kind {
            BodyKind::Wheel | BodyKind::Glider => {
                let (body, contact, state) = single_body(spec, &system.beam);
                Vehicle {
                    bodies: vec![body],
                    contacts: vec![contact],
                    force_elements: Vec::new(),
                    states: vec![state],
                }
            }
            BodyKind::SprungMass => sprung_mass(spec, &system.beam, gravity),
            BodyKind::BogieVehicle => bogie_vehicle(spec, &system.beam, gravity),
            BodyKind::MaglevVehicle => maglev_vehicle(spec, &system.beam, gravity),
            BodyKind::MovingForce => return Err(MOVING_FORCE_REFUSAL.into()),
        };
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
        // The first vehicle's contact keeps the name `contact` of the
        // single-body scenes; the others' are named after their vehicle.
        let offset = system.bodies.len();
        for contact in &mut vehicle.contacts {
            contact.body += offset;
            let named_by_preset =
                matches!(spec.kind, BodyKind::BogieVehicle | BodyKind::MaglevVehicle);
            if v > 0 && !named_by_preset {
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
        restitution.extend(vehicle.contacts.iter().map(|_| spec.restitution));
        for contact in &vehicle.contacts {
            // A follower above the track carries what its suspension
            // still transmits; it is open (slack) if that is nothing.
            let normal = contact
                .follower
                .map_or(share, |f| f.force(f.rest + spec.initial_height, 0.0));
            let flying = contact.follower.is_none() && spec.initial_height > 0.0;
            open.push(flying || normal == 0.0);
            forces.push(ContactForce {
                tangential: 0.0,
                normal,
            });
        }
        applied.push((offset, [spec.force_x, spec.force_y]));
        system.bodies.extend(vehicle.bodies);
        system.contacts.extend(vehicle.contacts);
        system.force_elements.extend(vehicle.force_elements);
        bodies.extend(vehicle.states);
    }
    if let Some(rail) = system.beam.track() {
        // The rail is the whole track: the system's abscissa starts at the
        // approach's start (`structure::track_seam`), so move the bodies.
        system.track.approach = 0.0;
        system.track.run_off = 0.0;
        let shift = rail.deck_start();
        bodies.iter_mut().for_each(|b| b.position.x += shift);
    }
    for name in &scene.couplings {
        let Some(b) = system.bodies.iter().position(|b| &b.name == name) else {
            return Err(format!("couplings: no body named {name:?}"));
        };
        system.couplings.push(b);
    }
    Ok(Assembly {
        system,
        bodies,
        forces,
        vehicle_forces: applied,
        restitution,
        open,
    })
}

/// The constant generalized force on each body: its weight, plus the
/// applied force (fx, fy) on the driven body and the vehicles' constant
/// forces on their first bodies (`forces`: body index, force).
pub fn constant_forces<'a>(
    system: &'a System,
    forces: &'a [(usize, [f64; 2])],
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    system.bodies.iter().enumerate().map(move |(b, body)| {
        let weight = Vector3::new(0.0, -body.mass * system.gravity, 0.0);
        match forces.iter().find(|(first, _)| *first == b) {
            Some((_, f)) => weight + Vector3::new(f[0], f[1], 0.0),
            None => weight,
        }
    })
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
