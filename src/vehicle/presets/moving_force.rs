//! The moving-force preset: a point force at constant speed with no body
//! (its weight plus `force_y`, or each axle of an HSLM `train`), run as a
//! crossing of prescribed forces (`moving_load`), never built into bodies.

use super::{refuse_unless, Preset, Reach, Vehicle};
use crate::beam::Beam;
use crate::scene::fields::{Access, Default as FieldDefault, Field, Rule};
use crate::scene::{fmt_f64, quoted, BodyKind, BodySpec, Checks, Scene};

/// Why a scene of moving forces has no system of bodies and contacts.
pub const MOVING_FORCE_REFUSAL: &str =
    "body.kind = \"moving_force\": a moving force has no body for the contact \
     iteration to move; `guideway run SCENE` and `guideway sweep SCENE` run it as a \
     crossing of prescribed forces (the library's moving_load::ForceRun and Crossing)";

/// Whether the scene's vehicles are moving forces (validation has made
/// them all moving forces or none): the run is then a crossing of
/// prescribed forces, not a system of bodies.
pub fn is_moving_force_scene(scene: &Scene) -> bool {
    (scene.vehicles.iter()).any(|v| v.kind == BodyKind::MovingForce)
}

pub struct MovingForce;

impl Preset for MovingForce {
    const DESCRIPTION: &'static str = "moving force (no body)";
    const ROWS: &'static [Field] = TRAIN_ROWS;
    const ROWS_BEFORE: &'static str = "body.force_x";

    /// A train names an HSLM train and replaces the force's own (so
    /// `force_y` must be left at 0).
    fn check(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        let Some(name) = &body.train else {
            return;
        };
        if crate::vehicle::hslm::hslm(name).is_none() {
            checks.fail(
                format!("{prefix}.train"),
                quoted(name),
                "must name a built-in train: HSLM-A1 … HSLM-A10",
            );
        } else if body.force_y != 0.0 {
            checks.fail(
                format!("{prefix}.force_y"),
                fmt_f64(body.force_y),
                "must be 0 for a moving force with a train (each axle carries the train's force)",
            );
        }
    }

    fn refuse_stray(checks: &mut Checks, prefix: &str, body: &BodySpec) {
        if let Some(name) = &body.train {
            refuse_unless(checks, prefix, "train", quoted(name), "moving_force");
        }
    }

    fn build(_spec: &BodySpec, _beam: &Beam, _gravity: f64) -> Result<Vehicle, String> {
        Err(MOVING_FORCE_REFUSAL.into())
    }

    /// A train's axles trail behind its first by the train's length.
    fn reach(spec: &BodySpec) -> Option<Reach> {
        let train = spec.train.as_deref().and_then(crate::vehicle::hslm::hslm);
        Some(Reach {
            ahead: 0.0,
            behind: train.map_or(0.0, |t| t.length()),
        })
    }

    /// A moving force is a load, not a body.
    fn body_names(_spec: &BodySpec) -> Vec<String> {
        Vec::new()
    }

    fn on_followers(_spec: &BodySpec) -> bool {
        false
    }

    fn contact_rows(_spec: &BodySpec) -> usize {
        0
    }
}

/// The field table's rows of the fields this preset owns.
const TRAIN_ROWS: &[Field] = &[Field {
    path: "body.train",
    unit: "",
    default: FieldDefault::Absent,
    rule: Rule::Words,
    note: "HSLM-A1 ... HSLM-A10; moving_force only",
    doc: "",
    access: Access::None,
}];
