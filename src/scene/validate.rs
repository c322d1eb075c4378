//! The rules a scene must satisfy before a model is built from it.
//!
//! Every rule is checked and every broken one reported, so that a person can
//! fix a scene file in one pass.

use super::fields::{Access, Rule, FIELDS};
use super::{
    BodyKind, DampingSpec, EndSupport, ForceProfile, FoundationSpec, JointKind, Scene, SceneError,
};
use crate::scene::error::Problem;
use std::collections::HashSet;

/// Output-name prefixes the simulation uses itself; a body may not take one.
const RESERVED_BODY_NAMES: [&str; 4] = ["contact", "energy", "sensor", "solver"];

/// More elements than this is a typo, not a model (and memory to match).
pub const MAX_ELEMENTS: usize = 100_000;

/// Longest scene, body or sensor name (characters). The scene name becomes
/// the FMU's model identifier and so a file name inside the FMU, which a
/// file system limits to 255 bytes.
pub const MAX_NAME_CHARS: usize = 64;

/// Longest description (characters): one line of text, copied into the
/// FMU's modelDescription.xml and documentation.
pub const MAX_DESCRIPTION_CHARS: usize = 1000;

/// Largest scene text (bytes): a scene is a few kB; the limit keeps a
/// hostile file from taking memory and time before any rule is checked.
pub const MAX_SCENE_BYTES: u64 = 10_000_000;

/// Most sensors: each adds an output column to every row of a run.
pub const MAX_SENSORS: usize = 10_000;

/// Most intermediate supports.
pub const MAX_INTERMEDIATE_SUPPORTS: usize = 10_000;

/// Largest `solver.max_iterations`: each iteration integrates the whole
/// beam over a step, so the cap bounds the work of one step.
pub const MAX_ITERATIONS: u32 = 1000;

// The magnitudes every real of a scene keeps (the contact laws' own rules
// read them too, below the scene).
pub use crate::numbers::{MAX_MAGNITUDE, MIN_MAGNITUDE};

/// More vehicles than this is a typo, not a train.
pub const MAX_VEHICLES: usize = 1_000;

/// Rows of a prescribed-speed table.
pub const MAX_SPEED_ROWS: usize = 10_000;

pub(super) fn validate(scene: &Scene) -> Result<(), SceneError> {
    let mut checks = Checks::default();
    check_name(&mut checks, scene);
    let length_ok = check_beam(&mut checks, scene);
    check_track(&mut checks, scene);
    check_bodies(&mut checks, scene, length_ok);
    check_sensors(&mut checks, scene, length_ok);
    check_sections(&mut checks, scene, length_ok);
    check_solver(&mut checks, scene);
    checks.problems.extend(super::irregularity::problems(scene));
    checks.problems.extend(super::on_deck::problems(scene));
    check_couplings(&mut checks, scene);
    checks.problems.extend(super::limits::problems(scene));
    if checks.problems.is_empty() {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            problems: checks.problems,
        })
    }
}

fn check_name(checks: &mut Checks, scene: &Scene) {
    let valid = !scene.name.is_empty()
        && scene
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if !valid {
        checks.fail(
            "name",
            quoted(&scene.name),
            "must be non-empty and use only ASCII letters, digits, '-', '_' and '.'",
        );
    }
    checks.name_length("name", &scene.name);
    let description = &scene.description;
    if description.contains(['\n', '\r']) {
        checks.fail("description", quoted(description), "must be one line");
    }
    if let Some((at, c)) = description
        .chars()
        .enumerate()
        .find(|&(_, c)| !is_xml_char(c))
    {
        checks.fail(
            "description",
            quoted(description),
            format!(
                "character {at} is U+{:04X}, which XML 1.0 cannot carry (the description goes \
                 into the FMU's modelDescription.xml)",
                c as u32
            ),
        );
    }
    let chars = description.chars().count();
    if chars > MAX_DESCRIPTION_CHARS {
        checks.fail(
            "description",
            quoted(description),
            format!("has {chars} characters, more than the limit of {MAX_DESCRIPTION_CHARS}"),
        );
    }
}

/// A character XML 1.0 can carry: tab, line feed, carriage return, and
/// everything from U+0020 on except U+FFFE and U+FFFF (Rust's `char`
/// already excludes the surrogates).
pub fn is_xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}')
}

/// Rayleigh damping: non-negative coefficients, ratios in [0, 1), two
/// distinct modes or frequencies (else α and β are undetermined).
fn check_damping(checks: &mut Checks, damping: &DampingSpec) {
    match damping {
        DampingSpec::Coefficients { alpha, beta } => {
            checks.non_negative("beam.damping.alpha", *alpha);
            checks.non_negative("beam.damping.beta", *beta);
        }
        DampingSpec::Modal { ratio } => check_ratio(checks, "beam.damping.ratio", *ratio),
        DampingSpec::Modes { ratio, modes } => {
            check_ratio(checks, "beam.damping.ratio", *ratio);
            if modes[0] < 1 || modes[1] < 1 || modes[0] == modes[1] {
                checks.fail(
                    "beam.damping.modes",
                    format!("{modes:?}"),
                    "must be two different mode numbers, counted from 1",
                );
            }
        }
        DampingSpec::Frequencies {
            ratios,
            frequencies,
        } => {
            for (i, ratio) in ratios.iter().enumerate() {
                check_ratio(checks, &format!("beam.damping.ratios[{i}]"), *ratio);
            }
            for (i, f) in frequencies.iter().enumerate() {
                checks.positive(&format!("beam.damping.frequencies[{i}]"), *f);
            }
            if frequencies[0] == frequencies[1] {
                checks.fail(
                    "beam.damping.frequencies",
                    format!("{frequencies:?}"),
                    "must be two different frequencies (Hz)",
                );
                return;
            }
            let omega = frequencies.map(|f| std::f64::consts::TAU * f);
            let c = crate::beam::Rayleigh::from_ratios(omega, *ratios);
            if c.mass < 0.0 || c.stiffness < 0.0 {
                checks.fail(
                    "beam.damping.ratios",
                    format!("{ratios:?}"),
                    format!(
                        "give negative Rayleigh coefficients (alpha = {:e}, beta = {:e}) at \
                         frequencies {frequencies:?} Hz; the ratio may fall at most in \
                         proportion to the frequency and rise at most with it",
                        c.mass, c.stiffness
                    ),
                );
            }
        }
    }
}

