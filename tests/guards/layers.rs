//! The layering of `src/` (docs/architecture.md, "The folders"): no physics
//! module names the scene format, and no module names a layer above its
//! own. Read from the source text: every `crate::` path outside unit tests.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The top-level modules of the library, lowest layer first; modules in one
/// entry are one layer and may use each other. The order is the table of
/// docs/architecture.md.
const LAYERS: &[&[&str]] = &[
    &["numbers", "input_file", "signal"],
    &["linalg"],
    &["structure"],
    &["vehicle"],
    &["contact"],
    &["system"],
    // The state (with the `DynamicState` an integrator advances) lies
    // below the solver that advances it.
    &["state"],
    &["solver"],
    &["energy"],
    &["outputs"],
    &["scene"],
    // vehicle/presets: each kind's spec, rules and build read the scene's
    // `BodySpec` and place contacts, so they sit between the file format
    // and the build (`top_module`).
    &["presets"],
    &["build"],
    &["simulation"],
    &["design", "moving_load"],
    &["model"],
    &["fmi_common", "fmi2", "fmi3"],
    &["report"],
    &["fmu"],
    &["study"],
    &["check"],
];

/// The physics: none of it may name `crate::scene`, the file format.
const PHYSICS: &[&str] = &[
    "linalg",
    "structure",
    "vehicle",
    "contact",
    "solver",
    "state",
    "system",
    "energy",
    "outputs",
];

/// The FMI fronts: generic over the model layer's `model::FmuModel` seam
/// (DESIGN.md step 11), they name no module but each other and `model`.
const FMI_FRONTS: &[&str] = &["fmi_common", "fmi2", "fmi3"];

/// What the FMI fronts may name: each other and the model layer.
const FMI_MAY_NAME: &[&str] = &["fmi_common", "fmi2", "fmi3", "model"];

/// Words of the scene format and the physics that the FMI fronts' code
/// (outside comments and unit tests) never uses, not even through a path
/// the model layer re-exports (`model::SceneDynamics`) or in a message.
const FMI_UNSPOKEN: &[&str] = &["scene", "beam", "dynamics", "vehicle", "contact"];

/// Arrows that still run up, each with its reason: (importing file under
/// src/, the module it names, why). An entry that no longer matches any
/// import fails the test, so that the list only shrinks. None is left: the
/// last, `Simulation::static_envelope`, became `design::envelope_of_run`.
const EXCEPTIONS: &[(&str, &str, &str)] = &[];

/// One `crate::` path found outside unit tests.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Arrow {
    file: String,
    from: String,
    to: String,
    path: String,
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file of the library (not the binary's `main.rs`, `cli/`).
fn library_files(dir: &Path, found: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if path.is_dir() && !(dir == src() && name == "cli") {
            library_files(&path, found);
        } else if name.ends_with(".rs") && !(dir == src() && name == "main.rs") {
            found.push(path);
        }
    }
}

/// The file's path under src/, with `/` separators.
fn relative(path: &Path) -> String {
    let rel = path.strip_prefix(src()).unwrap();
    rel.to_str().unwrap().replace('\\', "/")
}

/// The top-level module a file belongs to (`structure/beam/mod.rs` →
/// `structure`, `system.rs` → `system`).
fn top_module(rel: &str) -> String {
    if rel.starts_with("vehicle/presets/") {
        return "presets".to_string();
    }
    let first = rel.split('/').next().unwrap();
    first.trim_end_matches(".rs").to_string()
}

