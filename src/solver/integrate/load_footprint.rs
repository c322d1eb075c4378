//! The entries of a structure's load vector that the contacts' loads were
//! added to, so that the next integration clears only those: a beam's load
//! vector is zero but under the contacts, and clearing all of it at every
//! integration was 6.7 % of a 2,500-element viaduct's step (issue 29).

use nalgebra::DVector;

use crate::contact::ContactFrame;
use crate::system::System;

/// Which entries of one load vector may be non-zero.
#[derive(Debug, Clone)]
pub struct LoadFootprint {
    /// The entries loads were added to since the last clear (with repeats).
    entries: Vec<usize>,
    /// Some entry beyond `entries` may be non-zero: a load spread over the
    /// whole vector (a modal basis), or a vector not yet cleared.
    whole: bool,
}

impl Default for LoadFootprint {
    /// The footprint of a vector whose content is unknown: cleared whole.
    fn default() -> LoadFootprint {
        LoadFootprint {
            entries: Vec::new(),
            whole: true,
        }
    }
}

impl LoadFootprint {
    /// Zero every entry of `load` that may be non-zero (the bits of
    /// zeroing all of it), and start a new footprint.
    pub fn clear(&mut self, load: &mut DVector<f64>) {
        if self.whole {
            load.as_mut_slice().fill(0.0);
        } else {
            for &i in &self.entries {
                load[i] = 0.0;
            }
        }
        self.entries.clear();
        self.whole = false;
    }

    /// Note the entries the loads at `frames` are added to
    /// (`loads_but_laws` scatters a load at each frame on the beam).
    pub fn note(&mut self, system: &System, frames: &[ContactFrame]) {
        for frame in frames.iter().filter(|f| f.on_beam) {
            for &dof in frame.shape.dofs.iter().flatten() {
                match system.beam.load_coordinate(dof) {
                    Some(entry) => self.entries.push(entry),
                    None => self.whole = true,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assemble::assemble;
    use crate::contact::ContactForce;
    use crate::integrate::{add_loads_but_laws, contact_frames, HeldFollowers, TrackPart};

    #[test]
    fn clearing_the_noted_entries_gives_the_bits_of_clearing_all() {
        let assembly = assemble(&crate::integrate::fixtures::two_paper_wheels()).unwrap();
        let system = assembly.system;
        let bodies = assembly.bodies;
        let u = DVector::from_fn(system.beam.free_dofs(), |i, _| 1e-3 * libm::cos(i as f64));
        let v = DVector::zeros(u.len());
        let force = |normal: f64| ContactForce {
            tangential: 0.0,
            normal,
        };
        let mut footprint = LoadFootprint::default();
        let mut load = DVector::from_element(u.len(), f64::NAN);
        let mut body_loads = vec![nalgebra::Vector3::zeros(); bodies.len()];
        let applied = body_loads.clone();
        let mut frames = Vec::new();
        // Two configurations, the wheels on other elements in the second.
        for (step, at) in [[2.7, 15.9], [9.1, 4.2]].iter().enumerate() {
            let located = (at.as_slice(), [TrackPart::Beam; 2].as_slice());
            contact_frames(&system, &u, &bodies, located, &mut frames).unwrap();
            footprint.clear(&mut load);
            let mut expected = DVector::zeros(u.len());
            let forces = [force(1e5 * (step + 1) as f64), force(-3e4)];
            for out in [&mut load, &mut expected] {
                let loads = (&mut *out, body_loads.as_mut_slice());
                let followers = (forces.as_slice(), HeldFollowers::<()>::default());
                add_loads_but_laws(&system, &frames, followers, &applied, (&bodies, &v), loads);
            }
            footprint.note(&system, &frames);
            let bits = |x: &DVector<f64>| x.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&load), bits(&expected), "configuration {step}");
            assert!(load.iter().filter(|x| **x != 0.0).count() >= 4);
        }
    }
}