fn check_ratio(checks: &mut Checks, path: &str, ratio: f64) {
    if checks.finite(path, ratio) && !(0.0..1.0).contains(&ratio) {
        checks.fail(path, fmt_f64(ratio), "must be a damping ratio in [0, 1)");
    }
}

/// Every number of the scene itself that the field table reads whose path
/// starts with one of `prefixes`, against its row's rule in the row's
/// words (by part of the scene, so that problems keep the file's order);
/// the checks of each part add the rules that tie fields to each other.
fn check_scene_fields(checks: &mut Checks, scene: &Scene, prefixes: &[&str]) {
    for f in FIELDS.iter() {
        if !matches!(f.access, Access::Scene(..) | Access::Beam(..)) {
            continue;
        }
        if !prefixes.iter().any(|p| f.path.starts_with(p)) {
            continue;
        }
        let Some(x) = f.value(scene, 0) else { continue };
        if let Some(words) = f.rule.problem(x, scene.track.approach) {
            // (a count reads as one: `0`, not `0.0`)
            let shown = match f.rule {
                Rule::Elements => format!("{x}"),
                _ => fmt_f64(x),
            };
            checks.fail(f.path, shown, words);
        }
    }
}

/// Returns whether the beam length is usable for range checks elsewhere.
fn check_beam(checks: &mut Checks, scene: &Scene) -> bool {
    let beam = &scene.beam;
    check_scene_fields(checks, scene, &["beam."]);
    let length_ok = Rule::Positive.problem(beam.length, 0.0).is_none();
    if let Some(f1) = beam.frequency {
        // Reading a scene turns f1 into EI; a scene built in code gives EI.
        checks.fail(
            "beam.frequency",
            fmt_f64(f1),
            "is read from a scene file only; give beam.bending_stiffness here",
        );
    }
    if let Some(foundation) = &beam.foundation {
        check_foundation(checks, foundation);
    }
    if let Some(damping) = &beam.damping {
        check_damping(checks, damping);
    }

    check_intermediate_supports(checks, scene, length_ok);
    check_springs(checks, scene, length_ok);
    check_joints(checks, scene, length_ok);
    check_leftward_over_joints(checks, scene);
    check_held(checks, scene);
    length_ok
}

/// Intermediate supports: at most `MAX_INTERMEDIATE_SUPPORTS`, strictly
/// inside the beam, increasing.
fn check_intermediate_supports(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let beam = &scene.beam;
    let supports = &beam.supports;
    let mut previous: Option<f64> = None;
    let count = supports.intermediate.len();
    if count > MAX_INTERMEDIATE_SUPPORTS {
        checks.fail(
            "beam.supports.intermediate",
            format!("{count} supports"),
            format!("must hold at most {MAX_INTERMEDIATE_SUPPORTS}"),
        );
    }
    let listed = supports.intermediate.iter().take(MAX_INTERMEDIATE_SUPPORTS);
    for (i, &x) in listed.enumerate() {
        let path = format!("beam.supports.intermediate[{i}]");
        if !checks.finite(&path, x) {
            continue;
        }
        if length_ok && !(x > 0.0 && x < beam.length) {
            checks.fail(
                &path,
                fmt_f64(x),
                format!(
                    "must lie strictly inside the beam, 0 < x < beam.length = {}",
                    fmt_f64(beam.length)
                ),
            );
        }
        if let Some(before) = previous {
            if x <= before {
                checks.fail(
                    &path,
                    fmt_f64(x),
                    format!(
                        "must be greater than the support before it ({})",
                        fmt_f64(before)
                    ),
                );
            }
        }
        previous = Some(x);
    }
}

/// The supports, springs, joints and foundation hold the beam against
/// rigid motion.
fn check_held(checks: &mut Checks, scene: &Scene) {
    let (beam, supports) = (&scene.beam, &scene.beam.supports);
    let held = |end: EndSupport| match end {
        EndSupport::Pinned => 1,
        EndSupport::Clamped => 2,
        EndSupport::Free => 0,
    };
    let springs: usize = supports
        .springs
        .iter()
        .map(|s| usize::from(s.vertical > 0.0) + usize::from(s.rotational > 0.0))
        .sum();
    let joints: usize = beam
        .joints
        .iter()
        .map(|j| match j.kind {
            JointKind::Continuous => 1,
            JointKind::Separate => 2,
            JointKind::Hinge => 0,
        })
        .sum();
    let hinges = beam
        .joints
        .iter()
        .filter(|j| j.kind == JointKind::Hinge)
        .count();
    let constraints = (held(supports.left)
        + held(supports.right)
        + supports.intermediate.len()
        + springs
        + joints)
        .saturating_sub(hinges);
    // A foundation holds every rigid motion by itself.
    if constraints < 2 && beam.foundation.is_none() {
        checks.fail(
            "beam.supports",
            format!(
                "left = {:?}, right = {:?}, {} intermediate",
                supports.left,
                supports.right,
                supports.intermediate.len()
            )
            .to_lowercase(),
            "must hold the beam against rigid motion (e.g. two pinned ends, or one clamped end)",
        );
    }
}

