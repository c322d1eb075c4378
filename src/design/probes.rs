//! The design outputs of a scene as probes of the beam's state: the one
//! list the static envelope, the speed sweep and their tests read, in the
//! order and with the names of the run's outputs.

use super::{supports, BeamDynamics, SectionForces};
use crate::beam::{Beam, Shape};
use crate::scene::Scene;
use nalgebra::DVector;

/// What a probe reads.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Read {
    Deflection(f64),
    Velocity(f64),
    Acceleration(f64),
    Moment(f64),
    Shear(f64),
    Reaction(usize),
    SupportMoment(usize),
}

impl BeamDynamics<'_> {
    /// The vector a sensor reading interpolates.
    fn vector(&self, read: Read) -> &DVector<f64> {
        match read {
            Read::Velocity(_) => self.velocity(),
            Read::Acceleration(_) => self.acceleration(),
            _ => self.displacement(),
        }
    }
}

/// One design output: its name (`sensor.<name>.deflection`, …) and what
/// it reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    pub name: String,
    read: Read,
}

impl Probe {
    fn new(name: String, read: Read) -> Probe {
        Probe { name, read }
    }

    /// The value in `state` (the unit of the run's output of that name).
    pub fn value(&self, beam: &Beam, state: &BeamDynamics) -> f64 {
        match self.read {
            Read::Deflection(x) => state.deflection_at(beam, x),
            Read::Velocity(x) => state.velocity_at(beam, x),
            Read::Acceleration(x) => state.acceleration_at(beam, x),
            Read::Moment(x) => state.section_forces(beam, x).moment,
            Read::Shear(x) => state.section_forces(beam, x).shear,
            Read::Reaction(node) => state.reaction(beam, node)[0],
            Read::SupportMoment(node) => state.reaction(beam, node)[1],
        }
    }

    /// The elements whose DOFs the value reads on a mesh: a point's or a
    /// section's element, a support's elements either side of its node
    /// (its springs act on that node's DOFs).
    pub(super) fn elements(&self, beam: &Beam) -> [Option<usize>; 2] {
        match self.read {
            Read::Reaction(node) | Read::SupportMoment(node) => [
                node.checked_sub(1),
                (node < beam.elements()).then_some(node),
            ],
            Read::Deflection(x)
            | Read::Velocity(x)
            | Read::Acceleration(x)
            | Read::Moment(x)
            | Read::Shear(x) => [Some(beam.element_at(x)), None],
        }
    }

    /// Whether the output has a static counterpart (velocity and
    /// acceleration have none): the DAF is defined for it.
    pub fn is_static(&self) -> bool {
        !matches!(self.read, Read::Velocity(_) | Read::Acceleration(_))
    }
}

/// Every design output of `scene` on `beam`: per sensor deflection,
/// velocity and acceleration; per section moment and shear; per support
/// (with `reactions = true`) the reaction, and the moment where it has one.
pub fn probes(scene: &Scene, beam: &Beam) -> Vec<Probe> {
    let mut list = Vec::new();
    for s in &scene.sensors {
        let (name, x) = (&s.name, s.position);
        list.push(Probe::new(
            format!("sensor.{name}.deflection"),
            Read::Deflection(x),
        ));
        list.push(Probe::new(
            format!("sensor.{name}.velocity"),
            Read::Velocity(x),
        ));
        list.push(Probe::new(
            format!("sensor.{name}.acceleration"),
            Read::Acceleration(x),
        ));
    }
    for s in &scene.sections {
        let (name, x) = (&s.name, s.position);
        list.push(Probe::new(
            format!("section.{name}.moment"),
            Read::Moment(x),
        ));
        list.push(Probe::new(format!("section.{name}.shear"), Read::Shear(x)));
    }
    if scene.reactions {
        for s in supports(beam) {
            let name = &s.name;
            list.push(Probe::new(
                format!("support.{name}.reaction"),
                Read::Reaction(s.node),
            ));
            if s.has_moment {
                list.push(Probe::new(
                    format!("support.{name}.moment"),
                    Read::SupportMoment(s.node),
                ));
            }
        }
    }
    list
}

/// The value of largest magnitude, sign kept, of each probe over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignPeaks {
    pub peaks: Vec<f64>,
}

impl DesignPeaks {
    /// Zero for each of `count` probes.
    pub fn new(count: usize) -> DesignPeaks {
        DesignPeaks {
            peaks: vec![0.0; count],
        }
    }

    /// Take in the probes' `values` at one instant (`ProbeReader::read`).
    pub fn take_in(&mut self, values: &[f64]) {
        for (peak, &value) in self.peaks.iter_mut().zip(values) {
            if value.abs() > peak.abs() {
                *peak = value;
            }
        }
    }
}

