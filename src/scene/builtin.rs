//! Scenes that ship with guideway: the examples of Lee (1994).

use super::{BodyKind, Scene};

/// The scene `guideway run` uses when none is given.
pub const DEFAULT_SCENE: &str = "lee1994-wheel-10";

const BUILTINS: [(&str, &str); 4] = [
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
];

/// Names and one-line descriptions of the built-in scenes.
pub fn builtins() -> &'static [(&'static str, &'static str)] {
    &BUILTINS
}

/// The built-in scene of that name: the paper's model 1 beam (two
/// elements, sensor `midspan` at L/2) with the body, initial speed (m/s) and
/// time step (s) of the paper's example.
pub fn builtin(name: &str) -> Option<Scene> {
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
