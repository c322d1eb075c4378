//! A scene as TOML with units and rules as comments: the starting point for
//! a new scene file (`guideway scenes --show`).

use super::Scene;
use toml_edit::{DocumentMut, Item, Table, Value};

/// Comment after each field: unit, meaning, rule.
const FIELD_NOTES: &[(&str, &str)] = &[
    ("name", "letters, digits, - _ . ; the FMU's model name"),
    ("description", "one line"),
    (
        "gravity",
        "m/s^2, downward on every body; 0 in the paper's scenes",
    ),
    ("track.approach", "m, rigid ground before the beam (x < 0)"),
    ("track.run_off", "m, rigid ground after the beam (x > L)"),
    (
        "track.irregularities.type",
        "step | ramp | cosine_dip | sine | table | random; only its fields",
    ),
    (
        "track.irregularities.position",
        "m, centre of a step or a cosine dip",
    ),
    ("track.irregularities.height", "m, rise of a step or a ramp"),
    (
        "track.irregularities.smoothing",
        "m, > 0, rounding of a step or a ramp",
    ),
    ("track.irregularities.start", "m, where a ramp begins"),
    ("track.irregularities.length", "m, > 0, length of a ramp"),
    (
        "track.irregularities.wavelength",
        "m, > 0, of a cosine dip or a sine",
    ),
    ("track.irregularities.depth", "m, of a cosine dip"),
    ("track.irregularities.amplitude", "m, of a sine"),
    ("track.irregularities.phase", "rad, of a sine"),
    (
        "track.irregularities.points",
        "[[x, r], ...] in m, x increasing, 2 to 100 000",
    ),
    (
        "track.irregularities.file",
        "CSV of rows x, r (m), relative to the scene file",
    ),
    (
        "track.irregularities.spectrum",
        "iso8608 | fra | german_low | german_high",
    ),
    (
        "track.irregularities.class",
        "A ... H (iso8608), 1 ... 6 (fra)",
    ),
    ("track.irregularities.seed", "0 to 4294967295"),
    ("track.irregularities.shortest_wavelength", "m, > 0"),
    (
        "track.irregularities.longest_wavelength",
        "m, > shortest_wavelength",
    ),
    (
        "track.irregularities.spacing",
        "m, <= shortest / 4; default shortest / 10",
    ),
    ("body.suspension.stiffness", "N/m, vertical spring, > 0"),
    ("body.suspension.damping", "N s/m, vertical damper, >= 0"),
    (
        "body.suspension.unsprung_mass",
        "kg, the glider under the spring, >= 0 (0: the massless follower)",
    ),
    (
        "body.bogie.car_inertia",
        "kg m^2, > 0, car body pitch inertia",
    ),
    ("body.bogie.bogie_mass", "kg, > 0, one bogie"),
    ("body.bogie.bogie_inertia", "kg m^2, > 0, one bogie"),
    (
        "body.bogie.wheelset_mass",
        "kg, > 0, or 0: massless followers under the axles",
    ),
    (
        "body.bogie.bogie_half_distance",
        "m, l_c > l_t: half the distance of the bogie centres",
    ),
    (
        "body.bogie.axle_half_distance",
        "m, l_t > 0: half a bogie's axle distance",
    ),
    ("body.bogie.primary_stiffness", "N/m, k1 > 0, per axle"),
    ("body.bogie.primary_damping", "N s/m, c1 >= 0, per axle"),
    ("body.bogie.secondary_stiffness", "N/m, k2 > 0, per bogie"),
    ("body.bogie.secondary_damping", "N s/m, c2 >= 0, per bogie"),
    (
        "body.bogie.wheel_radius",
        "m, > 0, with wheelset_inertia: rolling wheelsets",
    ),
    (
        "body.bogie.wheelset_inertia",
        "kg m^2, > 0, with wheel_radius",
    ),
    (
        "body.maglev.car_inertia",
        "kg m^2, > 0, car body pitch inertia",
    ),
    ("body.maglev.magnets", "1 to 1000, centred on the car body"),
    ("body.maglev.magnet_spacing", "m, > 0"),
    (
        "body.maglev.magnet_mass",
        "kg, > 0, or 0: massless followers under the magnets' stations",
    ),
    (
        "body.maglev.stiffness",
        "N/m, k > 0, one magnet's suspension",
    ),
    (
        "body.maglev.damping",
        "N s/m, c >= 0, one magnet's suspension",
    ),
    (
        "body.contact_law.law",
        "rigid (Lee's constraint, the default), hertz or ems (docs/contact-laws.md)",
    ),
    (
        "body.contact_law.preset",
        "wheel-rail (Hertz, 0.46 m wheel on a 0.3 m rail head) or ems (10 mm gap, PD control)",
    ),
    (
        "body.contact_law.coefficient",
        "N/m^1.5, Hertz C_H > 0, or from the radii",
    ),
    (
        "body.contact_law.wheel_radius",
        "m, > 0, Hertz: rolling radius",
    ),
    (
        "body.contact_law.rail_radius",
        "m, > 0, Hertz: rail head transverse radius",
    ),
    (
        "body.contact_law.elastic_modulus",
        "Pa, > 0, Hertz: steel if left out",
    ),
    (
        "body.contact_law.poisson_ratio",
        "in [0, 0.5), Hertz: steel if left out",
    ),
    (
        "body.contact_law.nominal_gap",
        "m, > 0, EMS: the air gap held",
    ),
    ("body.contact_law.proportional_gain", "1/m, EMS: K_p / i0"),
    ("body.contact_law.derivative_gain", "s/m, EMS: K_d / i0"),
    (
        "body.contact_law.max_force",
        "N, > 0, EMS: saturation; twice the static load if left out",
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
        "beam.supports.springs.at",
        "m, 0 <= at <= L: an elastic support",
    ),
    ("beam.supports.springs.vertical", "N/m, >= 0"),
    ("beam.supports.springs.rotational", "N m/rad, >= 0"),
    ("beam.supports.springs.vertical_damping", "N s/m, >= 0"),
    (
        "beam.supports.springs.rotational_damping",
        "N m s/rad, >= 0",
    ),
    ("beam.joints.at", "m, 0 < at, at + gap < L, increasing"),
    ("beam.joints.kind", "continuous | hinge | separate"),
    ("beam.joints.gap", "m, rail gap >= 0, separate joints only"),
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
        "body.restitution",
        "0 (plastic) to 1 (elastic), at a landing",
    ),
    (
        "body.initial_height",
        "m, >= 0, above its place on the track",
    ),
    ("reactions", "true: support.<name>.reaction outputs"),
    (
        "sensors.name",
        "identifier; output sensor.<name>.deflection",
    ),
    ("sensors.position", "m, 0 <= x <= L"),
    (
        "sections.name",
        "identifier; outputs section.<name>.moment, .shear",
    ),
    ("sections.position", "m, 0 <= x <= L"),
    ("couplings", "bodies that are the FMU's coupling points"),
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
    (
        "solver.end_time",
        "s, run to here, past the exit, unless a contact leaves the track",
    ),
    (
        "solver.start",
        "rest | static: deflected under the vehicles' weight",
    ),
    ("solver.structure", "full | modal: the beam's lowest modes"),
    ("solver.modes", "modal: how many of the lowest modes"),
    ("solver.max_frequency", "Hz, modal: every mode up to this"),
];

