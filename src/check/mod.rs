//! A railway bridge's dynamic check (EN 1991-2 §6.4, EN 1990 Annex A2)
//! from its short description to a report: every case the code asks for
//! run as moving forces (`study::sweep`), every rule applied with its
//! clause, the results gathered for `report`.

pub mod lm71;
pub mod report;
pub mod rules;
pub mod spec;

use serde::Serialize;

use crate::moving_load::{Axle, Crossing, RealTrain, HSLM_TRAINS};
use crate::scene::{DampingSpec, Scene, SectionSpec, SensorSpec, StructureKind};
use crate::signal::{cut_off, low_pass_zero_phase};
use crate::study::sweep::{sweep, EnvelopeRow, Loads, SpeedUnit, DEFAULT_MAX_SWEEP_STEPS};
use rules::*;
pub use spec::{BridgeSpec, TrackKind};

/// Points along each span the envelopes are read at (fractions of it).
pub const STATIONS: [f64; 5] = [0.1, 0.3, 0.5, 0.7, 0.9];

/// A point of the bridge its outputs are read at: a sensor and a section.
#[derive(Debug, Clone, Serialize)]
pub struct Station {
    pub name: String,
    /// Abscissa (m) from the left end.
    pub position: f64,
    /// Over an intermediate support (hogging moment, no deflection).
    pub support: bool,
}

/// The stations of a bridge: `STATIONS` of each span (`x10` … `x90` on one
/// span; `s1x10` … on a continuous beam) and each intermediate support
/// (`support1` …), left to right; and the index of the midspan the
/// midspan checks read (of the longest span, the first if several).
pub fn stations(spec: &BridgeSpec) -> (Vec<Station>, usize) {
    let spans = spec.span_lengths();
    let longest = spec.longest_span();
    let (mut out, mut main, mut start) = (Vec::new(), 0, 0.0);
    for (i, &l) in spans.iter().enumerate() {
        for f in STATIONS {
            let pct = (f * 100.0).round() as i64;
            let name = if spec.is_continuous() {
                format!("s{}x{pct:02}", i + 1)
            } else {
                format!("x{pct:02}")
            };
            if pct == 50 && l == longest && main == 0 {
                main = out.len();
            }
            let support = false;
            out.push(Station {
                name,
                position: start + f * l,
                support,
            });
        }
        start += l;
        if i + 1 < spans.len() {
            let name = format!("support{}", i + 1);
            out.push(Station {
                name,
                position: start,
                support: true,
            });
        }
    }
    (out, main)
}

/// One mass case of §6.4.6.3.2 and what it gives.
#[derive(Debug, Clone, Serialize)]
pub struct MassCase {
    /// `lower`, `upper` or `nominal`.
    pub name: String,
    pub mass_per_length: f64,
    /// f1, f3 (Hz) of this mass with the bridge's EI; the filter cut-off.
    pub f1: f64,
    pub f3: f64,
    pub cut_off: f64,
}

/// One run: a train at a speed on one mass case.
#[derive(Debug, Clone, Serialize)]
pub struct Run {
    pub mass_case: String,
    pub train: String,
    pub speed_kmh: f64,
    pub acceleration: f64,
    pub acceleration_filtered: f64,
    pub daf_deflection: f64,
    pub daf_moment: f64,
    /// Peak |deflection| (m) and |moment| (N m) at each station.
    pub deflections: Vec<f64>,
    pub moments: Vec<f64>,
    /// The static midspan moment of the same train (N m).
    pub static_moment: f64,
    /// The static |moment| (N m) of the same train at each station.
    pub static_moments: Vec<f64>,
}

/// One row of the PASS/FAIL table.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub clause: String,
    pub check: String,
    pub value: String,
    pub limit: String,
    /// `PASS`, `FAIL` or `INFO`.
    pub status: String,
}

