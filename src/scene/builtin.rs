//! Scenes that ship with guideway: the examples of Lee (1994), trains of
//! bogie vehicles on multi-span bridges (TOML files in `trains/`), and the
//! bridge templates a bridge engineer starts from (the repository's
//! `scenes/` files, so that a user with only the binary has them).

use super::{BodyKind, Scene};

/// The scene `guideway run` uses when none is given.
pub const DEFAULT_SCENE: &str = "lee1994-wheel-10";

const BUILTINS: [(&str, &str); 9] = [
    (
        "lee1994-wheel-1",
        "Lee (1994) model 1: wheel rolling at 1 m/s onto a 24 m simply supported beam, dt = 0.005 s",
    ),
    (
        "lee1994-wheel-10",
        "Lee (1994) model 1: wheel rolling at 10 m/s onto a 24 m simply supported beam, dt = 0.0025 s (default)",
    ),
    (
        "lee1994-wheel-100",
        "Lee (1994) model 1: wheel rolling at 100 m/s onto a 24 m simply supported beam, dt = 0.0025 s",
    ),
    (
        "lee1994-glider-30",
        "Lee (1994) model 2: maglev glider (J = 0, r = 0) at 30 m/s over a 24 m simply supported beam, dt = 0.005 s",
    ),
    (
        "train-3-coaches-2x25-5",
        "three coaches on rolling wheelsets at 5 m/s from the approach over a 2 x 25 m continuous bridge onto the run-off, then 1 s of free vibration",
    ),
    (
        "train-2-coaches-2x40-100",
        "two coaches on glider wheelsets at 100 km/h over the middle pier of a 2 x 40 m continuous bridge, from the static start until the front wheelset nears the end",
    ),
    (
        "train-8-coaches-3x25-300",
        "eight coaches on glider wheelsets at 300 km/h from the approach over a 3 x 25 m continuous bridge onto the run-off, then 1 s of free vibration (Hertz wheel-rail contacts, HHT, alpha = -0.1, 0.5 ms)",
    ),
    (
        "bridge25-hslm",
        "bridge template: 25 m simply supported bridge, f1 = 4.0 Hz, 2 % damping, HSLM-A1 as moving forces at 50 m/s (`guideway sweep bridge25-hslm --speeds 100:400:5 --unit km/h --trains hslm`)",
    ),
    (
        "train-8-coaches-20m-300-hertz",
        "bridge template: eight coaches on Hertz wheel-rail contacts at 300 km/h over a 20 m span (12 t/m, f1 = 5.5 Hz, 1.5 %)",
    ),
];

/// The train scenes, as TOML (they are read like any scene file).
const TRAINS: [(&str, &str); 3] = [
    (
        "train-3-coaches-2x25-5",
        include_str!("trains/train-3-coaches-2x25-5.toml"),
    ),
    (
        "train-2-coaches-2x40-100",
        include_str!("trains/train-2-coaches-2x40-100.toml"),
    ),
    (
        "train-8-coaches-3x25-300",
        include_str!("trains/train-8-coaches-3x25-300.toml"),
    ),
];

/// Bridge templates: the shipped scene files, as TOML (built-ins like the
/// others, listed, run and guarded bit for bit; `bridge25_hslm`, the
/// file's own name, is the moving-force template's former name).
const TEMPLATES: [(&str, &str); 3] = [
    (
        "bridge25-hslm",
        include_str!("../../scenes/bridge25_hslm.toml"),
    ),
    (
        "bridge25_hslm",
        include_str!("../../scenes/bridge25_hslm.toml"),
    ),
    (
        "train-8-coaches-20m-300-hertz",
        include_str!("../../scenes/train-8-coaches-20m-300-hertz.toml"),
    ),
];

/// Names and one-line descriptions of the bridge templates (built-ins a
/// bridge engineer starts a scene file from).
pub fn templates() -> impl Iterator<Item = (&'static str, &'static str)> {
    BUILTINS
        .iter()
        .copied()
        .filter(|(name, _)| TEMPLATES.iter().any(|(template, _)| template == name))
}

/// The shipped scene file a bridge template is (relative to the
/// repository's root).
pub fn template_file(name: &str) -> Option<&'static str> {
    match name {
        "bridge25-hslm" | "bridge25_hslm" => Some("scenes/bridge25_hslm.toml"),
        "train-8-coaches-20m-300-hertz" => Some("scenes/train-8-coaches-20m-300-hertz.toml"),
        _ => None,
    }
}

/// Names and one-line descriptions of the built-in scenes.
pub fn builtins() -> &'static [(&'static str, &'static str)] {
    &BUILTINS
}

/// The built-ins a release ships as FMUs with cross-check results: the
/// paper's (a train's reference CSV would run to hundreds of MB; a
/// template is a file to start from, exported once edited).
pub fn fmu_builtins() -> impl Iterator<Item = &'static (&'static str, &'static str)> {
    BUILTINS.iter().filter(|(name, _)| {
        TRAINS.iter().all(|(train, _)| train != name)
            && TEMPLATES.iter().all(|(template, _)| template != name)
    })
}

/// The built-in scene of that name: the paper's model 1 beam (two
/// elements, sensor `midspan` at L/2) with the body, initial speed (m/s) and
/// time step (s) of the paper's example.
pub fn builtin(name: &str) -> Option<Scene> {
    if let Some((_, text)) = TRAINS.iter().find(|(known, _)| *known == name) {
        return Some(Scene::from_toml_str(text).expect("a built-in train scene is valid"));
    }
    if let Some((_, text)) = TEMPLATES.iter().find(|(known, _)| *known == name) {
        let mut scene = Scene::from_toml_str(text).expect("a bridge template is valid");
        // Named and described as listed (the former name keeps the file's).
        if let Some(&(name, description)) = BUILTINS.iter().find(|(known, _)| *known == name) {
            scene.name = name.to_string();
            scene.description = description.to_string();
        }
        return Some(scene);
    }
    let (kind, initial_speed, step) = match name {
        "lee1994-wheel-1" => (BodyKind::Wheel, 1.0, 0.005),
        "lee1994-wheel-10" => (BodyKind::Wheel, 10.0, 0.0025),
        "lee1994-wheel-100" => (BodyKind::Wheel, 100.0, 0.0025),
        "lee1994-glider-30" => (BodyKind::Glider, 30.0, 0.005),
        _ => return None,
    };
    let &(name, description) = BUILTINS.iter().find(|(known, _)| *known == name)?;
    let mut scene = Scene::lee1994(kind, initial_speed, step);
    scene.name = name.to_string();
    scene.description = description.to_string();
    Some(scene)
}
