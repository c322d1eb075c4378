//! Speed sweeps of moving forces: a scene's forces, or every HSLM train,
//! run at every speed of a range, in parallel on the machine's cores; per
//! run every design output's peak (at the sensors, sections and supports)
//! and its dynamic amplification against the static envelope of the same
//! forces on the same structure; the deck acceleration also as EN 1991-2
//! §6.4.6.5(4) counts it (`crate::signal`).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use crate::beam::Beam;
use crate::design::{envelope_of_loads, probes, DesignPeaks, Probe, ProbeReader, StaticEnvelope};
use crate::moving_load::{
    exit_time, run_end, scene_axles, vehicle_axles, Axle, Crossing, HslmTrain,
};
use crate::outputs::{output_name, reports, QuantityKind};
use crate::scene::{Scene, SensorSpec};
use crate::signal::{cut_off, low_pass_zero_phase, signed_peak};

/// Speeds per sweep.
pub const MAX_SPEEDS: usize = 10_000;
/// Steps of one run.
pub const MAX_STEPS_PER_RUN: u64 = 10_000_000;
/// Steps of a whole sweep by default (about a minute of CPU on a 20-element
/// beam; the full HSLM sweep of README takes 5 million).
pub const DEFAULT_MAX_SWEEP_STEPS: u64 = 200_000_000;
pub use crate::signal::MAX_RECORDED_SAMPLES;

/// The unit the speeds of a sweep are given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpeedUnit {
    MetresPerSecond,
    KilometresPerHour,
}

impl SpeedUnit {
    pub fn parse(text: &str) -> Result<SpeedUnit, String> {
        match text {
            "m/s" => Ok(SpeedUnit::MetresPerSecond),
            "km/h" => Ok(SpeedUnit::KilometresPerHour),
            _ => Err(format!("--unit {text:?}: want \"m/s\" or \"km/h\"")),
        }
    }

    /// Metres per second in one of this unit.
    pub fn in_metres_per_second(self) -> f64 {
        match self {
            SpeedUnit::MetresPerSecond => 1.0,
            SpeedUnit::KilometresPerHour => 1.0 / 3.6,
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            SpeedUnit::MetresPerSecond => "m/s",
            SpeedUnit::KilometresPerHour => "km/h",
        }
    }
}

/// The speeds of `start:stop:step` (inclusive of `stop` when the steps land
/// on it), in the unit given: all > 0, stop >= start, step > 0, at most
/// `MAX_SPEEDS`; a single number is one speed.
pub fn parse_speeds(text: &str) -> Result<Vec<f64>, String> {
    let bad = |rule: &str| format!("--speeds {text:?}: {rule}");
    let number = |part: &str, what: &str| -> Result<f64, String> {
        let x: f64 = part
            .trim()
            .parse()
            .map_err(|_| bad(&format!("{what} {part:?} is not a number")))?;
        if !x.is_finite() || x.abs() > crate::scene::MAX_MAGNITUDE {
            return Err(bad(&format!(
                "{what} {part} is not a finite speed within ±1e15"
            )));
        }
        Ok(x)
    };
    let parts: Vec<&str> = text.split(':').collect();
    let (start, stop, step) = match parts.as_slice() {
        [single] => {
            let v = number(single, "the speed")?;
            (v, v, 1.0)
        }
        [start, stop, step] => (
            number(start, "start")?,
            number(stop, "stop")?,
            number(step, "step")?,
        ),
        _ => return Err(bad("want START:STOP:STEP (e.g. 100:400:5) or one speed")),
    };
    if start <= 0.0 {
        return Err(bad(&format!("start {start} must be > 0")));
    }
    if stop < start {
        return Err(bad(&format!("stop {stop} is below start {start}")));
    }
    if step <= 0.0 {
        return Err(bad(&format!("step {step} must be > 0")));
    }
    let count = ((stop - start) / step + 1e-9).floor() + 1.0;
    if count > MAX_SPEEDS as f64 {
        return Err(bad(&format!(
            "{count} speeds, more than the limit of {MAX_SPEEDS}"
        )));
    }
    Ok((0..count as usize)
        .map(|i| start + i as f64 * step)
        .collect())
}

/// One run of the sweep: a load at a speed, and what the deck did.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvelopeRow {
    /// The HSLM train, or the scene's name for its own forces.
    pub train: String,
    /// Speed in the sweep's unit, as given.
    pub speed: f64,
    /// Speed (m/s).
    pub speed_m_s: f64,
    /// Largest |deflection| at the sensors (m).
    pub peak_deflection: f64,
    /// Largest |acceleration| at the sensors (m/s²).
    pub peak_acceleration: f64,
    /// Largest |acceleration| at the sensors low-passed with zero phase at
    /// `acceleration_cut_off` (EN 1991-2 §6.4.6.5(4)); the raw peak where
    /// the step is too coarse to filter (m/s²).
    pub peak_acceleration_filtered: f64,
    /// The cut-off max(30 Hz, 1.5 f1, f3) of the filtered peak (Hz).
    pub acceleration_cut_off: f64,
    /// Dynamic amplification: peak_deflection over the largest |static
    /// deflection| at the sensors under the same forces crawling across.
    pub daf: f64,
    /// Every design output of the scene (`design::probes`), as a run
    /// reports it.
    pub design: Vec<DesignPeak>,
}

