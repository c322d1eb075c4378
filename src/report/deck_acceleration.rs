//! The deck accelerations of a run as EN 1991-2 §6.4.6.5(4) counts them:
//! each sensor's acceleration is recorded at the steps of the run and, at
//! its end, low-passed with zero phase at max(30 Hz, 1.5 f1, f3)
//! (`signal`, the same filter as the sweep's) before its peak
//! is read.

use crate::beam::Beam;
use crate::scene::Scene;
use crate::signal::{cut_off, low_pass_zero_phase, signed_peak, MAX_RECORDED_SAMPLES};

/// The sensors' acceleration records of a run on its step grid.
pub struct DeckRecord {
    /// Sensor name and its `sensor.<name>.acceleration` column.
    sensors: Vec<(String, usize)>,
    records: Vec<Vec<f64>>,
    step: f64,
    start: Option<f64>,
    /// Set when the records would exceed `MAX_RECORDED_SAMPLES`.
    too_long: bool,
}

/// The filtered peaks of a run and the cut-off they were filtered at.
pub struct FilteredPeaks {
    /// max(30 Hz, 1.5 f1, f3) of the deck (Hz).
    pub cut_off_hz: f64,
    /// Per sensor, the filtered acceleration of largest magnitude, sign kept.
    pub peaks: Vec<(String, f64)>,
}

impl DeckRecord {
    /// For the sensors of `names` with an acceleration output; `None`
    /// when there is none.
    pub fn new(names: &[String], step: f64) -> Option<DeckRecord> {
        let sensors: Vec<(String, usize)> = names
            .iter()
            .enumerate()
            .filter_map(|(k, n)| {
                let sensor = n.strip_prefix("sensor.")?.strip_suffix(".acceleration")?;
                Some((sensor.to_string(), k))
            })
            .collect();
        (!sensors.is_empty()).then(|| DeckRecord {
            records: vec![Vec::new(); sensors.len()],
            sensors,
            step,
            start: None,
            too_long: false,
        })
    }

    /// The next row (its columns are design outputs: the summary reads
    /// them anyway). Rows off the step grid (a run's last row at its exit
    /// event) are left out: the filter needs equally spaced samples.
    pub fn push(&mut self, time: f64, values: &[f64]) {
        let start = *self.start.get_or_insert(time);
        let samples = self.records[0].len();
        let on_grid = start + samples as f64 * self.step;
        if self.too_long || (time - on_grid).abs() > 1e-6 * self.step {
            return;
        }
        if ((samples + 1) * self.sensors.len()) as u64 > MAX_RECORDED_SAMPLES {
            self.too_long = true;
            return;
        }
        for (record, (_, column)) in self.records.iter_mut().zip(&self.sensors) {
            record.push(values[*column]);
        }
    }

    /// The filtered peaks, with the cut-off from the first and third
    /// natural frequencies of `scene`'s beam; `None` when the records
    /// were too long to keep or the beam's frequencies cannot be found.
    /// Where the step is too coarse for the cut-off every frequency the
    /// record holds is counted (the raw peak), as in the sweep.
    pub fn finish(self, scene: &Scene) -> Option<FilteredPeaks> {
        if self.too_long {
            return None;
        }
        let to_hz = 0.5 / std::f64::consts::PI;
        let beam = Beam::new(&scene.beam).ok()?;
        let f: Vec<f64> = beam
            .cut_off_frequencies(3)
            .ok()?
            .iter()
            .map(|w| w * to_hz)
            .collect();
        let third = f.get(2).or(f.last()).copied()?;
        let cut_off_hz = cut_off(*f.first()?, third);
        let peaks = self
            .sensors
            .into_iter()
            .zip(self.records)
            .map(|((name, _), record)| {
                let filtered = low_pass_zero_phase(&record, self.step, cut_off_hz);
                (name, signed_peak(filtered.as_deref().unwrap_or(&record)))
            })
            .collect();
        Some(FilteredPeaks { cut_off_hz, peaks })
    }
}
