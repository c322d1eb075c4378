//! Speed sweeps of vehicle scenes (every body kind, trains): the scene run
//! at every speed of a range, each run exactly as `guideway run` would run
//! the scene with its speeds edited (`scene_at_speed`), in parallel; per
//! run the same envelope row as a moving-force sweep (design peaks, the
//! filtered deck acceleration, DAF against the static envelope of the
//! vehicles' static axle loads).

use super::sweep::{
    in_parallel, largest_sensor_peak, with_deck_sensor, DesignPeak, EnvelopeRow, SpeedUnit,
};
use crate::design::{probes, StaticEnvelope};
use crate::outputs::{reports, QuantityKind};
use crate::report::{check_run_length, RunSummary};
use crate::scene::{BodySpec, Scene, SpeedSpec};
use crate::simulation::run_end::{run_end, RunEnd};

/// How every run of a sweep is made from the scene: the speed factor is
/// `speed / reference`; the end and the track follow from it.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedPlan {
    /// |body.initial_speed| (m/s): the speed the scene is written for.
    pub reference: f64,
    /// The scene's end relative to the speed: none (the run ends at the
    /// last exit, whatever the speed), the time it runs on after the last
    /// exit (s), or the distance travelled when it ends before that.
    pub end: SweepEnd,
    /// The approach and run-off every run of the sweep has (m): the
    /// scene's, lengthened to hold its fastest run to its end.
    pub approach: f64,
    pub run_off: f64,
}

/// How the end of a sweep's run follows from its speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SweepEnd {
    /// No `solver.end_time`: the run ends when the last contact leaves.
    LastExit,
    /// `end_time` = the last exit at the run's speed + this (s): the free
    /// vibration after the vehicles have left lasts as long at every speed.
    AfterExit(f64),
    /// The scene ends before the last exit: `end_time` = this factor (the
    /// scene's end time at its own speed) / the speed factor, so every run
    /// ends at the same place.
    SameDistance(f64),
}

impl SpeedPlan {
    /// The plan of sweeping `scene` over `speeds` (m/s); refused when its
    /// first vehicle does not move (nothing to scale).
    pub fn new(scene: &Scene, speeds: &[f64]) -> Result<SpeedPlan, String> {
        let reference = scene.vehicles[0].initial_speed.abs();
        if !(reference > 0.0 && reference.is_finite()) {
            return Err(format!(
                "body.initial_speed = {}: a sweep scales every vehicle's speed by \
                 speed / |body.initial_speed|, so the first vehicle must move",
                scene.vehicles[0].initial_speed
            ));
        }
        let end = match scene.solver.end_time {
            None => SweepEnd::LastExit,
            Some(end_time) => match last_exit(scene) {
                Some(exit) if end_time >= exit => SweepEnd::AfterExit(end_time - exit),
                _ => SweepEnd::SameDistance(end_time),
            },
        };
        let fastest = speeds.iter().fold(0.0f64, |a, &v| a.max(v)) / reference;
        let (mut approach, mut run_off) = (scene.track.approach, scene.track.run_off);
        if let SweepEnd::AfterExit(tail) = end {
            // Over the free vibration a faster run goes further: the track
            // grows by what the fastest vehicle travels beyond the scene's.
            let extra = |v: &BodySpec| tail * v.initial_speed.abs() * (fastest - 1.0).max(0.0);
            for v in scene.vehicles.iter() {
                if v.initial_speed > 0.0 {
                    run_off = run_off.max(scene.track.run_off + extra(v));
                } else {
                    approach = approach.max(scene.track.approach + extra(v));
                }
            }
        }
        Ok(SpeedPlan {
            reference,
            end,
            approach,
            run_off,
        })
    }
}

/// When the last contact leaves the beam at the vehicles' initial speeds
/// (`simulation::run_end`'s estimate), if one moves.
fn last_exit(scene: &Scene) -> Option<f64> {
    let mut open = scene.clone();
    open.solver.end_time = None;
    match run_end(&open) {
        RunEnd::LastExit { distance, speed } => Some(distance / speed),
        RunEnd::EndTime(_) | RunEnd::NoExit => None,
    }
}

