//! The accelerations M⁻¹ (r − K u − C v) on the few coordinates the design
//! outputs read, without a solve: with w = M⁻¹ e_j (M symmetric, w found
//! once), the acceleration of coordinate j is wᵀ r − wᵀ (K u + C v), the
//! point loads' few terms and one dot with the internal forces the step's
//! end keeps, against a mass solve of the whole structure every row (the
//! same value up to the solve's rounding). On the full Hermite mesh the
//! rows are the design outputs' elements' coordinates; under a rail over
//! the deck, the deck's coordinates the sensors read (the loads on the
//! rail's, the state entries interleaved).

use nalgebra::DVector;

use super::section_forces::PointLoad;
use super::Structure;

/// At most this many coordinates are read through rows; beyond, the
/// whole solve is cheaper than the dots (tuning: four sensors' or two
/// sections' elements).
const MAX_ROW_COORDINATES: usize = 16;

/// Entries of a row M⁻¹ e_j below this fraction of its largest are left
/// out: M⁻¹'s entries decay geometrically away from the diagonal, and
/// what they would add is far below the dot's own rounding (ε = 2.2e-16
/// of the largest term), so a row reads a fixed stretch of the structure
/// whatever its length (tuning).
const ROW_CUT: f64 = 1e-20;

/// The row M⁻¹ e_j of one coordinate j, on the stretch `start..` where its
/// entries are at least `ROW_CUT` of its largest (zero elsewhere).
struct Row {
    coordinate: usize,
    start: usize,
    inverse_mass: Vec<f64>,
}

/// The rows of the coordinates some elements' fields read.
pub struct AccelerationRows {
    rows: Vec<Row>,
}

impl AccelerationRows {
    /// The rows of the coordinates of `elements` (on the full Hermite mesh
    /// only: its coordinates are the free DOFs); `None` on another kind of
    /// structure, or where the rows would cost more than the solve
    /// (`of_coordinates`).
    pub fn of_elements(
        structure: &Structure,
        elements: impl IntoIterator<Item = usize>,
    ) -> Option<AccelerationRows> {
        let Structure::Hermite(_) = structure else {
            return None;
        };
        let coordinates = (elements.into_iter())
            .filter(|&e| e < structure.elements())
            .flat_map(|e| structure.element_dofs(e).iter().flatten().copied());
        Self::of_coordinates(structure, coordinates.collect())
    }

    /// The rows of the deck's coordinates the sensors at deck abscissae
    /// `positions` read under a rail over the deck (the state entries
    /// interleaved: `TrackBeam::deck_deflection_coordinates`); `None` on
    /// another kind of structure, or where the rows would cost more than
    /// the solve (`of_coordinates`).
    pub fn of_deck_sensors(
        structure: &Structure,
        positions: impl IntoIterator<Item = f64>,
    ) -> Option<AccelerationRows> {
        let track = structure.track()?;
        let coordinates = (positions.into_iter())
            .flat_map(|x| track.deck_deflection_coordinates(x))
            .collect();
        Self::of_coordinates(structure, coordinates)
    }

    /// The rows of state entries `coordinates`; `None` where there are
    /// none, or where the rows would cost more than the solve (more than
    /// `MAX_ROW_COORDINATES`, or a quarter of the coordinates).
    fn of_coordinates(
        structure: &Structure,
        mut coordinates: Vec<usize>,
    ) -> Option<AccelerationRows> {
        coordinates.sort_unstable();
        coordinates.dedup();
        let n = structure.coordinates();
        let cheaper = coordinates.len() <= MAX_ROW_COORDINATES && 4 * coordinates.len() <= n;
        (cheaper && !coordinates.is_empty()).then(|| AccelerationRows {
            rows: (coordinates.into_iter())
                .map(|j| Row::new(structure, j))
                .collect(),
        })
    }

    /// `out[j]` for each row's coordinate j: the acceleration under the
    /// point loads `loads` with the state's internal forces `internal` =
    /// K u + C v (`Structure::internal_forces`); the other entries
    /// untouched. Each load's shape and weights are taken once for all the
    /// rows, each row's sum running on the stack in the loads' order (no
    /// buffer on the heap); a term whose row entry is zero outside the
    /// row's stretch adds a zero to a sum that started at +0, which leaves
    /// it as it was, so it is skipped where its weight is finite (0 · ∞
    /// would be NaN).
    pub fn write(
        &self,
        structure: &Structure,
        loads: &[PointLoad],
        internal: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let mut sums = [0.0; MAX_ROW_COORDINATES];
        let sums = &mut sums[..self.rows.len()];
        for point in loads {
            let shape = structure.shape(point.element, point.x);
            for (k, dof) in shape.dofs.iter().enumerate() {
                let coordinate = dof.and_then(|dof| structure.load_coordinate(dof));
                let weight = point.force * shape.n[k] + point.couple * shape.dn[k];
                for (sum, row) in sums.iter_mut().zip(&self.rows) {
                    match coordinate.and_then(|i| row.entry(i)) {
                        Some(w) => *sum += w * weight,
                        None if weight.is_finite() => {}
                        None => *sum += 0.0 * weight,
                    }
                }
            }
        }
        for (sum, row) in sums.iter().zip(&self.rows) {
            let stretch = &internal.as_slice()[row.start..][..row.inverse_mass.len()];
            out[row.coordinate] = sum - dot(&row.inverse_mass, stretch);
        }
    }
}

