//! The contact frames of the last accepted configuration, kept so that the
//! next step's start and the output rows of that configuration do not
//! search the same foot points again.
//!
//! A search from a converged foot point evaluates the axis there, finds a
//! correction below the convergence threshold and returns that same frame,
//! bit for bit: recalling it is exact. That holds on a track of one beam,
//! for frames on it (on several beams the element walk may end on another
//! beam's end element). Off the beam, a contact on the approach, the
//! run-off or beyond the track has the frame of its centre alone (the
//! ground, the profile or the beam's end corner), whatever the guess: it
//! is kept too (most of a train's contacts are there). A contact on the
//! beam's part with a frame off it (the start corner, taken where the
//! search's foot point fell before the beam) is not: a search from the
//! corner's abscissa may land on the beam.

use nalgebra::{DVector, Vector2};

use super::step_end::same_bits_in;
use super::{DynamicState, IntegrationError};
use crate::body::BodyState;
use crate::contact::ContactFrame;
use crate::system::{System, TrackPart};

/// Above this many structure coordinates the comparison of the state costs
/// more than the foot-point searches it saves are worth; nothing is kept.
const MAX_COORDINATES: usize = 1024;

/// The frames of one configuration: the structure's state vector, the
/// bodies' centres and angles (a follower hangs off its body's centre, so
/// its frame turns with the body) and each contact's part of the track.
#[derive(Debug, Clone, Default)]
pub struct FrameMemo {
    displacement: DVector<f64>,
    poses: Vec<(Vector2<f64>, f64)>,
    parts: Vec<TrackPart>,
    frames: Vec<ContactFrame>,
    kept: bool,
}

impl FrameMemo {
    /// Keep `frames`, found for displacement `u` and `bodies` on `parts`,
    /// where recalling them is exact (see the module's comment).
    pub fn keep(
        &mut self,
        system: &System,
        (u, bodies): (&DVector<f64>, &[BodyState]),
        parts: &[TrackPart],
        frames: &[ContactFrame],
    ) {
        self.kept = u.len() <= MAX_COORDINATES
            && system.beam.segments().len() == 1
            && (frames.iter().zip(parts)).all(|(f, &part)| f.on_beam || part != TrackPart::Beam);
        if !self.kept {
            return;
        }
        if self.displacement.len() == u.len() {
            self.displacement.copy_from(u);
        } else {
            self.displacement = u.clone();
        }
        self.poses.clear();
        self.poses
            .extend(bodies.iter().map(|b| (b.position, b.angle)));
        self.parts.clear();
        self.parts.extend_from_slice(parts);
        self.frames.clear();
        self.frames.extend_from_slice(frames);
    }

    /// The kept frames if they are those of this configuration searched
    /// from `guesses` (each its frame's own abscissa) on `parts`.
    pub fn recall(
        &self,
        (u, bodies): (&DVector<f64>, &[BodyState]),
        (guesses, parts): (&[f64], &[TrackPart]),
    ) -> Option<&[ContactFrame]> {
        let bits = |a: f64, b: f64| a.to_bits() == b.to_bits();
        let same = self.kept
            && self.parts == parts
            && same_bits_in(self.displacement.as_slice(), u.as_slice())
            && self.poses.len() == bodies.len()
            && (self.poses.iter().zip(bodies)).all(|((c, angle), b)| {
                bits(c.x, b.position.x) && bits(c.y, b.position.y) && bits(*angle, b.angle)
            })
            && self.frames.len() == guesses.len()
            && self.frames.iter().zip(guesses).all(|(f, &g)| bits(f.x, g));
        same.then_some(self.frames.as_slice())
    }

    /// `contact_frames`, from the kept frames where they are this
    /// configuration's.
    pub fn contact_frames(
        &self,
        system: &System,
        u: &DVector<f64>,
        bodies: &[BodyState],
        located: (&[f64], &[TrackPart]),
        frames: &mut Vec<ContactFrame>,
    ) -> Result<(), IntegrationError> {
        match self.recall((u, bodies), located) {
            Some(kept) => {
                frames.clear();
                frames.extend_from_slice(kept);
                Ok(())
            }
            None => super::contact_frames(system, u, bodies, located, frames),
        }
    }

