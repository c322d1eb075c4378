//! The static envelope of a scene's loads crossing the beam quasi-statically,
//! the reference of the dynamic amplification factor.
//!
//! The loads are the contacts' static shares of their vehicles' weight and
//! vertical applied force (the contact forces a run starts from), at the
//! spacing the contacts start with; in a scene of moving forces, the forces
//! themselves. The group is moved along the beam from
//! before the first load enters to after the last has left, and at each
//! position the static response of the actual structure (its supports,
//! spans and clamps) is read at every sensor, section and support.

use std::collections::BTreeMap;

use nalgebra::DVector;

use super::probes::{probes, Probe, ProbeReader};
use super::{BeamDynamics, PointLoad};
use crate::assemble::{assemble, static_shares};
use crate::band::BandLdlt;
use crate::beam::Beam;
use crate::moving_load::{is_moving_force_scene, scene_axles};
use crate::scene::Scene;

/// Fewest load positions of a crossing.
const MIN_POSITIONS: usize = 2_000;
/// Most load positions of a crossing.
const MAX_POSITIONS: usize = 50_000;
/// Bound on evenly spaced positions × free DOFs, the cost of the static
/// solves (each O(DOFs) with K factored once): a fraction of a second.
const MAX_WORK: usize = 50_000_000;

/// The largest static magnitude of each design quantity over the crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticEnvelope {
    /// Output name (`sensor.<name>.deflection`, `section.<name>.moment`,
    /// `section.<name>.shear`, `support.<name>.reaction`,
    /// `support.<name>.moment`) → max over load positions of |value|.
    pub peaks: BTreeMap<String, f64>,
    /// Load positions evaluated.
    pub positions: usize,
}

impl StaticEnvelope {
    /// The dynamic amplification of output `name` whose largest magnitude
    /// over a run was `dynamic_peak`: dynamic_peak / static peak; `None`
    /// where the static response is zero or the output is not enveloped.
    pub fn amplification(&self, name: &str, dynamic_peak: f64) -> Option<f64> {
        let reference = *self.peaks.get(name)?;
        (reference > 0.0 && dynamic_peak.is_finite()).then(|| dynamic_peak.abs() / reference)
    }
}

/// The static envelope of `scene`'s loads crossing its beam (see the
/// module): its contacts' static loads, or its moving forces.
pub fn static_envelope(scene: &Scene) -> Result<StaticEnvelope, String> {
    let (beam, loads) = static_loads(scene)?;
    envelope_of_loads(scene, &beam, &loads)
}

/// The beam of `scene` and its loads: (abscissa at the start, downward
/// force) of each contact's static share, or of each moving force.
fn static_loads(scene: &Scene) -> Result<(Beam, Vec<(f64, f64)>), String> {
    if is_moving_force_scene(scene) {
        let beam = Beam::new(&scene.beam)?;
        let loads = scene_axles(scene)
            .iter()
            .map(|a| (a.position, -a.force))
            .collect();
        return Ok((beam, loads));
    }
    let assembly = assemble(scene)?;
    let loads = static_shares(&assembly);
    Ok((assembly.system.beam, loads))
}

/// The static envelope of `loads` ((abscissa at the start, downward force))
/// crossing `beam` together, read at `scene`'s sensors, sections and
/// supports. Bounded: at most `MAX_POSITIONS` evenly spaced positions
/// with positions × DOFs ≤ `MAX_WORK`, and `MAX_POSITIONS` more that put a
/// load on a sensor or section.
pub fn envelope_of_loads(
    scene: &Scene,
    beam: &Beam,
    loads: &[(f64, f64)],
) -> Result<StaticEnvelope, String> {
    let reads: Vec<Probe> = probes(scene, beam)
        .into_iter()
        .filter(Probe::is_static)
        .collect();
    let mut peaks = vec![0.0f64; reads.len()];
    let first = loads.iter().map(|l| l.0).fold(f64::INFINITY, f64::min);
    let last = loads.iter().map(|l| l.0).fold(f64::NEG_INFINITY, f64::max);
    if reads.is_empty() || !first.is_finite() {
        return Ok(StaticEnvelope {
            peaks: BTreeMap::new(),
            positions: 0,
        });
    }
    let stiffness = stiffness_factor(scene, beam)?;
    let shifts = shifts(scene, beam, loads, (first, last), reads.len());
    let at_rest = DVector::zeros(beam.coordinates());
    let at_rest = || BeamDynamics::at_rest(beam, at_rest.clone(), Vec::new());
    let mut responses: [BeamDynamics; 4] = std::array::from_fn(|_| at_rest());
    let rows = beam.modal().map(|_| ProbeReader::new(&reads, beam));
    let mut values = Vec::with_capacity(reads.len());
    // Four positions at a time: their solves side by side.
    for group in shifts.chunks(responses.len()) {
        for (response, &shift) in responses.iter_mut().zip(group) {
            let on_beam = loads
                .iter()
                .map(|&(x, normal)| (x + shift, normal))
                .filter(|&(x, _)| (0.0..=beam.length).contains(&x))
                .map(|(x, normal)| PointLoad::vertical(beam, x, -normal));
            response.set_static_loads(beam, stiffness.as_ref(), on_beam)?;
        }
        let group = &mut responses[..group.len()];
        solve_group(stiffness.as_ref(), group);
        for response in group.iter() {
            read_all((&reads, rows.as_ref()), beam, response, &mut values);
            for (peak, value) in peaks.iter_mut().zip(&values) {
                *peak = peak.max(value.abs());
            }
        }
    }
    Ok(StaticEnvelope {
        peaks: reads.into_iter().map(|r| r.name).zip(peaks).collect(),
        positions: shifts.len(),
    })
}

