//! The HSLM-A trains of EN 1991-2, Annex E (Table E.1, Figure E.1): each
//! builds as moving forces with the right axle count and positions.

use guideway::moving_load::{hslm, scene_axles, HSLM_TRAINS};
use guideway::scene::{BodyKind, Scene};

/// Table E.1 again, written out here: N, D (m), d (m), P (kN).
const TABLE: [(&str, usize, f64, f64, f64); 10] = [
    ("HSLM-A1", 18, 18.0, 2.0, 170.0),
    ("HSLM-A2", 17, 19.0, 3.5, 200.0),
    ("HSLM-A3", 16, 20.0, 2.0, 180.0),
    ("HSLM-A4", 15, 21.0, 3.0, 190.0),
    ("HSLM-A5", 14, 22.0, 2.0, 170.0),
    ("HSLM-A6", 13, 23.0, 2.0, 180.0),
    ("HSLM-A7", 13, 24.0, 2.0, 190.0),
    ("HSLM-A8", 12, 25.0, 2.5, 190.0),
    ("HSLM-A9", 11, 26.0, 2.0, 210.0),
    ("HSLM-A10", 11, 27.0, 2.0, 210.0),
];

/// Power car axles 0, 3, 14, 17 m; 2 × 3.525 m to the end coach's bogie
/// (3 m); 15 m on to the first shared bogie; N + 1 shared bogies D apart,
/// each two axles d apart; then the same backwards.
fn expected_offsets(n: usize, coach: f64, bogie: f64) -> Vec<f64> {
    let mut x = vec![0.0, 3.0, 14.0, 17.0, 24.05, 27.05];
    for k in 0..=n {
        let first = 42.05 + k as f64 * coach;
        x.extend([first, first + bogie]);
    }
    let last = 42.05 + n as f64 * coach + bogie;
    x.extend([last + 15.0, last + 18.0]);
    x.extend([0.0, 3.0, 14.0, 17.0].iter().map(|p| last + 25.05 + p));
    x
}

fn check_train(index: usize) {
    let (name, n, coach, bogie, p_kn) = TABLE[index];
    let train = hslm(name).expect("the train is built in");
    assert_eq!(train, HSLM_TRAINS[index]);
    let axles = train.axles();
    assert_eq!(
        axles.len(),
        2 * n + 14,
        "{name}: 8 power-car, 4 end-coach, 2(N + 1) shared axles"
    );
    let expected = expected_offsets(n, coach, bogie);
    for (k, ((offset, force), want)) in axles.iter().zip(&expected).enumerate() {
        assert!(
            (offset - want).abs() < 1e-9,
            "{name} axle {k}: {offset} m, expected {want} m"
        );
        assert_eq!(*force, -p_kn * 1e3, "{name} axle {k}: force");
    }
    // Symmetric front to back.
    let length = train.length();
    for (front, back) in axles.iter().zip(axles.iter().rev()) {
        assert!(
            (front.0 - (length - back.0)).abs() < 1e-9,
            "{name}: not symmetric"
        );
    }
    // As a scene's moving force: the first axle at initial_position, the
    // others behind it, all at the train's speed.
    let mut scene = Scene::load("lee1994-glider-30").expect("built-in");
    scene.body.kind = BodyKind::MovingForce;
    scene.body.force_y = 0.0;
    scene.body.train = Some(name.to_lowercase());
    scene.body.initial_position = 1.0;
    scene
        .validate()
        .expect("a moving-force train scene is valid");
    let placed = scene_axles(&scene);
    assert_eq!(placed.len(), axles.len());
    for (axle, (offset, _)) in placed.iter().zip(&axles) {
        assert_eq!(axle.position, 1.0 - offset);
        assert_eq!(axle.speed, 30.0);
    }
}

macro_rules! train_tests {
    ($($test:ident: $index:expr,)*) => {$(
        #[test]
        fn $test() {
            check_train($index);
        }
    )*};
}

train_tests! {
    hslm_a1_builds: 0,
    hslm_a2_builds: 1,
    hslm_a3_builds: 2,
    hslm_a4_builds: 3,
    hslm_a5_builds: 4,
    hslm_a6_builds: 5,
    hslm_a7_builds: 6,
    hslm_a8_builds: 7,
    hslm_a9_builds: 8,
    hslm_a10_builds: 9,
}

#[test]
fn unknown_trains_and_trains_on_bodies_are_refused() {
    let mut scene = Scene::load("lee1994-glider-30").expect("built-in");
    scene.body.train = Some("HSLM-A11".into());
    let message = scene.validate().unwrap_err().to_string();
    assert!(message.contains("body.train"), "{message}");
    scene.body.kind = BodyKind::MovingForce;
    scene.body.force_y = 0.0;
    let message = scene.validate().unwrap_err().to_string();
    assert!(message.contains("HSLM-A1 … HSLM-A10"), "{message}");
}

#[test]
fn a_moving_force_scene_is_refused_by_the_contact_simulation_with_the_way_out() {
    let mut scene = Scene::load("lee1994-glider-30").expect("built-in");
    scene.body.kind = BodyKind::MovingForce;
    scene.validate().expect("valid");
    let message = guideway::Simulation::new(&scene).err().expect("refused");
    assert!(message.contains("guideway sweep"), "{message}");
}
