//! The rules of `[track.on_deck]` (the rail over the deck): its values,
//! and what the rest of the scene must be for the rail-over-deck model to
//! hold it (a deck on its supports only, sleepers at the rail's nodes
//! unless the rail is meshed at them,
//! HHT-α on the full mesh); what it cannot do yet is refused with the
//! reason.

use super::{BodyKind, DampingSpec, Scene, StructureKind};
use crate::mesh::Mesh;
use crate::scene::error::Problem;
use crate::structure::rail_on_deck::RailOnDeck;

/// Most rail elements from the approach's start to the run-off's end: the
/// beam's own bound (`validate::MAX_ELEMENTS`).
const MAX_RAIL_ELEMENTS: f64 = super::validate::MAX_ELEMENTS as f64;

/// Every broken rule of `track.on_deck` (none when the track has none).
pub(super) fn problems(scene: &Scene) -> Vec<Problem> {
    let Some(spec) = &scene.track.on_deck else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut fail = |path: &str, value: String, rule: &str| {
        out.push(Problem::new(format!("track.on_deck.{path}"), value, rule))
    };
    // On sleepers the continuous layer is not built: its values are
    // refused rather than silently unused.
    let layer = spec.sleepers.is_none();
    for (path, value) in [
        ("rail_bending_stiffness", Some(spec.rail_bending_stiffness)),
        ("rail_mass_per_length", Some(spec.rail_mass_per_length)),
        ("stiffness", Some(spec.stiffness()).filter(|_| layer)),
        ("ground_stiffness", spec.ground_stiffness.filter(|_| layer)),
    ] {
        if let Some(x) = value.filter(|x| !(x.is_finite() && *x > 0.0)) {
            let rule = if path == "stiffness" && spec.stiffness.is_none() && spec.preset.is_none() {
                "the layer needs a stiffness > 0 (N/m²) or a preset (\"ballasted\" or \"slab\")"
            } else {
                "must be finite and > 0"
            };
            fail(path, format!("{x:?}"), rule);
        }
    }
    for (path, value) in [
        ("damping", spec.damping),
        ("ground_damping", spec.ground_damping),
    ] {
        if let Some(x) = value.filter(|x| !(x.is_finite() && *x >= 0.0)) {
            fail(path, format!("{x:?}"), "must be finite and >= 0");
        }
    }
    out.extend(sleeper_problems(scene));
    out.extend(layout_problems(scene));
    out.extend(unsupported(scene));
    out
}

/// The rules of `track.on_deck.sleepers`: every value given or preset and
/// in its range, the continuous layer's fields left out, and the spacing
/// a whole number of the deck's elements (sleepers sit at the rail's
/// nodes) unless `rail_elements_per_bay` meshes the rail at the sleepers.
fn sleeper_problems(scene: &Scene) -> Vec<Problem> {
    let Some(spec) = scene.track.on_deck.as_ref() else {
        return Vec::new();
    };
    let Some(sleepers) = spec.sleepers else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let layer = [
        ("preset", spec.preset.map(|_| f64::NAN)),
        ("stiffness", spec.stiffness),
        ("damping", spec.damping),
        ("ground_stiffness", spec.ground_stiffness),
        ("ground_damping", spec.ground_damping),
    ];
    for (path, value) in layer {
        if let Some(value) = value {
            out.push(Problem::new(
                format!("track.on_deck.{path}"),
                format!("{value:?}"),
                "is the continuous layer's: on sleepers the rail rests on them only; leave it \
                 out (the pads' and the ballast's values are in track.on_deck.sleepers)",
            ));
        }
    }
    let resolved = sleepers.resolve();
    for (name, value, rule) in resolved.problems() {
        let path = format!("track.on_deck.sleepers.{name}");
        out.push(Problem::new(path, format!("{value:?}"), rule));
    }
    // A rail meshed at the sleepers has a node at each whatever the deck's.
    if !(resolved.spacing > 0.0 && resolved.spacing.is_finite())
        || resolved.rail_elements_per_bay.is_some()
    {
        return out;
    }
    let Ok(element_length) = crate::structure::track_seam::deck_element_length(&scene.beam) else {
        return out;
    };
    let rail = RailOnDeck {
        deck_length: scene.beam.length,
        deck_bending_stiffness: scene.beam.bending_stiffness,
        rail_bending_stiffness: spec.rail_bending_stiffness,
        track_stiffness: 0.0,
        ground_stiffness: 0.0,
        approach: scene.track.approach,
        run_off: scene.track.run_off,
        element_length,
        sleepers: Some(resolved),
    };
    if let Some(rule) = rail.sleeper_problem(&scene.beam) {
        out.push(Problem::new(
            "track.on_deck.sleepers.spacing",
            format!("{:?}", resolved.spacing),
            rule,
        ));
    }
    out
}

