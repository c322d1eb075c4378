//! The accelerations M⁻¹ (r − K u − C v) on the few coordinates the design
//! outputs read, without a solve: with w = M⁻¹ e_j (M symmetric, w found
//! once), the acceleration of coordinate j is wᵀ r − wᵀ (K u + C v), the
//! point loads' few terms and one dot with the internal forces the step's
//! end keeps, against a mass solve of the whole structure every row (the
//! same value up to the solve's rounding).

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
    /// structure, or where the rows would cost more than the solve (more
    /// than `MAX_ROW_COORDINATES`, or a quarter of the coordinates).
    pub fn of_elements(
        structure: &Structure,
        elements: impl IntoIterator<Item = usize>,
    ) -> Option<AccelerationRows> {
        let Structure::Hermite(_) = structure else {
            return None;
        };
        let mut coordinates: Vec<usize> = elements
            .into_iter()
            .filter(|&e| e < structure.elements())
            .flat_map(|e| structure.element_dofs(e).iter().flatten().copied())
            .collect();
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
    /// untouched.
    pub fn write(
        &self,
        structure: &Structure,
        loads: &[PointLoad],
        internal: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let shapes: Vec<_> = (loads.iter())
            .map(|load| (structure.shape(load.element, load.x), load))
            .collect();
        for row in &self.rows {
            let mut load = 0.0;
            for (shape, point) in &shapes {
                for (k, dof) in shape.dofs.iter().enumerate() {
                    let w = dof.map_or(0.0, |dof| row.at(dof));
                    load += w * (point.force * shape.n[k] + point.couple * shape.dn[k]);
                }
            }
            let stretch = &internal.as_slice()[row.start..][..row.inverse_mass.len()];
            out[row.coordinate] = load - dot(&row.inverse_mass, stretch);
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

    /// The row's entry at coordinate `i`.
    fn at(&self, i: usize) -> f64 {
        i.checked_sub(self.start)
            .and_then(|k| self.inverse_mass.get(k))
            .copied()
            .unwrap_or(0.0)
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
            frequency: None,
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
            joints: Vec::new(),
            foundation: None,
            damping: Some(DampingSpec::Coefficients {
                alpha: 0.3,
                beta: 2e-4,
            }),
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
        let wave = |i: usize, k: f64| 1e-4 * ((i as f64) * k).sin() + 3e-5;
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
