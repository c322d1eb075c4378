//! A scene as TOML with units and rules as comments: the starting point for
//! a new scene file (`guideway scenes --show`).

use super::Scene;
use toml_edit::{DocumentMut, Item, Table, Value};

/// Comment after each field: unit, meaning, rule.
const FIELD_NOTES: [(&str, &str); 46] = [
    ("name", "letters, digits, - _ . ; the FMU's model name"),
    ("description", "one line"),
    (
        "gravity",
        "m/s^2, downward on every body; 0 in the paper's scenes",
    ),
    ("track.approach", "m, rigid ground before the beam (x < 0)"),
    ("track.run_off", "m, rigid ground after the beam (x > L)"),
    ("body.suspension.stiffness", "N/m, vertical spring, > 0"),
    ("body.suspension.damping", "N s/m, vertical damper, >= 0"),
    (
        "body.suspension.unsprung_mass",
        "kg, the glider under the spring, >= 0 (0: the massless follower)",
    ),
    (
        "body.bogie.wheelset_mass",
        "kg, > 0, or 0: massless followers under the axles",
    ),
    (
        "body.maglev.magnet_mass",
        "kg, > 0, or 0: massless followers under the magnets' stations",
    ),
    ("beam.length", "m, L"),
    ("beam.mass_per_length", "kg/m"),
    ("beam.bending_stiffness", "N m^2, EI > 0"),
    (
        "beam.surface_offset",
        "m, h: neutral axis to top surface, >= 0",
    ),
    ("beam.elements", "Hermite cubic elements, >= 1"),
    ("beam.supports.left", "pinned | clamped | free"),
    ("beam.supports.right", "pinned | clamped | free"),
    (
        "beam.supports.intermediate",
        "m, pinned supports strictly inside, increasing",
    ),
    (
        "beam.damping.alpha",
        "1/s, Rayleigh C = alpha M + beta K, >= 0",
    ),
    (
        "beam.damping.beta",
        "s, Rayleigh stiffness coefficient, >= 0",
    ),
    (
        "beam.damping.ratio",
        "damping ratio at both `modes`, 0 <= ratio < 1",
    ),
    ("beam.damping.modes", "two different bending modes, from 1"),
    (
        "beam.damping.ratios",
        "damping ratios at `frequencies`, [0, 1)",
    ),
    ("beam.damping.frequencies", "Hz, two different, > 0"),
    ("body.name", "identifier; outputs are <name>.x, ..."),
    (
        "body.kind",
        "wheel | glider | sprung_mass | bogie_vehicle | maglev_vehicle | moving_force",
    ),
    ("body.mass", "kg, > 0"),
    ("body.inertia", "kg m^2, centroidal J; wheel only"),
    ("body.radius", "m, r; wheel only"),
    (
        "body.initial_position",
        "m, contact abscissa at t = 0, -approach <= x < L",
    ),
    ("body.initial_speed", "m/s, positive to the right"),
    (
        "body.prescribed_speed",
        "m/s, or [[t, v], ...]: held by a tractive force",
    ),
    ("body.train", "HSLM-A1 ... HSLM-A10; moving_force only"),
    ("body.force_x", "N, constant force on the body's centre"),
    ("body.force_y", "N, y up: the paper's load is -600 kN"),
    (
        "sensors.name",
        "identifier; output sensor.<name>.deflection",
    ),
    ("sensors.position", "m, 0 <= x <= L"),
    ("solver.step", "s, fixed internal time step"),
    (
        "solver.velocity_tolerance",
        "m/s, on the velocity error |e|",
    ),
    ("solver.gap_tolerance", "m, on the gap error |g|"),
    (
        "solver.tolerance",
        "relative error of the summary figures; chooses the step",
    ),
    ("solver.max_iterations", "per stage and step"),
    (
        "solver.integrator",
        "rk4 (the paper's, explicit) | hht (implicit) | auto",
    ),
    (
        "solver.numerical_damping",
        "HHT's -alpha in [0, 1/3]; 0 conserves energy",
    ),
    (
        "solver.force_profile",
        "held (the paper's) | linear | quadratic: RK4's force in the step",
    ),
    ("solver.end_time", "s, stop here if the body has not left"),
];

/// Comment above each table.
const TABLE_NOTES: [(&str, &str); 6] = [
    ("beam", "Euler-Bernoulli beam on the x axis from 0 to L"),
    ("track", "Rigid ground before and after the beam"),
    (
        "body.suspension",
        "sprung_mass: vertical spring-damper over an unsprung glider",
    ),
    (
        "body",
        "The moving body: a rolling wheel or a maglev glider",
    ),
    ("sensors", "A point whose deflection is reported"),
    (
        "solver",
        "Fixed-step solver; add end_time = <s> to stop before the exit",
    ),
];

/// Column at which field comments start, where the line allows.
const COMMENT_COLUMN: usize = 36;

impl Scene {
    /// The scene as TOML with each field's unit and rule as a comment;
    /// reads back to the same scene.
    pub fn to_annotated_toml(&self) -> String {
        let mut document: DocumentMut = self
            .to_toml_string()
            .parse()
            .expect("serialised TOML parses");
        annotate_table(document.as_table_mut(), "");
        let header = format!(
            "# guideway scene `{}`. Units: m, kg, s, N. See README, \"Scene files\".\n",
            self.name
        );
        header + &document.to_string()
    }
}

fn annotate_table(table: &mut Table, prefix: &str) {
    for (key, item) in table.iter_mut() {
        let path = if prefix.is_empty() {
            key.get().to_string()
        } else {
            format!("{prefix}.{}", key.get())
        };
        match item {
            Item::Value(value) => annotate_value(value, key.get(), &path),
            Item::Table(inner) => {
                note_table(inner, &path);
                annotate_table(inner, &path);
            }
            Item::ArrayOfTables(array) => {
                for inner in array.iter_mut() {
                    note_table(inner, &path);
                    annotate_table(inner, &path);
                }
            }
            Item::None => {}
        }
    }
}

fn note_table(table: &mut Table, path: &str) {
    if let Some((_, note)) = TABLE_NOTES.iter().find(|(p, _)| *p == path) {
        table.decor_mut().set_prefix(format!("\n# {note}\n"));
    }
}

fn annotate_value(value: &mut Value, key: &str, path: &str) {
    if let Value::Float(number) = value {
        if let Ok(readable) = float_literal(*number.value()).parse::<Value>() {
            *value = readable;
        }
    }
    let Some((_, note)) = FIELD_NOTES.iter().find(|(p, _)| *p == path) else {
        return;
    };
    let line = format!("{key} = {}", value.to_string().trim());
    let padding = COMMENT_COLUMN.saturating_sub(line.len()).max(2);
    value
        .decor_mut()
        .set_suffix(format!("{}# {note}", " ".repeat(padding)));
}

/// `1e9` rather than `1000000000.0`, `1e-7` rather than `0.0000001`; the
/// same `f64` either way.
fn float_literal(x: f64) -> String {
    let magnitude = x.abs();
    if x.is_finite() && x != 0.0 && !(1e-3..1e5).contains(&magnitude) {
        format!("{x:e}")
    } else {
        format!("{x:?}")
    }
}
