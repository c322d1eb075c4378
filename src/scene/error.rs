//! What can be wrong with a scene, reported so that a person can fix it.

use std::fmt;

/// One thing wrong with a scene: which field, what it held, which rule it
/// breaks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// Dotted path of the field, e.g. `beam.bending_stiffness` or
    /// `sensors[1].name`.
    pub path: String,
    /// The offending value as written in the scene (`-1e9`, `"a b"`,
    /// `missing`); empty when the problem is not about a single value.
    pub value: String,
    /// The rule that value breaks, e.g. `must be > 0`.
    pub rule: String,
}

impl Problem {
    pub fn new(path: impl Into<String>, value: impl Into<String>, rule: impl Into<String>) -> Self {
        Problem {
            path: path.into(),
            value: value.into(),
            rule: rule.into(),
        }
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.value.is_empty() {
            write!(f, "{}: {}", self.path, self.rule)
        } else {
            write!(f, "{} = {}: {}", self.path, self.value, self.rule)
        }
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SceneError {
    /// The file could not be read.
    Read { path: String, message: String },
    /// Neither a readable file nor the name of a built-in scene.
    NotFound { name: String },
    /// The text is not TOML, or does not have the scene's shape (unknown
    /// field, wrong type, missing field). Serde stops at the first such
    /// problem.
    Parse {
        /// Dotted path of the field serde was reading (empty at top level).
        path: String,
        /// 1-based line and column, when the TOML parser knows them.
        location: Option<(usize, usize)>,
        message: String,
    },
    /// Parsed, but values break the rules; every problem is listed.
    Invalid { problems: Vec<Problem> },
    /// Longer than `MAX_SCENE_BYTES`: not read at all.
    TooLarge { bytes: u64 },
}

/// Problems listed in an error message; the rest are counted.
const LISTED_PROBLEMS: usize = 50;

impl SceneError {
    /// The field-level problems (one for a parse error, all for an invalid
    /// scene, none for a read error).
    pub fn problems(&self) -> Vec<Problem> {
        match self {
            SceneError::Invalid { problems } => problems.clone(),
            SceneError::Parse { path, message, .. } => {
                vec![Problem::new(path.clone(), "", message.clone())]
            }
            SceneError::TooLarge { bytes } => {
                vec![Problem::new("", format!("{bytes} bytes"), too_large_rule())]
            }
            SceneError::Read { .. } | SceneError::NotFound { .. } => Vec::new(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Read { path, message } => {
                write!(f, "cannot read scene file `{path}`: {message}")
            }
            SceneError::NotFound { name } => {
                // The templates are built-ins (`templates` filters them):
                // listing the built-ins names each once.
                let names: Vec<&str> = super::builtins().iter().map(|(n, _)| *n).collect();
                write!(
                    f,
                    "`{name}` is neither a scene file nor a built-in scene (built-ins: {})",
                    names.join(", ")
                )
            }
            SceneError::Parse {
                path,
                location,
                message,
            } => {
                write!(f, "scene does not parse")?;
                if let Some((line, column)) = location {
                    write!(f, " (line {line}, column {column})")?;
                }
                writeln!(f, ":")?;
                let message = message.replace('\n', "\n    ");
                if path.is_empty() {
                    write!(f, "  {message}")
                } else {
                    write!(f, "  {path}: {message}")
                }
            }
            SceneError::Invalid { problems } => {
                let count = problems.len();
                let noun = if count == 1 { "problem" } else { "problems" };
                write!(f, "scene is not valid ({count} {noun}):")?;
                for problem in problems.iter().take(LISTED_PROBLEMS) {
                    write!(f, "\n  {problem}")?;
                }
                if count > LISTED_PROBLEMS {
                    write!(f, "\n  ... and {} more", count - LISTED_PROBLEMS)?;
                }
                Ok(())
            }
            SceneError::TooLarge { bytes } => {
                write!(f, "scene is {bytes} bytes: {}", too_large_rule())
            }
        }
    }
}

impl std::error::Error for SceneError {}

fn too_large_rule() -> String {
    format!(
        "a scene file must be at most {} bytes (10 MB)",
        super::validate::MAX_SCENE_BYTES
    )
}

/// Turn a serde error from the TOML deserializer into a `SceneError::Parse`
/// naming the field.
pub(super) fn from_toml_error(
    error: serde_path_to_error::Error<toml::de::Error>,
    text: &str,
) -> SceneError {
    let mut path = error.path().to_string();
    if path == "." {
        path.clear();
    }
    let inner = error.into_inner();
    let mut message = inner.message().trim().to_string();
    if message.is_empty() {
        message = "malformed TOML".to_string();
    }
    // serde words these at the enclosing table; point the path at the
    // field itself so it says what to delete, rename or add.
    for (prefix, rewritten) in [
        ("unknown field `", "unknown field"),
        ("missing field `", "missing field (required)"),
    ] {
        if let Some(field) = quoted_name_after(&message, prefix) {
            let field = field.to_string();
            let already_named = path == field || path.ends_with(&format!(".{field}"));
            if !already_named {
                path = if path.is_empty() {
                    field.clone()
                } else {
                    format!("{path}.{field}")
                };
            }
            message = message.replacen(&format!("{prefix}{field}`"), rewritten, 1);
        }
    }
    message = plain_type_names(&message);
    let location = inner.span().map(|span| line_and_column(text, span.start));
    SceneError::Parse {
        path,
        location,
        message,
    }
}

/// serde names Rust types (`f64`, `struct BeamSpec`); say what to write.
fn plain_type_names(message: &str) -> String {
    let mut message = message
        .replace("expected f64", "expected a number")
        .replace("expected usize", "expected a whole number >= 0")
        .replace("expected u32", "expected a whole number >= 0");
    if let Some(at) = message.find("expected struct ") {
        message.truncate(at);
        message.push_str("expected a table");
    }
    message
}

fn quoted_name_after<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = message.strip_prefix(prefix)?;
    rest.split('`').next()
}

/// 1-based line and column of a byte offset.
fn line_and_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}