/// A Winkler foundation: a positive modulus (given or from the preset), a
/// non-negative damping.
fn check_foundation(checks: &mut Checks, foundation: &FoundationSpec) {
    match foundation.stiffness {
        Some(k) => {
            checks.positive("beam.foundation.stiffness", k);
        }
        None if foundation.preset.is_none() => checks.fail(
            "beam.foundation.stiffness",
            "missing",
            "a foundation needs a modulus > 0 (N/m²) or a preset (\"ballasted\" or \"slab\")",
        ),
        None => {}
    }
    if let Some(c) = foundation.damping {
        checks.non_negative("beam.foundation.damping", c);
    }
}

/// Elastic supports: on the track, finite non-negative springs and dampers.
fn check_springs(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let springs = &scene.beam.supports.springs;
    if springs.len() > MAX_INTERMEDIATE_SUPPORTS {
        checks.fail(
            "beam.supports.springs",
            format!("{} springs", springs.len()),
            format!("must hold at most {MAX_INTERMEDIATE_SUPPORTS}"),
        );
        return;
    }
    for (i, spring) in springs.iter().enumerate() {
        let path = |field: &str| format!("beam.supports.springs[{i}].{field}");
        for (field, value) in [
            ("vertical", spring.vertical),
            ("rotational", spring.rotational),
            ("vertical_damping", spring.vertical_damping),
            ("rotational_damping", spring.rotational_damping),
        ] {
            checks.non_negative(&path(field), value);
        }
        let length = scene.beam.length;
        if checks.finite(&path("at"), spring.at) && length_ok {
            if !(0.0..=length).contains(&spring.at) {
                checks.fail(
                    path("at"),
                    fmt_f64(spring.at),
                    format!(
                        "must lie on the track, 0 <= x <= beam.length = {}",
                        fmt_f64(length)
                    ),
                );
            } else if in_gap(scene, spring.at) {
                checks.fail(path("at"), fmt_f64(spring.at), "must not lie in a rail gap");
            }
        }
    }
}

/// Joints: strictly inside the track, increasing, gaps only at separate
/// joints, each beam at least as long as its gap is wide apart.
fn check_joints(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let joints = &scene.beam.joints;
    if joints.len() > MAX_INTERMEDIATE_SUPPORTS {
        checks.fail(
            "beam.joints",
            format!("{} joints", joints.len()),
            format!("must hold at most {MAX_INTERMEDIATE_SUPPORTS}"),
        );
        return;
    }
    let mut previous_end: Option<f64> = None;
    for (i, joint) in joints.iter().enumerate() {
        let path = |field: &str| format!("beam.joints[{i}].{field}");
        let at_ok = checks.finite(&path("at"), joint.at);
        checks.non_negative(&path("gap"), joint.gap);
        if joint.gap != 0.0 && joint.kind != JointKind::Separate {
            checks.fail(
                path("gap"),
                fmt_f64(joint.gap),
                "must be 0 unless kind = \"separate\" (only separate beams leave a gap)",
            );
        }
        if !(at_ok && joint.gap.is_finite()) {
            continue;
        }
        let end = joint.at + joint.gap;
        if length_ok && !(joint.at > 0.0 && end < scene.beam.length) {
            checks.fail(
                path("at"),
                fmt_f64(joint.at),
                format!(
                    "must lie strictly inside the track with its gap, 0 < at and at + gap < \
                     beam.length = {}",
                    fmt_f64(scene.beam.length)
                ),
            );
        }
        if let Some(before) = previous_end {
            if joint.at <= before {
                checks.fail(
                    path("at"),
                    fmt_f64(joint.at),
                    format!(
                        "must lie after the joint before it and its gap ({})",
                        fmt_f64(before)
                    ),
                );
            }
        }
        previous_end = Some(end);
    }
    check_gap_crossing(checks, scene);
    check_supports_off_gaps(checks, scene);
}

/// No intermediate support in a rail gap or at a separate joint's end.
fn check_supports_off_gaps(checks: &mut Checks, scene: &Scene) {
    let joints = &scene.beam.joints;
    for (i, &x) in scene.beam.supports.intermediate.iter().enumerate() {
        let separate_end = joints
            .iter()
            .any(|j| j.kind == JointKind::Separate && (x == j.at || x == j.at + j.gap));
        if in_gap(scene, x) || separate_end {
            checks.fail(
                format!("beam.supports.intermediate[{i}]"),
                fmt_f64(x),
                "must not lie in a rail gap or at a separate joint (whose beam ends are \
                 pinned already)",
            );
        }
    }
}

/// Only wheels cross rail gaps, and only gaps narrower than their radius.
/// Every vehicle, each with the path its fields are named by.
pub(super) fn bodies_with_paths(scene: &Scene) -> impl Iterator<Item = (String, &super::BodySpec)> {
    let vehicles = scene.vehicles.iter().enumerate();
    vehicles.map(|(k, v)| (super::vehicle_path(k), v))
}

