//! The figures of merit of one run, as JSON and as a short human summary.

use super::deck_acceleration::DeckRecord;
use super::exits::VehicleExit;
use super::trace::Trace;
use crate::design::StaticEnvelope;
use crate::outputs::{classify, output_name, reports, QuantityKind};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// What `guideway run --summary` writes. `None` becomes JSON `null`: the
/// body did not exit, or the simulation has no such output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// Time (s) at which the last contact left the beam (of a train: the
    /// last vehicle's, `set_vehicles`).
    pub exit_time: Option<f64>,
    /// Nominal speed V (eq. 24, m/s) at the exit: the first vehicle's, or
    /// with the vehicles' exits set after a run to `solver.end_time`, that
    /// of the vehicle that left last.
    pub exit_nominal_speed: Option<f64>,
    /// Largest nominal speed V (m/s) over the run: the first vehicle's
    /// (each vehicle's exit speeds are in `vehicles`).
    pub peak_nominal_speed: Option<f64>,
    /// Per sensor, the most negative (downward) deflection (m), sign kept.
    pub peak_sensor_deflection: BTreeMap<String, f64>,
    /// max |E(t) − E(0)| / |E(0)| of `energy.balance`, E(0) being the
    /// initial total energy.
    pub max_energy_drift: Option<f64>,
    /// Internal steps taken (rows of the CSV after the initial one).
    pub steps: usize,
    /// Contact-force iterations, summed over the steps.
    pub iterations: Option<u64>,
    /// Wall-clock time (s) of the solve alone.
    pub wall_time_s: f64,
    /// The integrator that ran, and for `auto` why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<String>,
    /// Each contact's entries onto and exits from the beam (and off the
    /// track), in time order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<SummaryEvent>,
    /// Per design output (every `sensor.*`, `section.*` and `support.*`
    /// column), the value of largest magnitude over the run, sign kept.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub peak_design: BTreeMap<String, f64>,
    /// Dynamic amplification factor per output with a static counterpart
    /// (sensor deflections, section moments and shears, reactions): the
    /// largest magnitude over the run over the largest magnitude of the
    /// static response to the same loads crossing quasi-statically
    /// (`design::static_envelope`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub dynamic_amplification: BTreeMap<String, f64>,
    /// Per contact, the normal (wheel–rail, magnet) force of largest
    /// magnitude over the run, sign kept (`<contact>.normal_force`, N). The
    /// tangential forces are left out: on rolling wheels they are a few N
    /// against loads of 1e5 N, set by the contact iteration's tolerance,
    /// not by the step, and their peaks do not converge as figures.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub peak_contact_force: BTreeMap<String, f64>,
    /// The cut-off (Hz) of the deck accelerations EN 1991-2 §6.4.6.5(4)
    /// counts, max(30 Hz, 1.5 f1, f3): `peak_design` holds, beside each
    /// `sensor.<name>.acceleration`, its peak low-passed there with zero
    /// phase, `sensor.<name>.acceleration_filtered`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub acceleration_cut_off_hz: Option<f64>,
    /// Per vehicle, when its first and last contact left the beam and its
    /// speed then, whether or not the run went on to `solver.end_time`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vehicles: Vec<VehicleExit>,
}

/// One event of a run: which contact, what, when.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SummaryEvent {
    pub contact: String,
    /// `entry` (onto the beam), `exit` (off the beam), `left_track`,
    /// `lift_off` or `landing`.
    pub kind: String,
    /// Time (s).
    pub time: f64,
}

impl SummaryEvent {
    /// The events of a run, named after their contacts.
    pub fn list(sim: &crate::simulation::Simulation) -> Vec<SummaryEvent> {
        use crate::simulation::EventKind;
        sim.events()
            .iter()
            .map(|e| SummaryEvent {
                contact: sim.system().contacts[e.contact].name.clone(),
                kind: match e.kind {
                    EventKind::Entry => "entry",
                    EventKind::Exit => "exit",
                    EventKind::LeftTrack => "left_track",
                    EventKind::LiftOff => "lift_off",
                    EventKind::Landing => "landing",
                }
                .to_string(),
                time: e.time,
            })
            .collect()
    }
}

