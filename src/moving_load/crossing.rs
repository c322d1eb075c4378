//! The beam under moving forces, stepped with Newmark's average
//! acceleration (β = 1/4, γ = 1/2): M a + C v + K u = f(t), the forces
//! placed at their positions at each step's end; on the full mesh or in
//! the modal coordinates of a modal structure (one damping ratio in every
//! mode).

use std::borrow::Cow;
use std::ops::Deref;

use nalgebra::DVector;

use super::Axle;
use crate::beam::{Beam, EffectiveFactor};
use crate::design::{BeamDynamics, DesignPeaks, PointLoad, ProbeReader};

const BETA: f64 = 0.25;
const GAMMA: f64 = 0.5;

/// The beam a crossing steps: borrowed (a sweep's runs share one) or its
/// own (a run that outlives the scope it was built in: `guideway run`).
enum Held<'a> {
    Borrowed(&'a Beam),
    Owned(Box<Beam>),
}

impl Deref for Held<'_> {
    type Target = Beam;
    fn deref(&self) -> &Beam {
        match self {
            Held::Borrowed(beam) => beam,
            Held::Owned(beam) => beam,
        }
    }
}

/// Steps a crossing of `axles` over `beam` with a fixed step.
pub struct Crossing<'a> {
    beam: Held<'a>,
    axles: Cow<'a, [Axle]>,
    step: f64,
    /// Factor of M + γ Δt C + β Δt² K.
    factor: EffectiveFactor,
    time: f64,
    u: DVector<f64>,
    v: DVector<f64>,
    a: DVector<f64>,
    load: DVector<f64>,
    /// The forces on the beam at `time`, as `load` was built from them.
    placed: Vec<PointLoad>,
    rhs: DVector<f64>,
    scratch: DVector<f64>,
}

/// The largest magnitudes at one sensor over a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Peaks {
    /// Largest |w| (m).
    pub deflection: f64,
    /// Largest |ẅ| (m/s²).
    pub acceleration: f64,
}

