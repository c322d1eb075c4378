//! A scene as TOML with units and rules as comments: the starting point for
//! a new scene file (`guideway scenes --show`).

use super::Scene;
use toml_edit::{DocumentMut, Item, Table, Value};

/// Comment above each table.
pub(super) const TABLE_NOTES: &[(&str, &str)] = &[
    ("beam", "Euler-Bernoulli beam on the x axis from 0 to L"),
    ("track", "Rigid ground before and after the beam"),
    (
        "body.suspension",
        "sprung_mass: vertical spring-damper over an unsprung glider",
    ),
    (
        "body",
        "The vehicle (or moving force): its kind, mass, start and loads",
    ),
    ("sensors", "A point whose deflection is reported"),
    (
        "solver",
        "Fixed-step solver; end_time = <s> runs on past the exit to that time",
    ),
    (
        "track.irregularities",
        "An irregularity of the running surface, summed into r(x)",
    ),
    (
        "track.on_deck",
        "A rail over the deck on a layer, on the ground off it: the contacts run on the rail",
    ),
    (
        "track.on_deck.sleepers",
        "Discrete supports in place of the layer: sleepers on pads over the ballast",
    ),
    (
        "beam.damping",
        "Structural damping: Rayleigh, one of three shapes, or { ratio } alone in every mode",
    ),
    (
        "beam.supports.springs",
        "An elastic support: springs and dampers to the ground",
    ),
    ("beam.joints", "Where one span ends and the next begins"),
    (
        "beam.foundation",
        "A Winkler foundation under the whole beam (a rail on its track bed)",
    ),
    (
        "body.bogie",
        "bogie_vehicle: car body on two bogies on four wheelsets",
    ),
    (
        "body.maglev",
        "maglev_vehicle: car body over N magnets on spring-dampers",
    ),
    (
        "vehicles",
        "Another vehicle of the train: the fields of [body]",
    ),
    (
        "vehicles.bogie",
        "bogie_vehicle: car body on two bogies on four wheelsets",
    ),
    (
        "vehicles.maglev",
        "maglev_vehicle: car body over N magnets on spring-dampers",
    ),
    (
        "sections",
        "A cross-section whose moment and shear are reported",
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
            "# guideway scene `{}`. Units: m, kg, s, N. See docs/scenes.md.\n",
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

/// The note of a field, from the field table; a train's `[[vehicles]]`
/// share the body's.
fn field_note(path: &str) -> Option<&'static str> {
    super::fields::field(path).map(|f| f.note)
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
    let Some(note) = field_note(path) else {
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
