//! The massless follower (`sprung_mass` with `unsprung_mass = 0`): on rigid
//! ground over a cosine dip it is the base-excited single-DOF oscillator,
//! solved here independently; on Yang & Yau's beam (the case of
//! tests/physics/sprung_mass.rs) the sprung mass over a glider of decreasing mass
//! converges to it.

use guideway::{Advance, Scene, Simulation};

use crate::common::yang_yau::{LENGTH, SPRUNG, STIFFNESS};
use crate::common::{largest_difference, peak, GRAVITY};

const DAMPING: f64 = 2.0e4;
/// Height of the sprung mass above its contact point at rest (assemble.rs).
const HEIGHT: f64 = 1.0;

const GROUND_SPEED: f64 = 20.0;
const GROUND_START: f64 = -190.0;
const DIP_AT: f64 = -170.0;
const DIP_LENGTH: f64 = 10.0;
const DIP_DEPTH: f64 = 0.01;
const GROUND_STEP: f64 = 1.0e-4;
const GROUND_END: f64 = 2.5;

fn ground_scene() -> Scene {
    ground_scene_with(DAMPING)
}

fn ground_scene_with(damping: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "follower-on-ground"
gravity = {GRAVITY:?}
[beam]
length = 25.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 2
[track]
approach = 200.0
[[track.irregularities]]
type = "cosine_dip"
position = {DIP_AT:?}
wavelength = {DIP_LENGTH:?}
depth = {DIP_DEPTH:?}
[body]
name = "car"
kind = "sprung_mass"
mass = {SPRUNG:?}
initial_position = {GROUND_START:?}
initial_speed = {GROUND_SPEED:?}
[body.suspension]
stiffness = {STIFFNESS:?}
damping = {damping:?}
unsprung_mass = 0.0
[solver]
integrator = "rk4"
step = {GROUND_STEP:?}
end_time = {GROUND_END:?}
"#
    ))
    .expect("valid scene")
}

/// The dip r(x) and its slope.
fn dip(x: f64) -> (f64, f64) {
    let s = x - DIP_AT;
    if s.abs() >= 0.5 * DIP_LENGTH {
        return (0.0, 0.0);
    }
    let k = 2.0 * std::f64::consts::PI / DIP_LENGTH;
    (
        -0.5 * DIP_DEPTH * (1.0 + libm::cos(k * s)),
        0.5 * DIP_DEPTH * k * libm::sin(k * s),
    )
}

/// The base-excited oscillator M z̈ = −k (z − r) − c (ż − ṙ), base
/// r(x0 + V t), z the sprung mass's rise above its rest height; classical
/// RK4 with `substeps` steps per output step. Returns (z, z̈) at each time.
fn base_excited(times: &[f64], substeps: usize) -> (Vec<f64>, Vec<f64>) {
    let acceleration = |t: f64, z: f64, zd: f64| {
        let (r, slope) = dip(GROUND_START + GROUND_SPEED * t);
        (-STIFFNESS * (z - r) - DAMPING * (zd - GROUND_SPEED * slope)) / SPRUNG
    };
    let h = GROUND_STEP / substeps as f64;
    let (mut t, mut z, mut zd) = (0.0, 0.0, 0.0);
    let (mut heights, mut accelerations) = (Vec::new(), Vec::new());
    for &target in times {
        while t < target - 0.5 * h {
            let k1 = (zd, acceleration(t, z, zd));
            let k2 = (
                zd + 0.5 * h * k1.1,
                acceleration(t + 0.5 * h, z + 0.5 * h * k1.0, zd + 0.5 * h * k1.1),
            );
            let k3 = (
                zd + 0.5 * h * k2.1,
                acceleration(t + 0.5 * h, z + 0.5 * h * k2.0, zd + 0.5 * h * k2.1),
            );
            let k4 = (
                zd + h * k3.1,
                acceleration(t + h, z + h * k3.0, zd + h * k3.1),
            );
            z += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            zd += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            t += h;
        }
        heights.push(z);
        accelerations.push(acceleration(t, z, zd));
    }
    (heights, accelerations)
}

