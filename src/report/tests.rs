//! Unit tests of the report sinks: CSV columns, the summary, plots and
//! their legends, the streaming run.

use super::*;
use crate::scene::{builtin, Scene, DEFAULT_SCENE};
use crate::simulation::OutputKind;

fn scene() -> Scene {
    builtin(DEFAULT_SCENE).unwrap()
}

/// A made-up run of the default scene: 5 rows at the scene's step, exit at
/// the last one.
fn synthetic_trace() -> Trace {
    let mut trace = Trace::with_names([
        "wheel.nominal_speed",
        "sensor.midspan.deflection",
        "energy.balance",
        "solver.iterations",
    ]);
    trace.kinds[3] = OutputKind::Integer;
    let rows = [
        (0.0, [10.0, 0.0, 150_000.0, 0.0]),
        (0.0025, [10.5, -0.05, 150_000.3, 4.0]),
        (0.005, [11.2, -0.19, 149_999.4, 3.0]),
        (0.0075, [10.1, -0.12, 150_000.0, 3.0]),
        (0.008, [9.96, 0.02, 150_000.15, 2.0]),
    ];
    for (time, values) in rows {
        trace.push(time, &values);
    }
    trace
}

#[test]
fn trace_columns_follow_the_pushed_rows() {
    let trace = synthetic_trace();
    assert_eq!(trace.len(), 5);
    assert_eq!(
        trace.column("sensor.midspan.deflection").unwrap(),
        [0.0, -0.05, -0.19, -0.12, 0.02]
    );
    assert!(trace.column("wheel.x").is_none());
}

#[test]
fn summary_takes_peaks_exit_drift_and_sums() {
    let summary = RunSummary::from_trace(&scene(), &synthetic_trace(), Some(0.008), 0.5);
    assert_eq!(summary.scene, "lee1994-wheel-10");
    assert_eq!(summary.exit_time, Some(0.008));
    assert_eq!(summary.exit_nominal_speed, Some(9.96));
    assert_eq!(summary.peak_nominal_speed, Some(11.2));
    assert_eq!(summary.peak_sensor_deflection["midspan"], -0.19);
    let drift = summary.max_energy_drift.unwrap();
    assert!((drift - 0.6 / 150_000.0).abs() < 1e-15, "{drift}");
    assert_eq!(summary.steps, 4);
    assert_eq!(summary.iterations, Some(12));
    assert_eq!(summary.wall_time_s, 0.5);
}

#[test]
fn summary_without_exit_or_outputs_has_nulls() {
    let mut trace = Trace::with_names(["other"]);
    trace.push(0.0, &[1.0]);
    trace.push(0.1, &[2.0]);
    let summary = RunSummary::from_trace(&scene(), &trace, None, 0.0);
    let json: serde_json::Value = serde_json::from_str(&summary.to_json()).unwrap();
    for key in [
        "exit_time",
        "exit_nominal_speed",
        "peak_nominal_speed",
        "max_energy_drift",
        "iterations",
    ] {
        assert!(json[key].is_null(), "{key} should be null: {json}");
    }
    assert_eq!(json["steps"], 1);
    assert_eq!(json["peak_sensor_deflection"], serde_json::json!({}));

    // Exited, but the exit speed is only known with a speed output.
    let with_exit = RunSummary::from_trace(&scene(), &synthetic_trace(), None, 0.0);
    assert_eq!(with_exit.exit_nominal_speed, None, "no exit, no exit speed");
}

#[test]
fn summary_json_has_the_documented_keys() {
    let summary = RunSummary::from_trace(&scene(), &synthetic_trace(), Some(0.008), 0.25);
    let json: serde_json::Value = serde_json::from_str(&summary.to_json()).unwrap();
    assert_eq!(json["scene"], "lee1994-wheel-10");
    assert_eq!(json["exit_time"], 0.008);
    assert_eq!(json["peak_sensor_deflection"]["midspan"], -0.19);
    assert_eq!(json["iterations"], 12);
    assert_eq!(json["wall_time_s"], 0.25);
    let back: RunSummary = serde_json::from_value(json).unwrap();
    assert_eq!(back, summary);
}