    /// The contact frames of the dynamic state `d`, each contact on its
    /// part `parts` of the track, from the kept frames where they are
    /// this configuration's.
    pub fn frames_of(
        &self,
        system: &System,
        d: &DynamicState,
        parts: &[TrackPart],
    ) -> Result<Vec<ContactFrame>, IntegrationError> {
        let mut frames = Vec::new();
        let located = (d.contact_x.as_slice(), parts);
        self.contact_frames(
            system,
            &d.beam_displacement,
            &d.bodies,
            located,
            &mut frames,
        )?;
        Ok(frames)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assemble::assemble;
    use crate::structure::profile::IrregularitySpec;

    /// Two paper wheels on a four-element beam, and their frames searched
    /// from abscissae away from the foot points.
    fn searched() -> (System, DVector<f64>, Vec<BodyState>, Vec<ContactFrame>) {
        let assembly = assemble(&crate::integrate::fixtures::two_paper_wheels()).unwrap();
        let system = assembly.system;
        let u = DVector::from_fn(system.beam.free_dofs(), |i, _| 3e-2 * libm::sin(i as f64));
        let mut frames = Vec::new();
        let located = ([2.7, 15.9], [TrackPart::Beam; 2]);
        let bodies = assembly.bodies;
        super::super::contact_frames(&system, &u, &bodies, (&located.0, &located.1), &mut frames)
            .unwrap();
        (system, u, bodies, frames)
    }

    #[test]
    fn recalled_frames_are_those_a_new_search_finds_bit_for_bit() {
        let (system, u, bodies, frames) = searched();
        let parts = [TrackPart::Beam; 2];
        let mut memo = FrameMemo::default();
        memo.keep(&system, (&u, &bodies), &parts, &frames);
        // The next search starts from the frames' own abscissae.
        let guesses: Vec<f64> = frames.iter().map(|f| f.x).collect();
        let recalled = memo.recall((&u, &bodies), (&guesses, &parts)).unwrap();
        let mut searched = Vec::new();
        super::super::contact_frames(&system, &u, &bodies, (&guesses, &parts), &mut searched)
            .unwrap();
        assert_eq!(fields_of(recalled), fields_of(&searched));
    }

    #[test]
    fn frames_on_the_approach_and_the_run_off_are_recalled_as_searched() {
        // Three paper wheels: on the approach, on the beam and on the
        // run-off, on flat ground and on a track with an irregularity
        // (where the frames off the beam are feet of searches on the
        // profile).
        for irregular in [false, true] {
            let mut scene = crate::integrate::fixtures::two_paper_wheels();
            scene.track.approach = 20.0;
            scene.track.run_off = 20.0;
            if irregular {
                scene.track.irregularities = vec![IrregularitySpec::Sine {
                    amplitude: 0.01,
                    wavelength: 3.0,
                    phase: 0.2,
                }];
            }
            let mut third = scene.vehicles[0].clone();
            third.name = "third".into();
            scene.vehicles.push(third);
            let assembly = assemble(&scene).unwrap();
            let (system, mut bodies) = (assembly.system, assembly.bodies);
            let u = DVector::from_fn(system.beam.free_dofs(), |i, _| 3e-2 * libm::sin(i as f64));
            let places = [-4.0, 9.3, system.beam.length + 0.1];
            for (contact, x) in system.contacts.iter().zip(places) {
                bodies[contact.body].position.x = x;
            }
            let mut frames = Vec::new();
            super::super::contact_frames_at_bodies(&system, &u, &bodies, &mut frames).unwrap();
            let parts: Vec<TrackPart> = places.iter().map(|&x| system.track_part(x)).collect();
            assert_eq!(
                parts,
                [TrackPart::Approach, TrackPart::Beam, TrackPart::RunOff]
            );
            assert!(!frames[0].on_beam && frames[1].on_beam && !frames[2].on_beam);
            let mut memo = FrameMemo::default();
            memo.keep(&system, (&u, &bodies), &parts, &frames);
            let guesses: Vec<f64> = frames.iter().map(|f| f.x).collect();
            let recalled = memo.recall((&u, &bodies), (&guesses, &parts)).unwrap();
            let mut searched = Vec::new();
            let located = (guesses.as_slice(), parts.as_slice());
            super::super::contact_frames(&system, &u, &bodies, located, &mut searched).unwrap();
            assert_eq!(fields_of(recalled), fields_of(&searched), "{irregular}");
            assert_eq!(fields_of(recalled), fields_of(&frames), "{irregular}");
        }
    }

    /// Every number and DOF of each frame, as bits.
    fn fields_of(frames: &[ContactFrame]) -> Vec<Vec<u64>> {
        let fields = |f: &ContactFrame| {
            let mut v = vec![f.x, f.deflection, f.slope, f.curvature, f.cos, f.sin];
            v.extend(f.shape.n.iter().chain(&f.shape.dn).chain(&f.shape.ddn));
            let mut bits: Vec<u64> = v.into_iter().map(f64::to_bits).collect();
            bits.extend(
                f.shape
                    .dofs
                    .iter()
                    .map(|d| d.map_or(u64::MAX, |i| i as u64)),
            );
            bits.push(f.on_beam as u64);
            bits
        };
        frames.iter().map(fields).collect()
    }

    #[test]
    fn any_change_of_the_configuration_is_a_miss() {
        let (system, u, bodies, frames) = searched();
        let parts = [TrackPart::Beam; 2];
        let guesses: Vec<f64> = frames.iter().map(|f| f.x).collect();
        let mut memo = FrameMemo::default();
        memo.keep(&system, (&u, &bodies), &parts, &frames);
        let mut moved_u = u.clone();
        moved_u[1] += 1e-15;
        assert!(memo
            .recall((&moved_u, &bodies), (&guesses, &parts))
            .is_none());
        let mut moved_bodies = bodies.clone();
        moved_bodies[1].position.y += 1e-12;
        assert!(memo
            .recall((&u, &moved_bodies), (&guesses, &parts))
            .is_none());
        // A body turned about its centre moves the followers hung off it.
        let mut turned = bodies.clone();
        turned[0].angle += 1e-12;
        assert!(memo.recall((&u, &turned), (&guesses, &parts)).is_none());
        let other_guesses = [guesses[0], guesses[1] + 1e-9];
        assert!(memo
            .recall((&u, &bodies), (&other_guesses, &parts))
            .is_none());
        let other_parts = [TrackPart::Beam, TrackPart::RunOff];
        assert!(memo
            .recall((&u, &bodies), (&guesses, &other_parts))
            .is_none());
        // A frame off the beam on the beam's part (the start corner) is
        // never kept.
        let mut off = frames.clone();
        off[0].on_beam = false;
        memo.keep(&system, (&u, &bodies), &parts, &off);
        assert!(memo.recall((&u, &bodies), (&guesses, &parts)).is_none());
    }
}