/// Histories of the outputs `names` at every step until the run ends.
fn histories(scene: &Scene, names: &[&str]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let mut sim = Simulation::new(scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let index: Vec<usize> = names
        .iter()
        .map(|n| all.iter().position(|x| x == n).expect(n))
        .collect();
    let mut values = vec![0.0; all.len()];
    let (mut times, mut out) = (Vec::new(), vec![Vec::new(); names.len()]);
    let dt = scene.solver.step;
    let end = scene
        .solver
        .end_time
        .map_or(u64::MAX, |t| (t / dt).round() as u64);
    for k in 1..=end {
        let advance = sim.advance_to(k as f64 * dt).expect("no solver error");
        if advance != Advance::Reached {
            break;
        }
        sim.output_values(&mut values);
        times.push(sim.time());
        for (series, &i) in out.iter_mut().zip(&index) {
            series.push(values[i]);
        }
    }
    (times, out)
}

#[test]
fn follower_on_rigid_ground_is_the_base_excited_oscillator() {
    let scene = ground_scene();
    let (times, out) = histories(
        &scene,
        &[
            "car.y",
            "car.ay",
            "contact.normal_force",
            "contact.irregularity",
        ],
    );
    let last = *times.last().unwrap();
    assert!((last - GROUND_END).abs() < 1e-9, "ran to {last} s");
    let rise: Vec<f64> = out[0].iter().map(|y| y - HEIGHT).collect();
    let (z, zdd) = base_excited(&times, 10);
    let (peak_z, peak_a) = (peak(&z), peak(&zdd));
    // The dip does excite the oscillator (its period 0.38 s, the dip's 0.5 s).
    assert!(peak_z > 0.5 * DIP_DEPTH, "{peak_z}");
    assert!(peak(&out[3]) > 0.99 * DIP_DEPTH);
    let (dz, da) = (
        largest_difference(&rise, &z),
        largest_difference(&out[1], &zdd),
    );
    eprintln!(
        "follower on ground: height {:.3e} of peak {peak_z:.4e} m, acceleration {:.3e} of \
         peak {peak_a:.4e} m/s2",
        dz / peak_z,
        da / peak_a
    );
    // What is left is geometric: the follower's gap is measured along the
    // surface normal (slopes up to 3e-3 here), the reference's vertically.
    assert!(dz <= 0.005 * peak_z, "height: {dz} against {peak_z}");
    assert!(da <= 0.005 * peak_a, "acceleration: {da} against {peak_a}");
    // The contact force is what the suspension transmits: the sprung
    // mass's weight plus its inertia force.
    for (n, a) in out[2].iter().zip(&out[1]) {
        let expected = SPRUNG * (GRAVITY + a);
        assert!(
            (n - expected).abs() < 1e-3 * SPRUNG * GRAVITY,
            "{n} vs {expected}"
        );
    }
}

const BEAM_STEP: f64 = 1.25e-5;

/// Yang & Yau's sprung mass crossing their 25 m beam at 100 km/h (the case
/// of tests/physics/sprung_mass.rs), over a contact body of `unsprung` kg (0: the
/// follower).
fn beam_scene(unsprung: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "sprung-mass"
gravity = {GRAVITY:?}
[beam]
length = {LENGTH:?}
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 20
[body]
name = "car"
kind = "sprung_mass"
mass = {SPRUNG:?}
initial_speed = {:?}
[body.suspension]
stiffness = {STIFFNESS:?}
damping = {DAMPING:?}
unsprung_mass = {unsprung:?}
[[sensors]]
name = "midspan"
position = {:?}
[solver]
integrator = "rk4"
step = {BEAM_STEP:?}
"#,
        100.0 / 3.6,
        LENGTH / 2.0
    ))
    .expect("valid scene")
}