impl ProbeReader<'_> {
    /// The value of each probe in `state`, in their order, into `values`.
    pub fn read(&self, beam: &Beam, state: &BeamDynamics, values: &mut Vec<f64>) {
        values.clear();
        match &self.rows {
            Some(rows) => read_rows(self.probes, rows, (beam, state), values),
            None => read_on_mesh(self.probes, (beam, state), values),
        }
    }
}

/// Each probe read from the state's DOFs.
fn read_on_mesh(probes: &[Probe], (beam, state): (&Beam, &BeamDynamics), values: &mut Vec<f64>) {
    // A section's moment and shear come from one evaluation.
    let mut section: Option<(f64, SectionForces)> = None;
    // And a sensor's three values from one shape.
    let mut sensor: Option<(f64, Shape)> = None;
    values.extend(probes.iter().map(|probe| match probe.read {
        Read::Deflection(x) | Read::Velocity(x) | Read::Acceleration(x) => {
            let shape = match sensor.take() {
                Some((at, shape)) if at == x => shape,
                _ => beam.shape(beam.element_at(x), x),
            };
            let value = beam.dot(&shape, &shape.n, state.vector(probe.read));
            sensor = Some((x, shape));
            value
        }
        Read::Moment(x) | Read::Shear(x) => {
            let forces = match section {
                Some((at, forces)) if at == x => forces,
                _ => state.section_forces(beam, x),
            };
            section = Some((x, forces));
            forces.of(probe.read)
        }
        _ => probe.value(beam, state),
    }));
}

/// Each probe read through its rows over the modes.
fn read_rows(
    probes: &[Probe],
    rows: &[Row],
    (beam, state): (&Beam, &BeamDynamics),
    values: &mut Vec<f64>,
) {
    let (u, a) = state.damped_state();
    let mut section: Option<(f64, SectionForces)> = None;
    values.extend(probes.iter().zip(rows).map(|(probe, row)| match row {
        Row::Point(row) => row.dot(state.vector(probe.read)),
        Row::Section { x, moment, shear } => {
            let forces = match section {
                Some((at, forces)) if at == *x => forces,
                _ => {
                    let share = state.section_load_share(beam, *x);
                    SectionForces {
                        moment: moment[0].dot(u) + moment[1].dot(a) + share.moment,
                        shear: shear[0].dot(u) + shear[1].dot(a) + share.shear,
                    }
                }
            };
            section = Some((*x, forces));
            forces.of(probe.read)
        }
        Row::State => probe.value(beam, state),
    }));
}

impl SectionForces {
    /// The moment or the shear, as `read` asks.
    fn of(self, read: Read) -> f64 {
        match read {
            Read::Moment(_) => self.moment,
            _ => self.shear,
        }
    }
}

/// Probes made ready to be read at every step of a run on one structure.
/// On a modal structure each point and section probe is a row over the k
/// modal coordinates, found once by reading the probe in the k unit
/// states: one dot product of length k per value and step, where reading
/// through the element's DOFs takes four (a point) or twenty (a section:
/// the end forces and three Gauss points), each of length k. Equal to the
/// DOFs' reading up to rounding (the same sums in another order).
pub struct ProbeReader<'a> {
    probes: &'a [Probe],
    rows: Option<Vec<Row>>,
}

/// One probe as rows over the modal coordinates.
enum Row {
    /// w, ẇ or ẅ at a point: the shape row over the modes, dotted with
    /// q, q̇ or q̈.
    Point(DVector<f64>),
    /// A section's moment and shear: each a row dotted with the damped
    /// displacement ũ plus a row dotted with the damped acceleration ã,
    /// plus the point loads' share (`section_load_share`).
    Section {
        x: f64,
        moment: [DVector<f64>; 2],
        shear: [DVector<f64>; 2],
    },
    /// Read from the state as `Probe::value` does (reactions).
    State,
}

/// Most modes read as rows: building a section's rows costs 2k readings
/// of 20 k each, what 2k steps of reading through the DOFs cost.
const MAX_ROW_MODES: usize = 256;
/// Most probes × modes read as rows (four rows each at most: 32 MB).
const MAX_ROW_ENTRIES: usize = 1_000_000;

