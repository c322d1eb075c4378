//! The start of a run: a scene built into the façade's parts (system,
//! run setup, state at t = 0, stepper, output catalogue), the bodies
//! placed at rest or in static equilibrium.

use nalgebra::{DVector, Vector3};

use super::Simulation;
use crate::assemble::{assemble, constant_forces, Assembly};
use crate::contact::ContactForce;
use crate::integrate::{
    choose_integrator, contact_frames, contact_frames_at_bodies, loads, DynamicState,
};
use crate::outputs::{acceleration_elements, acceleration_sensors, catalogue};
use crate::scene::{Scene, StartKind};
use crate::solver::stepper::{heaviest_and_deflection, RunSetup, Stepper};
use crate::state::{ContactStatus, SimState};
use crate::static_start::{place_on_profile, static_start};
use crate::structure::acceleration_rows::AccelerationRows;
use crate::system::{System, TrackPart};
use crate::vehicle::speed::SpeedSpec;

impl Simulation {
    pub(super) fn build(scene: &Scene, open_ends: bool) -> Result<Simulation, String> {
        let mut assembly = assemble(scene)?;
        let envelope_loads = crate::build::static_shares(&assembly);
        assembly.system.track.open_ends = open_ends;
        let setup = run_setup(scene, &mut assembly);
        let vehicle_forces = std::mem::take(&mut assembly.vehicle_forces);
        let applied: Vec<Vector3<f64>> = constant_forces(
            &assembly.system,
            &setup.vehicle_first_bodies,
            &vehicle_forces,
        )
        .collect();
        let u = start_displacement(scene, &mut assembly, &applied)?;
        let system = assembly.system;
        let (integrator, integrator_choice) = choose_integrator(&system, &scene.solver)?;
        let dynamic = initial_state(&system, u, &assembly.bodies, &assembly.forces, &applied)?;
        let sensor_names: Vec<String> = scene.sensors.iter().map(|s| s.name.clone()).collect();
        let section_names: Vec<String> = scene.sections.iter().map(|s| s.name.clone()).collect();
        let (outputs, quantities): (_, Vec<_>) =
            catalogue(&system, &sensor_names, &section_names, scene.reactions)
                .into_iter()
                .unzip();
        let sensors: Vec<f64> = scene.sensors.iter().map(|s| s.position).collect();
        let sections: Vec<f64> = scene.sections.iter().map(|s| s.position).collect();
        let acceleration_rows = match system.beam.track() {
            None => AccelerationRows::of_elements(
                &system.beam,
                acceleration_elements(&system.beam, (&sensors, &sections), &quantities),
            ),
            Some(_) => acceleration_sensors(&quantities).and_then(|read| {
                AccelerationRows::of_deck_sensors(&system.beam, read.iter().map(|&i| sensors[i]))
            }),
        };
        let step = scene.solver.step;
        let stepper = Stepper::new(integrator, &system, step, &assembly.open, &dynamic);
        let start = (dynamic, assembly.forces.as_slice(), vehicle_forces);
        let state = state_at_start(&system, start, step, &assembly.open)?;
        let mut simulation = Simulation {
            sensors,
            envelope_loads,
            sections,
            acceleration_rows,
            setup,
            params: crate::build::solver_parameters(&scene.solver),
            stepper,
            integrator_choice,
            state,
            system,
            outputs,
            needs: crate::outputs::Needs::of(&quantities),
            quantities,
            read: None,
        };
        simulation.state.initial_energy = simulation.energy_balance();
        Ok(simulation)
    }
}

/// How the run drives the system: where the vehicles' forces act, the
/// prescribed speeds, the restitutions, when the run ends and the force
/// profile.
fn run_setup(scene: &Scene, assembly: &mut Assembly) -> RunSetup {
    let vehicle_first_bodies = std::mem::take(&mut assembly.vehicle_first_bodies);
    let drives = driven_bodies(scene, &vehicle_first_bodies, assembly.system.bodies.len());
    RunSetup {
        vehicle_first_bodies,
        drives,
        restitution: std::mem::take(&mut assembly.restitution),
        stop_at_beam_exit: scene.solver.end_time.is_none(),
        force_profile: scene.solver.force_profile,
    }
}

/// The beam's displacements at t = 0: zero (at rest, the bodies placed on
/// the profile where there is one) or the static deflection (the bodies
/// and contact forces moved to their equilibrium).
fn start_displacement(
    scene: &Scene,
    assembly: &mut Assembly,
    applied: &[Vector3<f64>],
) -> Result<DVector<f64>, String> {
    let coordinates = assembly.system.beam.coordinates();
    Ok(match scene.solver.start {
        StartKind::Rest if assembly.system.profile.is_some() => {
            let u = DVector::zeros(coordinates);
            place_on_profile(&mut assembly.system, &mut assembly.bodies, &u)?;
            u
        }
        StartKind::Rest => DVector::zeros(coordinates),
        StartKind::Static => static_start(
            &mut assembly.system,
            &mut assembly.bodies,
            &mut assembly.forces,
            applied,
        )?,
    })
}