fn check_gap_crossing(checks: &mut Checks, scene: &Scene) {
    // Under a rail (track.on_deck) the contacts run on the rail, which
    // spans the deck's gaps and joints.
    if scene.track.on_deck.is_some() {
        return;
    }
    let Some((i, widest)) = scene
        .beam
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.gap > 0.0)
        .max_by(|a, b| a.1.gap.total_cmp(&b.1.gap))
    else {
        return;
    };
    for (prefix, body) in bodies_with_paths(scene) {
        match (body.kind, body.radius) {
            (BodyKind::Wheel, Some(r)) if widest.gap >= r => checks.fail(
                format!("beam.joints[{i}].gap"),
                fmt_f64(widest.gap),
                format!(
                    "must be less than the radius of {prefix} ({}): a wheel rolls over a gap \
                     narrower than its radius",
                    fmt_f64(r)
                ),
            ),
            (BodyKind::Wheel, _) => {}
            _ => checks.fail(
                format!("beam.joints[{i}].gap"),
                fmt_f64(widest.gap),
                format!(
                    "must be 0 with {prefix}.kind = {:?}: gliders, sprung masses and bogie \
                     vehicles touch the track at a point, which would fall into a rail gap; \
                     only wheels cross gaps",
                    body.kind
                )
                .to_lowercase(),
            ),
        }
    }
}

/// Joints (separate or hinged) are crossed moving right only: a contact
/// body that starts moving left on a track with joints is refused before
/// the run, not stopped at the first joint.
fn check_leftward_over_joints(checks: &mut Checks, scene: &Scene) {
    if scene.track.on_deck.is_some()
        || scene
            .beam
            .joints
            .iter()
            .all(|j| j.kind == JointKind::Continuous)
    {
        return;
    }
    for (prefix, body) in bodies_with_paths(scene) {
        let prescribed_left = match &body.prescribed_speed {
            Some(super::SpeedSpec::Constant(v)) => *v < 0.0,
            Some(super::SpeedSpec::Table(rows)) => rows.iter().any(|r| r[1] < 0.0),
            None => false,
        };
        if body.kind == BodyKind::MovingForce || !(body.initial_speed < 0.0 || prescribed_left) {
            continue;
        }
        let (field, value) = if body.initial_speed < 0.0 {
            ("initial_speed", fmt_f64(body.initial_speed))
        } else {
            ("prescribed_speed", "a speed below 0".to_string())
        };
        checks.fail(
            format!("{prefix}.{field}"),
            value,
            "must not be negative on a track with beam.joints (separate or hinge): joints are \
             crossed moving right only; mirror the scene (x → beam.length − x) to run it the \
             other way",
        );
    }
}

/// Whether `x` lies strictly inside the gap of a separate joint.
pub(crate) fn in_gap(scene: &Scene, x: f64) -> bool {
    scene
        .beam
        .joints
        .iter()
        .any(|j| j.kind == JointKind::Separate && x > j.at && x < j.at + j.gap)
}

fn check_bodies(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let Some(first) = scene.vehicles.first() else {
        checks.fail("body", "missing", "a scene needs a vehicle ([body])");
        return;
    };
    check_body(checks, scene, "body", first, length_ok);
    let besides_body = scene.vehicles.len() - 1;
    if besides_body > MAX_VEHICLES {
        checks.fail(
            "vehicles",
            format!("{besides_body} vehicles"),
            format!("at most {MAX_VEHICLES} besides [body]"),
        );
        return;
    }
    check_moving_forces_alone(checks, scene);
    let mut names = HashSet::from([first.name.as_str()]);
    for (k, vehicle) in scene.vehicles.iter().enumerate().skip(1) {
        let prefix = super::vehicle_path(k);
        check_body(checks, scene, &prefix, vehicle, length_ok);
        if !names.insert(vehicle.name.as_str()) {
            checks.fail(
                format!("{prefix}.name"),
                quoted(&vehicle.name),
                "must differ from the names of [body] and the other vehicles",
            );
        }
    }
}

/// The rules of one vehicle, `[body]` or `[[vehicles]]`, at `prefix`.
fn check_body(
    checks: &mut Checks,
    scene: &Scene,
    prefix: &str,
    body: &super::BodySpec,
    length_ok: bool,
) {
    let path = |field: &str| format!("{prefix}.{field}");
    check_body_name(checks, &path("name"), &body.name);
    check_vehicle_fields(checks, prefix, body);
    crate::vehicle::presets::check(checks, prefix, body);
    check_wheelsets_on_track(checks, prefix, body, scene);
    if checks.finite(&path("initial_position"), body.initial_position) && length_ok {
        let x = body.initial_position;
        let (approach, end) = (scene.track.approach, scene.beam.length);
        if !(x >= -approach && x < end) {
            let rule = if approach > 0.0 {
                format!(
                    "must lie on the approach or the beam, -track.approach = {} <= x < \
                     beam.length = {}",
                    fmt_f64(-approach),
                    fmt_f64(end)
                )
            } else {
                format!(
                    "must lie on the beam, 0 <= x < beam.length = {}",
                    fmt_f64(end)
                )
            };
            checks.fail(path("initial_position"), fmt_f64(x), rule);
        } else if in_gap(scene, x) {
            checks.fail(
                path("initial_position"),
                fmt_f64(x),
                "must not lie in a rail gap (between beam.joints[].at and at + gap)",
            );
        }
    }
    check_prescribed_speed(checks, prefix, body);
    check_flight(checks, scene, prefix, body);
    check_contact_law(checks, prefix, body);
}

