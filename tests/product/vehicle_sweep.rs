//! `guideway sweep` of vehicle scenes (issue 26 item 5): a sweep equals
//! the runs done one by one with `guideway run` (the speed edited in the
//! scene's text) bit for bit, on 1 and 2 threads; a sprung mass crawling
//! across at a prescribed speed deflects the beam by the static P L³ / 48 EI
//! of its whole weight; every vehicle kind holds a prescribed speed on
//! every one of its bodies.

use crate::common;
use common::cli::guideway_ok;
use std::collections::BTreeMap;
use std::path::Path;

use guideway::scene::{Scene, SpeedSpec};
use guideway::Simulation;

/// A train of two sprung masses, 8 m apart, from the approach over a 20 m
/// beam (a section at the quarter point, reactions) and onto the run-off,
/// ending when the rear one has left: `{speed}` is each one's speed.
const TRAIN: &str = r#"
name = "two-sprung-masses"
gravity = 9.81
reactions = true
[beam]
length = 20.0
mass_per_length = 6000.0
bending_stiffness = 8.0e9
surface_offset = 0.0
elements = 8
[beam.damping]
ratio = 0.02
modes = [1, 3]
[track]
approach = 12.0
run_off = 12.0
[body]
name = "front"
kind = "sprung_mass"
mass = 20000.0
initial_position = -2.0
initial_speed = {speed}
[body.suspension]
stiffness = 2.0e6
damping = 4.0e4
unsprung_mass = 2000.0
[[vehicles]]
name = "rear"
kind = "sprung_mass"
mass = 20000.0
initial_position = -10.0
initial_speed = {speed}
[vehicles.suspension]
stiffness = 2.0e6
damping = 4.0e4
unsprung_mass = 2000.0
[[sensors]]
name = "mid"
position = 10.0
[[sections]]
name = "quarter"
position = 5.0
[solver]
step = 0.002
integrator = "hht"
"#;

/// The sweep's CSV as (header, rows of numbers after the train's name).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("the envelope is written");
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    let header = header.split(',').map(str::to_string).collect();
    let rows = lines
        .map(|line| {
            line.split(',')
                .skip(1)
                .map(|x| {
                    if x.is_empty() {
                        f64::NAN
                    } else {
                        x.parse().unwrap()
                    }
                })
                .collect()
        })
        .collect();
    (header, rows)
}