/// Events the terminal summary lists (the JSON has them all).
const EVENTS_SHOWN: usize = 24;

impl RunSummary {
    /// Summarise a trace of `scene`'s outputs.
    pub fn from_trace(
        scene: &Scene,
        trace: &Trace,
        exit_time: Option<f64>,
        wall_time_s: f64,
    ) -> RunSummary {
        let mut builder = SummaryBuilder::new(scene, &trace.names);
        let mut values = vec![0.0; trace.columns.len()];
        for (row, &time) in trace.time.iter().enumerate() {
            for (value, column) in values.iter_mut().zip(&trace.columns) {
                *value = column[row];
            }
            builder.push(time, &values);
        }
        builder.finish(exit_time, wall_time_s)
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a summary always serialises to JSON")
    }
}

/// Builds a `RunSummary` row by row, so that a run streamed to a file needs
/// no trace in memory.
pub struct SummaryBuilder {
    scene: String,
    speed: Option<usize>,
    sensors: Vec<(String, usize)>,
    energy: Option<usize>,
    iterations_column: Option<usize>,
    rows: usize,
    last_speed: Option<f64>,
    peak_speed: Option<f64>,
    peak_deflection: Vec<Option<f64>>,
    initial_energy: Option<f64>,
    max_drift: f64,
    iterations: u64,
    /// Design outputs: name, column and the value of largest magnitude.
    design: Vec<(String, usize, Option<f64>)>,
    /// The scene whose static envelope the amplification factors are
    /// relative to, when there are design outputs. The envelope is computed
    /// in `finish`, not before the run: at 1,000 elements its thousands of
    /// static solves take longer than the whole start-up otherwise.
    envelope_of: Option<Scene>,
    /// Contact forces: name, column and the value of largest magnitude.
    contact_forces: Vec<(String, usize, Option<f64>)>,
    /// The sensors' accelerations, for the filtered peaks.
    deck: Option<DeckRecord>,
}

impl SummaryBuilder {
    /// For rows of the outputs `names` of `scene`'s simulation.
    pub fn new(scene: &Scene, names: &[String]) -> SummaryBuilder {
        // By a map: 10,000 sensors looked up among 30,000 outputs one by
        // one were 3e8 comparisons.
        let columns: std::collections::HashMap<&str, usize> = names
            .iter()
            .enumerate()
            .rev()
            .map(|(k, n)| (n.as_str(), k))
            .collect();
        let find = |name: &str| columns.get(name).copied();
        let sensors: Vec<(String, usize)> = scene
            .sensors
            .iter()
            .filter_map(|s| {
                let column = find(&output_name(QuantityKind::Sensor, &s.name))?;
                Some((s.name.clone(), column))
            })
            .collect();
        let design = design_columns(names);
        let contact_forces = names
            .iter()
            .enumerate()
            .filter(|(_, n)| reports(n, QuantityKind::NormalForce))
            .map(|(k, n)| (n.clone(), k, None))
            .collect();
        SummaryBuilder {
            contact_forces,
            deck: DeckRecord::new(names, scene.solver.step),
            envelope_of: (!design.is_empty()).then(|| scene.clone()),
            scene: scene.name.clone(),
            // The first vehicle's (the paper's one body); a train's
            // vehicles' exit speeds are `RunSummary::vehicles`.
            speed: find(&output_name(
                QuantityKind::NominalSpeed,
                &scene.vehicles[0].name,
            )),
            peak_deflection: vec![None; sensors.len()],
            sensors,
            energy: find(&output_name(QuantityKind::Balance, "")),
            iterations_column: find(&output_name(QuantityKind::Iterations, "")),
            rows: 0,
            last_speed: None,
            peak_speed: None,
            initial_energy: None,
            max_drift: 0.0,
            iterations: 0,
            design,
        }
    }