impl<'a> ProbeReader<'a> {
    /// `probes` on `beam`: as rows when it is modal, with at most
    /// `MAX_ROW_MODES` modes and `MAX_ROW_ENTRIES` probes × modes (beyond,
    /// through the DOFs as on a mesh). Built once for all of a sweep's
    /// runs.
    pub fn new(probes: &'a [Probe], beam: &Beam) -> ProbeReader<'a> {
        let rows = beam
            .modal()
            .map(|basis| basis.modes())
            .filter(|&k| k <= MAX_ROW_MODES && probes.len() * k <= MAX_ROW_ENTRIES)
            .map(|k| {
                let units = unit_states(beam, k);
                probes
                    .iter()
                    .map(|p| row_of(p.read, beam, &units))
                    .collect()
            });
        ProbeReader { probes, rows }
    }

    /// The probes, in the order `read` gives their values.
    pub fn probes(&self) -> &'a [Probe] {
        self.probes
    }
}

/// For each modal coordinate j, the beam at rest without loads with
/// ũ = e_j, and with ã = e_j (at rest the damped state is the state).
fn unit_states(beam: &Beam, modes: usize) -> Vec<[BeamDynamics<'static>; 2]> {
    let zero = DVector::zeros(modes);
    (0..modes)
        .map(|j| {
            let unit = DVector::from_fn(modes, |i, _| if i == j { 1.0 } else { 0.0 });
            let state = |u: &DVector<f64>, a: &DVector<f64>| {
                BeamDynamics::with_acceleration(
                    beam,
                    (u.clone(), zero.clone(), a.clone()),
                    Vec::new(),
                )
            };
            [state(&unit, &zero), state(&zero, &unit)]
        })
        .collect()
}

/// The rows of one probe: its reading in each unit state (it is linear in
/// the state).
fn row_of(read: Read, beam: &Beam, units: &[[BeamDynamics; 2]]) -> Row {
    let row = |value: &dyn Fn(&BeamDynamics) -> f64, k: usize| {
        DVector::from_iterator(units.len(), units.iter().map(|s| value(&s[k])))
    };
    match read {
        Read::Deflection(x) | Read::Velocity(x) | Read::Acceleration(x) => {
            Row::Point(row(&|s| s.deflection_at(beam, x), 0))
        }
        Read::Moment(x) | Read::Shear(x) => {
            let forces: Vec<[SectionForces; 2]> = units
                .iter()
                .map(|s| s.each_ref().map(|s| s.section_forces(beam, x)))
                .collect();
            let rows = |k: usize, moment: bool| {
                let of = |f: &SectionForces| if moment { f.moment } else { f.shear };
                DVector::from_iterator(forces.len(), forces.iter().map(|f| of(&f[k])))
            };
            Row::Section {
                x,
                moment: [rows(0, true), rows(1, true)],
                shear: [rows(0, false), rows(1, false)],
            }
        }
        Read::Reaction(_) | Read::SupportMoment(_) => Row::State,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{scene_for, BridgeSpec};
    use crate::design::PointLoad;

    /// On a modal structure with one damping ratio in every mode, every
    /// probe's row reading equals its reading through the element's DOFs
    /// (`Probe::value`, the definition) in a moving state under point
    /// loads, one of them exactly on a section and one just left of it.
    #[test]
    fn rows_over_the_modes_read_what_the_dofs_read() {
        let spec = BridgeSpec::from_toml_str(crate::check::spec::EXAMPLE).unwrap();
        let scene = scene_for(&spec, 12000.0, 8.0e10, 0.02).unwrap();
        let beam = crate::study::sweep::structure_of(&scene).unwrap();
        let k = beam.modal().expect("modal").modes();
        let list = probes(&scene, &beam);
        let reader = ProbeReader::new(&list, &beam);
        assert!(reader.rows.is_some());
        // A state with every mode moving: q, q̇, q̈ of mixed signs and sizes.
        let field = |scale: f64, phase: f64| {
            DVector::from_fn(k, |j, _| {
                scale * libm::sin((j as f64 + phase) * 1.7) / (1.0 + j as f64)
            })
        };
        let loads = [(10.0, -190e3), (9.0, -190e3), (6.3, -170e3), (13.7, -170e3)]
            .map(|(x, f)| PointLoad::vertical(&beam, x, f))
            .to_vec();
        let state = BeamDynamics::with_acceleration(
            &beam,
            (field(1e-3, 0.3), field(2e-2, 1.1), field(0.5, 2.0)),
            loads,
        );
        let mut values = Vec::new();
        reader.read(&beam, &state, &mut values);
        for (probe, &value) in list.iter().zip(&values) {
            let expected = probe.value(&beam, &state);
            assert!(
                (value - expected).abs() <= 1e-10 * expected.abs(),
                "{}: {value} vs {expected}",
                probe.name
            );
        }
    }
}