#[test]
fn a_vanishing_unsprung_mass_converges_to_the_follower_on_the_beam() {
    let names = [
        "sensor.midspan.deflection",
        "car.ay",
        "contact.normal_force",
    ];
    let (times, follower) = histories(&beam_scene(0.0), &names);
    let crossing = LENGTH / (100.0 / 3.6);
    let last = *times.last().unwrap();
    assert!((last - crossing).abs() < 0.01 * crossing, "ran to {last} s");
    let peaks: Vec<f64> = follower.iter().map(|h| peak(h)).collect();
    // The follower loads the beam: the midspan deflection is about the
    // static one under the sprung weight.
    let static_w = SPRUNG * GRAVITY * LENGTH.powi(3) / (48.0 * 8.5347e10);
    assert!(
        (0.8 * static_w..1.5 * static_w).contains(&peaks[0]),
        "{} vs {static_w}",
        peaks[0]
    );
    eprintln!("unsprung mass (kg) | midspan | sprung acceleration | contact force (of peak)");
    let mut previous = [f64::INFINITY; 3];
    for unsprung in [57.5, 5.75, 0.575] {
        let (t, glider) = histories(&beam_scene(unsprung), &names);
        let n = t.len().min(times.len());
        let differences: Vec<f64> = (0..3)
            .map(|i| largest_difference(&glider[i][..n], &follower[i][..n]) / peaks[i])
            .collect();
        eprintln!(
            "{unsprung:>18} | {:.3e} | {:.3e} | {:.3e}",
            differences[0], differences[1], differences[2]
        );
        for i in 0..3 {
            assert!(
                differences[i] < previous[i],
                "{unsprung} kg, output {i}: {} not below {}",
                differences[i],
                previous[i]
            );
        }
        previous = [differences[0], differences[1], differences[2]];
    }
    // At 0.01 % of the sprung mass the glider is the follower to 0.1 %.
    assert!(previous.iter().all(|&d| d < 1e-3), "{previous:?}");
}

#[test]
fn the_follower_keeps_the_energy_balance() {
    // Undamped the balance holds the suspension's energy; damped the
    // dissipated energy is accounted for.
    for damping in [0.0, DAMPING] {
        let scene = ground_scene_with(damping);
        let names = [
            "energy.balance",
            "energy.spring",
            "energy.dissipated",
            "energy.gravity_work",
        ];
        let (_, out) = histories(&scene, &names);
        let e0 = out[0][0];
        let drift = out[0].iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        let spring = peak(&out[1]);
        let dissipated = *out[2].last().unwrap();
        eprintln!(
            "follower, c = {damping}: drift {drift:.3e} J, spring energy up to {spring:.4e} J, \
             dissipated {dissipated:.4e} J"
        );
        assert!(spring > 10.0, "{spring}");
        assert!(drift < 1e-6 * spring, "drift {drift} J of {spring} J");
        if damping > 0.0 {
            assert!(dissipated > 1e3 * drift, "{dissipated} vs {drift}");
        } else {
            assert_eq!(dissipated, 0.0);
        }
    }
}

#[test]
fn a_negative_unsprung_mass_is_refused_with_the_field_named() {
    let mut scene = ground_scene();
    scene.vehicles[0].suspension.as_mut().unwrap().unsprung_mass = -1.0;
    let message = scene.validate().unwrap_err().to_string();
    assert!(
        message.contains("body.suspension.unsprung_mass"),
        "{message}"
    );
}

#[test]
fn the_follower_cannot_pull_the_body_flies_where_the_surface_drops_away() {
    // A 50 mm, 2 m dip at 20 m/s drops the surface at up to 100 g: the
    // suspension would have to pull, so it goes slack and the body falls.
    let mut scene = ground_scene_with(0.0);
    scene.track.irregularities = vec![guideway::scene::IrregularitySpec::CosineDip {
        position: DIP_AT,
        wavelength: 2.0,
        depth: 0.05,
    }];
    let (_, out) = histories(&scene, &["contact.normal_force", "car.ay"]);
    assert!(out[0].iter().all(|&n| n >= 0.0));
    let slack: Vec<f64> = out[0]
        .iter()
        .zip(&out[1])
        .filter(|(&n, _)| n == 0.0)
        .map(|(_, &a)| a)
        .collect();
    eprintln!("slack at {} of {} steps", slack.len(), out[0].len());
    assert!(slack.len() > 10, "{}", slack.len());
    // Slack, the body falls freely (its acceleration from the last force).
    assert!(
        slack.iter().all(|a| (a + GRAVITY).abs() < 1e-9),
        "{slack:?}"
    );
}