/// Every number of one vehicle that the field table reads (`body.*` rows,
/// named at `prefix`), against its row's rule in the row's words; only
/// present values are checked (a kind's missing block is its preset's
/// problem). `initial_position` (`Rule::OnTrack`) is left to `check_body`,
/// whose one message gives both ends of the track.
fn check_vehicle_fields(checks: &mut Checks, prefix: &str, body: &super::BodySpec) {
    for f in FIELDS.iter() {
        let Access::Vehicle(get, _) = f.access else {
            continue;
        };
        if f.rule == Rule::OnTrack {
            continue;
        }
        let Some(x) = get(body) else { continue };
        if let Some(words) = f.rule.problem(x, 0.0) {
            let field = f.path.strip_prefix("body.").unwrap_or(f.path);
            checks.fail(format!("{prefix}.{field}"), fmt_f64(x), words);
        }
    }
}

/// A vehicle's name: an identifier of at most `MAX_NAME_CHARS`, not one the
/// simulation's own outputs use.
fn check_body_name(checks: &mut Checks, path: &str, name: &str) {
    checks.name_length(path, name);
    if !is_identifier(name) {
        checks.fail(
            path,
            quoted(name),
            "must be an identifier: a letter or '_' followed by letters, digits or '_'",
        );
    } else if RESERVED_BODY_NAMES.contains(&name) {
        checks.fail(
            path,
            quoted(name),
            format!(
                "is reserved for the simulation's own outputs ({})",
                RESERVED_BODY_NAMES.join(", ")
            ),
        );
    }
}

/// A compliant contact law on contact bodies with mass: refused with
/// massless followers (their suspension is already their law) and for a
/// moving force (no contact).
fn check_contact_law(checks: &mut Checks, prefix: &str, body: &super::BodySpec) {
    let Some(law) = &body.contact_law else {
        return;
    };
    let path = |field: &str| format!("{prefix}.contact_law.{field}");
    match law.resolve() {
        Err((field, value, rule)) => checks.fail(path(field), value, rule),
        Ok(super::ResolvedLaw::Rigid) => {}
        Ok(_) => {
            if body.kind.on_followers(body) || body.kind == BodyKind::MovingForce {
                checks.fail(
                    path("law"),
                    format!("{:?}", law.law.clone().unwrap_or_default()),
                    "needs contact bodies with mass (a massless follower's law is its \
                     suspension; a moving force has no contact)",
                );
            }
        }
    }
}

/// A start above the track is ≥ 0 and needs the
/// rest start (the static start puts every vehicle on the beam).
fn check_flight(checks: &mut Checks, scene: &Scene, prefix: &str, body: &super::BodySpec) {
    let path = |field: &str| format!("{prefix}.{field}");
    // restitution's [0, 1] and the height's >= 0 are the table's rows.
    let height = body.initial_height;
    if height > 0.0 && scene.solver.start == super::StartKind::Static {
        checks.fail(
            path("initial_height"),
            fmt_f64(height),
            "must be 0 with solver.start = \"static\" (the static start sets every vehicle \
             on the beam)",
        );
    }
}

/// A prescribed speed: finite speeds, a table of at most `MAX_SPEED_ROWS`
/// rows with strictly increasing times, starting at the initial speed, on
/// any vehicle (tractive forces on each of its bodies hold it), not on a
/// moving force.
fn check_prescribed_speed(checks: &mut Checks, prefix: &str, body: &super::BodySpec) {
    use super::SpeedSpec;
    let path = format!("{prefix}.prescribed_speed");
    let Some(speed) = &body.prescribed_speed else {
        return;
    };
    if body.kind == BodyKind::MovingForce {
        checks.fail(
            &path,
            "present",
            "a moving force has no body to hold: its speed is initial_speed",
        );
        return;
    }
    let ok = match speed {
        SpeedSpec::Constant(v) => checks.finite(&path, *v),
        SpeedSpec::Table(rows) if rows.is_empty() || rows.len() > MAX_SPEED_ROWS => {
            checks.fail(
                &path,
                format!("{} rows", rows.len()),
                format!("a table needs 1 to {MAX_SPEED_ROWS} rows"),
            );
            false
        }
        SpeedSpec::Table(rows) => {
            let mut ok = true;
            for (i, [t, v]) in rows.iter().enumerate() {
                ok &= checks.finite(&format!("{path}[{i}][0]"), *t);
                ok &= checks.finite(&format!("{path}[{i}][1]"), *v);
            }
            for (i, pair) in rows.windows(2).enumerate() {
                if ok && pair[1][0] <= pair[0][0] {
                    checks.fail(
                        format!("{path}[{}][0]", i + 1),
                        fmt_f64(pair[1][0]),
                        "times must increase strictly from row to row",
                    );
                    ok = false;
                }
            }
            ok
        }
    };
    let start = speed.speed_at(0.0);
    if ok && body.initial_speed.is_finite() && body.initial_speed != start {
        checks.fail(
            format!("{prefix}.initial_speed"),
            fmt_f64(body.initial_speed),
            format!(
                "must equal the prescribed speed at t = 0, {}",
                fmt_f64(start)
            ),
        );
    }
}

