//! The compliant contact laws (`[body.contact_law]`) against independent
//! references: Hertz's static compression and the undamped drop's energy
//! balance in closed form, the two-DOF frequencies of a suspended
//! wheelset on the linearised Hertz stiffness, the EMS magnets of a maglev
//! car (no tension, no lost contact, within saturation and the gap band,
//! converged under refinement), and the eight-coach train on Hertz
//! wheelsets (converged, no lift-off) where the rigid contact is not.

use guideway::simulation::EventKind;
use guideway::{Advance, Scene, Simulation};
use std::f64::consts::PI;

use crate::common::{coach_bogie_on_gliders, GRAVITY};
/// A 0.46 m wheel on a 0.3 m rail head, steel (E = 210 GPa, ν = 0.3).
const WHEEL_RADIUS: f64 = 0.46;

/// Hertz's C_H for the preset `wheel-rail`, written out here: the
/// equivalent sphere R_e = √(R_w R_r) on a plane, C_H = (4/3) E* √R_e,
/// E* = E / (2 (1 − ν²)) (Johnson, Contact Mechanics, 1985, §4.2).
fn preset_hertz_coefficient() -> f64 {
    let e_star = 2.1e11 / (2.0 * (1.0 - 0.3 * 0.3));
    4.0 / 3.0 * e_star * (0.46_f64 * 0.3).sqrt().sqrt()
}

/// Histories of the outputs `names` at every step, and the run's events.
fn run(scene: &Scene, names: &[&str]) -> (Vec<f64>, Vec<Vec<f64>>, Vec<EventKind>) {
    let mut sim = Simulation::new(scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let index: Vec<usize> = names
        .iter()
        .map(|n| all.iter().position(|x| x == n).expect(n))
        .collect();
    let mut values = vec![0.0; all.len()];
    let (mut times, mut out) = (Vec::new(), vec![Vec::new(); names.len()]);
    let dt = scene.solver.step;
    let end = (scene.solver.end_time.expect("an end time") / dt).round() as u64;
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
    let events = sim.events().iter().map(|e| e.kind).collect();
    (times, out, events)
}

/// A wheel of mass `mass` on rigid ground (the approach), standing or
/// rolling at `speed`, on Hertz's law; `extra` adds TOML to `[track]`.
fn wheel_on_ground(mass: f64, speed: f64, height: f64, step: f64, end: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "hertz-wheel"
gravity = {GRAVITY:?}
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 2.3539e10
surface_offset = 0.0
elements = 2
[track]
approach = 200.0
[body]
name = "wheel"
kind = "wheel"
mass = {mass:?}
inertia = 100.0
radius = {WHEEL_RADIUS:?}
initial_position = -150.0
initial_speed = {speed:?}
initial_height = {height:?}
[body.contact_law]
preset = "wheel-rail"
[solver]
integrator = "rk4"
step = {step:?}
end_time = {end:?}
"#
    ))
    .expect("valid scene")
}

#[test]
fn a_hertz_wheel_at_rest_on_rigid_ground_sits_at_its_static_compression() {
    let mass = 1400.0;
    let scene = wheel_on_ground(mass, 0.0, 0.0, 1.0e-5, 0.05);
    let (_, h, events) = run(&scene, &["wheel.y", "contact.normal_force"]);
    let weight = mass * GRAVITY;
    let compression = libm::pow(weight / preset_hertz_coefficient(), 2.0 / 3.0);
    for (y, force) in h[0].iter().zip(&h[1]) {
        let sunk = WHEEL_RADIUS - y;
        assert!(
            (sunk / compression - 1.0).abs() < 1e-6,
            "{sunk} vs {compression}"
        );
        assert!((force / weight - 1.0).abs() < 1e-6, "{force} vs {weight}");
    }
    assert!(events.is_empty(), "{events:?}");
}