#[test]
fn the_follower_rolls_from_the_approach_over_the_beam_onto_the_run_off() {
    // RK4, and HHT-α (α = 0) at 0.1 ms, which restarts at the beam's ends.
    for hht in [false, true] {
        let mut scene = beam_scene(0.0);
        scene.track.approach = 10.0;
        scene.track.run_off = 30.0;
        scene.vehicles[0].initial_position = -5.0;
        scene.solver.end_time = Some(1.5);
        if hht {
            scene = with_hht(scene, 0.0, 1.0e-4);
        }
        let step = scene.solver.step;
        let mut sim = Simulation::new(&scene).expect("builds");
        let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
        let balance = all.iter().position(|n| n == "energy.balance").unwrap();
        let mut values = vec![0.0; all.len()];
        let e0 = sim.initial_energy();
        let mut drift: f64 = 0.0;
        let steps = (1.5 / step).round() as u64;
        for k in 1..=steps {
            assert_eq!(sim.advance_to(k as f64 * step).unwrap(), Advance::Reached);
            sim.output_values(&mut values);
            drift = drift.max((values[balance] - e0).abs());
        }
        let kinds: Vec<guideway::simulation::EventKind> =
            sim.events().iter().map(|e| e.kind).collect();
        eprintln!("HHT {hht}: events {kinds:?}, energy drift {drift:.3e} J");
        assert_eq!(
            kinds,
            [
                guideway::simulation::EventKind::Entry,
                guideway::simulation::EventKind::Exit
            ]
        );
        // Gravity does about M g × 0.2 mm ≈ 11 J of work as the beam deflects.
        assert!(drift < 1e-6, "{drift}");
    }
}

/// `scene` with HHT-α (numerical damping `damping`) at step `step`.
fn with_hht(mut scene: Scene, damping: f64, step: f64) -> Scene {
    scene.solver.integrator = guideway::scene::IntegratorKind::Hht;
    scene.solver.numerical_damping = damping;
    scene.solver.step = step;
    scene
}

#[test]
fn the_follower_with_hht_converges_to_the_rk4_crossing() {
    // Yang & Yau's crossing: RK4 at 12.5 µs is the reference; HHT-α
    // (α = 0) at 0.2 and 0.1 ms converges towards it.
    let names = [
        "sensor.midspan.deflection",
        "car.ay",
        "contact.normal_force",
    ];
    let (times, reference) = histories(&beam_scene(0.0), &names);
    let peaks: Vec<f64> = reference.iter().map(|h| peak(h)).collect();
    let mut errors = Vec::new();
    for step in [2.0e-4, 1.0e-4] {
        let (t, hht) = histories(&with_hht(beam_scene(0.0), 0.0, step), &names);
        let every = (step / BEAM_STEP).round() as usize;
        let mut worst = [0.0f64; 3];
        let mut when = [0.0f64; 3];
        for (k, &tk) in t.iter().enumerate() {
            let r = (k + 1) * every - 1;
            if r >= times.len() {
                break;
            }
            assert!((times[r] - tk).abs() < 1e-9, "{} vs {tk}", times[r]);
            for i in 0..3 {
                let e = (hht[i][k] - reference[i][r]).abs() / peaks[i];
                if e > worst[i] {
                    worst[i] = e;
                    when[i] = tk;
                }
            }
        }
        eprintln!(
            "follower HHT-α, Δt = {step}: midspan {:.3e}, sprung acceleration {:.3e}, \
             contact force {:.3e} (of the RK4 peaks), largest at {when:?} s",
            worst[0], worst[1], worst[2]
        );
        errors.push(worst);
    }
    // The deflection, carried by the low modes, is second order; the
    // sprung acceleration and the contact force also carry the beam's
    // highest modes (20 elements: ω Δt ≈ 1 and more at these steps), which
    // no step here resolves, so their error shrinks more slowly.
    assert!(errors[1][0] < 0.35 * errors[0][0], "{errors:?}");
    for i in 1..3 {
        assert!(errors[1][i] < 0.7 * errors[0][i], "{errors:?}");
    }
    let bounds = [2e-4, 2e-2, 5e-5];
    for i in 0..3 {
        assert!(errors[1][i] < bounds[i], "{errors:?}");
    }
}