/// Everything the report shows.
#[derive(Debug, Clone, Serialize)]
pub struct CheckResult {
    pub spec: BridgeSpec,
    /// Where the outputs are read, and which is the midspan checked.
    pub stations: Vec<Station>,
    pub main_station: usize,
    /// EN 1991-2 Table 6.2: LΦ (m) of Φ and φ″.
    pub determinant_length: f64,
    /// LM71 (α = 1) at each station, solved on the mesh (continuous
    /// beams; a simply supported span uses the closed form).
    pub lm71: Vec<lm71::Lm71Effects>,
    pub bending_stiffness: f64,
    pub damping_percent: f64,
    pub damping_table: f64,
    pub damping_additional: f64,
    pub design_speed: f64,
    pub acceleration_limit: f64,
    pub mass_cases: Vec<MassCase>,
    pub runs: Vec<Run>,
    pub verdicts: Vec<Verdict>,
    pub assumptions: Vec<String>,
    /// Time (s), raw and filtered acceleration (m/s²) at midspan for the
    /// worst run.
    pub worst: Option<Run>,
    pub worst_history: Vec<(f64, f64, f64)>,
    /// Resonant speeds v = f1 D / i per train (km/h), first mass case.
    pub resonances: Vec<(String, f64)>,
}

/// A train of the check: its name, each axle's distance behind the
/// leading one (m) and force (N, up positive), and the regular spacing
/// (m) that sets its resonant speeds.
type Train = (String, Vec<(f64, f64)>, f64);

/// The trains of the check: HSLM-A1 … A10 from 7 m, HSLM-B below
/// (EN 1991-2 Annex E, E.1(2)), and the shipped real trains unless turned
/// off, as (name, axle offsets and forces, the regular spacing that sets
/// its resonances).
fn trains(spec: &BridgeSpec) -> Vec<Train> {
    let mut out: Vec<Train> = match spec.settings.hslm_b {
        Some(b) if !spec.is_continuous() && spec.span < 7.0 => {
            let axles = (0..b.forces)
                .map(|i| (i as f64 * b.spacing, -170e3))
                .collect();
            vec![("HSLM-B".into(), axles, b.spacing)]
        }
        _ => HSLM_TRAINS
            .iter()
            .map(|t| (t.name.to_string(), t.axles(), t.coach_length))
            .collect(),
    };
    if spec.settings.real_trains {
        out.extend(
            RealTrain::shipped()
                .into_iter()
                .map(|t| (t.name.clone(), t.forces(), t.regular_spacing)),
        );
    }
    out
}

/// The moving-force scene of one mass case: stations as sensors and
/// sections; the damping ratio `zeta` in every mode (EN 1991-2 §6.4.6.3.1
/// gives one ζ for the structure), on the modal structure keeping every
/// mode of the mesh (so the runs are the mesh's own, in modal
/// coordinates).
pub fn scene_for(spec: &BridgeSpec, mass: f64, ei: f64, zeta: f64) -> Result<Scene, String> {
    let s = &spec.settings;
    let text = format!(
        "name = \"{name}\"\ngravity = 9.81\n[beam]\nlength = {l:?}\nmass_per_length = {mass:?}\n\
         bending_stiffness = {ei:?}\nsurface_offset = 0.0\nelements = {n}\n\
         supports = {{ intermediate = {supports:?} }}\n\
         [body]\nname = \"train\"\n\
         kind = \"moving_force\"\nmass = 1.0\ninitial_position = 0.0\ninitial_speed = 50.0\n\
         [solver]\nstep = {dt:?}\n",
        name = "check",
        l = spec.length(),
        n = s.elements * spec.span_lengths().len(),
        supports = spec.intermediate_supports(),
        dt = s.step,
    );
    let mut scene = Scene::from_toml_str(&text).map_err(|e| e.to_string())?;
    for station in stations(spec).0 {
        let (name, position) = (station.name, station.position);
        if !station.support {
            scene.sensors.push(SensorSpec {
                name: name.clone(),
                position,
            });
        }
        scene.sections.push(SectionSpec { name, position });
    }
    scene.validate().map_err(|e| e.to_string())?;
    // Set after the scene rules, which refuse a modal structure under
    // moving forces because `guideway run` steps those on the full mesh;
    // the sweep steps the structure `structure_of` reduces.
    scene.beam.damping = Some(DampingSpec::Modal { ratio: zeta });
    scene.solver.structure = StructureKind::Modal;
    // every mode of the mesh is kept
    scene.solver.modes = Some(crate::beam::Beam::new(&scene.beam)?.free_dofs());
    Ok(scene)
}

