//! A state copied into an existing one, reusing its storage: the FMU takes
//! a roll-back copy before every communication step (`model::step`), and a
//! fresh `clone` allocates each of the state's vectors (`clone_from` of a
//! derived `Clone` does too).

use super::{not_finite, ContactStatus, DynamicState, SimState};
use crate::body::BodyState;
use crate::contact::ContactForce;
use nalgebra::{DVector, Vector3};

/// `into = from`, in `into`'s storage when the lengths match.
fn copy_vector(into: &mut DVector<f64>, from: &DVector<f64>) {
    if into.len() == from.len() {
        // (The slices' copy: `Matrix::copy_from` costs several times more on
        // the few numbers of a small mesh.)
        into.as_mut_slice().copy_from_slice(from.as_slice());
    } else {
        *into = from.clone();
    }
}

impl DynamicState {
    /// `*self = source.clone()` without allocating when the shapes match.
    pub fn copy_from(&mut self, source: &DynamicState) {
        // Every field is named, so that a new one cannot be forgotten here.
        let DynamicState {
            beam_displacement,
            beam_velocity,
            beam_acceleration,
            body_accelerations,
            beam_load,
            body_loads,
            bodies,
            contact_x,
            dissipated,
            beam_dissipated,
            tractive_work,
            numerical_dissipation,
        } = source;
        copy_vector(&mut self.beam_displacement, beam_displacement);
        copy_vector(&mut self.beam_velocity, beam_velocity);
        copy_vector(&mut self.beam_acceleration, beam_acceleration);
        copy_vector(&mut self.beam_load, beam_load);
        self.body_accelerations.clone_from(body_accelerations);
        self.body_loads.clone_from(body_loads);
        self.bodies.clone_from(bodies);
        self.contact_x.clone_from(contact_x);
        self.dissipated = *dissipated;
        self.beam_dissipated = *beam_dissipated;
        self.tractive_work = *tractive_work;
        self.numerical_dissipation = *numerical_dissipation;
    }
}

impl SimState {
    /// `*self = source.clone()` without allocating when the shapes match
    /// (the events list grows: its storage is reused up to its capacity).
    pub fn copy_from(&mut self, source: &SimState) {
        let SimState {
            time,
            grid_step,
            dynamic,
            force_history,
            step_history,
            vehicle_forces,
            external_work,
            gravity_work,
            initial_energy,
            last_iterations,
            last_position_iterations,
            last_velocity_error,
            last_gap_error,
            steps,
            total_iterations,
            parts,
            events,
            events_dropped,
            exit_time,
            contacts,
            impact_loss,
            coupling_loads,
            last_applied,
            pending_restart,
        } = source;
        self.time = *time;
        self.grid_step = *grid_step;
        self.dynamic.copy_from(dynamic);
        self.force_history.clone_from(force_history);
        self.step_history = *step_history;
        self.vehicle_forces.clone_from(vehicle_forces);
        self.external_work = *external_work;
        self.gravity_work = *gravity_work;
        self.initial_energy = *initial_energy;
        self.last_iterations = *last_iterations;
        self.last_position_iterations = *last_position_iterations;
        self.last_velocity_error = *last_velocity_error;
        self.last_gap_error = *last_gap_error;
        self.steps = *steps;
        self.total_iterations = *total_iterations;
        self.parts.clone_from(parts);
        self.events.clone_from(events);
        self.events_dropped = *events_dropped;
        self.exit_time = *exit_time;
        self.contacts.clone_from(contacts);
        self.impact_loss = *impact_loss;
        self.coupling_loads.clone_from(coupling_loads);
        self.last_applied.clone_from(last_applied);
        self.pending_restart.clone_from(pending_restart);
    }
}

/// 0 when every scalar of `s` that a checked copy sums is finite, NaN
/// otherwise.
fn scalars_not_finite(s: &SimState) -> f64 {
    not_finite(&[
        s.time,
        s.external_work,
        s.gravity_work,
        s.initial_energy,
        s.last_velocity_error,
        s.last_gap_error,
        s.exit_time.unwrap_or(0.0),
        s.impact_loss,
        s.step_history[0],
        s.step_history[1],
    ])
}