#[test]
fn the_follower_with_hht_keeps_the_energy_balance() {
    // α = 0 (the trapezoidal rule) undamped and damped; α = −0.1 books
    // the energy its numerical damping removes.
    for (damping, numerical) in [(0.0, 0.0), (DAMPING, 0.0), (DAMPING, 0.1)] {
        let mut scene = with_hht(beam_scene(0.0), numerical, 1.0e-4);
        scene.vehicles[0].suspension.as_mut().unwrap().damping = damping;
        let names = [
            "energy.balance",
            "energy.gravity_work",
            "energy.dissipated",
            "energy.numerical_dissipation",
        ];
        let (_, out) = histories(&scene, &names);
        let e0 = out[0][0];
        let drift = out[0].iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        let gravity = peak(&out[1]);
        let (dissipated, numeric) = (*out[2].last().unwrap(), *out[3].last().unwrap());
        eprintln!(
            "follower HHT-α = {}, c = {damping}: drift {drift:.3e} J against {gravity:.4e} J of \
             gravity work; dampers {dissipated:.3e} J, numerical damping {numeric:.3e} J",
            -numerical
        );
        assert!(gravity > 1.0, "{gravity}");
        assert!(drift < 1e-5 * gravity, "drift {drift} J of {gravity} J");
        if damping > 0.0 {
            assert!(dissipated > 1e2 * drift, "{dissipated} vs {drift}");
        }
        if numerical > 0.0 {
            assert!(numeric > 0.0, "{numeric}");
        }
    }
}

/// The largest body acceleration now, in g.
fn largest_acceleration(sim: &Simulation) -> f64 {
    sim.body_accelerations()
        .iter()
        .map(|a| a.xy().norm() / GRAVITY)
        .fold(0.0, f64::max)
}

#[test]
fn a_follower_at_rest_on_the_statically_deflected_beam_stays_at_rest() {
    // At midspan, where the deflected surface is level, with RK4 and with
    // HHT-α: the static start loads the beam with the sprung weight and
    // sets the body at its suspension's rest above the deflected surface.
    let static_w = SPRUNG * GRAVITY * LENGTH.powi(3) / (48.0 * 8.5347e10);
    for hht in [false, true] {
        let mut scene = beam_scene(0.0);
        scene.vehicles[0].initial_position = 0.5 * LENGTH;
        scene.vehicles[0].initial_speed = 0.0;
        scene.solver.start = guideway::scene::StartKind::Static;
        scene.solver.end_time = Some(1.0);
        if hht {
            scene = with_hht(scene, 0.0, 1.0e-3);
        }
        let mut sim = Simulation::new(&scene).expect("builds");
        let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
        let at = |n: &str| all.iter().position(|x| x == n).expect(n);
        let (midspan, force) = (at("sensor.midspan.deflection"), at("contact.normal_force"));
        let mut values = vec![0.0; all.len()];
        sim.output_values(&mut values);
        let deflection = values[midspan];
        assert!(
            (deflection.abs() - static_w).abs() < 1e-9 * static_w,
            "{deflection} vs {static_w}"
        );
        assert_eq!(values[force], SPRUNG * GRAVITY);
        let mut worst = largest_acceleration(&sim);
        for k in 1..=200 {
            let t = k as f64 * scene.solver.step;
            assert_eq!(sim.advance_to(t).unwrap(), Advance::Reached);
            worst = worst.max(largest_acceleration(&sim));
        }
        sim.output_values(&mut values);
        eprintln!(
            "follower at rest (HHT {hht}): largest acceleration {worst:.3e} g over 200 steps, \
             midspan {deflection:.6e} m (static {static_w:.6e} m), now {:.6e} m",
            values[midspan]
        );
        assert!(worst < 1e-9, "largest body acceleration {worst:e} g");
        assert!((values[midspan] - deflection).abs() < 1e-9 * static_w);
    }
}