impl<'a> Crossing<'a> {
    /// The beam at rest and undeformed at t = 0 under the forces there.
    pub fn new(beam: &'a Beam, axles: &'a [Axle], step: f64) -> Result<Crossing<'a>, String> {
        Crossing::holding(Held::Borrowed(beam), Cow::Borrowed(axles), step)
    }

    fn holding(beam: Held<'a>, axles: Cow<'a, [Axle]>, step: f64) -> Result<Crossing<'a>, String> {
        if !(step > 0.0 && step.is_finite()) {
            return Err(format!("the step must be > 0 (got {step})"));
        }
        let (c, k) = (GAMMA * step, BETA * step * step);
        // The full mesh keeps its plain band factor (its runs bit for bit).
        let factor = match beam.modal() {
            None => EffectiveFactor::Band(beam.factor_effective(c, k)?),
            Some(_) => beam.effective_factor(c, k)?,
        };
        let n = beam.coordinates();
        let z = || DVector::zeros(n);
        let mut crossing = Crossing {
            beam,
            axles,
            step,
            factor,
            time: 0.0,
            u: z(),
            v: z(),
            a: z(),
            load: z(),
            placed: Vec::new(),
            rhs: z(),
            scratch: z(),
        };
        crossing.place_loads(0.0);
        crossing.a.copy_from(&crossing.load);
        crossing.beam.solve_mass(&mut crossing.a);
        Ok(crossing)
    }

    /// `new` on a beam and axles of its own.
    pub fn owning(beam: Beam, axles: Vec<Axle>, step: f64) -> Result<Crossing<'static>, String> {
        Crossing::holding(Held::Owned(Box::new(beam)), Cow::Owned(axles), step)
    }

    /// The beam the forces cross.
    pub fn beam(&self) -> &Beam {
        &self.beam
    }

    /// The fixed step (s).
    pub fn step_size(&self) -> f64 {
        self.step
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// When the last force has left the beam (s).
    pub fn exit_time(&self) -> f64 {
        exit_time(self.beam.length, &self.axles)
    }

    /// The load vector of the forces at time `t` (those on the beam).
    fn place_loads(&mut self, t: f64) {
        self.load.fill(0.0);
        self.placed.clear();
        let length = self.beam.length;
        for axle in self.axles.iter() {
            let x = axle.at(t);
            if (0.0..=length).contains(&x) {
                let shape = self.beam.shape(self.beam.element_at(x), x);
                self.beam
                    .scatter(&shape, &shape.n, axle.force, &mut self.load);
                self.placed.push(PointLoad {
                    x,
                    element: shape.element,
                    force: axle.force,
                    couple: 0.0,
                });
            }
        }
    }

    /// One step: predictors, then (M + γΔt C + βΔt² K) a₁ = f₁ − C ṽ − K ũ.
    pub fn step(&mut self) {
        let dt = self.step;
        self.time += dt;
        self.place_loads(self.time);
        self.u.axpy(dt, &self.v, 1.0);
        self.u.axpy(dt * dt * (0.5 - BETA), &self.a, 1.0);
        self.v.axpy(dt * (1.0 - GAMMA), &self.a, 1.0);
        self.beam
            .internal_forces(&self.u, &self.v, &mut self.scratch, &mut self.rhs);
        self.rhs.zip_apply(&self.load, |r, f| *r = f - *r);
        self.factor.solve_mut(&mut self.rhs);
        std::mem::swap(&mut self.a, &mut self.rhs);
        self.u.axpy(BETA * dt * dt, &self.a, 1.0);
        self.v.axpy(GAMMA * dt, &self.a, 1.0);
    }

    /// Deflection w at `x` (m, up positive).
    pub fn deflection(&self, x: f64) -> f64 {
        self.beam.deflection(&self.u, x)
    }

    /// Acceleration ẅ at `x` (m/s², up positive).
    pub fn acceleration(&self, x: f64) -> f64 {
        self.beam.deflection(&self.a, x)
    }

    /// The forces on the beam now, as point loads.
    pub fn point_loads(&self) -> &[PointLoad] {
        &self.placed
    }

    /// The free DOFs' displacement, velocity and acceleration now.
    pub fn state(&self) -> (&DVector<f64>, &DVector<f64>, &DVector<f64>) {
        (&self.u, &self.v, &self.a)
    }

    /// Continue from a saved state: time (s) and the free DOFs'
    /// displacement, velocity and acceleration (of the beam's length: the
    /// caller checks), the forces placed as at that time.
    pub fn set_state(&mut self, time: f64, (u, v, a): (&[f64], &[f64], &[f64])) {
        self.time = time;
        self.u.copy_from_slice(u);
        self.v.copy_from_slice(v);
        self.a.copy_from_slice(a);
        self.place_loads(time);
    }

    /// The beam now, for its design outputs: Newmark's acceleration
    /// satisfies the equation of motion at the step's end.
    pub fn dynamics(&self) -> BeamDynamics<'static> {
        let state = (self.u.clone(), self.v.clone(), self.a.clone());
        BeamDynamics::with_acceleration(&self.beam, state, self.placed.clone())
    }

    /// Step until the last force has left the beam, and on to `end` (s)
    /// if that is later (`run_end`), recording the design outputs `probes`
    /// after each step
    /// (the state at rest at t = 0 is zero); refused when that is more
    /// than `max_steps` steps.
    pub fn design_peaks(
        &mut self,
        probes: &ProbeReader,
        end: f64,
        max_steps: u64,
    ) -> Result<DesignPeaks, String> {
        self.design_peaks_watching(probes, end, max_steps, |_, _, _| {})
    }

    /// `design_peaks`, calling `watch` with the crossing, its design
    /// outputs' state and the probes' values after each step (to record
    /// time histories).
    pub fn design_peaks_watching(
        &mut self,
        probes: &ProbeReader,
        end: f64,
        max_steps: u64,
        mut watch: impl FnMut(&Crossing, &BeamDynamics, &[f64]),
    ) -> Result<DesignPeaks, String> {
        let steps = self.steps_to(end, max_steps)?;
        let count = probes.probes().len();
        let mut peaks = DesignPeaks::new(count);
        let mut values = Vec::with_capacity(count);
        let mut now = self.dynamics();
        for _ in 0..steps {
            self.step();
            now.update((&self.u, &self.v, &self.a), self.placed.iter().copied());
            probes.read(&self.beam, &now, &mut values);
            peaks.take_in(&values);
            watch(self, &now, &values);
        }
        Ok(peaks)
    }

    /// Steps to `run_end(end, exit)`, refused beyond `max_steps`.
    fn steps_to(&self, end: f64, max_steps: u64) -> Result<u64, String> {
        let end = run_end(end, self.exit_time());
        let steps = (end / self.step).ceil();
        if steps.is_nan() || steps > max_steps as f64 {
            return Err(format!(
                "the crossing needs {steps} steps of {} s, more than the limit of {max_steps}",
                self.step
            ));
        }
        Ok(steps as u64)
    }

    /// Kinetic + strain energy of the beam (J).
    pub fn beam_energy(&self) -> f64 {
        self.beam.kinetic_energy(&self.v) + self.beam.strain_energy(&self.u)
    }

    /// Step until the last force has left the beam, and on to `end` (s)
    /// if that is later (`run_end`), and return the peaks at each of
    /// `sensors` (abscissae);
    /// refused when that is more than `max_steps` steps.
    pub fn peaks(
        &mut self,
        sensors: &[f64],
        end: f64,
        max_steps: u64,
    ) -> Result<Vec<Peaks>, String> {
        let steps = self.steps_to(end, max_steps)?;
        let mut peaks = vec![Peaks::default(); sensors.len()];
        for _ in 0..steps {
            self.step();
            for (peak, &x) in peaks.iter_mut().zip(sensors) {
                peak.deflection = peak.deflection.max(self.deflection(x).abs());
                peak.acceleration = peak.acceleration.max(self.acceleration(x).abs());
            }
        }
        Ok(peaks)
    }
}

