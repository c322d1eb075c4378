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
use crate::simulation::Simulation;
use crate::structure::Structure;

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

/// The static envelope of `scene` (the summary's amplification reference)
/// on `simulation`'s beam, with the loads it took before its static start:
/// assembling the scene again would solve a modal beam's eigenproblem a
/// second time.
pub fn envelope_of_run(simulation: &Simulation, scene: &Scene) -> Result<StaticEnvelope, String> {
    if is_moving_force_scene(scene) {
        return static_envelope(scene);
    }
    envelope_of_loads(
        scene,
        &simulation.system().beam,
        simulation.envelope_loads(),
    )
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
    let influence = stiffness
        .as_ref()
        .and_then(|factor| Influence::new(beam, factor, &reads, loads.len()));
    let peaks = match influence {
        Some(influence) => influence_peaks(beam, &influence, &reads, loads, &shifts),
        None => solved_peaks(beam, stiffness.as_ref(), &reads, loads, &shifts)?,
    };
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

/// The loads at `shift` from their start that are on the beam.
fn placed<'a>(
    beam: &'a Beam,
    loads: &'a [(f64, f64)],
    shift: f64,
) -> impl Iterator<Item = PointLoad> + 'a {
    loads
        .iter()
        .map(move |&(x, normal)| (x + shift, normal))
        .filter(|&(x, _)| (0.0..=beam.length).contains(&x))
        .map(|(x, normal)| PointLoad::vertical(beam, x, -normal))
}

/// The largest |value| of each read over the positions `shifts`, the
/// structure's static response solved at each (K factored once).
fn solved_peaks(
    beam: &Beam,
    stiffness: Option<&BandLdlt>,
    reads: &[Probe],
    loads: &[(f64, f64)],
    shifts: &[f64],
) -> Result<Vec<f64>, String> {
    let mut peaks = vec![0.0f64; reads.len()];
    let at_rest = DVector::zeros(beam.coordinates());
    let at_rest = || BeamDynamics::at_rest(beam, at_rest.clone(), Vec::new());
    let mut responses: [BeamDynamics; 4] = std::array::from_fn(|_| at_rest());
    let rows = beam.modal().map(|_| ProbeReader::new(reads, beam));
    let mut values = Vec::with_capacity(reads.len());
    // Four positions at a time: their solves side by side.
    for group in shifts.chunks(responses.len()) {
        for (response, &shift) in responses.iter_mut().zip(group) {
            response.set_static_loads(beam, stiffness, placed(beam, loads, shift))?;
        }
        let group = &mut responses[..group.len()];
        solve_group(stiffness, group);
        for response in group.iter() {
            read_all((reads, rows.as_ref()), beam, response, &mut values);
            for (peak, value) in peaks.iter_mut().zip(&values) {
                *peak = peak.max(value.abs());
            }
        }
    }
    Ok(peaks)
}

/// Most entries of K⁻¹ the influence rows keep (16 MiB).
const MAX_INFLUENCE_ENTRIES: usize = 2_000_000;

/// K⁻¹'s rows at the DOFs the reads look at on a full mesh: with them a
/// position's displacements there are a sum over the loads' few DOFs
/// (Maxwell–Betti: the read DOFs' influence lines), one solve per read DOF
/// instead of one per position. Equal to the solve's up to rounding (the
/// same sum in another order).
struct Influence {
    /// The free DOFs the reads' values depend on, ascending.
    dofs: Vec<usize>,
    /// `rows[i * dofs.len() + j]` = (K⁻¹)ᵢ,dofs[j] (K symmetric: the column).
    rows: Vec<f64>,
}

impl Influence {
    /// The rows of `factor` (K's) at `reads`' DOFs on a full mesh, when a
    /// position's sum over `loads` loads (four DOFs each) costs less than a
    /// solve (about 16 multiply-adds a DOF) and the rows fit
    /// `MAX_INFLUENCE_ENTRIES`; `None` otherwise (solve each position).
    fn new(beam: &Beam, factor: &BandLdlt, reads: &[Probe], loads: usize) -> Option<Influence> {
        if !matches!(beam, Structure::Hermite(_)) {
            return None;
        }
        let mut dofs: Vec<usize> = reads
            .iter()
            .flat_map(|read| read.elements(beam))
            .flatten()
            .flat_map(|element| beam.element_dofs(element).iter().flatten().copied())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        let n = beam.coordinates();
        let cheaper = 4 * loads * dofs.len() <= 16 * n;
        if !cheaper || dofs.len() * n > MAX_INFLUENCE_ENTRIES {
            return None;
        }
        let width = dofs.len();
        let mut rows = vec![0.0; n * width];
        let mut column = vec![0.0; n];
        for (j, &dof) in dofs.iter().enumerate() {
            column.fill(0.0);
            column[dof] = 1.0;
            factor.solve_in_place(&mut column);
            for (row, value) in rows.chunks_exact_mut(width).zip(&column) {
                row[j] = *value;
            }
        }
        Some(Influence { dofs, rows })
    }