#[test]
fn a_dropped_hertz_wheel_reaches_the_compression_its_energy_allows_and_never_pulls() {
    // Undamped: m g (f + δ_max) = (2/5) C_H δ_max^{5/2}, solved by
    // bisection, with f = h − δ_s the fall to the first touch (the wheel
    // starts h above its place on the rail, where it sits δ_s deep).
    let (mass, height) = (1400.0, 2.0e-4);
    let scene = wheel_on_ground(mass, 0.0, height, 2.0e-7, 0.03);
    let (_, h, events) = run(&scene, &["wheel.y", "contact.normal_force"]);
    let c = preset_hertz_coefficient();
    let weight = mass * GRAVITY;
    let static_compression = libm::pow(weight / c, 2.0 / 3.0);
    let fall = height - static_compression;
    let residual = |d: f64| 0.4 * c * libm::pow(d, 2.5) - weight * (fall + d);
    let (mut low, mut high) = (0.0, 1e-2);
    for _ in 0..200 {
        let mid = 0.5 * (low + high);
        if residual(mid) > 0.0 {
            high = mid;
        } else {
            low = mid;
        }
    }
    let deepest = h[0]
        .iter()
        .map(|y| WHEEL_RADIUS - y)
        .fold(f64::MIN, f64::max);
    // The drop's peak is several times the static compression.
    assert!(low > 3.0 * static_compression);
    assert!((deepest / low - 1.0).abs() < 1e-4, "{deepest} vs {low}");
    // Never a tensile force; it leaves the rail and lands again.
    assert!(h[1].iter().all(|&f| f >= 0.0));
    let landings = events.iter().filter(|k| **k == EventKind::Landing).count();
    assert!(landings >= 2, "{events:?}");
}

/// The peak of |Σ w(t) s(t) e^{−iωt}| (Hann window w) over `f` in
/// [low, high] Hz, scanned in steps of `resolution` Hz.
fn spectral_peak(times: &[f64], signal: &[f64], (low, high, resolution): (f64, f64, f64)) -> f64 {
    let n = signal.len();
    let mean = signal.iter().sum::<f64>() / n as f64;
    let (t0, span) = (times[0], times[n - 1] - times[0]);
    let windowed: Vec<f64> = (times.iter().zip(signal))
        .map(|(t, s)| (s - mean) * libm::sin(PI * (t - t0) / span).powi(2))
        .collect();
    let magnitude = |f: f64| {
        let w = 2.0 * PI * f;
        let (mut re, mut im) = (0.0, 0.0);
        for (t, s) in times.iter().zip(&windowed) {
            re += s * libm::cos(w * t);
            im -= s * libm::sin(w * t);
        }
        re.hypot(im)
    };
    let steps = ((high - low) / resolution) as usize;
    let mut best = (low, 0.0);
    for k in 0..=steps {
        let f = low + k as f64 * resolution;
        let m = magnitude(f);
        if m > best.1 {
            best = (f, m);
        }
    }
    best.0
}

#[test]
fn a_suspended_wheelset_over_a_dip_rings_at_the_two_dof_frequencies_of_its_hertz_stiffness() {
    // Sprung mass M on k above a wheelset m on Hertz's law, on rigid
    // ground, undamped. Linearised at the static load W = (M + m) g the
    // contact stiffness is k_H = (3/2) C_H^{2/3} W^{1/3}, and
    //   M z₁'' = −k (z₁ − z₂),  m z₂'' = k (z₁ − z₂) − k_H z₂
    // rings at the two roots ω² of its characteristic polynomial.
    let (sprung, wheelset, k) = (5750.0, 1400.0, 1.595e6);
    let weight = (sprung + wheelset) * GRAVITY;
    let k_h = 1.5 * libm::pow(preset_hertz_coefficient(), 2.0 / 3.0) * libm::cbrt(weight);
    // det [[k − M ω², −k], [−k, k + k_H − m ω²]] = 0.
    let (a, b, c) = (
        sprung * wheelset,
        -(k * wheelset + (k + k_h) * sprung),
        k * k_h,
    );
    let root = (b * b - 4.0 * a * c).sqrt();
    let hz = |w2: f64| w2.sqrt() / (2.0 * PI);
    let (low, high) = (hz((-b - root) / (2.0 * a)), hz((-b + root) / (2.0 * a)));
    assert!(high > 100.0 && low < 5.0, "{low} {high}");
    let scene = Scene::from_toml_str(&format!(
        r#"
name = "p2"
gravity = {GRAVITY:?}
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 2.3539e10
surface_offset = 0.0
elements = 2
[track]
approach = 200.0
[[track.irregularities]]
type = "cosine_dip"
position = -195.0
wavelength = 0.1
depth = 2.0e-6
[[track.irregularities]]
type = "cosine_dip"
position = -192.0
wavelength = 4.0
depth = 2.0e-4
[body]
name = "car"
kind = "sprung_mass"
mass = {sprung:?}
initial_position = -198.0
initial_speed = 20.0
[body.suspension]
stiffness = {k:?}
damping = 0.0
unsprung_mass = {wheelset:?}
[body.contact_law]
preset = "wheel-rail"
[solver]
integrator = "rk4"
step = 2.0e-5
end_time = 4.0
"#
    ))
    .expect("valid scene");
    let (times, h, events) = run(&scene, &["contact.normal_force", "car.y"]);
    assert!(events.is_empty(), "{events:?}");
    // After both dips (x > −190 m at 0.4 s): free vibration.
    let after = times.iter().position(|&t| t > 0.45).unwrap();
    let (t, force, body) = (&times[after..], &h[0][after..], &h[1][after..]);
    let fast = spectral_peak(
        &t[..25_000],
        &force[..25_000],
        (0.8 * high, 1.2 * high, 0.01),
    );
    // The body's motion, every 20th sample (its mode is 60 times slower).
    let every = |x: &[f64]| x.iter().step_by(20).copied().collect::<Vec<f64>>();
    let slow = spectral_peak(&every(t), &every(body), (0.8 * low, 1.25 * low, 0.001));
    println!("P2-type: {fast:.3} Hz (2-DOF {high:.3}); body: {slow:.4} Hz (2-DOF {low:.4})");
    assert!((fast / high - 1.0).abs() < 0.03, "{fast} vs {high}");
    assert!((slow / low - 1.0).abs() < 0.03, "{slow} vs {low}");
    // Never tensile.
    assert!(force.iter().all(|&f| f > 0.0));
}