#[test]
fn human_summary_names_every_figure() {
    let text = RunSummary::from_trace(&scene(), &synthetic_trace(), Some(0.008), 0.002).to_string();
    for expected in [
        "exit time          0.008000 s",
        "exit speed V       9.9600 m/s",
        "peak speed V       11.2000 m/s",
        "-0.190000 m at sensor midspan",
        "max energy drift   4.000e-4 %",
        "steps              4",
        "iterations         12 (3.00 per step)",
        "2.000 ms",
    ] {
        assert!(text.contains(expected), "{expected:?} missing from\n{text}");
    }
}

#[test]
fn energy_drift_of_a_blown_up_run_is_infinite() {
    let mut trace = Trace::with_names(["energy.balance"]);
    trace.push(0.0, &[2.0]);
    trace.push(1.0, &[f64::NAN]);
    let summary = RunSummary::from_trace(&scene(), &trace, None, 0.0);
    assert_eq!(summary.max_energy_drift, Some(f64::INFINITY));
}

#[test]
fn csv_has_a_header_and_full_precision_rows() {
    let mut trace = Trace::with_names(["a", "n"]);
    trace.kinds[1] = OutputKind::Integer;
    trace.push(0.0, &[0.1 + 0.2, 3.0]);
    trace.push(0.0025, &[-1e-7, 4.0]);
    trace.push(0.005, &[f64::NAN, 5.0]);
    let mut bytes = Vec::new();
    csv::write_csv(&trace, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert_eq!(
        text,
        "time,a,n\n0.0,0.30000000000000004,3\n0.0025,-1e-7,4\n0.005,NaN,5\n"
    );
    // Every real reads back bit for bit.
    let second: Vec<f64> = text
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(second, [0.0025, -1e-7, 4.0]);
}

#[test]
fn static_deflection_is_the_papers_0_1728_m() {
    let delta = plot::static_deflection(&scene());
    assert!((delta - 0.1728).abs() < 1e-12, "{delta}");
}

fn assert_png(path: &std::path::Path) {
    let bytes = std::fs::read(path).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    assert!(
        bytes.len() > 5_000,
        "suspiciously small plot: {} bytes",
        bytes.len()
    );
}

#[test]
fn plot_is_written_with_and_without_text() {
    let dir = tempfile::tempdir().unwrap();
    let trace = synthetic_trace();

    let labelled = dir.path().join("labelled.png");
    plot::write_plot(&scene(), &trace, &labelled).unwrap();
    assert_png(&labelled);

    let bare = dir.path().join("bare.png");
    plot::draw(&scene(), &trace, &bare, plot::Text::Omitted).unwrap();
    assert_png(&bare);
}

#[test]
fn plot_survives_empty_and_constant_data() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.png");
    plot::write_plot(&scene(), &Trace::with_names(["x"]), &path).unwrap();
    assert_png(&path);

    let mut flat = Trace::with_names(["wheel.nominal_speed", "energy.balance"]);
    flat.push(0.0, &[10.0, 0.0]);
    flat.push(1.0, &[10.0, 0.0]);
    plot::write_plot(&scene(), &flat, &path).unwrap();
}

#[test]
fn plot_into_a_missing_directory_is_an_error_not_a_panic() {
    let error = plot::write_plot(
        &scene(),
        &synthetic_trace(),
        std::path::Path::new("/no/such/dir/plot.png"),
    )
    .unwrap_err();
    assert!(error.contains("/no/such/dir/plot.png"), "{error}");
}

#[test]
fn stop_time_defaults_to_ten_rigid_beam_travel_times() {
    let mut scene = scene();
    assert_eq!(stop_time(&scene), Ok(10.0 * 24.0 / 10.0));
    scene.vehicles[0].initial_speed = 0.0;
    let error = stop_time(&scene).unwrap_err();
    assert!(error.contains("body.initial_speed = 0.0"), "{error}");
    assert!(error.contains("solver.end_time"), "{error}");
    scene.solver.end_time = Some(1.5);
    assert_eq!(stop_time(&scene), Ok(1.5));
}

/// A train's progress follows the vehicle that leaves last: the paper's
/// wheel at x = 0 and a second one at x = −6 m on the 24 m beam, both at
/// 10 m/s. The rear one travels 30 m to leave, so at x = 9 m it is half
/// way (0.5), whatever the front wheel's x; by time alone, 0.1 of the stop.
#[test]
fn progress_follows_the_last_vehicle_to_leave() {
    let mut scene = Scene::lee1994(crate::scene::BodyKind::Wheel, 10.0, 0.0025);
    let mut rear = scene.vehicles[0].clone();
    rear.name = "rear".to_string();
    rear.initial_position = -6.0;
    scene.vehicles.push(rear);
    let names: Vec<String> = ["wheel.x", "rear.x"].map(String::from).to_vec();
    assert_eq!(progress_column(&scene, &names), Some(1));
    let fraction = stream::progress_fraction(&scene, &names, 0.0, 30.0);
    assert_eq!(fraction(3.0, &[24.0, 9.0]), 0.5);
    assert_eq!(fraction(3.0, &[24.0, -6.0]), 0.1);
    assert_eq!(fraction(3.0, &[24.0, 30.0]), 1.0);
}