/// f1 and f3 (Hz): of a simply supported span n² f1 (closed form); of a
/// continuous beam its mesh's modes.
fn frequencies(spec: &BridgeSpec, m: f64, ei: f64) -> Result<(f64, f64), String> {
    if !spec.is_continuous() {
        let f1 = first_frequency(spec.span, m, ei);
        return Ok((f1, 9.0 * f1));
    }
    let scene = scene_for(spec, m, ei, 0.0)?;
    let omega = crate::beam::Beam::new(&scene.beam)?.frequencies(3)?;
    let hz = |w: f64| w / std::f64::consts::TAU;
    Ok((hz(omega[0]), hz(omega[2])))
}

/// EI (N m²): given, or from f1 at the nominal mass (closed form on one
/// span; on a continuous beam scaled from its mesh's f1 at a reference
/// EI, f ∝ √EI).
fn bending_stiffness(spec: &BridgeSpec) -> Result<f64, String> {
    let (l, m) = (spec.span, spec.mass_per_length);
    match (spec.first_frequency, spec.bending_stiffness) {
        (Some(f1), _) if !spec.is_continuous() => Ok(stiffness_from_frequency(l, m, f1)),
        (Some(f1), _) => {
            let reference = 1e10;
            let (f, _) = frequencies(spec, m, reference)?;
            Ok(reference * (f1 / f).powi(2))
        }
        (None, Some(ei)) => Ok(ei),
        (None, None) => Err("give first_frequency or bending_stiffness".into()),
    }
}

/// Run the whole check on `threads` threads.
pub fn run_check(spec: &BridgeSpec, threads: usize) -> Result<CheckResult, String> {
    spec.validate()?;
    let l = spec.longest_span();
    let ei = bending_stiffness(spec)?;
    let table = damping_lower_limit(spec.bridge_type, l);
    let extra = additional_damping(l);
    let zeta = (table + extra) / 100.0;
    let design_speed = maximum_design_speed(spec.line_speed);
    let mut cases = mass_cases(spec, ei)?;
    let (station_list, main_station) = stations(spec);
    let trains = trains(spec);
    let at = Stations {
        list: &station_list,
        main: main_station,
    };
    let (runs, resonances) = sweep_cases(spec, (ei, zeta), &mut cases, &trains, &at, threads)?;
    let acceleration_limit = match spec.track {
        TrackKind::Ballasted => spec.settings.acceleration_limit_ballasted,
        TrackKind::DirectFastened => spec.settings.acceleration_limit_direct_fastened,
    };
    let lm71 = lm71_rows(spec, ei, &station_list)?;
    let mut result = CheckResult {
        determinant_length: determinant_length(&spec.span_lengths()),
        lm71,
        stations: station_list,
        main_station,
        spec: spec.clone(),
        bending_stiffness: ei,
        damping_percent: table + extra,
        damping_table: table,
        damping_additional: extra,
        design_speed,
        acceleration_limit,
        mass_cases: cases,
        runs,
        verdicts: Vec::new(),
        assumptions: Vec::new(),
        worst: None,
        worst_history: Vec::new(),
        resonances,
    };
    result.verdicts = verdicts(&result);
    result.assumptions = assumptions(&result);
    worst_case(&mut result, &trains, zeta)?;
    Ok(result)
}

/// A train's name and one of its resonant speeds (km/h).
type Resonance = (String, f64);

/// The stations of a check and the one whose results lead.
struct Stations<'a> {
    list: &'a [Station],
    main: usize,
}