/// The run's state at t = 0 from its dynamic state, the contact forces
/// and the vehicles' applied forces; each contact on the part of the track it
/// starts on, open where `open` says.
fn state_at_start(
    system: &System,
    (dynamic, forces, vehicle_forces): (DynamicState, &[ContactForce], Vec<[f64; 2]>),
    step: f64,
    open: &[bool],
) -> Result<SimState, String> {
    let parts: Vec<TrackPart> = (dynamic.contact_x.iter())
        .map(|&x| system.track_part(x))
        .collect();
    let contacts = initial_contacts(system, &dynamic, &parts, open)?;
    Ok(SimState {
        time: 0.0,
        grid_step: 0,
        dynamic,
        force_history: forces.iter().map(|&f| [f; 3]).collect(),
        step_history: [step; 2],
        vehicle_forces,
        external_work: 0.0,
        gravity_work: 0.0,
        initial_energy: 0.0,
        last_iterations: 0,
        last_position_iterations: 0,
        last_velocity_error: 0.0,
        last_gap_error: 0.0,
        steps: 0,
        total_iterations: 0,
        parts,
        events: Vec::new(),
        events_dropped: 0,
        exit_time: None,
        contacts,
        impact_loss: 0.0,
        coupling_loads: vec![[0.0; 3]; system.couplings.len()],
        last_applied: Vec::new(),
        pending_restart: Vec::new(),
    })
}

/// Every body of each vehicle at a prescribed speed, and its speed: a
/// vehicle's bodies run from its first body (`firsts`) to the next
/// vehicle's.
fn driven_bodies(scene: &Scene, firsts: &[usize], bodies: usize) -> Vec<(usize, SpeedSpec)> {
    let ends = firsts.iter().skip(1).copied().chain([bodies]);
    scene
        .vehicles
        .iter()
        .zip(firsts.iter().zip(ends))
        .filter_map(|(spec, (&first, end))| Some((spec.prescribed_speed.clone()?, first..end)))
        .flat_map(|(speed, range)| range.map(move |b| (b, speed.clone())))
        .collect()
}

/// Each contact's status at t = 0: open where its vehicle starts above the
/// track, with its gap.
fn initial_contacts(
    system: &System,
    d: &DynamicState,
    parts: &[TrackPart],
    open: &[bool],
) -> Result<Vec<ContactStatus>, String> {
    let mut frames = Vec::new();
    let located = (d.contact_x.as_slice(), parts);
    contact_frames(
        system,
        &d.beam_displacement,
        &d.bodies,
        located,
        &mut frames,
    )
    .map_err(|e| no_start_point(system, &d.beam_displacement, e))?;
    let statuses = system.contacts.iter().zip(&frames).zip(open);
    Ok(statuses
        .map(|((contact, frame), &open)| {
            let centre = &contact.point(&d.bodies[contact.body]).position;
            ContactStatus {
                open,
                gap: frame.gap(&system.beam, contact.radius(), centre),
                ..ContactStatus::default()
            }
        })
        .collect())
}

/// Why a contact has no point on the track at the start, naming what
/// likely put it there: the heaviest body and the beam's largest static
/// deflection (a coach of 1e15 kg deflects the beam past any foot point).
fn no_start_point(
    system: &System,
    u: &DVector<f64>,
    error: crate::integrate::IntegrationError,
) -> String {
    use crate::numbers::fmt_number;
    let crate::integrate::IntegrationError::LostContact { contact, x, .. } = error else {
        return format!("{error:?}");
    };
    let name = system
        .contacts
        .get(contact)
        .map_or("?", |c| c.name.as_str());
    format!(
        "no contact point at the start for {name} (x = {}): {}",
        fmt_number(x),
        heaviest_and_deflection(system, u)
    )
}

/// The dynamic state at t = 0: at rest on the beam deflected by `u` (zero
/// or the static deflection), with loads and accelerations consistent with
/// the initial contact forces (the implicit scheme starts from them).
fn initial_state(
    system: &System,
    u: DVector<f64>,
    bodies: &[crate::body::BodyState],
    forces: &[ContactForce],
    applied: &[Vector3<f64>],
) -> Result<DynamicState, String> {
    let n = system.beam.coordinates();
    let mut frames = Vec::new();
    contact_frames_at_bodies(system, &u, bodies, &mut frames)
        .map_err(|e| no_start_point(system, &u, e))?;
    let mut beam_load = DVector::zeros(n);
    let mut body_loads = vec![Vector3::zeros(); bodies.len()];
    loads(
        system,
        &frames,
        forces,
        applied,
        bodies,
        &DVector::zeros(n),
        &mut beam_load,
        &mut body_loads,
    );
    let mut beam_acceleration = DVector::zeros(n);
    // The start is at rest: the beam's velocity is zero.
    let at_rest = DVector::zeros(n);
    system
        .beam
        .accelerations((&u, &at_rest), &beam_load, &mut beam_acceleration);
    let body_accelerations = system
        .bodies
        .iter()
        .zip(&body_loads)
        .map(|(body, load)| body.acceleration(load))
        .collect();
    Ok(DynamicState {
        beam_displacement: u,
        beam_velocity: DVector::zeros(n),
        beam_acceleration,
        body_accelerations,
        beam_load,
        body_loads,
        bodies: bodies.to_vec(),
        contact_x: frames.iter().map(|f| f.x).collect(),
        dissipated: 0.0,
        beam_dissipated: 0.0,
        tractive_work: 0.0,
        numerical_dissipation: 0.0,
    })
}