/// One design output's maximum over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignPeak {
    /// The output's name (`sensor.midspan.acceleration`, …).
    pub name: String,
    /// The value of largest magnitude over the run, sign kept.
    pub peak: f64,
    /// The output has a static counterpart (not velocity or acceleration).
    pub is_static: bool,
    /// |peak| over the static envelope's peak of the same output under
    /// the same forces (`design::static_envelope`); `None` for velocity
    /// and acceleration, or where the static response is zero.
    pub daf: Option<f64>,
}

/// The structure a scene's crossings step: its mesh, reduced to the modes
/// `solver.structure = "modal"` keeps (where one damping ratio in every
/// mode is exact).
pub fn structure_of(scene: &Scene) -> Result<Beam, String> {
    let beam = Beam::new(&scene.beam)?;
    match scene.solver.mode_selection() {
        Some(selection) => beam.reduce_to_modes(selection),
        None => Ok(beam),
    }
}

/// What a sweep runs: the scene's own forces, or trains put in place of
/// all of them. A train is one load with one start and speed: those of
/// the scene's first force (`[body]`), the train's template (its leading
/// axle starts there); the scene's other forces are not run with it.
#[derive(Debug, Clone)]
pub enum Loads {
    Scene,
    Trains(Vec<HslmTrain>),
    /// Named trains as axles: each one's distance behind the leading axle
    /// (m) and vertical force (N, up positive), the leading axle starting
    /// where the scene's `[body]` does.
    Axles(Vec<(String, Vec<(f64, f64)>)>),
}

/// One load of the sweep, ready to run at any speed.
struct Load {
    name: String,
    /// Axles at unit speed (the speed scales them).
    axles: Vec<Axle>,
    /// Its static envelope on the scene's structure.
    statics: StaticEnvelope,
}

/// The scene the sweep reads its outputs from: a midspan sensor (the
/// deck) when it has none.
pub(super) fn with_deck_sensor(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    if scene.sensors.is_empty() {
        scene.sensors.push(SensorSpec {
            name: "midspan".into(),
            position: 0.5 * scene.beam.length,
        });
    }
    scene
}

/// The loads of the sweep with their static envelopes.
fn sweep_loads(scene: &Scene, beam: &Beam, loads: &Loads) -> Result<Vec<Load>, String> {
    let named: Vec<(String, Vec<Axle>)> = match loads {
        Loads::Scene => vec![(scene.name.clone(), scene_axles(scene))],
        Loads::Trains(trains) => trains
            .iter()
            .map(|t| {
                let mut spec = scene.vehicles[0].clone();
                spec.train = Some(t.name.to_string());
                (t.name.to_string(), vehicle_axles(&spec, scene.gravity))
            })
            .collect(),
        Loads::Axles(trains) => trains
            .iter()
            .map(|(name, offsets)| {
                let start = scene.vehicles[0].initial_position;
                let speed = scene.vehicles[0].initial_speed;
                let axles = offsets
                    .iter()
                    .map(|&(offset, force)| Axle {
                        position: start - offset,
                        speed,
                        force,
                    })
                    .collect();
                (name.clone(), axles)
            })
            .collect(),
    };
    named
        .into_iter()
        .map(|(name, axles)| {
            let axles = at_speed(&axles, 1.0);
            let forces: Vec<(f64, f64)> = axles.iter().map(|a| (a.position, -a.force)).collect();
            let statics = envelope_of_loads(scene, beam, &forces)?;
            Ok(Load {
                name,
                axles,
                statics,
            })
        })
        .collect()
}