#[test]
fn travel_position_prefers_the_contact_abscissa() {
    let names: Vec<String> = ["wheel.x", "contact.position"].map(String::from).to_vec();
    assert_eq!(output_names::travel_position(&names, "wheel"), Some(1));
    assert_eq!(output_names::travel_position(&names[..1], "wheel"), Some(0));
    assert_eq!(output_names::travel_position(&names[..1], "glider"), None);
}

/// A body sliding at constant speed along the default scene's beam; fails
/// at `fail_at` if given.
struct Slider {
    time: f64,
    speed: f64,
    length: f64,
    fail_at: Option<f64>,
    outputs: Vec<crate::simulation::OutputInfo>,
}

impl Slider {
    fn new(speed: f64, fail_at: Option<f64>) -> Slider {
        let output = |name: &str, kind| crate::simulation::OutputInfo {
            name: name.to_string(),
            unit: "",
            description: String::new(),
            kind,
        };
        Slider {
            time: 0.0,
            speed,
            length: 24.0,
            fail_at,
            outputs: vec![
                output("wheel.x", OutputKind::Real),
                output("wheel.nominal_speed", OutputKind::Real),
                output("solver.iterations", OutputKind::Integer),
            ],
        }
    }
}

impl Steppable for Slider {
    fn time(&self) -> f64 {
        self.time
    }
    fn outputs(&self) -> &[crate::simulation::OutputInfo] {
        &self.outputs
    }
    fn output_values(&self, values: &mut [f64]) {
        values.copy_from_slice(&[self.speed * self.time, self.speed, 2.0]);
    }
    fn advance_to(&mut self, t: f64) -> Result<crate::simulation::Advance, crate::SolverError> {
        if self.fail_at.is_some_and(|fail| t > fail) {
            return Err(crate::SolverError {
                time: self.time,
                message: "diverged".into(),
            });
        }
        let exit = self.length / self.speed;
        if t >= exit {
            self.time = exit;
            return Ok(crate::simulation::Advance::Exited { time: exit });
        }
        self.time = t;
        Ok(crate::simulation::Advance::Reached)
    }
}

#[test]
fn drive_records_every_step_up_to_the_exit() {
    let scene = scene();
    let mut fractions = Vec::new();
    let run = drive(&scene, &mut Slider::new(10.0, None), |p| {
        fractions.push(p.fraction)
    })
    .unwrap();
    // 2.4 s at 0.0025 s: 960 steps, the last one landing on the exit.
    assert_eq!(run.exit_time, Some(2.4));
    let time = &run.trace.time;
    assert_eq!(time.len(), 961);
    assert_eq!(time[0], 0.0);
    assert_eq!(time[1], 0.0025);
    assert_eq!(time[401], 401.0 * 0.0025, "exact multiples of the step");
    assert_eq!(*time.last().unwrap(), 2.4);
    assert_eq!(fractions.len(), 960);
    assert!(fractions.windows(2).all(|w| w[1] >= w[0]));
    assert!((fractions[479] - 0.5).abs() < 1e-9, "{}", fractions[479]);
    assert_eq!(*fractions.last().unwrap(), 1.0);

    let summary = run.summary(&scene);
    assert_eq!(summary.steps, 960);
    assert_eq!(summary.iterations, Some(2 * 960));
    assert_eq!(summary.exit_nominal_speed, Some(10.0));
}

#[test]
fn drive_stops_at_the_end_time_without_an_exit() {
    let mut scene = scene();
    scene.solver.end_time = Some(0.01);
    let run = drive(&scene, &mut Slider::new(10.0, None), |_| {}).unwrap();
    assert_eq!(run.exit_time, None);
    assert_eq!(run.trace.time, [0.0, 0.0025, 0.005, 0.0075, 0.01]);
    assert_eq!(run.summary(&scene).exit_nominal_speed, None);
}