    /// The columns the summary reads.
    pub fn columns(&self) -> Vec<usize> {
        let sensors = self.sensors.iter().map(|(_, k)| *k);
        let design = self.design.iter().map(|(_, k, _)| *k);
        let forces = self.contact_forces.iter().map(|(_, k, _)| *k);
        let single = [self.speed, self.energy, self.iterations_column];
        single
            .into_iter()
            .flatten()
            .chain(sensors)
            .chain(design)
            .chain(forces)
            .collect()
    }

    /// The next row (the first is the initial state).
    pub fn push(&mut self, time: f64, values: &[f64]) {
        if let Some(v) = self.speed.map(|k| values[k]) {
            self.last_speed = Some(v);
            self.peak_speed = finite_extreme(self.peak_speed, v, f64::max);
        }
        for ((_, column), peak) in self.sensors.iter().zip(&mut self.peak_deflection) {
            *peak = finite_extreme(*peak, values[*column], f64::min);
        }
        for (_, column, peak) in self.design.iter_mut().chain(&mut self.contact_forces) {
            let v = values[*column];
            if v.is_finite() && peak.is_none_or(|p| v.abs() > p.abs()) {
                *peak = Some(v);
            }
        }
        if let Some(deck) = &mut self.deck {
            deck.push(time, values);
        }
        if let Some(e) = self.energy.map(|k| values[k]) {
            self.push_energy(e);
        }
        if let Some(n) = self.iterations_column.map(|k| values[k]) {
            if self.rows > 0 {
                self.iterations += n.max(0.0) as u64;
            }
        }
        self.rows += 1;
    }

    /// max |E − E0| / |E0|; no drift without a usable E0. A non-finite
    /// energy later in the run is an infinite drift.
    fn push_energy(&mut self, e: f64) {
        match self.initial_energy {
            None if self.rows == 0 => self.initial_energy = Some(e),
            None => {}
            Some(initial) => {
                let drift = if e.is_finite() {
                    ((e - initial) / initial).abs()
                } else {
                    f64::INFINITY
                };
                self.max_drift = self.max_drift.max(drift);
            }
        }
    }

    pub fn finish(self, exit_time: Option<f64>, wall_time_s: f64) -> RunSummary {
        self.finish_with(exit_time, wall_time_s, |scene| {
            crate::design::static_envelope(scene).ok()
        })
    }

    /// `finish` with the static envelope from `envelope_of` (e.g. the
    /// simulation's, which needs no second assembly), asked for only when
    /// a design output needs it.
    pub fn finish_with(
        self,
        exit_time: Option<f64>,
        wall_time_s: f64,
        envelope_of: impl FnOnce(&Scene) -> Option<StaticEnvelope>,
    ) -> RunSummary {
        let usable = |e: &f64| e.is_finite() && *e != 0.0;
        // The reference of the amplification factors: bounded work (see
        // `design::static_envelope`), none for a beam without one.
        let envelope = self.envelope_of.as_ref().and_then(envelope_of);
        let filtered = self
            .deck
            .zip(self.envelope_of.as_ref())
            .and_then(|(deck, scene)| deck.finish(scene));
        let mut peak_design: BTreeMap<String, f64> = self
            .design
            .iter()
            .filter_map(|(name, _, peak)| Some((name.clone(), (*peak)?)))
            .collect();
        for (sensor, peak) in filtered.iter().flat_map(|f| &f.peaks) {
            peak_design.insert(format!("sensor.{sensor}.acceleration_filtered"), *peak);
        }
        RunSummary {
            scene: self.scene,
            exit_time,
            exit_nominal_speed: exit_time.and(self.last_speed),
            peak_nominal_speed: self.peak_speed,
            peak_sensor_deflection: self
                .sensors
                .into_iter()
                .zip(self.peak_deflection)
                .filter_map(|((name, _), peak)| Some((name, peak?)))
                .collect(),
            max_energy_drift: self.initial_energy.filter(usable).map(|_| self.max_drift),
            steps: self.rows.saturating_sub(1),
            iterations: self.iterations_column.map(|_| self.iterations),
            wall_time_s,
            integrator: None,
            events: Vec::new(),
            vehicles: Vec::new(),
            dynamic_amplification: self
                .design
                .iter()
                .filter_map(|(name, _, peak)| {
                    let envelope = envelope.as_ref()?;
                    Some((name.clone(), envelope.amplification(name, (*peak)?)?))
                })
                .collect(),
            peak_design,
            peak_contact_force: self
                .contact_forces
                .into_iter()
                .filter_map(|(name, _, peak)| Some((name, peak?)))
                .collect(),
            acceleration_cut_off_hz: filtered.map(|f| f.cut_off_hz),
        }
    }
}