impl Row {
    fn new(structure: &Structure, coordinate: usize) -> Row {
        let mut inverse_mass = DVector::zeros(structure.coordinates());
        inverse_mass[coordinate] = 1.0;
        structure.solve_mass(&mut inverse_mass);
        let largest = inverse_mass.amax();
        let kept = |w: &f64| w.abs() >= ROW_CUT * largest;
        let start = inverse_mass.iter().position(kept).unwrap_or(coordinate);
        let end = inverse_mass.iter().rposition(kept).map_or(start, |e| e + 1);
        Row {
            coordinate,
            start,
            inverse_mass: inverse_mass.as_slice()[start..end].to_vec(),
        }
    }

    /// The row's entry at coordinate `i`, `None` outside its stretch
    /// (where it is zero).
    fn entry(&self, i: usize) -> Option<f64> {
        i.checked_sub(self.start)
            .and_then(|k| self.inverse_mass.get(k))
            .copied()
    }
}
/// aᵀ b in four running sums (a fixed order: the same bits every call).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    let (chunks_a, chunks_b) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = (chunks_a.remainder().iter())
        .zip(chunks_b.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in chunks_a.zip(chunks_b) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structure::beam::{BeamSpec, DampingSpec, SpringSpec, SupportsSpec};
    use crate::structure::section_forces::load_vector;

    /// A continuous damped beam on 200 elements with a damped spring
    /// support, and a state with loads on it.
    fn damped_beam() -> Structure {
        let spec = BeamSpec {
            length: 100.0,
            mass_per_length: 2303.0,
            bending_stiffness: 8.5347e10,
            surface_offset: 0.0,
            elements: 200,
            supports: SupportsSpec {
                intermediate: vec![25.0, 50.0, 75.0],
                springs: vec![SpringSpec {
                    at: 60.0,
                    vertical: 1e9,
                    vertical_damping: 1e6,
                    ..Default::default()
                }],
                ..SupportsSpec::default()
            },
            damping: Some(DampingSpec::Coefficients {
                alpha: 0.3,
                beta: 2e-4,
            }),
            ..BeamSpec::default()
        };
        Structure::new(&spec).expect("beam")
    }

    /// The rows' accelerations are the whole solve's M⁻¹ (r − K u − C v)
    /// (`Structure::accelerations`, a band solve) at every coordinate of
    /// the elements read, to the solves' rounding, on a damped beam with a
    /// damper, loads on and off the rows' stretch; the other entries are
    /// left as they were.
    #[test]
    fn the_rows_give_the_whole_solves_accelerations_at_their_coordinates() {
        let beam = damped_beam();
        let n = beam.coordinates();
        let wave = |i: usize, k: f64| 1e-4 * libm::sin((i as f64) * k) + 3e-5;
        let (u, v) = (
            DVector::from_fn(n, |i, _| wave(i, 0.37)),
            DVector::from_fn(n, |i, _| 1e2 * wave(i, 0.11)),
        );
        let loads: Vec<PointLoad> = [(30.2, -1.2e5, 0.0), (61.3, -8e4, 2e3), (99.0, -5e4, 0.0)]
            .into_iter()
            .map(|(x, force, couple)| PointLoad {
                couple,
                ..PointLoad::vertical(&beam, x, force)
            })
            .collect();
        let mut whole = DVector::zeros(n);
        beam.accelerations((&u, &v), &load_vector(&beam, &loads), &mut whole);
        let (mut scratch, mut internal) = (DVector::zeros(n), DVector::zeros(n));
        beam.internal_forces(&u, &v, &mut scratch, &mut internal);
        let elements = [beam.element_at(37.5), beam.element_at(60.0)];
        let rows = AccelerationRows::of_elements(&beam, elements).expect("rows");
        let mut read = DVector::from_element(n, f64::NAN);
        rows.write(&beam, &loads, &internal, &mut read);
        let largest = whole.amax();
        let coordinates: Vec<usize> = (elements.iter())
            .flat_map(|&e| beam.element_dofs(e).iter().flatten().copied())
            .collect();
        assert_eq!(coordinates.len(), 8);
        for j in 0..n {
            match coordinates.contains(&j) {
                true => assert!(
                    (read[j] - whole[j]).abs() <= 1e-12 * largest,
                    "coordinate {j}: {} against {}",
                    read[j],
                    whole[j]
                ),
                false => assert!(read[j].is_nan(), "coordinate {j} written"),
            }
        }
        // The rows read a stretch, not the whole beam.
        assert!(rows.rows.iter().all(|r| r.inverse_mass.len() < n / 2));
    }

    /// A 20 m damped deck under a rail on a continuous ballasted layer, or
    /// on sleepers at 0.5 m, with 10 m of approach and run-off.
    fn rail_over_deck(sleepers: bool) -> Structure {
        use crate::structure::beam::{BeamSpec, FoundationPreset};
        use crate::structure::track_seam::TrackBeam;
        use crate::structure::track_sleepers::{SleeperPreset, SleepersSpec};
        use crate::structure::track_spec::OnDeckSpec;
        let deck = BeamSpec {
            length: 20.0,
            mass_per_length: 12000.0,
            bending_stiffness: 2.3539e10,
            surface_offset: 0.0,
            elements: 40,
            damping: Some(DampingSpec::Coefficients {
                alpha: 0.5,
                beta: 3e-4,
            }),
            ..BeamSpec::default()
        };
        let on_deck = OnDeckSpec {
            preset: Some(FoundationPreset::Ballasted),
            stiffness: None,
            damping: None,
            ground_stiffness: None,
            ground_damping: None,
            rail_bending_stiffness: 1.28e7,
            rail_mass_per_length: 120.0,
            sleepers: sleepers.then_some(SleepersSpec {
                preset: Some(SleeperPreset::Ballasted),
                spacing: Some(0.5),
                rail_elements_per_bay: None,
                pad_stiffness: None,
                pad_damping: None,
                sleeper_mass: None,
                ballast_stiffness: None,
                ballast_damping: None,
            }),
        };
        let track = TrackBeam::new(&deck, &on_deck, (10.0, 10.0)).expect("track");
        Structure::Track(Box::new(track))
    }

    /// Under a rail over the deck, the rows of the deck's coordinates two
    /// sensors read give the whole solve's accelerations there, to 1e-12 of
    /// the largest, with loads on the rail near and far from them, on a
    /// continuous layer and on sleepers; the other entries are untouched.
    #[test]
    fn the_rows_give_the_whole_solves_deck_accelerations_under_a_rail() {
        for sleepers in [false, true] {
            let track = rail_over_deck(sleepers);
            let n = track.coordinates();
            let wave = |i: usize, k: f64| 1e-4 * libm::sin((i as f64) * k) + 3e-5;
            let (u, v) = (
                DVector::from_fn(n, |i, _| wave(i, 0.37)),
                DVector::from_fn(n, |i, _| 1e2 * wave(i, 0.11)),
            );
            let loads: Vec<PointLoad> = [(14.3, -1.2e5), (22.0, -8e4), (38.5, -5e4)]
                .into_iter()
                .map(|(x, force)| PointLoad::vertical(&track, x, force))
                .collect();
            let mut whole = DVector::zeros(n);
            track.accelerations((&u, &v), &load_vector(&track, &loads), &mut whole);
            let (mut scratch, mut internal) = (DVector::zeros(n), DVector::zeros(n));
            track.internal_forces(&u, &v, &mut scratch, &mut internal);
            let sensors = [12.5, 15.25];
            let rows = AccelerationRows::of_deck_sensors(&track, sensors).expect("rows");
            let mut read = DVector::from_element(n, f64::NAN);
            rows.write(&track, &loads, &internal, &mut read);
            let largest = whole.amax();
            let beam = track.track().expect("a track");
            for x in sensors {
                let (by_rows, by_solve) = (
                    beam.deck_deflection(&read, x),
                    beam.deck_deflection(&whole, x),
                );
                assert!(
                    (by_rows - by_solve).abs() <= 1e-12 * largest,
                    "sleepers {sleepers}, x = {x}: {by_rows} against {by_solve}"
                );
            }
            let coordinates: Vec<usize> = (sensors.iter())
                .flat_map(|&x| beam.deck_deflection_coordinates(x))
                .collect();
            assert!((6..=8).contains(&coordinates.len()), "{coordinates:?}");
            for j in 0..n {
                match coordinates.contains(&j) {
                    true => assert!((read[j] - whole[j]).abs() <= 1e-12 * largest),
                    false => assert!(read[j].is_nan(), "coordinate {j} written"),
                }
            }
        }
    }

    /// Rows only where they are cheaper: not for more than
    /// `MAX_ROW_COORDINATES` coordinates nor on a modal structure.
    #[test]
    fn rows_only_where_cheaper_than_the_solve() {
        let beam = damped_beam();
        assert!(AccelerationRows::of_elements(&beam, 0..10).is_none());
        assert!(AccelerationRows::of_elements(&beam, [3]).is_some());
        assert!(AccelerationRows::of_elements(&beam, []).is_none());
        let modal = damped_beam()
            .reduce_to_modes(crate::modal::ModeSelection::Count(4))
            .expect("modes");
        assert!(AccelerationRows::of_elements(&modal, [3]).is_none());
    }
}