/// Every train at every speed of its series on every mass case (the
/// resonances of the first case listed), each case's cut-off set.
fn sweep_cases(
    spec: &BridgeSpec,
    (ei, zeta): (f64, f64),
    cases: &mut [MassCase],
    trains: &[Train],
    at: &Stations,
    threads: usize,
) -> Result<(Vec<Run>, Vec<Resonance>), String> {
    let design_speed = maximum_design_speed(spec.line_speed);
    let mut runs = Vec::new();
    let mut resonances = Vec::new();
    for (index, case) in cases.iter_mut().enumerate() {
        let scene = scene_for(spec, case.mass_per_length, ei, zeta)?;
        for (name, axles, spacing) in trains {
            let critical = resonant_speeds(case.f1, *spacing, 3);
            if index == 0 {
                resonances.extend(critical.iter().map(|&v| (name.clone(), v)));
            }
            let s = &spec.settings;
            let speeds = speed_series(
                design_speed,
                s.speed_step,
                s.fine_speed_step,
                s.resonance_band,
                &critical,
            );
            let loads = Loads::Axles(vec![(name.clone(), axles.clone())]);
            let unit = SpeedUnit::KilometresPerHour;
            let rows = sweep(
                &scene,
                &loads,
                (&speeds, unit),
                threads,
                DEFAULT_MAX_SWEEP_STEPS,
            )?;
            runs.extend(rows.iter().map(|r| run_of(&case.name, r, at.list, at.main)));
        }
        case.cut_off = cut_off(case.f1, case.f3);
    }
    Ok((runs, resonances))
}

/// LM71's static envelope at the stations, on continuous decks only (a
/// single span's is the closed form, `lm71::lm71_midspan`).
fn lm71_rows(
    spec: &BridgeSpec,
    ei: f64,
    stations: &[Station],
) -> Result<Vec<lm71::Lm71Effects>, String> {
    if !spec.is_continuous() {
        return Ok(Vec::new());
    }
    let scene = scene_for(spec, spec.mass_per_length, ei, 0.0)?;
    let beam = crate::beam::Beam::new(&scene.beam)?;
    let at: Vec<f64> = stations.iter().map(|s| s.position).collect();
    lm71::lm71_envelope(&beam, &at, 1.0)
}

/// §6.4.6.3.2: the lower and upper bounds of the mass (one nominal case
/// when neither is given or both equal it).
pub fn mass_cases(spec: &BridgeSpec, ei: f64) -> Result<Vec<MassCase>, String> {
    let lower = spec.mass_lower.unwrap_or(spec.mass_per_length);
    let upper = spec.mass_upper.unwrap_or(spec.mass_per_length);
    let named: Vec<(&str, f64)> = if lower == upper {
        vec![("nominal", lower)]
    } else {
        vec![("lower", lower), ("upper", upper)]
    };
    named
        .into_iter()
        .map(|(name, m)| {
            let (f1, f3) = frequencies(spec, m, ei)?;
            Ok(MassCase {
                name: name.into(),
                mass_per_length: m,
                f1,
                f3,
                cut_off: cut_off(f1, f3),
            })
        })
        .collect()
}

/// A sweep row as one run of the check.
fn run_of(case: &str, row: &EnvelopeRow, stations: &[Station], main: usize) -> Run {
    let design = |name: String| row.design.iter().find(|d| d.name == name);
    let peak = |name: String| design(name).map_or(0.0, |d| d.peak.abs());
    let static_of = |name: String| {
        design(name).map_or(0.0, |d| match d.daf {
            Some(daf) if daf > 0.0 => d.peak.abs() / daf,
            _ => 0.0,
        })
    };
    let midspan_moment = design(format!("section.{}.moment", stations[main].name));
    let daf_moment = midspan_moment.and_then(|d| d.daf).unwrap_or(0.0);
    let static_moment = midspan_moment.map_or(0.0, |d| {
        if daf_moment > 0.0 {
            d.peak.abs() / daf_moment
        } else {
            0.0
        }
    });
    Run {
        mass_case: case.into(),
        train: row.train.clone(),
        speed_kmh: row.speed,
        acceleration: row.peak_acceleration,
        acceleration_filtered: row.peak_acceleration_filtered,
        daf_deflection: row.daf,
        daf_moment,
        deflections: stations
            .iter()
            .map(|s| peak(format!("sensor.{}.deflection", s.name)))
            .collect(),
        moments: stations
            .iter()
            .map(|s| peak(format!("section.{}.moment", s.name)))
            .collect(),
        static_moment,
        static_moments: stations
            .iter()
            .map(|s| static_of(format!("section.{}.moment", s.name)))
            .collect(),
    }
}

fn verdict(clause: &str, check: &str, value: String, limit: String, status: &str) -> Verdict {
    Verdict {
        clause: clause.into(),
        check: check.into(),
        value,
        limit,
        status: status.into(),
    }
}

fn pass(ok: bool) -> &'static str {
    if ok {
        "PASS"
    } else {
        "FAIL"
    }
}