    /// `u` at the read DOFs under `loads` (their consistent load vector, as
    /// `add_loads`, times K⁻¹'s rows there); `at` is scratch of one entry a
    /// read DOF. The other entries of `u` are left as they are.
    fn displace(&self, beam: &Beam, loads: &[PointLoad], at: &mut [f64], u: &mut DVector<f64>) {
        let width = self.dofs.len();
        at.fill(0.0);
        for load in loads {
            let shape = beam.shape(load.element, load.x);
            for (k, dof) in shape.dofs.iter().enumerate() {
                let Some(i) = *dof else { continue };
                let scale = shape.n[k] * load.force + shape.dn[k] * load.couple;
                let row = &self.rows[i * width..(i + 1) * width];
                for (a, r) in at.iter_mut().zip(row) {
                    *a += scale * r;
                }
            }
        }
        for (&dof, &value) in self.dofs.iter().zip(at.iter()) {
            u[dof] = value;
        }
    }
}

/// `solved_peaks` through the influence rows: each position's reads from
/// the displacements at their DOFs (zero elsewhere: no read looks there).
fn influence_peaks(
    beam: &Beam,
    influence: &Influence,
    reads: &[Probe],
    loads: &[(f64, f64)],
    shifts: &[f64],
) -> Vec<f64> {
    let mut peaks = vec![0.0f64; reads.len()];
    let zero = DVector::zeros(beam.coordinates());
    let mut response = BeamDynamics::at_rest(beam, zero, Vec::new());
    let mut at = vec![0.0; influence.dofs.len()];
    let mut values = Vec::with_capacity(reads.len());
    let mut hints = vec![0; loads.len()];
    for &shift in shifts {
        let (on_beam, u) = response.static_parts_mut();
        place_near(beam, loads, shift, &mut hints, on_beam);
        influence.displace(beam, on_beam, &mut at, u);
        read_all((reads, None), beam, &response, &mut values);
        for (peak, value) in peaks.iter_mut().zip(&values) {
            *peak = peak.max(value.abs());
        }
    }
    peaks
}