/// Moving forces run without bodies: a scene has only moving forces or
/// none, and no irregularity (a force of fixed magnitude cannot feel one).
fn check_moving_forces_alone(checks: &mut Checks, scene: &Scene) {
    let body_kind = scene.vehicles.first().map(|v| v.kind);
    let moving = body_kind == Some(BodyKind::MovingForce);
    if moving && !scene.track.irregularities.is_empty() {
        checks.fail(
            "track.irregularities",
            format!("{} irregularities", scene.track.irregularities.len()),
            "would be ignored with body.kind = \"moving_force\" (a moving force keeps its \
             magnitude whatever the track's shape): run a vehicle that feels them \
             (kind = \"sprung_mass\", \"bogie_vehicle\" or \"maglev_vehicle\"), or leave them \
             out and scale the moving forces' results by EN 1991-2's allowance for track \
             irregularities (1 + φ'')",
        );
    }
    for (k, vehicle) in scene.vehicles.iter().enumerate().skip(1) {
        if (vehicle.kind == BodyKind::MovingForce) != moving {
            checks.fail(
                format!("{}.kind", super::vehicle_path(k)),
                format!("{:?}", vehicle.kind),
                "moving forces run without bodies: every vehicle is a moving_force if \
                 [body] is one, and none otherwise",
            );
        }
    }
}

/// A bogie vehicle's front and rear wheelsets, at initial_position ±
/// (bogie_half_distance + axle_half_distance), must start on the track.
fn check_wheelsets_on_track(
    checks: &mut Checks,
    prefix: &str,
    body: &super::BodySpec,
    scene: &Scene,
) {
    if !body.kind.starts_on_track() {
        return;
    }
    let Some(reach) = body.kind.reach(body) else {
        return;
    };
    let (front, rear) = (
        body.initial_position + reach.ahead,
        body.initial_position - reach.behind,
    );
    let (start, end) = (
        -scene.track.approach,
        scene.beam.length + scene.track.run_off,
    );
    if [front, rear, start, end].iter().all(|v| v.is_finite()) && (rear < start || front > end) {
        checks.fail(
            format!("{prefix}.initial_position"),
            fmt_f64(body.initial_position),
            format!(
                "puts the wheelsets (or magnets) at {} .. {} m, off the track {} .. {} m \
                 (the car body's centre, ± bogie_half_distance + axle_half_distance, or \
                 ± (magnets − 1) magnet_spacing / 2)",
                fmt_f64(rear),
                fmt_f64(front),
                fmt_f64(start),
                fmt_f64(end)
            ),
        );
    }
}

/// Gravity and the rigid ground: finite, non-negative lengths; ground
/// meets the beam only at an end whose deflection is held.
fn check_track(checks: &mut Checks, scene: &Scene) {
    check_scene_fields(checks, scene, &["gravity", "track."]);
    let track = &scene.track;
    let supports = &scene.beam.supports;
    for (path, length, end) in [
        ("track.approach", track.approach, supports.left),
        ("track.run_off", track.run_off, supports.right),
    ] {
        if length > 0.0 && end == EndSupport::Free {
            checks.fail(
                path,
                fmt_f64(length),
                "must be 0 next to a free beam end (rigid ground meets the beam only where \
                 its deflection is held: pinned or clamped)",
            );
        }
    }
}

/// Each coupling names a body of the scene, once.
fn check_couplings(checks: &mut Checks, scene: &Scene) {
    let count = scene.couplings.len();
    if count > MAX_SENSORS {
        checks.fail(
            "couplings",
            format!("{count} couplings"),
            format!("must hold at most {MAX_SENSORS}"),
        );
        return;
    }
    if count == 0 || scene.vehicles.len() > MAX_VEHICLES + 1 {
        return;
    }
    let bodies: HashSet<String> = scene.body_names().into_iter().collect();
    let mut seen = HashSet::new();
    for (i, name) in scene.couplings.iter().enumerate() {
        let path = format!("couplings[{i}]");
        if !bodies.contains(name) {
            let mut known: Vec<&String> = bodies.iter().collect();
            known.sort();
            known.truncate(20);
            let known: Vec<&str> = known.iter().map(|s| s.as_str()).collect();
            checks.fail(
                path,
                quoted(name),
                format!(
                    "must name a body of the scene (one of {})",
                    known.join(", ")
                ),
            );
        } else if !seen.insert(name.as_str()) {
            checks.fail(path, quoted(name), "must be unique among the couplings");
        }
    }
}

/// Sensors: at most `MAX_SENSORS`; each number against its row of the
/// field table; identifier names unique among the sensors; on the beam,
/// outside the rail gaps.
fn check_sensors(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let count = scene.sensors.len();
    if count > MAX_SENSORS {
        // One problem, not a million: the sensors themselves are not read.
        checks.fail(
            "sensors",
            format!("{count} sensors"),
            format!("must hold at most {MAX_SENSORS}"),
        );
        return;
    }
    let mut seen = HashSet::new();
    for (i, sensor) in scene.sensors.iter().enumerate() {
        let name_path = format!("sensors[{i}].name");
        checks.name_length(&name_path, &sensor.name);
        if !is_identifier(&sensor.name) {
            checks.fail(
                name_path,
                quoted(&sensor.name),
                "must be an identifier: a letter or '_' followed by letters, digits or '_'",
            );
        } else if !seen.insert(sensor.name.as_str()) {
            checks.fail(
                name_path,
                quoted(&sensor.name),
                "must be unique among the sensors",
            );
        }
        let position_path = format!("sensors[{i}].position");
        // The row's own rule (>= 0) is the table's; the beam's end is here.
        if !check_sensor_fields(checks, i, sensor) {
            continue;
        }
        if length_ok && sensor.position > scene.beam.length {
            checks.fail(
                position_path,
                fmt_f64(sensor.position),
                format!(
                    "must lie on the beam, 0 <= x <= beam.length = {}",
                    fmt_f64(scene.beam.length)
                ),
            );
        } else if in_gap(scene, sensor.position) {
            checks.fail(
                position_path,
                fmt_f64(sensor.position),
                "must not lie in a rail gap (between beam.joints[].at and at + gap)",
            );
        }
    }
}