/// The PASS/FAIL table.
fn verdicts(r: &CheckResult) -> Vec<Verdict> {
    let spec = &r.spec;
    let l = spec.longest_span();
    let mut out = vec![analysis_verdict(r)];
    out.push(verdict(
        "EN 1991-2 Table 6.6, §6.4.6.4 eq. (6.13)",
        "damping used ζ = ζ_table + Δζ",
        format!(
            "{:.3} % = {:.3} % + {:.3} %",
            r.damping_percent, r.damping_table, r.damping_additional
        ),
        format!(
            "{} span {l} m{}",
            spec.bridge_type.label(),
            if spec.is_continuous() {
                " (the longest)"
            } else {
                ""
            }
        ),
        "INFO",
    ));
    // §6.4.6.3.2(3): the acceleration from the lower bound of the mass.
    let lower = &r.mass_cases[0];
    let governing = r
        .runs
        .iter()
        .filter(|run| run.mass_case == lower.name)
        .max_by(|a, b| a.acceleration_filtered.total_cmp(&b.acceleration_filtered));
    if let Some(g) = governing {
        out.push(verdict(
            "EN 1990 A2.4.4.2.1(4)P; EN 1991-2 §6.4.6.5(4)",
            "peak deck acceleration (low-passed at max(30 Hz, 1.5 f1, f3))",
            format!(
                "{:.3} m/s² ({} at {:.1} km/h, {} mass; raw {:.3} m/s², cut-off {:.1} Hz)",
                g.acceleration_filtered,
                g.train,
                g.speed_kmh,
                g.mass_case,
                g.acceleration,
                lower.cut_off
            ),
            format!(
                "≤ {} m/s² ({})",
                r.acceleration_limit,
                track_label(spec.track)
            ),
            pass(g.acceleration_filtered <= r.acceleration_limit),
        ));
    }
    out.extend(load_effect_verdicts(r));
    out
}

/// EN 1991-2 §6.4.4: whether a dynamic analysis is required (a
/// continuous beam always: Figure 6.10 is for simply supported spans).
fn analysis_verdict(r: &CheckResult) -> Verdict {
    let spec = &r.spec;
    let l = spec.longest_span();
    let (required, why) = if spec.is_continuous() && spec.line_speed <= 200.0 {
        let why = "a continuous beam: Figure 6.10 is for simply supported spans; the dynamic \
                   analysis is run";
        (true, why.to_string())
    } else {
        let nominal_f1 = first_frequency(l, spec.mass_per_length, r.bending_stiffness);
        dynamic_analysis_required(spec.line_speed, l, nominal_f1)
    };
    let value = if required { "yes" } else { "not by §6.4.4" };
    verdict(
        "EN 1991-2 §6.4.4, Fig. 6.9/6.10",
        "dynamic analysis required",
        value.into(),
        why,
        "INFO",
    )
}

fn track_label(track: TrackKind) -> &'static str {
    match track {
        TrackKind::Ballasted => "ballasted track",
        TrackKind::DirectFastened => "direct fastened track",
    }
}

/// §6.4.6.5(3) (dynamic against LM71 × Φ) and A2.4.4.2.3(3) (L/600).
fn load_effect_verdicts(r: &CheckResult) -> Vec<Verdict> {
    let spec = &r.spec;
    let (l, l_phi) = (spec.longest_span(), r.determinant_length);
    let careful = spec.settings.carefully_maintained;
    let alpha = spec.settings.classification_factor;
    let n0 = r
        .mass_cases
        .iter()
        .map(|c| c.f1)
        .fold(f64::INFINITY, f64::min);
    let phi_irr = phi_irregularity(l_phi, n0, spec.line_speed / 3.6);
    let phi = dynamic_factor(l_phi, careful);
    let (m71, w71) = main_lm71(r, alpha);
    let mut out = vec![
        midspan_moment_verdict(r, (phi, phi_irr), m71),
        verdict(
            "EN 1990 A2.4.4.2.3(3)",
            "midspan deflection under Φ × α × LM71",
            format!("{:.2} mm", phi * w71 * 1e3),
            format!("≤ L/600 = {:.2} mm", deflection_limit(l) * 1e3),
            pass(phi * w71 <= deflection_limit(l)),
        ),
        comfort_verdict(r, phi),
    ];
    out.extend(hogging_verdict(r, (phi, phi_irr), alpha));
    out
}