/// The short summary printed at the end of `guideway run`.
impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let or_none = |x: Option<f64>, unit: &str, precision: usize| match x {
            Some(x) => format!("{x:.precision$} {unit}"),
            None => "-".to_string(),
        };
        writeln!(f, "scene              {}", self.scene)?;
        if let Some(integrator) = &self.integrator {
            writeln!(f, "integrator         {integrator}")?;
        }
        match self.exit_time {
            Some(t) => writeln!(f, "exit time          {t:.6} s")?,
            None => writeln!(f, "exit time          - (the body did not leave the beam)")?,
        }
        writeln!(
            f,
            "exit speed V       {}",
            or_none(self.exit_nominal_speed, "m/s", 4)
        )?;
        writeln!(
            f,
            "peak speed V       {}",
            or_none(self.peak_nominal_speed, "m/s", 4)
        )?;
        for (sensor, deflection) in &self.peak_sensor_deflection {
            writeln!(f, "peak deflection    {deflection:.6} m at sensor {sensor}")?;
        }
        self.fmt_design(f)?;
        let drift = self
            .max_energy_drift
            .map_or("-".to_string(), |d| format!("{:.3e} %", d * 100.0));
        writeln!(f, "max energy drift   {drift}")?;
        writeln!(f, "steps              {}", self.steps)?;
        let per_step = |n: u64| match self.steps {
            0 => n.to_string(),
            steps => format!("{n} ({:.2} per step)", n as f64 / steps as f64),
        };
        let iterations = self.iterations.map_or("-".to_string(), per_step);
        writeln!(f, "iterations         {iterations}")?;
        for e in self.events.iter().take(EVENTS_SHOWN) {
            writeln!(
                f,
                "event              {:<10} {} at {:.6} s",
                e.kind, e.contact, e.time
            )?;
        }
        self.fmt_vehicles(f)?;
        if self.events.len() > EVENTS_SHOWN {
            let more = self.events.len() - EVENTS_SHOWN;
            writeln!(f, "event              ... {more} more (all in --summary)")?;
        }
        write!(f, "wall time (solve)  {:.3} ms", self.wall_time_s * 1e3)
    }
}

impl RunSummary {
    /// Set the vehicles' exits; when the run did not end at the exit (it
    /// went on to `solver.end_time`), the exit is the run's own rule's (the
    /// last contact off the beam): the time and speed of the vehicle whose
    /// last contact left last, once every vehicle has left.
    pub fn set_vehicles(&mut self, vehicles: Vec<VehicleExit>) {
        if self.exit_time.is_none() {
            let exits: Option<Vec<(f64, &VehicleExit)>> = (vehicles.iter())
                .map(|v| Some((v.last_exit_time?, v)))
                .collect();
            let last = exits.and_then(|e| e.into_iter().max_by(|a, b| a.0.total_cmp(&b.0)));
            if let Some((time, vehicle)) = last {
                self.exit_time = Some(time);
                self.exit_nominal_speed = vehicle.last_exit_speed;
            }
        }
        self.vehicles = vehicles;
    }