/// Every number of sensor `i` that the field table reads (`sensors.*`
/// rows, named `sensors[i].*`), against its row's rule in the row's words;
/// whether every one keeps its rule.
fn check_sensor_fields(checks: &mut Checks, i: usize, sensor: &super::SensorSpec) -> bool {
    let mut ok = true;
    for f in FIELDS.iter() {
        let Access::Sensor(get, _) = f.access else {
            continue;
        };
        let Some(x) = get(sensor) else { continue };
        if let Some(words) = f.rule.problem(x, 0.0) {
            let field = f.path.strip_prefix("sensors.").unwrap_or(f.path);
            checks.fail(format!("sensors[{i}].{field}"), fmt_f64(x), words);
            ok = false;
        }
    }
    ok
}

/// Like the sensors: at most `MAX_SENSORS`, identifier names unique among
/// the sections, on the beam.
fn check_sections(checks: &mut Checks, scene: &Scene, length_ok: bool) {
    let count = scene.sections.len();
    if count > MAX_SENSORS {
        checks.fail(
            "sections",
            format!("{count} sections"),
            format!("must hold at most {MAX_SENSORS}"),
        );
        return;
    }
    let mut seen = HashSet::new();
    for (i, section) in scene.sections.iter().enumerate() {
        let name_path = format!("sections[{i}].name");
        checks.name_length(&name_path, &section.name);
        if !is_identifier(&section.name) {
            checks.fail(
                name_path,
                quoted(&section.name),
                "must be an identifier: a letter or '_' followed by letters, digits or '_'",
            );
        } else if !seen.insert(section.name.as_str()) {
            checks.fail(
                name_path,
                quoted(&section.name),
                "must be unique among the sections",
            );
        }
        let position_path = format!("sections[{i}].position");
        if checks.finite(&position_path, section.position)
            && length_ok
            && !(0.0..=scene.beam.length).contains(&section.position)
        {
            checks.fail(
                position_path,
                fmt_f64(section.position),
                format!(
                    "must lie on the beam, 0 <= x <= beam.length = {}",
                    fmt_f64(scene.beam.length)
                ),
            );
        }
    }
}

fn check_solver(checks: &mut Checks, scene: &Scene) {
    let solver = &scene.solver;
    check_scene_fields(checks, scene, &["solver."]);
    if let Some(rtol) = solver.tolerance {
        if checks.positive("solver.tolerance", rtol) && rtol >= 1.0 {
            checks.fail(
                "solver.tolerance",
                fmt_f64(rtol),
                "must be < 1 (a relative error)",
            );
        }
    }
    if !(1..=MAX_ITERATIONS).contains(&solver.max_iterations) {
        checks.fail(
            "solver.max_iterations",
            solver.max_iterations.to_string(),
            format!("must be between 1 and {MAX_ITERATIONS}"),
        );
    }
    let damping = solver.numerical_damping;
    if checks.finite("solver.numerical_damping", damping) && !(0.0..=1.0 / 3.0).contains(&damping) {
        checks.fail(
            "solver.numerical_damping",
            fmt_f64(damping),
            "must be between 0 and 1/3 (HHT-α's −α)",
        );
    }
    if let Some(end) = solver.end_time {
        checks.positive("solver.end_time", end);
    }
    // HHT-α's unknown is its end-of-step force: a shaped profile would be
    // silently ignored, so it is refused (under `auto` it serves the RK4 runs).
    if !solver.integrator.fits_force_shape() && solver.force_profile != ForceProfile::Held {
        checks.fail(
            "solver.force_profile",
            format!("{:?}", solver.force_profile).to_lowercase(),
            "must be \"held\" with integrator = \"hht\" (HHT-α solves for the end-of-step force; use \"rk4\" or \"auto\")",
        );
    }
    check_structure(checks, scene);
}

/// Most modes `solver.modes` may ask for (the list limit).
pub const MAX_MODES: usize = 10_000;

/// `solver.structure` and its `modes` or `max_frequency`.
fn check_structure(checks: &mut Checks, scene: &Scene) {
    let solver = &scene.solver;
    if solver.structure == super::StructureKind::Full {
        if let Some(DampingSpec::Modal { ratio }) = scene.beam.damping {
            check_every_mode_damping(checks, scene, ratio);
        }
        if let Some(k) = solver.modes {
            let rule = "is read only with solver.structure = \"modal\"";
            checks.fail("solver.modes", k.to_string(), rule);
        }
        if let Some(f) = solver.max_frequency {
            let rule = "is read only with solver.structure = \"modal\"";
            checks.fail("solver.max_frequency", fmt_f64(f), rule);
        }
        return;
    }
    match (solver.modes, solver.max_frequency) {
        (None, None) => checks.fail(
            "solver.structure",
            "\"modal\"",
            "needs solver.modes (how many modes) or solver.max_frequency (Hz)",
        ),
        (Some(k), Some(f)) => checks.fail(
            "solver.max_frequency",
            fmt_f64(f),
            format!("must not be given together with solver.modes = {k}: choose one"),
        ),
        (Some(k), None) if !(1..=MAX_MODES).contains(&k) => checks.fail(
            "solver.modes",
            k.to_string(),
            format!("must be between 1 and {MAX_MODES}"),
        ),
        (None, Some(f)) => {
            checks.positive("solver.max_frequency", f);
        }
        _ => {}
    }
    if crate::vehicle::presets::is_moving_force_scene(scene) {
        checks.fail(
            "solver.structure",
            "\"modal\"",
            "is not supported with body.kind = \"moving_force\" (the speed sweep \
             integrates the full beam)",
        );
    }
    if !scene.beam.joints.is_empty() {
        checks.fail(
            "solver.structure",
            "\"modal\"",
            format!(
                "is not supported with rail joints (beam.joints has {}): a joint's corner \
                 needs the nodal DOFs of both sides",
                scene.beam.joints.len()
            ),
        );
    }
}