/// Comment above each table.
const TABLE_NOTES: &[(&str, &str)] = &[
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
        "beam.damping",
        "Rayleigh structural damping, one of three shapes",
    ),
    (
        "beam.supports.springs",
        "An elastic support: springs and dampers to the ground",
    ),
    ("beam.joints", "Where one span ends and the next begins"),
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

/// The note of a field; a train's `[[vehicles]]` share the body's.
fn field_note(path: &str) -> Option<&'static str> {
    let path = match path.strip_prefix("vehicles.") {
        Some(rest) => format!("body.{rest}"),
        None => path.to_string(),
    };
    FIELD_NOTES
        .iter()
        .find(|(p, _)| *p == path)
        .map(|(_, note)| *note)
}

/// The field notes as a Markdown page, `docs/scene-fields.md` (the docs
/// test checks that the committed page is this).
pub fn field_notes_markdown() -> String {
    let mut page = String::from(
        "# Scene field notes\n\n\
         Generated from the notes `guideway scenes --show` writes beside each \
         field (`src/scene/annotate.rs`); do not edit by hand: \
         `GUIDEWAY_UPDATE_DOCS=1 cargo test --release --test docs` rewrites it. \
         The rules in full, with defaults, are in \
         [Scenes, every field](scenes.md#every-field). A train's `[[vehicles]]` \
         take the fields of `[body]`.\n\n\
         | table | what it holds |\n|---|---|\n",
    );
    for (path, note) in TABLE_NOTES {
        page += &format!("| `[{path}]` | {note} |\n");
    }
    page += "\n| field | unit, meaning, rule |\n|---|---|\n";
    for (path, note) in FIELD_NOTES {
        page += &format!("| `{path}` | {} |\n", note.replace('|', "\\|"));
    }
    page
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