    /// One line per vehicle (of a train: per coach): first and last
    /// contact off the beam, time and speed.
    fn fmt_vehicles(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |time: Option<f64>, speed: Option<f64>| match (time, speed) {
            (Some(t), Some(v)) => format!("{t:.6} s, {v:.4} m/s"),
            (Some(t), None) => format!("{t:.6} s"),
            _ => "-".to_string(),
        };
        for v in self.vehicles.iter().take(EVENTS_SHOWN) {
            writeln!(
                f,
                "vehicle exit       {}: first contact {}; last {}",
                v.vehicle,
                at(v.first_exit_time, v.first_exit_speed),
                at(v.last_exit_time, v.last_exit_speed)
            )?;
        }
        if self.vehicles.len() > EVENTS_SHOWN {
            let more = self.vehicles.len() - EVENTS_SHOWN;
            writeln!(f, "vehicle exit       ... {more} more (all in --summary)")?;
        }
        Ok(())
    }

    /// The design peaks and amplification factors, one line each, leaving
    /// out what the peak-deflection lines already say.
    fn fmt_design(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (name, peak) in &self.peak_design {
            let Some((place, quantity)) = split_design_name(name) else {
                continue;
            };
            let value = match quantity {
                "deflection" => continue,
                "velocity" => format!("{peak:.6} m/s"),
                "acceleration" => format!("{peak:.6} m/s²"),
                "acceleration_filtered" => {
                    let cut = self.acceleration_cut_off_hz.unwrap_or(f64::NAN);
                    let line = format!("{peak:.6} m/s² at {place} (EN 1991-2 below {cut:.1} Hz)");
                    writeln!(f, "filtered accel.    {line}")?;
                    continue;
                }
                "moment" => format!("{peak:.6e} N m"),
                _ => format!("{peak:.6e} N"),
            };
            let label = format!("peak {quantity}");
            writeln!(f, "{label:<18} {value} at {place}")?;
        }
        self.fmt_contact_forces(f)?;
        for (name, daf) in &self.dynamic_amplification {
            let (place, quantity) = split_design_name(name).unwrap_or((name.clone(), ""));
            writeln!(f, "DAF                {daf:.4} ({quantity} at {place})")?;
        }
        Ok(())
    }
}

impl RunSummary {
    /// The largest normal contact force over the contacts, in one line
    /// (the JSON has every contact's).
    fn fmt_contact_forces(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (quantity, label) in [(QuantityKind::NormalForce, "peak contact force")] {
            let of_kind = self.peak_contact_force.iter().filter_map(|(name, force)| {
                let named = classify(name).filter(|n| n.kind == quantity)?;
                Some((named.owner, *force))
            });
            let count = of_kind.clone().count();
            let Some((contact, force)) = of_kind.max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            else {
                continue;
            };
            let of = if count > 1 {
                format!(" (largest of {count} contacts)")
            } else {
                String::new()
            };
            writeln!(f, "{label:<18} {force:.6e} N at {contact}{of}")?;
        }
        Ok(())
    }
}

/// `sensor.midspan.acceleration` → ("sensor midspan", "acceleration").
fn split_design_name(name: &str) -> Option<(String, &str)> {
    let (kind, rest) = name.split_once('.')?;
    let (place, quantity) = rest.rsplit_once('.')?;
    Some((format!("{kind} {place}"), quantity))
}

/// The columns of `names` that are design outputs.
fn design_columns(names: &[String]) -> Vec<(String, usize, Option<f64>)> {
    names
        .iter()
        .enumerate()
        .filter(|(_, n)| {
            ["sensor.", "section.", "support."]
                .iter()
                .any(|p| n.starts_with(p))
        })
        .map(|(k, n)| (n.clone(), k, None))
        .collect()
}

/// The extreme so far by `pick` (`f64::max`, `f64::min`), ignoring
/// non-finite values.
fn finite_extreme(so_far: Option<f64>, value: f64, pick: fn(f64, f64) -> f64) -> Option<f64> {
    if !value.is_finite() {
        return so_far;
    }
    Some(so_far.map_or(value, |x| pick(x, value)))
}