/// Every event's (kind, time).
fn events(sim: &Simulation) -> Vec<(guideway::simulation::EventKind, f64)> {
    sim.events().iter().map(|e| (e.kind, e.time)).collect()
}

#[test]
fn a_slack_follower_is_an_open_contact_that_lifts_off_and_lands_without_an_impact() {
    // A 50 mm, 4 m bump at 20 m/s: over its crest the surface falls away
    // at up to 2.5 g, the suspension would pull, the contact opens.
    use guideway::simulation::EventKind::{Landing, LiftOff};
    for damping in [0.0, DAMPING] {
        let mut scene = ground_scene_with(damping);
        scene.track.irregularities = vec![guideway::scene::IrregularitySpec::CosineDip {
            position: DIP_AT,
            wavelength: 4.0,
            depth: -0.05,
        }];
        let mut sim = Simulation::new(&scene).expect("builds");
        let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
        let at = |n: &str| all.iter().position(|x| x == n).expect(n);
        let names = [
            "contact.state",
            "contact.normal_force",
            "car.ay",
            "energy.impact_loss",
            "energy.balance",
        ];
        let index: Vec<usize> = names.iter().map(|n| at(n)).collect();
        let mut values = vec![0.0; all.len()];
        let (mut times, mut out) = (vec![0.0], vec![Vec::new(); names.len()]);
        sim.output_values(&mut values);
        for (series, &i) in out.iter_mut().zip(&index) {
            series.push(values[i]);
        }
        let steps = (GROUND_END / GROUND_STEP).round() as u64;
        for k in 1..=steps {
            assert_eq!(
                sim.advance_to(k as f64 * GROUND_STEP).unwrap(),
                Advance::Reached
            );
            sim.output_values(&mut values);
            times.push(sim.time());
            for (series, &i) in out.iter_mut().zip(&index) {
                series.push(values[i]);
            }
        }
        let events = events(&sim);
        let slack = out[1].iter().filter(|&&n| n == 0.0).count();
        let drift = out[4]
            .iter()
            .map(|e| (e - out[4][0]).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "bump, c = {damping}: events {events:?}, slack {slack} steps, energy drift \
             {drift:.3e} J"
        );
        // Alternating from a lift-off; undamped, the body thrown up by the
        // bump goes on hopping on the level ground after it.
        assert!(events.len() >= 2, "{events:?}");
        for (i, &(kind, _)) in events.iter().enumerate() {
            assert_eq!(kind, if i % 2 == 0 { LiftOff } else { Landing });
        }
        assert!(slack > 10, "{slack}");
        // Open exactly where the force is zero, the body then in free fall.
        for k in 0..times.len() {
            let (state, force, ay) = (out[0][k], out[1][k], out[2][k]);
            assert_eq!(
                state,
                if force > 0.0 { 1.0 } else { 0.0 },
                "t = {}",
                times[k]
            );
            if force == 0.0 {
                assert!((ay + GRAVITY).abs() < 1e-9, "{ay}");
            }
        }
        // Each event lies in the step that saw its switch.
        for &(kind, time) in &events {
            let k = times.iter().position(|&t| t >= time - 1e-12).unwrap();
            let closed_after = out[0][k] == 1.0;
            assert_eq!(closed_after, kind == Landing, "{kind:?} at {time}");
            assert_eq!(out[0][k - 1] == 1.0, kind == LiftOff, "{kind:?} at {time}");
        }
        // No impact: nothing lost, and the force grows from zero again.
        assert!(out[3].iter().all(|&l| l == 0.0));
        for &(_, time) in events.iter().filter(|e| e.0 == Landing) {
            let landed = times.iter().position(|&t| t >= time).unwrap();
            let first = out[1][landed];
            assert!(
                first < 1e-2 * SPRUNG * GRAVITY,
                "{first} N just after landing"
            );
        }
        let spring = SPRUNG * GRAVITY * 0.05;
        assert!(drift < 1e-6 * spring, "drift {drift} J");
    }
}