/// §6.4.6.5(3) eq. (6.15): the largest (1 + φ′dyn + φ″/2) × the static
/// midspan moment over the runs against Φ × α × LM71's `m71`.
fn midspan_moment_verdict(r: &CheckResult, (phi, phi_irr): (f64, f64), m71: f64) -> Verdict {
    let careful = r.spec.settings.carefully_maintained;
    let dynamic = r
        .runs
        .iter()
        .map(|run| {
            enhanced_dynamic_effect(
                run.static_moment,
                (run.daf_moment - 1.0).max(0.0),
                phi_irr,
                careful,
            )
        })
        .fold(0.0, f64::max);
    let phi_dyn = r
        .runs
        .iter()
        .map(|run| run.daf_moment - 1.0)
        .fold(0.0, f64::max);
    let factor = if careful {
        "Φ2, φ″/2"
    } else {
        "Φ3, φ″"
    };
    let governs = if dynamic > phi * m71 {
        "dynamic (HSLM) governs: design for it"
    } else {
        "LM71 × Φ governs"
    };
    verdict(
        "EN 1991-2 §6.4.6.5(3) eq. (6.15), Annex C, §6.4.5.2",
        "midspan moment: (1 + φ′dyn + φ″/2) × HSLM against Φ × α × LM71",
        format!(
            "{:.0} kN m (φ′dyn = {phi_dyn:.3}, φ″ = {phi_irr:.4})",
            dynamic / 1e3
        ),
        format!(
            "Φ α LM71 = {:.3} × {:.0} kN m = {:.0} kN m ({factor}); {governs}",
            phi,
            m71 / 1e3,
            phi * m71 / 1e3
        ),
        "INFO",
    )
}

/// LM71 × `alpha` at the checked midspan: moment (N m) and deflection
/// (m); closed form on one span, the mesh's envelope on a continuous beam.
fn main_lm71(r: &CheckResult, alpha: f64) -> (f64, f64) {
    match r.lm71.get(r.main_station) {
        Some(e) => (alpha * e.sagging, alpha * e.deflection),
        None => lm71::lm71_midspan(r.spec.span, r.bending_stiffness, alpha),
    }
}

/// A continuous beam's hogging moment over its intermediate supports:
/// the largest (1 + φ′dyn + φ″/2) × the static effect of HSLM or a real
/// train (eq. (6.15)) against Φ × α × LM71's hogging (§6.3.2, the
/// distributed load on the unfavourable parts), at the support where
/// LM71's is largest.
fn hogging_verdict(r: &CheckResult, (phi, phi_irr): (f64, f64), alpha: f64) -> Option<Verdict> {
    let careful = r.spec.settings.carefully_maintained;
    let (i, station) = r
        .stations
        .iter()
        .enumerate()
        .filter(|(_, s)| s.support)
        .max_by(|a, b| {
            r.lm71[a.0]
                .hogging
                .abs()
                .total_cmp(&r.lm71[b.0].hogging.abs())
        })?;
    let m71 = alpha * r.lm71[i].hogging.abs();
    let dynamic = r
        .runs
        .iter()
        .map(|run| {
            let stat = run.static_moments[i];
            let phi_dyn = if stat > 0.0 {
                run.moments[i] / stat - 1.0
            } else {
                0.0
            };
            enhanced_dynamic_effect(stat, phi_dyn.max(0.0), phi_irr, careful)
        })
        .fold(0.0, f64::max);
    let governs = if dynamic > phi * m71 {
        "dynamic governs: design for it"
    } else {
        "LM71 × Φ governs"
    };
    Some(verdict(
        "EN 1991-2 §6.4.6.5(3) eq. (6.15), §6.3.2, Table 6.2 case 5.1",
        "hogging moment over the supports: (1 + φ′dyn + φ″/2) × HSLM against Φ × α × LM71",
        format!(
            "{:.0} kN m at {} ({:.2} m)",
            dynamic / 1e3,
            station.name,
            station.position
        ),
        format!(
            "Φ α LM71 = {phi:.3} × {:.0} kN m = {:.0} kN m (LΦ = {:.2} m); {governs}",
            m71 / 1e3,
            phi * m71 / 1e3,
            r.determinant_length
        ),
        "INFO",
    ))
}