/// Every run of the sweep (`speeds` in `unit`), `threads` at a time; rows
/// in the order train by train, speed by speed.
pub fn sweep(
    scene: &Scene,
    loads: &Loads,
    (speeds, unit): (&[f64], SpeedUnit),
    threads: usize,
    max_steps: u64,
) -> Result<Vec<EnvelopeRow>, String> {
    if !crate::moving_load::is_moving_force_scene(scene) {
        return match loads {
            Loads::Scene => super::vehicle_sweep::sweep(scene, (speeds, unit), threads, max_steps),
            _ => Err(format!(
                "--trains puts HSLM trains in place of moving forces: {}.body.kind must be \
                 \"moving_force\" (a vehicle scene sweeps its own vehicles)",
                scene.name
            )),
        };
    }
    let scene = &with_deck_sensor(scene);
    let beam = structure_of(scene)?;
    let probes = probes(scene, &beam);
    let loads = sweep_loads(scene, &beam, loads)?;
    let deck = DeckRecord::new(scene, &beam, &probes)?;
    let reader = ProbeReader::new(&probes, &beam);
    let jobs: Vec<(usize, f64)> = (0..loads.len())
        .flat_map(|l| speeds.iter().map(move |&v| (l, v)))
        .collect();
    let end = scene.solver.end_time.unwrap_or(f64::INFINITY);
    let total: f64 = jobs
        .iter()
        .map(|&(l, v)| {
            let axles = at_speed(&loads[l].axles, v * unit.in_metres_per_second());
            (run_end(end, exit_time(beam.length, &axles)) / scene.solver.step).ceil()
        })
        .sum();
    if total.is_nan() || total > max_steps as f64 {
        return Err(format!(
            "the sweep needs {total:.0} steps of solver.step = {} s in all, more than the \
             limit of {max_steps} (--max-steps)",
            scene.solver.step
        ));
    }
    let run = |(l, speed): (usize, f64)| -> Result<EnvelopeRow, String> {
        let speed_m_s = speed * unit.in_metres_per_second();
        let load = &loads[l];
        let axles = at_speed(&load.axles, speed_m_s);
        let mut crossing = Crossing::new(&beam, &axles, scene.solver.step)?;
        let mut history = deck.history(&crossing, end)?;
        let peaks =
            crossing.design_peaks_watching(&reader, end, MAX_STEPS_PER_RUN, |_, _, v| {
                for (record, &i) in history.iter_mut().zip(&deck.accelerations) {
                    record.push(v[i]);
                }
            })?;
        let mut row = envelope_row(load, (speed, speed_m_s), &probes, &peaks);
        deck.add_filtered(&mut row, &history, scene);
        Ok(row)
    };
    in_parallel(&jobs, threads, run)
}

/// What the sweep records of the deck's acceleration for the filtered
/// peak: the sensors, the step and the cut-off of EN 1991-2 §6.4.6.5(4).
struct DeckRecord {
    /// The index among the probes of each sensor's acceleration.
    accelerations: Vec<usize>,
    step: f64,
    cut_off: f64,
}

impl DeckRecord {
    fn new(scene: &Scene, beam: &Beam, probes: &[Probe]) -> Result<DeckRecord, String> {
        let accelerations = scene
            .sensors
            .iter()
            .map(|s| {
                let name = output_name(QuantityKind::SensorAcceleration, &s.name);
                probes.iter().position(|p| p.name == name).ok_or(name)
            })
            .collect::<Result<Vec<usize>, String>>()?;
        let to_hz = 0.5 / std::f64::consts::PI;
        let f: Vec<f64> = beam
            .cut_off_frequencies(3)?
            .iter()
            .map(|w| w * to_hz)
            .collect();
        let third = f.get(2).or(f.last()).copied().unwrap_or(0.0);
        Ok(DeckRecord {
            accelerations,
            step: scene.solver.step,
            cut_off: cut_off(f.first().copied().unwrap_or(0.0), third),
        })
    }

    /// Empty records for `crossing`'s run to `end`, refused when they
    /// would hold more than `MAX_RECORDED_SAMPLES`.
    fn history(&self, crossing: &Crossing, end: f64) -> Result<Vec<Vec<f64>>, String> {
        let steps = (run_end(end, crossing.exit_time()) / self.step).ceil();
        let samples = steps * self.accelerations.len() as f64;
        if samples.is_nan() || samples > MAX_RECORDED_SAMPLES as f64 {
            return Err(format!(
                "the filtered deck acceleration needs {samples:.0} samples ({steps:.0} steps × {} \
                 sensors), more than the limit of {MAX_RECORDED_SAMPLES} (fewer sensors or a \
                 shorter run)",
                self.accelerations.len()
            ));
        }
        let capacity = steps as usize;
        Ok(vec![Vec::with_capacity(capacity); self.accelerations.len()])
    }

    /// The filtered peaks into `row`: per sensor as the design output
    /// `sensor.<name>.acceleration_filtered`, and the largest.
    fn add_filtered(&self, row: &mut EnvelopeRow, history: &[Vec<f64>], scene: &Scene) {
        row.acceleration_cut_off = self.cut_off;
        let mut largest: f64 = 0.0;
        for (record, sensor) in history.iter().zip(&scene.sensors) {
            let peak = match low_pass_zero_phase(record, self.step, self.cut_off) {
                Some(filtered) => signed_peak(&filtered),
                None => signed_peak(record),
            };
            largest = largest.max(peak.abs());
            row.design.push(DesignPeak {
                name: format!("sensor.{}.acceleration_filtered", sensor.name),
                peak,
                is_static: false,
                daf: None,
            });
        }
        row.peak_acceleration_filtered = largest;
    }
}