/// The maglev car of the issue: 30 t over eight 600 kg magnets 3 m apart
/// on 800 kN/m, at 100 m/s from the approach over a 24 m span (the
/// Yang & Yau section) onto the run-off, each magnet on the `ems` preset.
fn maglev_scene(elements: usize, step: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
name = "maglev-ems"
gravity = {GRAVITY:?}
[beam]
length = 24.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = {elements}
[track]
approach = 30.0
run_off = 60.0
[body]
name = "car"
kind = "maglev_vehicle"
mass = 30000.0
initial_position = -12.0
initial_speed = 100.0
[body.contact_law]
preset = "ems"
[body.maglev]
car_inertia = 1.5e6
magnets = 8
magnet_spacing = 3.0
magnet_mass = 600.0
stiffness = 8.0e5
[[sensors]]
name = "mid"
position = 12.0
[solver]
integrator = "auto"
step = {step:?}
end_time = 0.55
start = "static"
"#
    ))
    .expect("valid scene")
}

/// Peak |value| over all the series.
fn peak(series: &[Vec<f64>]) -> f64 {
    series.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
}

#[test]
fn ems_magnets_hold_their_gap_without_tension_and_converge_under_refinement() {
    let magnets: Vec<String> = (1..=8).map(|i| format!("car_magnet{i}")).collect();
    let mut names: Vec<String> = magnets
        .iter()
        .map(|m| format!("{m}.normal_force"))
        .collect();
    names.extend(magnets.iter().map(|m| format!("{m}.gap")));
    names.push("sensor.mid.acceleration".into());
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    // Each magnet's static load F₀ = (M/8 + m) g; it saturates at 2 F₀.
    let load = (30000.0 / 8.0 + 600.0) * GRAVITY;
    let mut peaks = Vec::new();
    for (elements, step) in [(16, 5.0e-4), (32, 2.5e-4)] {
        let (_, h, events) = run(&maglev_scene(elements, step), &names);
        assert!(
            !events.contains(&EventKind::LiftOff),
            "lost contact: {events:?}"
        );
        let forces = &h[..8];
        let least = forces.iter().flatten().fold(f64::MAX, |m, &v| m.min(v));
        let most = peak(forces);
        // Compressive, never at zero nor at the saturation 2 F₀.
        assert!(least > 0.5 * load && most < 2.0 * load, "{least} {most}");
        // Within the band of the 10 mm nominal air gap.
        let gap = peak(&h[8..16]);
        assert!(gap < 0.01, "{gap}");
        let deck = peak(&h[16..]);
        println!("{elements} elements, {step} s: force {least:.1}..{most:.1} N, gap {gap:.3e} m, deck {deck:.4} m/s²");
        peaks.push((most, deck));
    }
    let change = |a: f64, b: f64| (b / a - 1.0).abs();
    assert!(change(peaks[0].0, peaks[1].0) < 0.02, "{peaks:?}");
    assert!(change(peaks[0].1, peaks[1].1) < 0.02, "{peaks:?}");
}