/// K's factor for the static solves; none on a modal structure, whose
/// static response is its modes' (Ω⁻² Φᵀ r).
fn stiffness_factor(scene: &Scene, beam: &Beam) -> Result<Option<BandLdlt>, String> {
    if beam.modal().is_some() {
        return Ok(None);
    }
    beam.stiffness_factor().map(Some).ok_or_else(|| {
        // The scene rules already refuse supports that leave the beam
        // free: what is left is rounding on a fine mesh.
        let n = scene.beam.elements as f64;
        format!(
            "beam.elements = {}: the stiffness matrix cannot be factorised in double \
             precision (its condition number grows as elements⁴, about {:.0e} here), so \
             the loads have no static response; use fewer elements",
            scene.beam.elements,
            n.powi(4)
        )
    })
}

/// Solves the load vectors `set_static_loads` left in `group`'s
/// displacements, four side by side (a modal structure's are solved).
fn solve_group(stiffness: Option<&BandLdlt>, group: &mut [BeamDynamics]) {
    let Some(factor) = stiffness else {
        return;
    };
    match group {
        [a, b, c, d] => factor
            .solve_each([a, b, c, d].map(|response| response.displacement_mut().as_mut_slice())),
        _ => {
            for response in group.iter_mut() {
                factor.solve_mut(response.displacement_mut());
            }
        }
    }
}

/// Every read's value of `response` into `values`: on a modal structure
/// as rows over its modes (one dot product each), on the mesh one by one.
fn read_all(
    (reads, rows): (&[Probe], Option<&ProbeReader>),
    beam: &Beam,
    response: &BeamDynamics,
    values: &mut Vec<f64>,
) {
    match rows {
        Some(reader) => reader.read(beam, response, values),
        None => {
            values.clear();
            values.extend(reads.iter().map(|r| r.value(beam, response)));
        }
    }
}

/// Shifts of the load group: evenly spaced from the last load at x = 0 to
/// the first at x = L, plus those that put a load exactly on a sensor or
/// section (where a moment or shear peaks with a kink, between samples).
fn shifts(
    scene: &Scene,
    beam: &Beam,
    loads: &[(f64, f64)],
    (first, last): (f64, f64),
    reads: usize,
) -> Vec<f64> {
    let (from, to) = (-last, beam.length - first);
    // And 16 per element along the whole travel: a train is longer than
    // the beam, and its group's peak lies between axle positions.
    let per_element = 16.0 * (to - from) / beam.min_element_length();
    let even = (4 * beam.elements())
        .max(per_element.min(MAX_POSITIONS as f64) as usize)
        .clamp(MIN_POSITIONS, MAX_POSITIONS)
        .min(MAX_WORK / beam.free_dofs().max(1))
        .max(2);
    let mut shifts: Vec<f64> = (0..even)
        .map(|k| from + (to - from) * k as f64 / (even - 1) as f64)
        .collect();
    let points = scene.sensors.iter().map(|s| s.position);
    let points = points.chain(scene.sections.iter().map(|s| s.position));
    let exact = points.flat_map(|p| loads.iter().map(move |l| p - l.0));
    // Each position costs a static solve and a reading of every output:
    // with 10,000 sensors, sections and supports the exact positions
    // (outputs × axles) made this grow as outputs² (minutes). Beyond the
    // work bound only the evenly spaced positions are kept for the rest.
    let per_position = beam.free_dofs() + reads;
    let exact_cap = (MAX_WORK / per_position.max(1)).saturating_sub(even);
    shifts.extend(exact.take(MAX_POSITIONS.min(exact_cap)));
    shifts
}