/// A deck without springs or a foundation of its own, and a rail of
/// bounded size (the deck's elements, and the approach, the run-off and
/// the gaps in elements of at most the deck's longest).
fn layout_problems(scene: &Scene) -> Vec<Problem> {
    let (beam, track) = (&scene.beam, &scene.track);
    let mut out = Vec::new();
    if !beam.supports.springs.is_empty() || beam.foundation.is_some() {
        out.push(Problem::new(
            "track.on_deck",
            "",
            "the deck under a rail rests on its supports only: leave beam.supports.springs \
             and beam.foundation out (the track's own layer is track.on_deck)",
        ));
    }
    if matches!(beam.damping, Some(DampingSpec::Modal { .. })) {
        out.push(Problem::new(
            "beam.damping",
            "{ ratio }",
            "one ratio in every mode is a modal structure's; under a rail over the deck give \
             Rayleigh damping (coefficients, frequencies or modes)",
        ));
    }
    // A deck the beam's own rules refuse is reported there.
    let Ok(mesh) = Mesh::new(beam) else {
        return out;
    };
    // The rail's elements off the deck are at most the deck's longest; on
    // sleepers with `rail_elements_per_bay`, spacing / that count.
    let mut h = mesh.element_length.iter().copied().fold(0.0, f64::max);
    let gaps: f64 = beam.joints.iter().map(|j| j.gap).sum();
    let off_deck = ((track.approach + track.run_off + gaps) / h).ceil();
    let mut elements = mesh.element_length.len() as f64 + off_deck;
    let mut field = (
        "track.approach".to_string(),
        format!("{:?}", track.approach),
    );
    let sleepers = track.on_deck.and_then(|d| d.sleepers).map(|s| s.resolve());
    if let Some(s) = sleepers.filter(|s| s.spacing > 0.0) {
        if let Some(per_bay) = s.rail_elements_per_bay.filter(|n| *n > 0) {
            h = s.spacing / per_bay as f64;
            elements = ((track.approach + beam.length + track.run_off) / h).ceil();
            let path = "track.on_deck.sleepers.rail_elements_per_bay";
            field = (
                path.into(),
                format!("{per_bay} (spacing {:?} m)", s.spacing),
            );
        }
    }
    if elements > MAX_RAIL_ELEMENTS {
        out.push(Problem::new(
            field.0,
            field.1,
            format!(
                "the rail from the approach to the run-off would have {elements:.0} elements \
                 of {h:?} m, more than {MAX_RAIL_ELEMENTS}"
            ),
        ));
    }
    out
}

/// What the rail over the deck does not do yet, each with the reason.
fn unsupported(scene: &Scene) -> Vec<Problem> {
    let mut out = Vec::new();
    let solver = &scene.solver;
    if !solver.integrator.steps_track_on_deck() {
        out.push(Problem::new(
            "solver.integrator",
            format!("{:?}", solver.integrator).to_lowercase(),
            "the rail over the deck is stepped by HHT-α only: set integrator = \"hht\"",
        ));
    }
    if solver.structure != StructureKind::Full {
        out.push(Problem::new(
            "solver.structure",
            "\"modal\"",
            crate::structure::seam::TRACK_NOT_MODAL,
        ));
    }
    if !scene.track.irregularities.is_empty() {
        out.push(Problem::new(
            "track.irregularities",
            format!("{} irregularities", scene.track.irregularities.len()),
            "are not built on a rail over the deck yet (the rail's abscissa starts at the \
             approach): leave them out",
        ));
    }
    if !scene.sections.is_empty() || scene.reactions {
        out.push(Problem::new(
            "sections",
            "",
            "sections and support reactions of a deck under a rail are not built yet (the \
             deck's element forces need the track layer's load): leave sections and \
             reactions out",
        ));
    }
    if scene
        .every_vehicle()
        .any(|v| v.kind == BodyKind::MovingForce)
    {
        out.push(Problem::new(
            "body.kind",
            "\"moving_force\"",
            "a crossing of moving forces runs on the bare beam; on a rail over the deck use a \
             vehicle (a glider of the force's mass)",
        ));
    }
    out
}