/// EN 1990 A2.4.4.3.2: the midspan deflection under LM71 × Φ with α = 1
/// against the passenger-comfort limit, when Figure A2.3's L/δ is given.
fn comfort_verdict(r: &CheckResult, phi: f64) -> Verdict {
    let s = &r.spec.settings;
    let l = r.spec.longest_span();
    let clause = "EN 1990 A2.4.4.3.2, Figure A2.3";
    let check = "passenger comfort: midspan deflection under Φ × LM71 (α = 1)";
    let (_, w71) = main_lm71(r, 1.0);
    let delta = phi * w71;
    let Some(ratio) = s.comfort_span_to_deflection else {
        return verdict(
            clause,
            check,
            format!("{:.2} mm", delta * 1e3),
            "not checked: give settings.comfort_span_to_deflection (L/δ read off Figure A2.3)"
                .into(),
            "INFO",
        );
    };
    let b_v = s.comfort_acceleration;
    let (arrangement, factor, label) = if r.spec.span_lengths().len() >= 3 {
        (
            SpanArrangement::ContinuousThreeOrMore,
            0.9,
            "continuous, three or more spans",
        )
    } else if r.spec.is_continuous() {
        (SpanArrangement::OneOrTwo, 0.7, "two continuous spans")
    } else {
        (SpanArrangement::OneOrTwo, 0.7, "one span")
    };
    let limit = comfort_deflection_limit(l, ratio, b_v, arrangement);
    verdict(
        clause,
        check,
        format!("{:.2} mm", delta * 1e3),
        format!(
            "≤ L / ({ratio} × {factor} / {b_v}) = {:.2} mm ({label}, b_v = {b_v} m/s²)",
            limit * 1e3
        ),
        pass(delta <= limit),
    )
}

/// Every assumption the report states.
fn assumptions(r: &CheckResult) -> Vec<String> {
    let mut out = model_assumptions(r);
    out.extend(check_assumptions(r));
    if !r.spec.is_continuous() && r.spec.span < 7.0 {
        out.push(
            "HSLM-B with N and d as given in settings.hslm_b (read off EN 1991-2 Figure E.8)."
                .into(),
        );
    }
    out
}

/// The model's assumptions: the beam, its damping, the speeds and the
/// filtered acceleration.
fn model_assumptions(r: &CheckResult) -> Vec<String> {
    let s = &r.spec.settings;
    vec![
        format!(
            "{} as an Euler–Bernoulli beam of {} Hermite elements per span; trains as \
             moving forces (no vehicle–bridge interaction, hence Δζ of §6.4.6.4); Newmark average \
             acceleration with a step of {} s, each run until the last axle leaves the bridge.",
            if r.spec.is_continuous() { "A continuous beam over pinned supports" } else { "One simply supported span" },
            s.elements, s.step
        ),
        format!(
            "EI = {:.4e} N m² {} (held for every mass case: {}).",
            r.bending_stiffness,
            if r.spec.first_frequency.is_some() { "from f1 at the nominal mass" } else { "as given" },
            if r.spec.is_continuous() {
                "f1 and f3 are the continuous beam's, from its mesh"
            } else {
                "f1 = (π/2L²)√(EI/m)"
            }
        ),
        "Damping ζ in every mode (EN 1991-2 §6.4.6.3.1 gives one ratio for the structure): the \
         runs are stepped in the modal coordinates of every mode of the mesh."
            .into(),
        format!(
            "Speeds from 40 m/s (144 km/h) to 1.2 × {} = {} km/h in {} km/h steps, {} km/h within ±{} % \
             of each resonant speed f1 D/i (i = 1, 2, 3) (§6.4.6.2).",
            r.spec.line_speed, r.design_speed, s.speed_step, s.fine_speed_step, 100.0 * s.resonance_band
        ),
        "Deck acceleration: the largest over nine stations (L/10 … 9L/10), low-passed with zero phase \
         (Butterworth, 4th order forwards and backwards, −3 dB at the cut-off max(30 Hz, 1.5 f1, f3)); the \
         raw peak beside it."
            .into(),
    ]
}