/// `scene` at sweep speed `speed` (m/s): every vehicle's initial and
/// prescribed speed times `speed / plan.reference` (a train moves as one,
/// its spacing kept; a speed table keeps its shape along the track, its
/// times divided by the factor), the end time and track of `plan`.
pub fn scene_at_speed(scene: &Scene, plan: &SpeedPlan, speed: f64) -> Scene {
    let factor = speed / plan.reference;
    let mut at = scene.clone();
    for v in at.vehicles.iter_mut() {
        v.initial_speed *= factor;
        v.prescribed_speed = v.prescribed_speed.take().map(|s| match s {
            SpeedSpec::Constant(u) => SpeedSpec::Constant(u * factor),
            SpeedSpec::Table(rows) => SpeedSpec::Table(
                rows.into_iter()
                    .map(|[t, u]| [t / factor, u * factor])
                    .collect(),
            ),
        });
    }
    at.track.approach = plan.approach;
    at.track.run_off = plan.run_off;
    at.solver.end_time = match plan.end {
        SweepEnd::LastExit => None,
        SweepEnd::AfterExit(tail) => last_exit(&at).map(|exit| exit + tail),
        SweepEnd::SameDistance(end_time) => Some(end_time / factor),
    };
    at
}

/// Every run of the sweep of vehicle scene `scene` (`speeds` in `unit`),
/// `threads` at a time, rows in the speeds' order; refused beyond
/// `max_steps` steps in all.
pub fn sweep(
    scene: &Scene,
    (speeds, unit): (&[f64], SpeedUnit),
    threads: usize,
    max_steps: u64,
) -> Result<Vec<EnvelopeRow>, String> {
    let scene = &with_deck_sensor(scene);
    let to_m_s = unit.in_metres_per_second();
    let in_m_s: Vec<f64> = speeds.iter().map(|v| v * to_m_s).collect();
    let plan = SpeedPlan::new(scene, &in_m_s)?;
    let runs: Vec<Scene> = in_m_s
        .iter()
        .map(|&v| scene_at_speed(scene, &plan, v))
        .collect();
    let mut total = 0u64;
    for (run, speed) in runs.iter().zip(speeds) {
        let at = |e: String| format!("at {speed} {}: {e}", unit.label());
        let per_run = super::sweep::MAX_STEPS_PER_RUN;
        total = total.saturating_add(check_run_length(run, per_run, "").map_err(at)?);
    }
    if total > max_steps {
        return Err(format!(
            "the sweep needs up to {total} steps of solver.step = {} s in all, more than the \
             limit of {max_steps} (--max-steps)",
            scene.solver.step
        ));
    }
    // The static loads do not depend on the speed: one envelope for all.
    let statics = crate::design::static_envelope(scene)?;
    let jobs: Vec<usize> = (0..runs.len()).collect();
    in_parallel(&jobs, threads, |i| {
        let summary = super::refine::summarise(&runs[i], super::sweep::MAX_STEPS_PER_RUN)
            .map_err(|e| format!("at {} {}: {e}", speeds[i], unit.label()))?;
        envelope_row(&runs[i], &statics, (speeds[i], in_m_s[i]), &summary)
    })
}