/// The text with `//` comments removed (doc comments name paths in prose).
fn without_comments(text: &str) -> String {
    text.lines()
        .map(|line| line.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The end (byte index) of the item that starts at `start`: its `;` if
/// that comes before any `{`, else its matching `}`.
fn item_end(text: &str, start: usize) -> usize {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    for (i, &b) in bytes.iter().enumerate().skip(start) {
        match b {
            b';' if depth == 0 => return i + 1,
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
    }
    text.len()
}

/// The text without the items marked `#[cfg(test)]` (unit tests, test
/// helpers); also returns the names of the test modules declared in
/// their own files (`#[cfg(test)] mod tests;`).
fn without_tests(text: &str) -> (String, Vec<String>) {
    const MARK: &str = "#[cfg(test)]";
    let mut kept = String::new();
    let mut test_files = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(MARK) {
        kept.push_str(&rest[..at]);
        let after = &rest[at + MARK.len()..];
        let end = item_end(after, 0);
        let item = after[..end].trim();
        // `mod tests;`, `pub(crate) mod fixtures;`: a module in its own file.
        if let Some((_, name)) = item.strip_suffix(';').and_then(|i| i.split_once("mod ")) {
            test_files.push(name.trim().to_string());
        }
        rest = &after[end..];
    }
    kept.push_str(rest);
    (kept, test_files)
}

/// The old paths kept in lib.rs (`pub use build as assemble;`,
/// `pub use structure::{beam, modal};`): alias → the top-level module it
/// stands for.
fn shims() -> BTreeMap<String, String> {
    let lib = without_comments(&fs::read_to_string(src().join("lib.rs")).unwrap());
    let mut found = BTreeMap::new();
    for statement in lib.split(';') {
        let Some(used) = statement.trim().strip_prefix("pub use ") else {
            continue;
        };
        let top = used.split("::").next().unwrap().split(' ').next().unwrap();
        let names = match used.find('{') {
            Some(open) => used[open + 1..].trim_end_matches('}').to_string(),
            None => used.rsplit("::").next().unwrap().to_string(),
        };
        for name in names.split(',') {
            let alias = name.split(" as ").last().unwrap().trim();
            if !alias.is_empty() {
                found.insert(alias.to_string(), top.to_string());
            }
        }
    }
    found
}

/// The first component of every `crate::` path in `code`, with the path
/// shown (`crate::{a::X, b::Y}` gives `a` and `b`).
fn crate_paths(code: &str) -> Vec<(String, String)> {
    let mut found = Vec::new();
    for (at, _) in code.match_indices("crate::") {
        let rest = &code[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let inner = &group[..group.find('}').unwrap_or(group.len())];
            for part in inner.split(',') {
                let name: String = part.trim().chars().take_while(is_ident).collect();
                if !name.is_empty() {
                    found.push((name, format!("crate::{{{}}}", inner.trim())));
                }
            }
            continue;
        }
        let path: String = rest
            .chars()
            .take_while(|c| is_ident(c) || *c == ':')
            .collect();
        let first = path.split("::").next().unwrap().to_string();
        found.push((first, format!("crate::{path}")));
    }
    found
}

fn is_ident(c: &char) -> bool {
    c.is_alphanumeric() || *c == '_'
}

/// Every arrow from one top-level module to another, outside unit tests.
fn arrows() -> Vec<Arrow> {
    let alias = shims();
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let mut test_files = BTreeSet::new();
    let mut code = Vec::new();
    for path in &files {
        let text = without_comments(&fs::read_to_string(path).unwrap());
        let (kept, tests) = without_tests(&text);
        let dir = path.parent().unwrap();
        let own = if path.file_name().unwrap() == "mod.rs" || dir == src() {
            dir.to_path_buf()
        } else {
            dir.join(path.file_stem().unwrap())
        };
        for name in tests {
            test_files.insert(own.join(format!("{name}.rs")));
            test_files.insert(own.join(&name).join("mod.rs"));
        }
        code.push((path.clone(), kept));
    }
    let mut found = Vec::new();
    for (path, kept) in code {
        if test_files.contains(&path) || path.ends_with("lib.rs") {
            continue;
        }
        let file = relative(&path);
        let from = top_module(&file);
        for (first, shown) in crate_paths(&kept) {
            let to = alias.get(&first).cloned().unwrap_or(first);
            if to != from {
                let (file, from, path) = (file.clone(), from.clone(), shown);
                found.push(Arrow {
                    file,
                    from,
                    to,
                    path,
                });
            }
        }
    }
    found.sort();
    found.dedup();
    found
}

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

fn excepted(arrow: &Arrow) -> bool {
    EXCEPTIONS
        .iter()
        .any(|(file, to, _)| *file == arrow.file && *to == arrow.to)
}

fn listed(arrows: &[Arrow]) -> String {
    arrows
        .iter()
        .map(|a| format!("  {} ({}) -> {}: {}", a.file, a.from, a.to, a.path))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn no_physics_module_names_the_scene_format() {
    let offending: Vec<Arrow> = arrows()
        .into_iter()
        .filter(|a| PHYSICS.contains(&a.from.as_str()) && a.to == "scene" && !excepted(a))
        .collect();
    assert!(
        offending.is_empty(),
        "physics modules that name crate::scene (the specs they need live in the physics: \
         structure::beam, structure::profile, solver::spec, solver::integrate):\n{}",
        listed(&offending)
    );
}

#[test]
fn the_fmi_fronts_name_only_the_model_seam() {
    let offending: Vec<Arrow> = arrows()
        .into_iter()
        .filter(|a| FMI_FRONTS.contains(&a.from.as_str()) && !FMI_MAY_NAME.contains(&a.to.as_str()))
        .collect();
    assert!(
        offending.is_empty(),
        "FMI fronts that name a module beside the model layer (ask model::FmuModel instead):\n{}",
        listed(&offending)
    );
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let mut spoken = Vec::new();
    for path in files {
        let file = relative(&path);
        if !FMI_FRONTS.contains(&top_module(&file).as_str()) || file.ends_with("tests.rs") {
            continue;
        }
        let (code, _) = without_tests(&without_comments(&fs::read_to_string(&path).unwrap()));
        let code = code.to_lowercase();
        spoken.extend(
            FMI_UNSPOKEN
                .iter()
                .filter(|w| code.contains(*w))
                .map(|w| format!("  {file}: {w}")),
        );
    }
    assert!(
        spoken.is_empty(),
        "FMI fronts that speak of the scene or the physics (the model's words come \
         through model::FmuModel):\n{}",
        spoken.join("\n")
    );
}

#[test]
fn every_top_level_module_has_a_layer() {
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let missing: BTreeSet<String> = files
        .iter()
        .map(|p| top_module(&relative(p)))
        .filter(|m| m != "lib" && layer_of(m).is_none())
        .collect();
    assert!(
        missing.is_empty(),
        "modules with no place in LAYERS (add them where docs/architecture.md puts them): \
         {missing:?}"
    );
}

#[test]
fn no_module_names_a_layer_above_its_own() {
    let upward: Vec<Arrow> = arrows()
        .into_iter()
        .filter(|a| match (layer_of(&a.from), layer_of(&a.to)) {
            (Some(from), Some(to)) => to > from,
            _ => false,
        })
        .filter(|a| !excepted(a))
        .collect();
    assert!(
        upward.is_empty(),
        "arrows up the layers (docs/architecture.md, \"The folders\"):\n{}",
        listed(&upward)
    );
}

#[test]
fn every_exception_still_applies() {
    let all = arrows();
    let stale: Vec<_> = EXCEPTIONS
        .iter()
        .filter(|(file, to, _)| !all.iter().any(|a| a.file == *file && a.to == *to))
        .collect();
    assert!(
        stale.is_empty(),
        "exceptions that no longer match an import (delete them): {stale:?}"
    );
}

#[test]
fn the_reader_finds_paths_and_skips_tests_and_comments() {
    let text = "use crate::a::B;\n// crate::c::D\n#[cfg(test)]\nmod tests {\n    use crate::e::F;\n    fn g() { let x = 1; }\n}\nfn h() -> crate::{i::J, k::L} {}\n";
    let (kept, tests) = without_tests(&without_comments(text));
    let firsts: Vec<String> = crate_paths(&kept).into_iter().map(|(f, _)| f).collect();
    assert_eq!(firsts, ["a", "i", "k"]);
    assert!(tests.is_empty());
    let (_, tests) = without_tests("#[cfg(test)]\nmod tests;\n");
    assert_eq!(tests, ["tests"]);
}
