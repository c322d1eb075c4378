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

impl BeamDynamics {
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

    /// Take in the values of `probes` in `state`.
    pub fn record(&mut self, probes: &[Probe], beam: &Beam, state: &BeamDynamics) {
        // A section's moment and shear come from one evaluation.
        let mut section: Option<(f64, SectionForces)> = None;
        // And a sensor's three values from one shape.
        let mut sensor: Option<(f64, Shape)> = None;
        for (peak, probe) in self.peaks.iter_mut().zip(probes) {
            let value = match probe.read {
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
                    match probe.read {
                        Read::Moment(_) => forces.moment,
                        _ => forces.shear,
                    }
                }
                _ => probe.value(beam, state),
            };
            if value.abs() > peak.abs() {
                *peak = value;
            }
        }
    }
}