/// The row of one run from its summary (the figures `guideway run
/// --summary` reports for the same scene, bit for bit).
fn envelope_row(
    scene: &Scene,
    statics: &StaticEnvelope,
    (speed, speed_m_s): (f64, f64),
    summary: &RunSummary,
) -> Result<EnvelopeRow, String> {
    let beam = crate::beam::Beam::new(&scene.beam)?;
    let peak = |name: &str| {
        summary
            .peak_design
            .get(name)
            .copied()
            .ok_or_else(|| format!("{name} has no finite value in the run at {speed_m_s} m/s"))
    };
    let mut design = Vec::new();
    for probe in probes(scene, &beam) {
        let value = peak(&probe.name)?;
        design.push(DesignPeak {
            daf: statics.amplification(&probe.name, value),
            is_static: probe.is_static(),
            name: probe.name,
            peak: value,
        });
    }
    let largest = |kind| largest_sensor_peak(&design, kind);
    let deflection = largest(QuantityKind::Sensor);
    let acceleration = largest(QuantityKind::SensorAcceleration);
    let mut filtered = 0.0f64;
    for sensor in &scene.sensors {
        let name = format!("sensor.{}.acceleration_filtered", sensor.name);
        let value = peak(&name)?;
        filtered = filtered.max(value.abs());
        design.push(DesignPeak {
            name,
            peak: value,
            is_static: false,
            daf: None,
        });
    }
    let static_deflection = statics
        .peaks
        .iter()
        .filter(|(name, _)| reports(name, QuantityKind::Sensor))
        .map(|(_, &peak)| peak)
        .fold(0.0, f64::max);
    Ok(EnvelopeRow {
        train: scene.name.clone(),
        speed,
        speed_m_s,
        peak_deflection: deflection,
        peak_acceleration: acceleration,
        peak_acceleration_filtered: filtered,
        acceleration_cut_off: summary.acceleration_cut_off_hz.unwrap_or(f64::NAN),
        daf: deflection / static_deflection,
        design,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::BodyKind;

    /// The paper's wheel (24 m, from x = 0 at 10 m/s: it leaves at 2.4 s)
    /// and a second one 6 m behind (it leaves at 3 s), with 1 s of free
    /// vibration after: at 20 m/s the last exit is at 30 / 20 = 1.5 s, the
    /// run ends at 2.5 s, and the run-off grows by the 10 m/s × 1 s more
    /// the front wheel travels over the free vibration.
    #[test]
    fn the_free_vibration_lasts_as_long_at_every_speed() {
        let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let mut rear = scene.vehicles[0].clone();
        rear.name = "rear".into();
        rear.initial_position = -6.0;
        scene.vehicles.push(rear);
        scene.track = crate::scene::TrackSpec {
            approach: 8.0,
            run_off: 15.0,
            irregularities: Vec::new(),
            on_deck: None,
        };
        scene.solver.end_time = Some(4.0);
        let plan = SpeedPlan::new(&scene, &[5.0, 20.0]).unwrap();
        assert_eq!(plan.end, SweepEnd::AfterExit(1.0));
        assert_eq!((plan.approach, plan.run_off), (8.0, 25.0));
        let fast = scene_at_speed(&scene, &plan, 20.0);
        assert_eq!(fast.solver.end_time, Some(2.5));
        assert_eq!(
            (
                fast.vehicles[0].initial_speed,
                fast.vehicles[1].initial_speed
            ),
            (20.0, 20.0)
        );
        assert_eq!(fast.vehicles[1].initial_position, -6.0);
        let slow = scene_at_speed(&scene, &plan, 5.0);
        assert_eq!(slow.solver.end_time, Some(7.0));
        assert_eq!(slow.track.run_off, 25.0, "one track for the whole sweep");
    }

    /// A scene that ends before its vehicle leaves ends at the same place
    /// at every speed; one without an end time ends at the exit; a speed
    /// table keeps its shape along the track.
    #[test]
    fn other_ends_and_speed_tables_follow_the_distance() {
        let mut scene = Scene::lee1994(BodyKind::Glider, 10.0, 0.0025);
        scene.vehicles[0].prescribed_speed = Some(SpeedSpec::Table(vec![[0.0, 10.0], [1.0, 12.0]]));
        scene.solver.end_time = Some(1.2);
        let plan = SpeedPlan::new(&scene, &[40.0]).unwrap();
        assert_eq!(plan.end, SweepEnd::SameDistance(1.2));
        let fast = scene_at_speed(&scene, &plan, 40.0);
        assert_eq!(fast.solver.end_time, Some(0.3));
        assert_eq!(
            fast.vehicles[0].prescribed_speed,
            Some(SpeedSpec::Table(vec![[0.0, 40.0], [0.25, 48.0]]))
        );
        assert_eq!(fast.track, scene.track);
        scene.solver.end_time = None;
        let plan = SpeedPlan::new(&scene, &[40.0]).unwrap();
        assert_eq!(scene_at_speed(&scene, &plan, 40.0).solver.end_time, None);
        scene.vehicles[0].initial_speed = 0.0;
        let refused = SpeedPlan::new(&scene, &[40.0]).unwrap_err();
        assert!(refused.contains("body.initial_speed = 0"), "{refused}");
    }
}
