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

/// The axles of Figure E.1 found by walking along the train vehicle by
/// vehicle from their ends and bogie centres (rather than by the chain of
/// axle spacings above): a power car is 3.525 + 3 + 11 + 3 + 3.525 m
/// between its ends, its axles 3.525 m from them; an end coach has 3.525 m
/// before its own bogie (3 m), then 15 m from that bogie's rear axle to the
/// first axle of the Jacobs bogie it shares with the first intermediate
/// coach, and ends at that bogie's centre; each intermediate coach is D
/// between the centres of its two Jacobs bogies, whose axles are d apart
/// about them; the rear end coach and power car mirror the front ones.
fn walk_figure_e1(n: usize, coach: f64, bogie: f64) -> Vec<f64> {
    let mut axles = Vec::new();
    // The leading power car's front end; its first axle is at 0.
    let front = -3.525;
    let power_car = |start: f64, axles: &mut Vec<f64>| {
        axles.extend([3.525, 6.525, 17.525, 20.525].map(|a| start + a));
        start + 24.05
    };
    let end_coach_front = power_car(front, &mut axles);
    axles.extend([end_coach_front + 3.525, end_coach_front + 6.525]);
    let first_jacobs_centre = end_coach_front + 6.525 + 15.0 + bogie / 2.0;
    let centres: Vec<f64> = (0..=n)
        .map(|k| first_jacobs_centre + k as f64 * coach)
        .collect();
    for c in &centres {
        axles.extend([c - bogie / 2.0, c + bogie / 2.0]);
    }
    // The rear end coach starts at the last Jacobs bogie's centre.
    let rear_coach_axle = centres[n] + bogie / 2.0 + 15.0;
    axles.extend([rear_coach_axle, rear_coach_axle + 3.0]);
    let rear_coach_end = rear_coach_axle + 3.0 + 3.525;
    power_car(rear_coach_end, &mut axles);
    axles
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
    // The same positions walking vehicle by vehicle; every intermediate
    // coach D long between its Jacobs bogies' centres.
    let walked = walk_figure_e1(n, coach, bogie);
    assert_eq!(walked.len(), axles.len(), "{name}: axle count of the walk");
    for (k, ((offset, _), want)) in axles.iter().zip(&walked).enumerate() {
        assert!(
            (offset - want).abs() < 1e-9,
            "{name} axle {k}: {offset} m, Figure E.1 walked gives {want} m"
        );
    }
    let jacobs = &axles[6..6 + 2 * (n + 1)];
    let centres: Vec<f64> = jacobs.chunks(2).map(|a| 0.5 * (a[0].0 + a[1].0)).collect();
    for pair in centres.windows(2) {
        assert!((pair[1] - pair[0] - coach).abs() < 1e-9, "{name}: D");
    }
    for axle in jacobs.chunks(2) {
        assert!((axle[1].0 - axle[0].0 - bogie).abs() < 1e-9, "{name}: d");
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
    scene.vehicles[0].kind = BodyKind::MovingForce;
    scene.vehicles[0].force_y = 0.0;
    scene.vehicles[0].train = Some(name.to_lowercase());
    scene.vehicles[0].initial_position = 1.0;
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
    scene.vehicles[0].train = Some("HSLM-A11".into());
    let message = scene.validate().unwrap_err().to_string();
    assert!(message.contains("body.train"), "{message}");
    scene.vehicles[0].kind = BodyKind::MovingForce;
    scene.vehicles[0].force_y = 0.0;
    let message = scene.validate().unwrap_err().to_string();
    assert!(message.contains("HSLM-A1 … HSLM-A10"), "{message}");
}

#[test]
fn a_moving_force_scene_is_refused_by_the_contact_simulation_with_the_way_out() {
    let mut scene = Scene::load("lee1994-glider-30").expect("built-in");
    scene.vehicles[0].kind = BodyKind::MovingForce;
    scene.validate().expect("valid");
    let message = guideway::Simulation::new(&scene).err().expect("refused");
    assert!(message.contains("guideway sweep"), "{message}");
}