#[test]
fn a_follower_dropped_from_above_the_track_lands_and_bounces_as_the_oscillator() {
    // Undamped, from h above its rest, at standstill: free fall until the
    // spring reaches its free length (s = M g / k above the rest), then
    // harmonic motion about the rest until it is free again, then a
    // flight as long as the fall was fast.
    use guideway::simulation::EventKind::{Landing, LiftOff};
    let mut scene = ground_scene_with(0.0);
    scene.track.irregularities.clear();
    scene.vehicles[0].initial_speed = 0.0;
    let s = SPRUNG * GRAVITY / STIFFNESS;
    let h = 0.1;
    scene.vehicles[0].initial_height = h;
    let mut sim = Simulation::new(&scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let state = all.iter().position(|n| n == "contact.state").unwrap();
    let mut values = vec![0.0; all.len()];
    sim.output_values(&mut values);
    assert_eq!(values[state], 0.0, "starts open");
    let steps = (0.6 / GROUND_STEP).round() as u64;
    for k in 1..=steps {
        assert_eq!(
            sim.advance_to(k as f64 * GROUND_STEP).unwrap(),
            Advance::Reached
        );
    }
    let fall = (2.0 * (h - s) / GRAVITY).sqrt();
    let speed = GRAVITY * fall;
    let omega = (STIFFNESS / SPRUNG).sqrt();
    let contact = (std::f64::consts::PI + 2.0 * libm::atan(s * omega / speed)) / omega;
    let expected = [
        (Landing, fall),
        (LiftOff, fall + contact),
        (Landing, fall + contact + 2.0 * speed / GRAVITY),
    ];
    let events = events(&sim);
    eprintln!("dropped follower: events {events:?}, expected {expected:?}");
    assert!(events.len() >= 3, "{events:?}");
    for (&(kind, time), &(expected_kind, expected_time)) in events.iter().zip(&expected) {
        assert_eq!(kind, expected_kind);
        assert!(
            (time - expected_time).abs() < 1e-6,
            "{time} vs {expected_time}"
        );
    }
}

#[test]
fn a_follower_started_above_its_rest_within_its_spring_oscillates_about_it() {
    // 20 mm above the rest is less than s = M g / k: the suspension still
    // carries M g − k h, the contact is closed and the body oscillates
    // harmonically about the rest with amplitude h.
    let mut scene = ground_scene_with(0.0);
    scene.track.irregularities.clear();
    scene.vehicles[0].initial_speed = 0.0;
    let h = 0.02;
    scene.vehicles[0].initial_height = h;
    scene.solver.end_time = Some(1.0);
    let (times, out) = histories(&scene, &["car.y", "contact.normal_force"]);
    let omega = (STIFFNESS / SPRUNG).sqrt();
    let worst = times
        .iter()
        .zip(&out[0])
        .map(|(&t, &y)| (y - HEIGHT - h * libm::cos(omega * t)).abs())
        .fold(0.0, f64::max);
    eprintln!("follower started {h} m high: largest error {worst:.3e} m");
    assert!(worst < 1e-6 * h, "{worst}");
    assert!(out[1].iter().all(|&n| n > 0.0));
}

/// Followers on rigid ground 2 km long: `bodies` as (name, start, speed),
/// a 50 mm, 4 m bump 20 m ahead of each start (it unloads the follower).
fn followers_on_ground(bodies: &[(&str, f64, f64)], hht: bool) -> Scene {
    let mut scene = ground_scene();
    scene.track.approach = 2000.0;
    scene.track.irregularities = bodies
        .iter()
        .map(
            |&(_, start, _)| guideway::scene::IrregularitySpec::CosineDip {
                position: start + 20.0,
                wavelength: 4.0,
                depth: -0.05,
            },
        )
        .collect();
    let spec = |&(name, start, speed): &(&str, f64, f64)| {
        let mut spec = scene.vehicles[0].clone();
        spec.name = name.into();
        spec.initial_position = start;
        spec.initial_speed = speed;
        spec
    };
    scene.vehicles = bodies.iter().map(spec).collect();
    if hht {
        scene = with_hht(scene, 0.0, 5.0e-4);
    }
    scene.validate().expect("valid");
    scene
}

#[test]
fn two_followers_far_apart_are_two_single_followers() {
    let (a, b) = (("car", -1500.0, 20.0), ("second", -500.0, 25.0));
    for hht in [false, true] {
        let quantities = ["y", "vy", "ay"];
        let single_a = histories(
            &followers_on_ground(&[a], hht),
            &[
                "car.y",
                "car.vy",
                "car.ay",
                "contact.normal_force",
                "contact.state",
            ],
        );
        let single_b = histories(
            &followers_on_ground(&[b], hht),
            &[
                "second.y",
                "second.vy",
                "second.ay",
                "contact.normal_force",
                "contact.state",
            ],
        );
        let pair = followers_on_ground(&[a, b], hht);
        let mut names: Vec<String> = quantities.iter().map(|q| format!("car.{q}")).collect();
        names.extend(["contact.normal_force".into(), "contact.state".into()]);
        names.extend(quantities.iter().map(|q| format!("second.{q}")));
        names.extend([
            "second_contact.normal_force".into(),
            "second_contact.state".into(),
        ]);
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let (_, together) = histories(&pair, &refs);
        let mut worst: f64 = 0.0;
        for (alone, offset) in [(&single_a.1, 0), (&single_b.1, 5)] {
            for (i, series) in alone.iter().enumerate() {
                let scale = peak(series).max(1.0);
                let difference = largest_difference(series, &together[offset + i]) / scale;
                worst = worst.max(difference);
            }
        }
        // Both lift off over their bumps.
        assert!(together[4].contains(&0.0) && together[9].contains(&0.0));
        let mut sim = Simulation::new(&pair).expect("builds");
        let end = pair.solver.end_time.unwrap();
        assert_eq!(sim.advance_to(end).unwrap(), Advance::Reached);
        let contacts: Vec<usize> = sim.events().iter().map(|e| e.contact).collect();
        eprintln!(
            "two followers (HHT {hht}): largest difference {worst:.3e} of the peaks; events of \
             contacts {contacts:?}"
        );
        assert!(contacts.contains(&0) && contacts.contains(&1));
        // RK4: each body's step is its own; HHT-α iterates the pair's
        // force laws together to the iteration's tolerance (1e-7 m/s).
        let bound = if hht { 1e-6 } else { 1e-12 };
        assert!(worst <= bound, "{worst}");
    }
}

#[test]
fn a_follower_too_stiff_for_the_hht_step_fails_with_a_message_not_a_panic() {
    // k β Δt² / M ≈ 1e3: the fixed point of the force law cannot settle.
    let mut scene = with_hht(beam_scene(0.0), 0.0, 2.5e-3);
    scene.vehicles[0].mass = 100.0;
    let suspension = scene.vehicles[0].suspension.as_mut().unwrap();
    suspension.stiffness = 1e9;
    suspension.damping = 1e7;
    let mut sim = Simulation::new(&scene).expect("builds");
    let error = sim.advance_to(0.1).expect_err("does not settle");
    eprintln!("stiff follower: {error}");
    let message = error.to_string();
    assert!(message.contains("force-law fixed-point"), "{message}");
    assert!(message.contains("solver.step"), "{message}");
}
