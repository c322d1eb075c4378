//! A state copied into an existing one, reusing its storage: the FMU takes
//! a roll-back copy before every communication step (`model::step`), and a
//! fresh `clone` allocates each of the state's vectors (`clone_from` of a
//! derived `Clone` does too).

use super::SimState;
use crate::integrate::DynamicState;
use nalgebra::DVector;

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
            body_force,
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
        self.body_force = *body_force;
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
        fine.solver.integrator = crate::scene::IntegratorKind::Hht;
        let coarse = Scene::lee1994(BodyKind::Glider, 30.0, 0.0025);
        let (a, b) = (state_after(&fine, 10), state_after(&coarse, 10));
        let mut into = a.clone();
        into.copy_from(&b);
        assert_eq!(into, b);
        into.copy_from(&a);
        assert_eq!(into, a);
    }
}