#[test]
fn drive_returns_the_steps_before_a_solver_failure() {
    let scene = scene();
    let error = drive(&scene, &mut Slider::new(10.0, Some(0.006)), |_| {}).unwrap_err();
    let RunError::Solver { error, partial } = error else {
        panic!("expected a solver failure");
    };
    assert_eq!(error.message, "diverged");
    assert_eq!(partial.trace.time, [0.0, 0.0025, 0.005]);
    assert_eq!(partial.exit_time, None);
}

/// A slider whose speed output turns NaN after `after` (an overflowing
/// state, as a huge speed or a subnormal radius gave on main).
struct Blowup {
    slider: Slider,
    after: f64,
}

impl Steppable for Blowup {
    fn time(&self) -> f64 {
        self.slider.time
    }
    fn outputs(&self) -> &[crate::simulation::OutputInfo] {
        &self.slider.outputs
    }
    fn output_values(&self, values: &mut [f64]) {
        self.slider.output_values(values);
        if self.slider.time > self.after {
            values[1] = f64::NAN;
        }
    }
    fn advance_to(&mut self, t: f64) -> Result<crate::simulation::Advance, crate::SolverError> {
        self.slider.advance_to(t)
    }
}

#[test]
fn a_non_finite_output_stops_the_run_and_is_never_recorded() {
    let scene = scene();
    let mut blowup = Blowup {
        slider: Slider::new(10.0, None),
        after: 0.006,
    };
    let error = drive(&scene, &mut blowup, |_| {}).unwrap_err();
    let RunError::Solver { error, partial } = error else {
        panic!("expected a solver failure, got {error:?}");
    };
    assert!(
        error.message.contains("output wheel.nominal_speed is NaN"),
        "{}",
        error.message
    );
    assert_eq!(error.time, 0.0075);
    assert_eq!(partial.trace.time, [0.0, 0.0025, 0.005]);
    assert!(partial
        .trace
        .columns
        .iter()
        .flatten()
        .all(|x| x.is_finite()));

    // non-finite from the start: refused before the first step
    let mut blowup = Blowup {
        slider: Slider::new(10.0, None),
        after: -1.0,
    };
    let error = drive(&scene, &mut blowup, |_| {}).unwrap_err();
    assert!(
        matches!(&error, RunError::Setup(m) if m.contains("wheel.nominal_speed is NaN at the start")),
        "{error:?}"
    );
}