/// The row of one run: its design peaks, with the deck's summary.
fn envelope_row(
    load: &Load,
    (speed, speed_m_s): (f64, f64),
    probes: &[Probe],
    peaks: &DesignPeaks,
) -> EnvelopeRow {
    let design: Vec<DesignPeak> = probes
        .iter()
        .zip(&peaks.peaks)
        .map(|(probe, &peak)| DesignPeak {
            name: probe.name.clone(),
            peak,
            is_static: probe.is_static(),
            daf: load.statics.amplification(&probe.name, peak),
        })
        .collect();
    let deflection = largest_sensor_peak(&design, QuantityKind::Sensor);
    let static_deflection = load
        .statics
        .peaks
        .iter()
        .filter(|(name, _)| reports(name, QuantityKind::Sensor))
        .map(|(_, &peak)| peak)
        .fold(0.0, f64::max);
    EnvelopeRow {
        train: load.name.clone(),
        speed,
        speed_m_s,
        peak_deflection: deflection,
        peak_acceleration: largest_sensor_peak(&design, QuantityKind::SensorAcceleration),
        peak_acceleration_filtered: 0.0,
        acceleration_cut_off: 0.0,
        daf: deflection / static_deflection,
        design,
    }
}

/// The axles moving at `speed` (the sign of each axle's own speed kept).
fn at_speed(axles: &[Axle], speed: f64) -> Vec<Axle> {
    axles
        .iter()
        .map(|a| Axle {
            speed: if a.speed < 0.0 { -speed } else { speed },
            ..*a
        })
        .collect()
}

/// `run` over every job on `threads` scoped threads taking the next job
/// as they finish one; results in the jobs' order, the first error wins.
pub(crate) fn in_parallel<J: Copy + Sync, R: Send>(
    jobs: &[J],
    threads: usize,
    run: impl Fn(J) -> Result<R, String> + Sync,
) -> Result<Vec<R>, String> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<R, String>>>> =
        Mutex::new((0..jobs.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, jobs.len().max(1)) {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(&job) = jobs.get(i) else {
                    break;
                };
                let result = run(job);
                results.lock().expect("no thread panics holding it")[i] = Some(result);
            });
        }
    });
    results
        .into_inner()
        .expect("no thread panicked")
        .into_iter()
        .map(|r| r.expect("every job ran"))
        .collect()
}

/// The envelope as CSV: one row per train and speed, the speed in km/h and
/// in m/s whatever the unit given (each column unique, the same columns
/// for either unit; the unit given is written as given); after the deck's
/// summary, every design output's peak and, where it has one, its DAF
/// (`<name>.daf`).
pub fn envelope_csv(rows: &[EnvelopeRow], unit: SpeedUnit) -> String {
    let mut text = "train,speed_km_h,speed_m_s,peak_deflection_m,peak_acceleration_m_s2,\
         peak_acceleration_filtered_m_s2,acceleration_cut_off_hz,daf"
        .to_string();
    // Every row has the same outputs (one scene); a DAF column after each
    // one with a static counterpart, empty where its static response is 0.
    if let Some(first) = rows.first() {
        for d in &first.design {
            text.push_str(&format!(",{}", d.name));
            if d.is_static {
                text.push_str(&format!(",{}.daf", d.name));
            }
        }
    }
    text.push('\n');
    for r in rows {
        text.push_str(&format!(
            "{},{},{},{},{},{},{},{}",
            r.train,
            speed_km_h(r, unit),
            r.speed_m_s,
            r.peak_deflection,
            r.peak_acceleration,
            r.peak_acceleration_filtered,
            r.acceleration_cut_off,
            r.daf
        ));
        for d in &r.design {
            text.push_str(&format!(",{}", d.peak));
            if d.is_static {
                match d.daf {
                    Some(x) => text.push_str(&format!(",{x}")),
                    None => text.push(','),
                }
            }
        }
        text.push('\n');
    }
    text
}

/// The row's speed in km/h: as given, or converted from m/s.
fn speed_km_h(row: &EnvelopeRow, unit: SpeedUnit) -> f64 {
    match unit {
        SpeedUnit::KilometresPerHour => row.speed,
        SpeedUnit::MetresPerSecond => row.speed_m_s * 3.6,
    }
}

/// The largest |peak| of the design outputs reporting `kind` (a sensor's
/// deflection or acceleration); 0 without sensors.
pub(super) fn largest_sensor_peak(design: &[DesignPeak], kind: QuantityKind) -> f64 {
    design
        .iter()
        .filter(|d| reports(&d.name, kind))
        .map(|d| d.peak.abs())
        .fold(0.0, f64::max)
}