/// Every peak (`peak_design`) and DAF (`<name>.daf`) of `guideway run
/// --summary` of the train at `speed` m/s.
fn run_one_by_one(dir: &Path, speed: &str) -> BTreeMap<String, f64> {
    let scene = dir.join(format!("train-{speed}.toml"));
    std::fs::write(&scene, TRAIN.replace("{speed}", speed)).unwrap();
    let summary = dir.join(format!("summary-{speed}.json"));
    guideway_ok(&[
        "run",
        scene.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
        "--quiet",
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(summary).unwrap()).unwrap();
    let mut figures = BTreeMap::new();
    for (name, value) in json["peak_design"].as_object().unwrap() {
        figures.insert(name.clone(), value.as_f64().unwrap());
    }
    for (name, value) in json["dynamic_amplification"].as_object().unwrap() {
        figures.insert(format!("{name}.daf"), value.as_f64().unwrap());
    }
    figures
}

/// The envelope of a sweep of the train over 8, 10 and 12 m/s on
/// `threads` threads.
fn sweep(dir: &Path, threads: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let scene = dir.join("train.toml");
    std::fs::write(&scene, TRAIN.replace("{speed}", "10.0")).unwrap();
    let out = dir.join(format!("sweep-{threads}.csv"));
    guideway_ok(&[
        "sweep",
        scene.to_str().unwrap(),
        "--speeds",
        "8:12:2",
        "--threads",
        threads,
        "--out",
        out.to_str().unwrap(),
    ]);
    read_csv(&out)
}

#[test]
fn a_vehicle_sweep_equals_the_runs_done_one_by_one() {
    let dir = tempfile::tempdir().unwrap();
    let (header, rows) = sweep(dir.path(), "2");
    assert_eq!(sweep(dir.path(), "1"), (header.clone(), rows.clone()));
    assert_eq!(rows.len(), 3);
    for (row, speed) in rows.iter().zip(["8.0", "10.0", "12.0"]) {
        let column = |name: &str| header.iter().position(|h| h == name).unwrap() - 1;
        assert_eq!(row[column("speed_m_s")], speed.parse::<f64>().unwrap());
        let one = run_one_by_one(dir.path(), speed);
        let design: Vec<&String> = header.iter().filter(|h| h.contains('.')).collect();
        // Every design output, its DAF and each filtered acceleration.
        assert_eq!(design.len(), one.len(), "{design:?} vs {one:?}");
        for name in design {
            let (swept, run) = (row[column(name)], one[name]);
            assert_eq!(swept.to_bits(), run.to_bits(), "{name} at {speed} m/s");
        }
        let deflection = one["sensor.mid.deflection"].abs();
        assert_eq!(row[column("peak_deflection_m")], deflection);
        let daf = one["sensor.mid.deflection.daf"];
        assert_eq!(
            row[column("daf")],
            daf,
            "one sensor: the deck's DAF is its own"
        );
    }
}

/// A sprung mass (20 t on 2 t) at a prescribed speed over a 20 m beam
/// (f1 = 5.6 Hz): crawling, it deflects midspan by the static deflection of
/// its whole weight, P L³ / 48 EI with P = (M + m) g.
const CRAWLER: &str = r#"
name = "crawler"
gravity = 9.81
[beam]
length = 20.0
mass_per_length = 6000.0
bending_stiffness = 8.0e9
surface_offset = 0.0
elements = 8
[beam.damping]
ratio = 0.02
modes = [1, 3]
[track]
approach = 2.0
run_off = 2.0
[body]
name = "car"
kind = "sprung_mass"
mass = 20000.0
initial_position = -1.0
initial_speed = 1.0
prescribed_speed = 1.0
[body.suspension]
stiffness = 2.0e6
damping = 4.0e4
unsprung_mass = 2000.0
[[sensors]]
name = "mid"
position = 10.0
[solver]
step = 0.004
integrator = "hht"
"#;

#[test]
fn a_sprung_mass_crawling_deflects_the_beam_by_its_static_deflection() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("crawler.toml");
    std::fs::write(&scene, CRAWLER).unwrap();
    let out = dir.path().join("sweep.csv");
    guideway_ok(&[
        "sweep",
        scene.to_str().unwrap(),
        "--speeds",
        "0.5:2:0.75",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (header, rows) = read_csv(&out);
    let column = |name: &str| header.iter().position(|h| h == name).unwrap() - 1;
    let weight = (20000.0 + 2000.0) * 9.81;
    let (length, stiffness) = (20.0f64, 8.0e9);
    let statics = weight * length.powi(3) / (48.0 * stiffness);
    let errors: Vec<f64> = rows
        .iter()
        .map(|row| row[column("peak_deflection_m")] / statics - 1.0)
        .collect();
    eprintln!("static {statics:.6e} m; relative excess at 0.5, 1.25, 2 m/s: {errors:?}");
    assert!(errors[0].abs() < 1e-4, "at 0.5 m/s: {}", errors[0]);
    assert!(
        errors[0].abs() < errors[2].abs(),
        "slower is closer: {errors:?}"
    );
    // The DAF's reference is the same closed form.
    let reference = rows[0][column("peak_deflection_m")] / rows[0][column("daf")];
    assert!(
        (reference / statics - 1.0).abs() < 1e-9,
        "{reference} vs {statics}"
    );
}

/// Each vehicle kind that has bodies, driven by a speed table (10 m/s,
/// then 14 m/s from t = 0.2 s): every body of it moves at the table's
/// speed at the end of the run.
#[test]
fn every_vehicle_kind_holds_a_prescribed_speed_on_every_body() {
    let kinds = [
        ("lee1994-wheel-10", None),
        ("lee1994-glider-30", None),
        ("train-3-coaches-2x25-5", Some(0.3)),
        ("train-2-coaches-2x40-100", Some(0.3)),
    ];
    for (name, end) in kinds {
        let mut scene = Scene::load(name).unwrap();
        check_driven(&mut scene, end);
    }
    for text in [CRAWLER.to_string(), maglev_crawler()] {
        let mut scene = Scene::from_toml_str(&text).unwrap();
        // RK4 holds the table to rounding (its step's ẍ is constant);
        // HHT-α's trapezoidal velocity update follows a corner of the
        // table one step late (1e-6 m/s here).
        scene.solver.integrator = guideway::scene::IntegratorKind::Rk4;
        scene.solver.step = 2.5e-4;
        check_driven(&mut scene, Some(0.3));
    }
}

/// The crawler as a maglev vehicle of three magnets.
fn maglev_crawler() -> String {
    let head = CRAWLER.split("[body.suspension]").next().unwrap();
    let tail = CRAWLER.split("unsprung_mass = 2000.0").nth(1).unwrap();
    format!(
        "{}[body.maglev]\ncar_inertia = 1e5\nmagnets = 3\nmagnet_spacing = 0.5\n\
         magnet_mass = 500.0\nstiffness = 2.0e6\ndamping = 4.0e4\n{tail}",
        head.replace("sprung_mass", "maglev_vehicle")
    )
}

/// Drive every vehicle of `scene` by the table, run it to `end` s (else
/// its own end time) and check every body's final horizontal speed.
fn check_driven(scene: &mut Scene, end: Option<f64>) {
    let table = |v: f64| SpeedSpec::Table(vec![[0.0, v], [0.2, 1.4 * v]]);
    for v in scene.vehicles.iter_mut() {
        v.prescribed_speed = Some(table(v.initial_speed));
    }
    let end = end.or(scene.solver.end_time).unwrap_or(0.3);
    let mut sim = Simulation::new(scene).expect("scene builds");
    let steps = (end / scene.solver.step).round() as u64;
    for k in 1..=steps {
        sim.advance_to(k as f64 * scene.solver.step)
            .expect("step converges");
    }
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    let mut checked = 0;
    for v in scene.vehicles.iter() {
        let held = 1.4 * v.initial_speed;
        for body in v.body_names() {
            let k = names.iter().position(|n| *n == format!("{body}.vx"));
            let vx = values[k.unwrap_or_else(|| panic!("no output {body}.vx"))];
            assert!(
                (vx - held).abs() <= 1e-12 * held,
                "{}: {body}.vx = {vx}, prescribed {held}",
                scene.name
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
}