/// One ratio for every mode on the full mesh: the mesh runs in the
/// coordinates of all its modes (a complete basis, so nothing is
/// truncated) where each mode gets its 2 ζ ω exactly. That needs the dense
/// eigenproblem of every free DOF and what the modal route takes.
fn check_every_mode_damping(checks: &mut Checks, scene: &Scene, ratio: f64) {
    let most = crate::beam::MAX_MODE_DOFS;
    // Two DOFs a node bound the free ones whatever the supports.
    let dofs = 2 * (scene.beam.elements + 1);
    let why = if dofs > most {
        Some(format!(
            "alone (the same ratio in every mode) damps every mode of the full mesh \
             exactly by running it in all its modes, which needs at most {most} DOFs \
             ({} elements; beam.elements = {} gives up to {dofs}): give \
             solver.structure = \"modal\" with solver.modes, or Rayleigh damping \
             {{ ratio, modes = [1, 3] }}",
            most / 2 - 1,
            scene.beam.elements
        ))
    } else if crate::vehicle::presets::is_moving_force_scene(scene) {
        Some(
            "alone (the same ratio in every mode) is not taken by moving forces on the \
             full mesh (they step its nodal DOFs): give Rayleigh damping \
             { ratio, modes = [1, 3] }"
                .to_string(),
        )
    } else if !scene.beam.joints.is_empty() {
        Some(
            "alone (the same ratio in every mode) runs the mesh in its modes, which rail \
             joints (beam.joints) do not allow: give Rayleigh damping \
             { ratio, modes = [1, 3] }"
                .to_string(),
        )
    } else {
        None
    };
    if let Some(rule) = why {
        checks.fail("beam.damping.ratio", fmt_f64(ratio), rule);
    }
}

/// A letter or `_`, then letters, digits or `_` (ASCII): safe inside
/// output names such as `sensor.<name>.deflection`.
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Shortest text that reads back as the same number (`-1.0`, `NaN`, `inf`).
pub(crate) fn fmt_f64(x: f64) -> String {
    format!("{x:?}")
}

/// A string as a quoted value in a problem; a long one is cut, so that a
/// 10 MB name does not make a 10 MB error message.
pub(crate) fn quoted(s: &str) -> String {
    const SHOWN: usize = 40;
    let chars = s.chars().count();
    if chars <= SHOWN + 10 {
        format!("{s:?}")
    } else {
        let head: String = s.chars().take(SHOWN).collect();
        format!("{head:?}... ({chars} characters)")
    }
}

/// The problems found so far; the vehicle presets add theirs
/// (`vehicle::presets::Preset::check`).
#[derive(Default)]
pub(crate) struct Checks {
    problems: Vec<Problem>,
}

impl Checks {
    pub(crate) fn fail(
        &mut self,
        path: impl Into<String>,
        value: impl Into<String>,
        rule: impl Into<String>,
    ) {
        self.problems.push(Problem::new(path, value, rule));
    }

    /// Check `x` against `rule` of the field table (whose words the
    /// message takes); reports and returns false when it breaks it.
    pub(crate) fn rule(&mut self, path: &str, x: f64, rule: Rule) -> bool {
        match rule.problem(x, 0.0) {
            Some(words) => {
                self.fail(path, fmt_f64(x), words);
                false
            }
            None => true,
        }
    }

    /// Finite and within ±`MAX_MAGNITUDE`.
    pub(crate) fn finite(&mut self, path: &str, x: f64) -> bool {
        self.rule(path, x, Rule::Finite)
    }

    /// Finite, > 0 and within [`MIN_MAGNITUDE`, `MAX_MAGNITUDE`].
    pub(crate) fn positive(&mut self, path: &str, x: f64) -> bool {
        self.rule(path, x, Rule::Positive)
    }

    /// At most `MAX_NAME_CHARS` characters.
    pub(crate) fn name_length(&mut self, path: &str, name: &str) {
        let chars = name.chars().count();
        if chars > MAX_NAME_CHARS {
            self.fail(
                path,
                quoted(name),
                format!("has {chars} characters, more than the limit of {MAX_NAME_CHARS}"),
            );
        }
    }

    /// Finite and >= 0.
    pub(crate) fn non_negative(&mut self, path: &str, x: f64) {
        self.rule(path, x, Rule::NonNegative);
    }

    /// A value `who` needs: reported when missing (a present one is
    /// checked by its row of the field table).
    pub(crate) fn required(&mut self, path: &str, x: Option<f64>, who: &str) {
        if x.is_none() {
            self.fail(path, "missing", format!("{who} a value > 0"));
        }
    }
}