#[test]
fn a_streamed_run_stops_when_asked_after_a_whole_row() {
    let scene = scene();
    let mut trace = Trace::for_outputs(Slider::new(10.0, None).outputs());
    let mut calls = 0;
    let error = drive_into(&scene, &mut Slider::new(10.0, None), &mut trace, |_| {
        calls += 1;
        if calls == 3 {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    })
    .unwrap_err();
    assert_eq!(
        error,
        StreamError::Interrupted {
            time: 0.0075,
            steps: 3
        }
    );
    assert_eq!(trace.time, [0.0, 0.0025, 0.005, 0.0075]);
}

#[test]
fn a_summary_built_row_by_row_matches_the_one_from_the_trace() {
    let trace = synthetic_trace();
    let mut builder = SummaryBuilder::new(&scene(), &trace.names);
    for (row, &time) in trace.time.iter().enumerate() {
        let values: Vec<f64> = trace.columns.iter().map(|c| c[row]).collect();
        builder.push(time, &values);
    }
    let streamed = builder.finish(Some(0.008), 1.0);
    let summary = RunSummary::from_trace(&scene(), &trace, Some(0.008), 1.0);
    assert_eq!(streamed, summary);
    assert_eq!(summary.steps, 4);
    assert_eq!(summary.iterations, Some(12));
    assert_eq!(summary.peak_nominal_speed, Some(11.2));
    assert_eq!(summary.exit_nominal_speed, Some(9.96));
    assert_eq!(summary.peak_sensor_deflection["midspan"], -0.19);
    let drift = summary.max_energy_drift.unwrap();
    assert!((drift - 0.6 / 150_000.0).abs() < 1e-15, "{drift}");
}

#[test]
fn a_decimated_trace_stays_bounded_and_keeps_first_and_last_rows() {
    let mut decimated = Decimated::new(Trace::with_names(["x"]), 100);
    for i in 0..100_001 {
        decimated.push(i as f64, &[2.0 * i as f64]);
    }
    let trace = decimated.finish();
    assert!(trace.len() >= 100 && trace.len() <= 201, "{}", trace.len());
    assert_eq!(trace.time[0], 0.0);
    assert_eq!(*trace.time.last().unwrap(), 100_000.0);
    assert!(trace.time.windows(2).all(|w| w[1] > w[0]));
    let stride = trace.time[1] - trace.time[0];
    assert!(trace.time[..trace.len() - 1]
        .windows(2)
        .all(|w| w[1] - w[0] == stride));
    assert!(trace
        .time
        .iter()
        .zip(&trace.columns[0])
        .all(|(t, x)| *x == 2.0 * t));
}

#[test]
fn the_run_length_is_refused_beyond_the_limit_and_below_the_time_resolution() {
    let mut scene = scene();
    // stop time if the body never left: 10 × 24 / 10 = 24 s, 9600 steps
    assert_eq!(check_run_length(&scene, 9600, ""), Ok(9600));
    let e = check_run_length(&scene, 9599, " (raise it)").unwrap_err();
    assert!(
        e.contains("9.6e3 steps") && e.ends_with("limit of 9599 steps (raise it)"),
        "{e}"
    );
    scene.vehicles[0].initial_speed = 1e14;
    let e = check_run_length(&scene, u64::MAX, "").unwrap_err();
    assert!(e.contains("no step would be taken"), "{e}");
    scene.vehicles[0].initial_speed = 5e-324;
    assert!(
        check_run_length(&scene, u64::MAX, "").is_err(),
        "an infinite run"
    );
}

#[test]
fn summary_lists_each_contacts_entry_and_exit() {
    use crate::simulation::Simulation;
    // The paper's wheel from 5 m before the beam onto 30 m of run-off.
    let mut scene = scene();
    scene.track.approach = 5.0;
    scene.track.run_off = 30.0;
    scene.vehicles[0].initial_position = -5.0;
    scene.solver.end_time = Some(3.0);
    let mut sim = Simulation::new(&scene).unwrap();
    sim.advance_to(3.0).unwrap();
    let mut summary = RunSummary::from_trace(&scene, &synthetic_trace(), None, 0.0);
    summary.events = super::SummaryEvent::list(&sim);
    let kinds: Vec<&str> = summary.events.iter().map(|e| e.kind.as_str()).collect();
    assert_eq!(kinds, ["entry", "exit"]);
    assert_eq!(summary.events[0].contact, "contact");
    assert!(
        (summary.events[0].time - 0.5).abs() < 1e-6,
        "{:?}",
        summary.events
    );
    let exit = summary.events[1].time;
    assert!((exit - 0.5 - 2.275).abs() < 1e-2, "{exit}");
    let text = summary.to_string();
    assert!(
        text.contains("event              entry      contact at 0.500000 s"),
        "{text}"
    );
    let json: RunSummary = serde_json::from_str(&summary.to_json()).unwrap();
    assert_eq!(json.events, summary.events);
    // A run without events keeps its JSON as it was.
    summary.events.clear();
    assert!(!summary.to_json().contains("events"));
}

#[test]
fn speed_ticks_stay_distinct_at_any_range() {
    // About ten ticks over the range: their labels must differ.
    for (low, high) in [(9.998, 10.003), (0.0, 1e4), (0.1, 0.1005), (10.0, 11.2)] {
        let span = high - low;
        let decimals = plot::tick_decimals(span).max(2);
        let labels: Vec<String> = (0..=10)
            .map(|k| plot::tick_label(low + span * k as f64 / 10.0, span, Some(decimals)))
            .collect();
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(unique.len(), labels.len(), "{low}..{high}: {labels:?}");
    }
    // The paper's speed axis keeps its two decimals.
    assert!(plot::tick_decimals(1.2) <= 2);
}

#[test]
fn round_off_around_zero_is_labelled_zero() {
    assert_eq!(plot::tick_label(-4.1e-25, 1.6e-5, None), "0");
    assert_eq!(plot::tick_label(2e-6, 1.6e-5, None), "2.0e-6");
    assert_eq!(plot::tick_label(-1e-17, 2.0, Some(2)), "0");
    assert_eq!(plot::tick_label(-0.2, 2.0, Some(2)), "-0.20");
}

#[test]
fn legends_go_to_the_corner_the_curves_leave_free() {
    use plotters::prelude::SeriesLabelPosition as At;
    let curve = |points: Vec<(f64, f64)>| plot::Curve {
        label: "c".into(),
        points,
    };
    let (x, y) = (0.0..1.0, 0.0..1.0);
    let ramp = |f: fn(f64) -> f64| {
        curve(
            (0..=100)
                .map(|k| (k as f64 / 100.0, f(k as f64 / 100.0)))
                .collect(),
        )
    };
    // A curve hugging the top: the legend goes below.
    let top = plot::least_crowded_corner(&[ramp(|_| 0.95)], &x, &y, 0.24).0;
    assert!(matches!(top, At::LowerRight | At::LowerLeft), "{top:?}");
    // A rise from lower left to upper right leaves the other two corners.
    let rise = plot::least_crowded_corner(&[ramp(|t| t)], &x, &y, 0.24).0;
    assert!(matches!(rise, At::UpperLeft | At::LowerRight), "{rise:?}");
    // A dip in the middle (the deflection) leaves the lower corners free.
    let dip = plot::least_crowded_corner(
        &[ramp(|t| 1.0 - libm::sin(std::f64::consts::PI * t))],
        &x,
        &y,
        0.24,
    )
    .0;
    assert!(matches!(dip, At::LowerRight | At::LowerLeft), "{dip:?}");
}

#[test]
fn a_curve_that_fills_its_panel_gets_room_above_it_for_the_legend() {
    use plotters::prelude::SeriesLabelPosition as At;
    // A force chattering over the whole panel (its range padded by 5 %):
    // every corner is crowded.
    let chatter = || plot::Curve {
        label: "c".into(),
        points: (0..=1000)
            .map(|k| (k as f64 / 1000.0, if k % 2 == 0 { 0.05 } else { 0.95 }))
            .collect(),
    };
    let x = 0.0..1.0;
    let (corner, y) = plot::legend_place(&[chatter()], &x, 0.0..1.0, 0.25);
    assert!(matches!(corner, At::UpperRight), "{corner:?}");
    // The data fill the lower three quarters; the box the top quarter.
    assert!((y.end - 4.0 / 3.0).abs() < 1e-12, "{y:?}");
    let (_, covered) = plot::least_crowded_corner(&[chatter()], &x, &y, 0.25);
    assert_eq!(covered, 0);
    // A curve that leaves a corner free keeps its range.
    let low = plot::Curve {
        label: "c".into(),
        points: vec![(0.0, 0.0), (1.0, 0.1)],
    };
    let (_, y) = plot::legend_place(&[low], &x, 0.0..1.0, 0.25);
    assert_eq!(y, 0.0..1.0);
}

#[test]
fn deflection_is_scaled_by_the_static_peak_of_the_actual_structure() {
    // One span, simply supported: P L³ / 48 EI = 0.1728 m.
    let (scale, label) = plot::deflection_scale(&scene());
    assert!((scale - 0.1728).abs() < 1e-9, "{scale}");
    assert!(label.contains("0.1728"), "{label}");
    // Clamped at both ends: P L³ / 192 EI, a quarter of it.
    let mut clamped = scene();
    clamped.beam.supports.left = crate::scene::EndSupport::Clamped;
    clamped.beam.supports.right = crate::scene::EndSupport::Clamped;
    let (scale, _) = plot::deflection_scale(&clamped);
    assert!((scale - 0.1728 / 4.0).abs() < 1e-9, "{scale}");
    // Two sensors with different static peaks: no single value, mm.
    let mut two = scene();
    two.sensors.push(crate::scene::SensorSpec {
        name: "quarter".into(),
        position: 6.0,
    });
    assert_eq!(
        plot::deflection_scale(&two),
        (1e-3, "deflection (mm)".to_string())
    );
}

/// The branch-free sum (four sums side by side, then the rest) finds a
/// non-finite value wherever it is, in lists of any length.
#[test]
fn a_non_finite_output_is_found_at_any_position() {
    for n in 0..12 {
        let outputs: Vec<crate::simulation::OutputInfo> = (0..n)
            .map(|k| crate::simulation::OutputInfo {
                name: format!("out{k}"),
                unit: "",
                description: String::new(),
                kind: OutputKind::Real,
            })
            .collect();
        let finite: Vec<f64> = (0..n).map(|k| k as f64 - 1e300).collect();
        assert_eq!(non_finite_output(&outputs, &finite), None);
        for k in 0..n {
            for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut values = finite.clone();
                values[k] = x;
                let found = non_finite_output(&outputs, &values);
                assert_eq!(found, Some(format!("output out{k} is {x}")), "{n} {k}");
            }
        }
    }
}
