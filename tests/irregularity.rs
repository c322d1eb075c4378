//! Track irregularities: a glider follows a sine profile on rigid ground
//! with the normal force of the curved path; random profiles regenerate
//! bit-for-bit from their seed and have their target spectrum.

use guideway::profile::Profile;
use guideway::scene::{BodyKind, IrregularitySpec};
use guideway::{Advance, Scene, Simulation};

const AMPLITUDE: f64 = 0.002;
const WAVELENGTH: f64 = 4.0;
const SPEED: f64 = 20.0;
const MASS: f64 = 3000.0;
const GRAVITY: f64 = 9.81;

/// A glider (no tangential force) at 20 m/s on 200 m of rigid approach
/// carrying a 2 mm sine of 4 m wavelength, under its weight alone.
fn sine_scene() -> Scene {
    let mut scene = Scene::lee1994(BodyKind::Glider, SPEED, 0.0005);
    scene.gravity = GRAVITY;
    scene.body.mass = MASS;
    scene.body.force_y = 0.0;
    scene.beam.surface_offset = 0.0;
    scene.track.approach = 200.0;
    scene.track.irregularities = vec![IrregularitySpec::Sine {
        amplitude: AMPLITUDE,
        wavelength: WAVELENGTH,
        phase: 0.3,
    }];
    scene.body.initial_position = -190.0;
    scene.solver.end_time = Some(4.0);
    scene.validate().expect("valid");
    scene
}

#[test]
fn glider_follows_a_sine_profile_with_the_normal_force_of_its_path() {
    let scene = sine_scene();
    let profile = Profile::new(&scene.track.irregularities, -200.0, 224.0)
        .unwrap()
        .unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let names: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let at = |n: &str| names.iter().position(|x| x == n).expect(n);
    let (x, y, vx) = (at("glider.x"), at("glider.y"), at("glider.vx"));
    let (normal, r_out) = (at("contact.normal_force"), at("contact.irregularity"));
    let mut values = vec![0.0; names.len()];
    let dt = sim.step_size();
    let (mut worst_y, mut worst_force, mut largest_dynamic) = (0.0f64, 0.0f64, 0.0f64);
    for k in 1..=(4.0 / dt).round() as u64 {
        assert_eq!(sim.advance_to(k as f64 * dt).unwrap(), Advance::Reached);
        sim.output_values(&mut values);
        let [r, slope, ..] = profile.at(values[x]);
        // On the profile (h = 0, r = 0: the centre is the contact point).
        worst_y = worst_y.max((values[y] - r).abs());
        assert!((values[r_out] - r).abs() < 1e-12);
        // The force held over the step is its mean, the force at mid-step:
        // N = m cos φ (g + V² r''), V the horizontal speed.
        let v = values[vx];
        let curvature = profile.at(values[x] - 0.5 * v * dt)[2];
        let cos = 1.0 / (1.0 + slope * slope).sqrt();
        let expected = MASS * cos * (GRAVITY + v * v * curvature);
        worst_force = worst_force.max((values[normal] - expected).abs());
        largest_dynamic = largest_dynamic.max((MASS * v * v * curvature).abs());
    }
    // The path's curvature changes the force by ±m V² A k² (20 % of the
    // weight here): matched to 0.1 % of that, and the height to 1e-4 A.
    let dynamic =
        MASS * SPEED * SPEED * AMPLITUDE * (2.0 * std::f64::consts::PI / WAVELENGTH).powi(2);
    assert!(
        (largest_dynamic / dynamic - 1.0).abs() < 0.01,
        "{largest_dynamic} vs {dynamic}"
    );
    assert!(
        worst_force < 1e-3 * dynamic,
        "force off by {worst_force} N (dynamic {dynamic} N)"
    );
    eprintln!("height {worst_y:e} m, force {worst_force:e} N of {dynamic} N");
    assert!(
        worst_y < 1e-4 * AMPLITUDE,
        "height off the profile by {worst_y} m"
    );
}
