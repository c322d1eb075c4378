//! A scene as TOML with units and rules as comments: the starting point for
//! a new scene file (`guideway scenes --show`).

use super::Scene;
use toml_edit::{DocumentMut, Item, Table, Value};

/// Comment above each of the scene's own tables; a preset's block
/// (`[body.bogie]`, ...) brings its own (`Preset::BLOCK_NOTE`).
const SCENE_TABLE_NOTES: &[(&str, &str)] = &[
    ("beam", "Euler-Bernoulli beam on the x axis from 0 to L"),
    (
        "track",
        "The ground before and after the beam: rigid, or under a rail ([track.on_deck])",
    ),
    (
        "body",
        "The vehicle (or moving force): its kind, mass, start and loads",
    ),
    (
        "body.contact_law",
        "How the body's contacts meet the running surface: Lee's rigid contact unless a law is chosen",
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
        "beam.supports",
        "How the beam is held: its two ends and pinned supports inside",
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
        "vehicles",
        "Another vehicle of the train: the fields of [body]",
    ),
    (
        "sections",
        "A cross-section whose moment and shear are reported",
    ),
];

/// The tables under which a preset's block stands: the first vehicle's
/// and each other vehicle of a train.
const VEHICLE_TABLES: [&str; 2] = ["body", "vehicles"];

/// Every table's note in the docs' order: the scene's own, each preset's
/// block after its vehicle table.
pub(super) fn table_notes() -> Vec<(String, &'static str)> {
    let mut notes = Vec::new();
    for &(path, note) in SCENE_TABLE_NOTES {
        notes.push((path.to_string(), note));
        if VEHICLE_TABLES.contains(&path) {
            for (block, note) in crate::vehicle::presets::block_notes() {
                notes.push((format!("{path}.{block}"), note));
            }
        }
    }
    notes
}

/// The note of the table at `path`: the scene's, or a preset's block's;
/// a train's `[vehicles.<block>]` shares `[body.<block>]`'s.
fn table_note(path: &str) -> Option<&'static str> {
    let as_body = path
        .strip_prefix("vehicles.")
        .map(|rest| format!("body.{rest}"));
    let own = SCENE_TABLE_NOTES
        .iter()
        .find(|(p, _)| *p == path || Some(*p) == as_body.as_deref());
    if let Some(&(_, note)) = own {
        return Some(note);
    }
    let (table, block) = path.split_once('.')?;
    if !VEHICLE_TABLES.contains(&table) {
        return None;
    }
    let notes = crate::vehicle::presets::block_notes();
    notes.into_iter().find(|(b, _)| *b == block).map(|(_, n)| n)
}

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
    if let Some(note) = table_note(path) {
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

#[cfg(test)]
mod tests {
    use crate::scene::{BodyKind, Scene, SuspensionSpec};

    /// A preset's block gets its preset's note above `[body.<block>]` and
    /// above each `[vehicles.<block>]` of a train.
    #[test]
    fn a_presets_block_carries_its_presets_note() {
        let mut scene = Scene::lee1994(BodyKind::SprungMass, 10.0, 0.0025);
        scene.vehicles[0].suspension = Some(SuspensionSpec {
            stiffness: 1e6,
            damping: 0.0,
            unsprung_mass: 50.0,
        });
        let mut second = scene.vehicles[0].clone();
        second.name = "second".into();
        scene.vehicles.push(second);
        let text = scene.to_annotated_toml();
        let notes = crate::vehicle::presets::block_notes();
        let (_, note) = notes.iter().find(|(b, _)| *b == "suspension").unwrap();
        assert!(note.starts_with("sprung_mass: "), "{note}");
        for table in ["[body.suspension]", "[vehicles.suspension]"] {
            let noted = format!("\n# {note}\n{table}\n");
            assert!(text.contains(&noted), "{table} without its note:\n{text}");
        }
    }

    /// Every table of every built-in scene's annotated TOML stands under a
    /// note, so a new table cannot come without one.
    #[test]
    fn every_table_of_every_built_in_scene_has_a_note() {
        for (name, _) in crate::scene::builtin::builtins() {
            let text = crate::scene::builtin::builtin(name)
                .unwrap()
                .to_annotated_toml();
            let lines: Vec<&str> = text.lines().collect();
            for (i, line) in lines.iter().enumerate() {
                if line.starts_with('[') {
                    let above = lines[..i].last().copied().unwrap_or("");
                    assert!(above.starts_with("# "), "{name}: {line} has no note");
                }
            }
        }
    }

    /// A preset whose block is a table (its fields' paths are
    /// `body.<block>.<field>`) gives it a note.
    #[test]
    fn every_presets_table_block_has_a_note() {
        let notes = crate::vehicle::presets::block_notes();
        let mut tables = 0;
        for (_, rows) in crate::vehicle::presets::rows() {
            for row in rows {
                let parts: Vec<&str> = row.path.split('.').collect();
                if let ["body", block, _, ..] = parts[..] {
                    assert!(notes.iter().any(|(b, _)| *b == block), "{}", row.path);
                    tables += 1;
                }
            }
        }
        assert!(tables > 0, "no preset's block is a table");
    }
}