/// `into = from` in `into`'s storage where the lengths match, with the sum
/// of `sum` over `from`'s elements (0 when their numbers are finite, NaN
/// otherwise: see `not_finite`), in one pass over them.
#[inline(always)] // (a call per list costs more than its few elements)
fn copy_summing<T: Copy>(into: &mut Vec<T>, from: &[T], sum: impl Fn(&T) -> f64) -> f64 {
    if into.len() != from.len() {
        into.clear();
        into.extend_from_slice(from);
        return from.iter().fold(0.0, |nan, x| nan + sum(x));
    }
    let mut nan = 0.0;
    for (to, x) in into.iter_mut().zip(from) {
        *to = *x;
        nan += sum(x);
    }
    nan
}

/// `copy_vector_summing` of the four beam vectors, in one loop when they
/// all have one length (as they do in every state `check_values` accepts).
fn copy_beam_summing(into: [&mut DVector<f64>; 4], from: [&DVector<f64>; 4]) -> f64 {
    let n = from[0].len();
    if into.iter().any(|v| v.len() != n) || from.iter().any(|v| v.len() != n) {
        return into
            .into_iter()
            .zip(from)
            .map(|(into, from)| copy_vector_summing(into, from))
            .sum();
    }
    let [i0, i1, i2, i3] = into.map(|v| &mut v.as_mut_slice()[..n]);
    let [f0, f1, f2, f3] = from.map(|v| &v.as_slice()[..n]);
    let mut nan = 0.0;
    for k in 0..n {
        let x = [f0[k], f1[k], f2[k], f3[k]];
        (i0[k], i1[k], i2[k], i3[k]) = (x[0], x[1], x[2], x[3]);
        nan += not_finite(&x);
    }
    nan
}

/// `copy_summing` of a beam vector.
#[allow(clippy::eq_op)] // x − x: see `not_finite`
fn copy_vector_summing(into: &mut DVector<f64>, from: &DVector<f64>) -> f64 {
    if into.len() != from.len() {
        *into = from.clone();
        return not_finite(from.as_slice());
    }
    let mut nan = 0.0;
    for (to, &x) in into.as_mut_slice().iter_mut().zip(from.as_slice()) {
        *to = x;
        nan += x - x;
    }
    nan
}

fn body_numbers(b: &BodyState) -> f64 {
    not_finite(&b.numbers())
}

impl DynamicState {
    /// `copy_from`, returning the sum x − x over the numbers
    /// `SimState::check_values` checks (0 or NaN).
    fn copy_summing_from(&mut self, source: &DynamicState) -> f64 {
        let DynamicState {
            beam_displacement,
            beam_velocity,
            beam_acceleration,
            body_accelerations,
            beam_load,
            body_loads,
            bodies,
            contact_x,
            dissipated,
            beam_dissipated,
            tractive_work,
            numerical_dissipation,
        } = source;
        let vector = |v: &Vector3<f64>| not_finite(v.as_slice());
        let beam = copy_beam_summing(
            [
                &mut self.beam_displacement,
                &mut self.beam_velocity,
                &mut self.beam_acceleration,
                &mut self.beam_load,
            ],
            [
                beam_displacement,
                beam_velocity,
                beam_acceleration,
                beam_load,
            ],
        );
        let nan = beam
            + copy_summing(&mut self.body_accelerations, body_accelerations, vector)
            + copy_summing(&mut self.body_loads, body_loads, vector)
            + copy_summing(&mut self.bodies, bodies, body_numbers)
            + copy_summing(&mut self.contact_x, contact_x, |x| not_finite(&[*x]));
        self.dissipated = *dissipated;
        self.beam_dissipated = *beam_dissipated;
        self.tractive_work = *tractive_work;
        self.numerical_dissipation = *numerical_dissipation;
        nan + not_finite(&[
            *dissipated,
            *beam_dissipated,
            *tractive_work,
            *numerical_dissipation,
        ])
    }
}

impl SimState {
    /// `copy_from` and `source.check_values(step)` in one pass over the
    /// numbers: the FMU copies every state a step reaches for the next
    /// step's roll-back, and checks it (a restore must accept it). On Err
    /// `self` holds the refused state.
    pub fn copy_checked_from(&mut self, source: &SimState, step: f64) -> Result<(), String> {
        let nan = self.copy_lists_summing(source) + scalars_not_finite(source);
        self.copy_rest_from(source);
        if nan != 0.0 {
            // The search names the number (and an Err whatever it finds).
            source.check_values(step)?;
            return Err("the state holds a non-finite number".into());
        }
        source.check_lengths_and_time(step)
    }