/// `placed` into `on_beam`, each load's element walked from `hints` (its
/// element at the last position, updated): the positions are evenly
/// spaced, so a walk of an element or two where `placed` bisected the
/// beam's nodes for every load (len29). The same elements as `placed`'s
/// on one beam (`HermiteBeam::element_near`); on several, `placed`'s.
fn place_near(
    beam: &Beam,
    loads: &[(f64, f64)],
    shift: f64,
    hints: &mut [usize],
    on_beam: &mut Vec<PointLoad>,
) {
    on_beam.clear();
    if beam.segments().len() != 1 {
        on_beam.extend(placed(beam, loads, shift));
        return;
    }
    for (&(x, normal), hint) in loads.iter().zip(hints.iter_mut()) {
        let x = x + shift;
        if (0.0..=beam.length).contains(&x) {
            *hint = beam.element_near(x, *hint);
            on_beam.push(PointLoad {
                x,
                element: *hint,
                force: -normal,
                couple: 0.0,
            });
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    const SPAN: f64 = 24.0;
    const EI: f64 = 1e9;
    const P: f64 = 600e3;

    /// Moving forces over `beam` (a TOML `[beam]` body with its supports)
    /// with the reactions and `reads` (TOML sensors and sections).
    fn scene(beam: &str, reads: &str) -> Scene {
        Scene::from_toml_str(&format!(
            "name = \"influence\"\ngravity = 10.0\nreactions = true\n\
             [beam]\nmass_per_length = 1250.0\nbending_stiffness = {EI}\n\
             surface_offset = 0.0\n{beam}\n\
             [body]\nname = \"force\"\nkind = \"moving_force\"\nmass = 60000.0\n\
             initial_position = 0.0\ninitial_speed = 10.0\n\
             {reads}\n[solver]\nstep = 0.001\n"
        ))
        .expect("scene is valid")
    }

    /// (reads, loads, shifts, beam) of `scene` with `loads` as the envelope
    /// takes them.
    fn parts(scene: &Scene, loads: &[(f64, f64)]) -> (Vec<Probe>, Vec<f64>, Beam) {
        let beam = Beam::new(&scene.beam).unwrap();
        let reads: Vec<Probe> = probes(scene, &beam)
            .into_iter()
            .filter(Probe::is_static)
            .collect();
        let first = loads.iter().map(|l| l.0).fold(f64::INFINITY, f64::min);
        let last = loads.iter().map(|l| l.0).fold(f64::NEG_INFINITY, f64::max);
        let shifts = shifts(scene, &beam, loads, (first, last), reads.len());
        (reads, shifts, beam)
    }

    #[test]
    fn the_influence_rows_give_the_solved_peaks_up_to_rounding() {
        // Three uneven spans, a clamped end, a vertical and a rotational
        // spring, sections inside elements and on a support, four loads.
        let beam = "length = 70.0\nelements = 35\n[beam.supports]\nleft = \"clamped\"\n\
                    right = \"free\"\nintermediate = [20.0, 44.0]\n\
                    [[beam.supports.springs]]\nat = 70.0\nvertical = 2e8\nrotational = 5e9\n";
        let reads = "[[sensors]]\nname = \"a\"\nposition = 9.3\n\
                     [[sensors]]\nname = \"b\"\nposition = 60.0\n\
                     [[sections]]\nname = \"s\"\nposition = 31.7\n\
                     [[sections]]\nname = \"t\"\nposition = 44.0\n";
        let scene = scene(beam, reads);
        let loads = [(0.0, P), (-2.5, P), (-17.5, 0.8 * P), (-20.0, 0.8 * P)];
        let (reads, shifts, beam) = parts(&scene, &loads);
        let factor = beam.stiffness_factor().unwrap();
        let influence = Influence::new(&beam, &factor, &reads, loads.len()).expect("taken");
        let fast = influence_peaks(&beam, &influence, &reads, &loads, &shifts);
        let solved = solved_peaks(&beam, Some(&factor), &reads, &loads, &shifts).unwrap();
        assert_eq!(fast.len(), 12);
        for ((read, fast), solved) in reads.iter().zip(&fast).zip(&solved) {
            let error = (fast - solved).abs() / solved.abs();
            assert!(error < 1e-12, "{}: {fast} vs {solved}", read.name);
        }
    }

    #[test]
    fn loads_placed_from_the_last_positions_elements_are_those_placed_anew() {
        // Uneven elements (a node on each support), the envelope's own
        // positions: evenly spaced, then the exact ones that put a load on
        // a read, which jump back along the beam.
        let beam = "length = 70.0\nelements = 35\n[beam.supports]\n\
                    intermediate = [20.0, 44.0]\n";
        let reads = "[[sensors]]\nname = \"a\"\nposition = 9.3\n\
                     [[sections]]\nname = \"s\"\nposition = 44.0\n";
        let scene = scene(beam, reads);
        let loads = [(0.0, P), (-2.5, P), (-17.5, 0.8 * P), (-40.0, 0.8 * P)];
        let (_, shifts, beam) = parts(&scene, &loads);
        assert!(
            shifts.windows(2).any(|w| w[1] < w[0]),
            "positions jump back"
        );
        let mut hints = vec![0; loads.len()];
        let mut walked = Vec::new();
        for &shift in &shifts {
            place_near(&beam, &loads, shift, &mut hints, &mut walked);
            let anew: Vec<PointLoad> = placed(&beam, &loads, shift).collect();
            assert_eq!(walked, anew, "shift {shift}");
        }
    }

    #[test]
    fn a_two_span_beams_support_moment_follows_its_influence_line() {
        // Two equal spans L, a load P at a in the first: the middle support
        // carries the moment −P a (L² − a²) / 4L² (three-moment equation)
        // and the reaction P (a/2L)(3 − a²/L²); the second span mirrors it.
        let beam = format!(
            "length = {}\nelements = 16\n[beam.supports]\nintermediate = [{SPAN}]\n",
            2.0 * SPAN
        );
        let reads = format!("[[sections]]\nname = \"middle\"\nposition = {SPAN}\n");
        let scene = scene(&beam, &reads);
        let envelope = static_envelope(&scene).unwrap();
        let (_, shifts, _) = parts(&scene, &[(0.0, P)]);
        let on_span = |x: f64| if x <= SPAN { x } else { 2.0 * SPAN - x };
        let moment = |a: f64| P * a * (SPAN * SPAN - a * a) / (4.0 * SPAN * SPAN);
        let reaction = |a: f64| P * a / (2.0 * SPAN) * (3.0 - a * a / (SPAN * SPAN));
        let on_beam = shifts.iter().filter(|x| (0.0..=2.0 * SPAN).contains(*x));
        let (mut peak_moment, mut peak_reaction) = (0.0f64, 0.0f64);
        for &x in on_beam {
            peak_moment = peak_moment.max(moment(on_span(x)));
            peak_reaction = peak_reaction.max(reaction(on_span(x)));
        }
        let close = |found: f64, expected: f64| (found - expected).abs() <= 1e-9 * expected;
        let found = envelope.peaks["section.middle.moment"];
        assert!(close(found, peak_moment), "{found} vs {peak_moment}");
        // Near P L / (6√3), the continuous maximum at a = L/√3.
        assert!((peak_moment / (P * SPAN / (6.0 * 3f64.sqrt())) - 1.0).abs() < 1e-5);
        let found = envelope.peaks["support.intermediate1.reaction"];
        assert!(close(found, peak_reaction), "{found} vs {peak_reaction}");
    }
}