/// The issue's eight coaches (bogie vehicles on 1400 kg glider wheelsets)
/// at 300 km/h from the approach over a 20 m simply supported span
/// (12 t/m, f₁ = 5.5 Hz, 1.5 % at modes 1 and 3) onto the run-off, every
/// wheelset on the `wheel-rail` Hertz preset, on the bare deck.
fn eight_coaches(elements: usize, step: f64) -> Scene {
    let mut text = format!(
        r#"
name = "eight-coaches-hertz"
gravity = {GRAVITY:?}
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 2.3539e10
surface_offset = 0.0
elements = {elements}
[beam.damping]
ratio = 0.015
modes = [1, 3]
[track]
approach = 190.0
run_off = 230.0
[[sensors]]
name = "mid"
position = 10.0
[solver]
integrator = "auto"
numerical_damping = 0.1
step = {step:?}
end_time = 2.6
start = "static"
"#
    );
    for i in 0..8 {
        let (table, sub) = if i == 0 {
            ("[body]", "body")
        } else {
            ("[[vehicles]]", "vehicles")
        };
        text += &format!(
            r#"
{table}
name = "coach{n}"
kind = "bogie_vehicle"
mass = 38884.0
initial_position = {x:?}
initial_speed = 83.3333
[{sub}.contact_law]
preset = "wheel-rail"
{bogie}
"#,
            bogie = coach_bogie_on_gliders(sub, 20000.0, 45000.0),
            n = i + 1,
            x = -11.0 - 24.0 * i as f64
        );
    }
    Scene::from_toml_str(&text).expect("valid scene")
}

#[test]
fn eight_coaches_on_hertz_wheelsets_converge_in_step_and_mesh_without_lifting_off() {
    let mut names: Vec<String> = (1..=8)
        .flat_map(|c| (1..=4).map(move |w| format!("coach{c}_wheelset{w}.normal_force")))
        .collect();
    names.push("sensor.mid.acceleration".into());
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let wheel_load = (38884.0 + 2.0 * 2400.0 + 4.0 * 1400.0) * GRAVITY / 4.0;
    let mut peaks = Vec::new();
    for (elements, step) in [(20, 5.0e-4), (20, 2.5e-4), (40, 5.0e-4)] {
        let (_, h, events) = run(&eight_coaches(elements, step), &names);
        assert!(!events.contains(&EventKind::LiftOff), "{events:?}");
        let (force, deck) = (peak(&h[..32]), peak(&h[32..]));
        let least = h[..32].iter().flatten().fold(f64::MAX, |m, &v| m.min(v));
        println!(
            "{elements} elements, {step} s: wheel force {least:.0}..{force:.0} N \
             (static {wheel_load:.0}), midspan acceleration {deck:.4} m/s²"
        );
        assert!(least > 0.0 && force < 2.0 * wheel_load, "{least} {force}");
        peaks.push((force, deck));
    }
    let change = |a: f64, b: f64| (b / a - 1.0).abs();
    for refined in [peaks[1], peaks[2]] {
        assert!(change(peaks[0].0, refined.0) < 0.02, "{peaks:?}");
        assert!(change(peaks[0].1, refined.1) < 0.02, "{peaks:?}");
    }
}

#[test]
fn rigid_massive_wheelsets_are_advised_the_well_posed_law_and_bad_laws_are_refused() {
    let hertz = eight_coaches(20, 5.0e-4);
    assert!(guideway::scene::advisories(&hertz).is_empty());
    let mut rigid = hertz.clone();
    for spec in rigid.vehicles.iter_mut() {
        spec.contact_law = None;
    }
    let advice = guideway::scene::advisories(&rigid);
    assert_eq!(advice.len(), 1, "{advice:?}");
    assert!(advice[0].contains("coach8") && advice[0].contains("\"wheel-rail\""));
    // A law's broken rule names the field, its value and the rule.
    let text = toml_of(&hertz).replace(
        "preset = \"wheel-rail\"",
        "law = \"ems\"\nnominal_gap = 0.01\nproportional_gain = 50.0\nderivative_gain = 0.5",
    );
    let error = Scene::from_toml_str(&text).unwrap_err().to_string();
    assert!(
        error.contains("body.contact_law.proportional_gain")
            && error.contains("negative stiffness"),
        "{error}"
    );
}

fn toml_of(scene: &Scene) -> String {
    toml::to_string(scene).expect("serializes")
}