    /// The lists of numbers copied, with the sum that is 0 when their
    /// numbers are finite (NaN otherwise: `not_finite`).
    fn copy_lists_summing(&mut self, source: &SimState) -> f64 {
        let forces = |f: &[ContactForce; 3]| {
            not_finite(&[
                f[0].tangential,
                f[0].normal,
                f[1].tangential,
                f[1].normal,
                f[2].tangential,
                f[2].normal,
            ])
        };
        let status = |c: &ContactStatus| not_finite(&[c.gap, c.impulse[0], c.impulse[1]]);
        self.dynamic.copy_summing_from(&source.dynamic)
            + copy_summing(&mut self.force_history, &source.force_history, forces)
            + copy_summing(&mut self.events, &source.events, |e| not_finite(&[e.time]))
            + copy_summing(&mut self.contacts, &source.contacts, status)
            + copy_summing(&mut self.vehicle_forces, &source.vehicle_forces, |f| {
                not_finite(f)
            })
    }

    /// Every field but the lists of `copy_lists_summing` (each named, so
    /// that a new field cannot be forgotten here).
    fn copy_rest_from(&mut self, source: &SimState) {
        let SimState {
            time,
            grid_step,
            dynamic: _,
            force_history: _,
            step_history,
            vehicle_forces: _,
            external_work,
            gravity_work,
            initial_energy,
            last_iterations,
            last_position_iterations,
            last_velocity_error,
            last_gap_error,
            steps,
            total_iterations,
            parts,
            events: _,
            events_dropped,
            exit_time,
            contacts: _,
            impact_loss,
            coupling_loads,
            last_applied,
            pending_restart,
        } = source;
        self.time = *time;
        self.grid_step = *grid_step;
        self.step_history = *step_history;
        self.external_work = *external_work;
        self.gravity_work = *gravity_work;
        self.initial_energy = *initial_energy;
        self.last_iterations = *last_iterations;
        self.last_position_iterations = *last_position_iterations;
        self.last_velocity_error = *last_velocity_error;
        self.last_gap_error = *last_gap_error;
        self.steps = *steps;
        self.total_iterations = *total_iterations;
        self.parts.clone_from(parts);
        self.events_dropped = *events_dropped;
        self.exit_time = *exit_time;
        self.impact_loss = *impact_loss;
        self.coupling_loads.clone_from(coupling_loads);
        self.last_applied.clone_from(last_applied);
        self.pending_restart.clone_from(pending_restart);
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{BodyKind, Scene};
    use crate::Simulation;

    fn state_after(scene: &Scene, steps: usize) -> crate::simulation::SimState {
        let mut sim = Simulation::new(scene).expect("valid scene");
        let step = scene.solver.step;
        sim.advance_to(steps as f64 * step).expect("advances");
        sim.state()
    }

    #[test]
    fn copy_equals_clone_and_reuses_the_storage() {
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let (early, late) = (state_after(&scene, 3), state_after(&scene, 400));
        assert_ne!(early, late);
        let mut into = early.clone();
        let storage = into.dynamic.beam_displacement.as_ptr();
        into.copy_from(&late);
        assert_eq!(into, late);
        assert_eq!(into.dynamic.beam_displacement.as_ptr(), storage);
        into.copy_from(&early);
        assert_eq!(into, early);
    }

    #[test]
    fn copy_between_shapes_equals_clone() {
        let mut fine = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        fine.beam.elements = 8;
        fine.solver.integrator = crate::solver::integrate::IntegratorKind::Hht;
        let coarse = Scene::lee1994(BodyKind::Glider, 30.0, 0.0025);
        let (a, b) = (state_after(&fine, 10), state_after(&coarse, 10));
        let mut into = a.clone();
        into.copy_from(&b);
        assert_eq!(into, b);
        into.copy_from(&a);
        assert_eq!(into, a);
    }

    #[test]
    fn a_checked_copy_equals_clone_between_any_shapes() {
        let mut fine = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        fine.beam.elements = 8;
        fine.solver.integrator = crate::solver::integrate::IntegratorKind::Hht;
        let coarse = Scene::lee1994(BodyKind::Glider, 30.0, 0.0025);
        let wheel = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let states = [
            state_after(&fine, 10),
            state_after(&coarse, 10),
            state_after(&wheel, 3),
            state_after(&wheel, 400),
        ];
        for from in &states {
            for into in &states {
                let mut copy = into.clone();
                copy.copy_checked_from(from, 0.0025).unwrap();
                assert_eq!(copy, *from);
            }
        }
    }

    type Corrupt = fn(&mut crate::simulation::SimState, f64);

    /// Each number `check_values` checks, named, and how to set it.
    fn corruptions() -> Vec<(&'static str, Corrupt)> {
        let all: &[(&str, Corrupt)] = &[
            ("time", |s, x| s.time = x),
            ("external work", |s, x| s.external_work = x),
            ("gravity work", |s, x| s.gravity_work = x),
            ("initial energy", |s, x| s.initial_energy = x),
            ("velocity error", |s, x| s.last_velocity_error = x),
            ("gap error", |s, x| s.last_gap_error = x),
            ("exit time", |s, x| s.exit_time = Some(x)),
            ("impact loss", |s, x| s.impact_loss = x),
            ("step history", |s, x| s.step_history[1] = x),
            ("vehicle force", |s, x| s.vehicle_forces[0][0] = x),
            ("dissipated", |s, x| s.dynamic.dissipated = x),
            ("beam dissipated", |s, x| s.dynamic.beam_dissipated = x),
            ("tractive work", |s, x| s.dynamic.tractive_work = x),
            ("numerical", |s, x| s.dynamic.numerical_dissipation = x),
            ("displacement", |s, x| {
                let n = s.dynamic.beam_displacement.len();
                s.dynamic.beam_displacement[n - 1] = x
            }),
            ("velocity", |s, x| s.dynamic.beam_velocity[0] = x),
            ("acceleration", |s, x| s.dynamic.beam_acceleration[1] = x),
            ("load", |s, x| s.dynamic.beam_load[2] = x),
            ("body acceleration", |s, x| {
                s.dynamic.body_accelerations[0].z = x
            }),
            ("body load", |s, x| s.dynamic.body_loads[0].x = x),
            ("angle", |s, x| s.dynamic.bodies[0].angle = x),
            ("body velocity", |s, x| s.dynamic.bodies[0].velocity.y = x),
            ("contact x", |s, x| s.dynamic.contact_x[0] = x),
            ("force history", |s, x| s.force_history[0][2].normal = x),
            ("event time", |s, x| s.events[0].time = x),
            ("impulse", |s, x| s.contacts[0].impulse[1] = x),
            ("gap", |s, x| s.contacts[0].gap = x),
        ];
        all.to_vec()
    }

    /// Every number `check_values` checks, made non-finite in turn, and its
    /// two other rules broken: the checked copy refuses each as it does.
    #[test]
    fn a_checked_copy_refuses_what_check_values_refuses() {
        use crate::simulation::{ContactEvent, EventKind};
        let step = 0.0025;
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, step);
        let mut good = state_after(&scene, 400);
        good.events.push(ContactEvent {
            contact: 0,
            time: 0.5,
            kind: EventKind::Entry,
        });
        let corruptions = corruptions();
        let mut copy = good.clone();
        assert_eq!(good.check_values(step), Ok(()));
        assert_eq!(copy.copy_checked_from(&good, step), Ok(()));
        for (what, corrupt) in &corruptions {
            for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut bad = good.clone();
                corrupt(&mut bad, x);
                let refused = bad.check_values(step).unwrap_err();
                assert!(refused.contains("non-finite"), "{what}: {refused}");
                let copied = copy.copy_checked_from(&bad, step).unwrap_err();
                assert_eq!(copied, refused, "{what} = {x}");
            }
        }
        let mut short = good.clone();
        short.dynamic.beam_velocity = nalgebra::DVector::zeros(1);
        let mut off_grid = good.clone();
        off_grid.time += 10.0 * step;
        for bad in [short, off_grid] {
            let refused = bad.check_values(step).unwrap_err();
            assert_eq!(copy.copy_checked_from(&bad, step), Err(refused));
        }
    }
}
