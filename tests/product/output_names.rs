//! The catalogue's names read both ways (DESIGN.md step 10): for every
//! output of every built-in scene and scene file, `outputs::classify`
//! gives back the quantity the catalogue built it for (and its owner's
//! name, read from the system and the scene), and `outputs::output_name`
//! of that gives back the name. A CSV reader that classifies a column
//! therefore finds what the live catalogue holds.

use guideway::outputs::{classify, output_name, Quantity, QuantityKind};
use guideway::scene::{builtin, builtins};
use guideway::{Scene, Simulation};

/// The built-in scenes and the project's scene files.
fn scenes() -> Vec<Scene> {
    let mut all: Vec<Scene> = builtins()
        .iter()
        .map(|(name, _)| builtin(name).unwrap())
        .collect();
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for path in files {
        all.push(Scene::load(path.to_str().unwrap()).unwrap());
    }
    all
}

/// The owner's name of `q` as the system and the scene hold it, where the
/// quantity's index says it (`None`: a support's, the run's own, or a
/// nominal speed, which is its body's or its attached contact's).
fn owner_of(sim: &Simulation, scene: &Scene, q: Quantity) -> Option<String> {
    use Quantity::*;
    let system = sim.system();
    let body = |b: usize| system.bodies[b].name.clone();
    let contact = |c: usize| system.contacts[c].name.clone();
    Some(match q {
        X(b) | Y(b) | Vx(b) | Vy(b) | Ax(b) | Ay(b) => body(b),
        AngularAcceleration(b) | Angle(b) | AngularVelocity(b) => body(b),
        ContactPosition(c) | TangentialForce(c) | NormalForce(c) | OnBeam(c) => contact(c),
        ContactClosed(c) | Gap(c) | MagnetAirGap(c) | MagnetCurrent(c) => contact(c),
        ImpulseTangential(c) | ImpulseNormal(c) | Irregularity(c) => contact(c),
        Sensor(i) | SensorVelocity(i) | SensorAcceleration(i) => scene.sensors[i].name.clone(),
        SensorFoundationLoad(i) | SensorRailDeflection(i) | SensorRailSeatForce(i) => {
            scene.sensors[i].name.clone()
        }
        SectionMoment(i) | SectionShear(i) => scene.sections[i].name.clone(),
        _ => return None,
    })
}

#[test]
fn every_output_name_reads_back_as_its_quantity_and_its_owner() {
    let mut checked = 0;
    let mut kinds = std::collections::HashSet::new();
    for scene in scenes() {
        // Moving forces have no `Simulation` (their outputs are the
        // structure's, named by the same catalogue).
        let Ok(sim) = Simulation::new(&scene) else {
            continue;
        };
        assert_eq!(sim.outputs().len(), sim.quantities().len());
        for (info, &q) in sim.outputs().iter().zip(sim.quantities()) {
            let named = classify(&info.name)
                .unwrap_or_else(|| panic!("{}: {} is not classified", scene.name, info.name));
            assert_eq!(named.kind, q.kind(), "{}: {}", scene.name, info.name);
            if let Some(owner) = owner_of(&sim, &scene, q) {
                assert_eq!(named.owner, owner, "{}: {}", scene.name, info.name);
            }
            assert_eq!(output_name(named.kind, named.owner), info.name);
            kinds.insert(q.kind());
            checked += 1;
        }
    }
    assert!(checked > 500, "{checked} outputs");
    // The scenes reach the bodies', contacts', sensors' and run's outputs.
    for kind in [
        QuantityKind::NominalSpeed,
        QuantityKind::NormalForce,
        QuantityKind::ContactClosed,
        QuantityKind::Ay,
        QuantityKind::Sensor,
        QuantityKind::Balance,
        QuantityKind::Iterations,
    ] {
        assert!(kinds.contains(&kind), "{kind:?} never checked");
    }
}

#[test]
fn names_that_are_no_output_are_not_classified() {
    for name in [
        "time",
        "sensor.midspan.acceleration_filtered",
        "sensor.midspan.deflection_error",
        "energy.x_total",
        "wheel",
        ".x",
        "wheel.speed",
    ] {
        assert_eq!(classify(name), None, "{name}");
    }
}