/// The checks' assumptions: the mass bounds, the National Annex's
/// choices, the determinant length, the real trains and what is not coded.
fn check_assumptions(r: &CheckResult) -> Vec<String> {
    let s = &r.spec.settings;
    vec![
        "Acceleration checked with the lower bound of the mass, load effects with every bound \
         (§6.4.6.3.2)."
            .into(),
        format!(
            "National Annex choices: γ_bt = {} m/s², γ_df = {} m/s² (recommended 3.5 and 5); α = {} \
             (LM71 classification factor); track {} maintained.",
            s.acceleration_limit_ballasted,
            s.acceleration_limit_direct_fastened,
            s.classification_factor,
            if s.carefully_maintained { "carefully" } else { "with standard" }
        ),
        if r.spec.is_continuous() {
            format!(
                "Determinant length LΦ = {:.3} m (EN 1991-2 Table 6.2 case 5.1: k × the mean span, \
                 k = 1.2, 1.3, 1.4, 1.5 for 2, 3, 4, ≥ 5 spans, not below the longest span); φ″ at \
                 the maximum line speed. Table 6.6, eq. (6.13) and L/600 read the longest span \
                 (the least damping); LM71 on the mesh's influence lines, its distributed load on \
                 the unfavourable parts (§6.3.2).",
                r.determinant_length
            )
        } else {
            "Determinant length LΦ = L (simply supported span); φ″ at the maximum line speed."
                .into()
        },
        format!(
            "Real trains {}: ICE 2 and Talgo AV as moving forces, axle loads of IAPF-07 Annex C \
             (src/moving_load/trains/*.toml name the source).",
            if s.real_trains { "run" } else { "turned off (settings.real_trains = false)" }
        ),
        "Passenger comfort (EN 1990 A2.4.4.3.2): L/δ of Figure A2.3 is an input \
         (settings.comfort_span_to_deflection), read off the figure by the engineer; × 0.7 for one \
         span, ÷ b_v."
            .into(),
        "Not coded: the flow chart's torsion and Annex F conditions, deck twist, the car-body acceleration of \
         vehicles."
            .into(),
    ]
}

/// The worst run (largest filtered acceleration) stepped again, its
/// midspan acceleration recorded raw and filtered.
fn worst_case(r: &mut CheckResult, trains: &[Train], zeta: f64) -> Result<(), String> {
    let Some(worst) = r
        .runs
        .iter()
        .max_by(|a, b| a.acceleration_filtered.total_cmp(&b.acceleration_filtered))
        .cloned()
    else {
        return Ok(());
    };
    let case = r
        .mass_cases
        .iter()
        .find(|c| c.name == worst.mass_case)
        .ok_or("mass case")?;
    let scene = scene_for(&r.spec, case.mass_per_length, r.bending_stiffness, zeta)?;
    let beam = crate::study::sweep::structure_of(&scene)?;
    let (_, offsets, _) = trains.iter().find(|t| t.0 == worst.train).ok_or("train")?;
    let speed = worst.speed_kmh / 3.6;
    let axles: Vec<Axle> = offsets
        .iter()
        .map(|&(o, f)| Axle {
            position: -o,
            speed,
            force: f,
        })
        .collect();
    let mut crossing = Crossing::new(&beam, &axles, scene.solver.step)?;
    let steps = (crossing.exit_time() / scene.solver.step).ceil() as usize;
    if steps > crate::study::sweep::MAX_STEPS_PER_RUN as usize {
        return Err(format!("the worst case needs {steps} steps"));
    }
    let x = r.stations[r.main_station].position;
    let mut raw = Vec::with_capacity(steps);
    for _ in 0..steps {
        crossing.step();
        raw.push(crossing.acceleration(x));
    }
    let filtered =
        low_pass_zero_phase(&raw, scene.solver.step, case.cut_off).unwrap_or_else(|| raw.clone());
    r.worst_history = raw
        .iter()
        .zip(&filtered)
        .enumerate()
        .map(|(i, (&a, &b))| ((i + 1) as f64 * scene.solver.step, a, b))
        .collect();
    r.worst = Some(worst);
    Ok(())
}