/// The largest |static deflection| at `sensor` as the axles crawl across
/// the beam in their order: the sum of each force times the influence line
/// (by Maxwell's reciprocity, the deflection under a unit load at the
/// sensor), sampled every eighth of the shortest element.
pub fn static_peak(beam: &Beam, axles: &[Axle], sensor: f64) -> Result<f64, String> {
    let mut unit = DVector::zeros(beam.coordinates());
    let shape = beam.shape(beam.element_at(sensor), sensor);
    beam.scatter(&shape, &shape.n, 1.0, &mut unit);
    let influence = beam.static_deflection(&unit)?;
    let speed = axles.iter().map(|a| a.speed.abs()).fold(0.0, f64::max);
    if speed == 0.0 {
        return Err("the forces do not move".into());
    }
    let dt = beam.min_element_length() / 8.0 / speed;
    let samples = (exit_time(beam.length, axles) / dt).ceil();
    if samples.is_nan() || samples > 1e8 {
        return Err(format!("the static crawl needs {samples} samples"));
    }
    let length = beam.length;
    let mut peak: f64 = 0.0;
    for k in 0..=samples as u64 {
        let t = k as f64 * dt;
        let w: f64 = axles
            .iter()
            .map(|axle| (axle.at(t), axle.force))
            .filter(|(x, _)| (0.0..=length).contains(x))
            .map(|(x, force)| force * beam.deflection(&influence, x))
            .sum();
        peak = peak.max(w.abs());
    }
    Ok(peak)
}

/// When a crossing whose last force leaves at `exit` (s) ends: at `end`
/// (`solver.end_time`, infinite when not set) if that is later, the beam
/// vibrating freely after the exit; never before the exit, so that every
/// run of a speed sweep sees the whole passage.
pub fn run_end(end: f64, exit: f64) -> f64 {
    if end.is_finite() {
        end.max(exit)
    } else {
        exit
    }
}

/// When the last of `axles` has left a beam of `length` (s); infinite if
/// one never does.
pub fn exit_time(length: f64, axles: &[Axle]) -> f64 {
    axles
        .iter()
        .map(|axle| {
            let edge = if axle.speed > 0.0 { length } else { 0.0 };
            let time = (edge - axle.position) / axle.speed;
            if time.is_nan() {
                f64::INFINITY
            } else {
                time.max(0.0)
            }
        })
        .fold(0.0, f64::max)
}
