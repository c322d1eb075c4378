//! The user guide stays in step with the code: its generated pages are
//! current, its links resolve, its command synopses match `guideway --help`
//! and its kind lists match the scene format.
//!
//! `GUIDEWAY_UPDATE_DOCS=1 cargo test --release --test guards docs::` rewrites the
//! generated pages (`docs/scene-fields.md`, `docs/cli-help.md`, the
//! annotated example in `docs/scenes.md`) instead of comparing them.

use crate::common;
use guideway::scene::field_notes_markdown;
use guideway::Scene;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// Pages linked from the guide that other branches write; each is checked
/// like any page once it exists (the test fails while a page listed here
/// exists, so that its name is taken off the list when it lands).
const PAGES_FROM_OTHER_BRANCHES: [&str; 0] = [];

/// The annotated example of `docs/scenes.md` follows this marker.
const ANNOTATED_MARKER: &str = "<!-- generated: guideway scenes --show lee1994-wheel-10 -->";
/// A command synopsis (README and `docs/cli.md`) follows this marker.
const SYNOPSIS_MARKER: &str = "<!-- synopsis:";
/// A table whose first column lists the values of a field follows
/// `<!-- kind list: FIELD -->`.
const KIND_LIST_MARKER: &str = "<!-- kind list: ";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(relative: &str) -> String {
    std::fs::read_to_string(root().join(relative))
        .unwrap_or_else(|e| panic!("cannot read {relative}: {e}"))
}

/// What `guideway args` prints, failing the test unless it succeeded.
fn guideway(args: &[&str]) -> String {
    common::cli::stdout(&common::cli::guideway_ok(args))
}

/// README.md and every page under docs/.
fn guide_pages() -> Vec<String> {
    let mut pages = vec!["README.md".to_string()];
    for entry in std::fs::read_dir(root().join("docs")).expect("docs/ exists") {
        let name = entry.expect("a directory entry").file_name();
        let name = name.to_string_lossy();
        if name.ends_with(".md") {
            pages.push(format!("docs/{name}"));
        }
    }
    pages.sort();
    pages
}

/// The committed file equals `expected`, or is rewritten under
/// `GUIDEWAY_UPDATE_DOCS`.
fn check_generated(relative: &str, expected: &str) {
    let path = root().join(relative);
    if std::env::var_os("GUIDEWAY_UPDATE_DOCS").is_some() {
        std::fs::write(&path, expected).expect("the page is writable");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == expected,
        "{relative} is out of date: GUIDEWAY_UPDATE_DOCS=1 cargo test --release --test guards docs:: rewrites it"
    );
}

// ---------------------------------------------------------------- Markdown

/// Lines outside fenced code blocks, with inline code removed.
fn prose_lines(text: &str) -> Vec<String> {
    let mut fenced = false;
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced && !line.starts_with("    ") {
            lines.push(without_inline_code(line));
        }
    }
    lines
}

fn without_inline_code(line: &str) -> String {
    line.split('`')
        .enumerate()
        .filter(|(i, _)| i % 2 == 0)
        .map(|(_, part)| part)
        .collect::<Vec<_>>()
        .join("")
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces
/// to hyphens.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a page's headings (repeated headings get -1, -2, ...).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut anchors = BTreeSet::new();
    for line in prose_lines(text) {
        let Some(heading) = line.strip_prefix('#') else {
            continue;
        };
        let base = slug(heading.trim_start_matches('#'));
        let count = seen.entry(base.clone()).or_insert(0);
        anchors.insert(match *count {
            0 => base,
            n => format!("{base}-{n}"),
        });
        *count += 1;
    }
    anchors
}

/// The targets of `[text](target)` links and images in prose.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    for line in prose_lines(text) {
        let mut rest = line.as_str();
        while let Some(start) = rest.find("](") {
            let after = &rest[start + 2..];
            let end = after.find(')').unwrap_or(after.len());
            targets.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    targets
}

// ------------------------------------------------------------------- links

/// Where a relative link of `page` leads: the file and the anchor.
fn resolve(page: &str, target: &str) -> (String, Option<String>) {
    let (file, anchor) = match target.split_once('#') {
        Some((file, anchor)) => (file, Some(anchor.to_string())),
        None => (target, None),
    };
    if file.is_empty() {
        return (page.to_string(), anchor);
    }
    let base = Path::new(page).parent().unwrap_or(Path::new(""));
    let mut parts: Vec<String> = Vec::new();
    for part in base.join(file).components() {
        match part.as_os_str().to_string_lossy().as_ref() {
            ".." => {
                parts.pop();
            }
            "." => {}
            other => parts.push(other.to_string()),
        }
    }
    (parts.join("/"), anchor)
}

fn is_external(target: &str) -> bool {
    target.starts_with("http://") || target.starts_with("https://") || target.starts_with("mailto:")
}

#[test]
fn every_relative_link_of_the_guide_resolves() {
    let mut broken = Vec::new();
    for page in guide_pages() {
        for target in link_targets(&read(&page)) {
            if is_external(&target) {
                continue;
            }
            let (file, anchor) = resolve(&page, &target);
            if PAGES_FROM_OTHER_BRANCHES.contains(&file.as_str()) {
                continue;
            }
            if !root().join(&file).exists() {
                broken.push(format!("{page}: {target} (no file {file})"));
            } else if let Some(anchor) = anchor.filter(|_| file.ends_with(".md")) {
                if !anchors(&read(&file)).contains(&anchor) {
                    broken.push(format!("{page}: {target} (no heading #{anchor} in {file})"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn pages_expected_from_other_branches_are_not_yet_here() {
    for page in PAGES_FROM_OTHER_BRANCHES {
        assert!(
            !root().join(page).exists(),
            "{page} has landed: take it off PAGES_FROM_OTHER_BRANCHES so that its links are checked"
        );
    }
}

#[test]
fn every_guide_page_is_reached_from_the_readme() {
    let mut reached = BTreeSet::from(["README.md".to_string()]);
    let mut to_visit = vec!["README.md".to_string()];
    while let Some(page) = to_visit.pop() {
        for target in link_targets(&read(&page)) {
            let (file, _) = resolve(&page, &target);
            let exists = root().join(&file).exists();
            if !is_external(&target)
                && file.ends_with(".md")
                && exists
                && reached.insert(file.clone())
            {
                to_visit.push(file);
            }
        }
    }
    let unreached: Vec<_> = guide_pages()
        .into_iter()
        .filter(|p| !reached.contains(p))
        .collect();
    assert!(
        unreached.is_empty(),
        "pages no link leads to: {unreached:?}"
    );
}

#[test]
fn the_readme_is_a_front_door() {
    let lines = read("README.md").lines().count();
    assert!(
        lines <= 300,
        "README.md has {lines} lines; the guide under docs/ takes the rest"
    );
}

// ------------------------------------------------------- generated pages

#[test]
fn the_field_notes_page_is_current() {
    check_generated("docs/scene-fields.md", &field_notes_markdown());
}

/// `docs/cli-help.md`: the help of `guideway` and of each command.
fn command_help_page() -> String {
    let mut page = String::from(
        "# Command help\n\n\
         The output of `guideway --help` and `guideway <command> --help`, \
         generated: do not edit by hand; \
         `GUIDEWAY_UPDATE_DOCS=1 cargo test --release --test guards docs::` rewrites it. \
         How the commands behave: [The command line](cli.md).\n",
    );
    page += &format!("\n## guideway\n\n```text\n{}```\n", guideway(&["--help"]));
    for command in subcommands() {
        let help = guideway(&[&command, "--help"]);
        page += &format!("\n## guideway {command}\n\n```text\n{help}```\n");
    }
    page
}

#[test]
fn the_command_help_page_is_current() {
    check_generated("docs/cli-help.md", &command_help_page());
}

/// The fenced block after the line that starts with `marker`.
fn block_after(text: &str, marker: &str) -> Option<(usize, usize)> {
    let at = text.find(marker)?;
    let open = at + text[at..].find("```")?;
    let start = open + text[open..].find('\n')? + 1;
    let end = start + text[start..].find("```")?;
    Some((start, end))
}

#[test]
fn the_annotated_example_is_what_scenes_show_prints() {
    let page = read("docs/scenes.md");
    let (start, end) =
        block_after(&page, ANNOTATED_MARKER).expect("docs/scenes.md has the annotated example");
    let shown = guideway(&["scenes", "--show", "lee1994-wheel-10"]);
    let expected = format!("{}{shown}{}", &page[..start], &page[end..]);
    check_generated("docs/scenes.md", &expected);
}

// ---------------------------------------------------------------- the CLI

/// The commands `guideway --help` lists (without `help`).
fn subcommands() -> Vec<String> {
    let help = guideway(&["--help"]);
    let listing = help
        .split("Commands:\n")
        .nth(1)
        .expect("--help lists the commands");
    listing
        .lines()
        .take_while(|line| !line.trim().is_empty())
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// The long options `guideway <command> --help` lists (without --help).
fn long_options(command: &str) -> BTreeSet<String> {
    guideway(&[command, "--help"])
        .lines()
        .filter(|line| line.trim_start().starts_with('-'))
        .filter_map(|line| line.split_whitespace().find(|word| word.starts_with("--")))
        .map(|word| word.trim_end_matches(',').to_string())
        .filter(|word| word != "--help" && word != "--version")
        .collect()
}

/// The long options named on one synopsis line.
fn synopsis_options(line: &str) -> BTreeSet<String> {
    line.split(|c: char| c.is_whitespace() || matches!(c, '[' | ']'))
        .filter(|word| word.starts_with("--") && word.len() > 2)
        .map(|word| word.split('=').next().unwrap_or(word).to_string())
        .collect()
}

fn check_synopsis(page: &str) {
    let text = read(page);
    let (start, end) =
        block_after(&text, SYNOPSIS_MARKER).unwrap_or_else(|| panic!("{page} has no synopsis"));
    let mut listed = Vec::new();
    for line in text[start..end].lines() {
        let command = line
            .split_whitespace()
            .nth(1)
            .expect("guideway <command> ...");
        listed.push(command.to_string());
        assert_eq!(
            synopsis_options(line),
            long_options(command),
            "{page}: the synopsis of `guideway {command}` against its --help"
        );
    }
    assert_eq!(
        listed,
        subcommands(),
        "{page}: the synopsis's commands against `guideway --help`"
    );
}

#[test]
fn the_synopses_match_the_help() {
    check_synopsis("README.md");
    check_synopsis("docs/cli.md");
}

// ------------------------------------------------------------ kind lists

/// A minimal valid scene to which one bad value is added.
const SCENE: &str = r#"
name = "kinds"
[beam]
length = 24.0
mass_per_length = 1250.0
bending_stiffness = 1e9
surface_offset = 0.6
elements = 2
[body]
name = "wheel"
kind = "wheel"
mass = 3000.0
inertia = 135.0
radius = 0.3
initial_speed = 10.0
"#;

/// Each field whose value is one of a list, and the scene that gives it
/// the unknown value `?`.
fn enum_fields() -> Vec<(&'static str, String)> {
    let appended = |table: &str| format!("{SCENE}{table}");
    vec![
        (
            "body.kind",
            SCENE.replace("kind = \"wheel\"", "kind = \"?\""),
        ),
        (
            "beam.supports.left",
            appended("[beam.supports]\nleft = \"?\"\n"),
        ),
        (
            "beam.supports.right",
            appended("[beam.supports]\nright = \"?\"\n"),
        ),
        (
            "beam.joints.kind",
            appended("[[beam.joints]]\nat = 12.0\nkind = \"?\"\n"),
        ),
        (
            "track.irregularities.type",
            appended("[[track.irregularities]]\ntype = \"?\"\n"),
        ),
        (
            "solver.integrator",
            appended("[solver]\nintegrator = \"?\"\n"),
        ),
        (
            "solver.force_profile",
            appended("[solver]\nforce_profile = \"?\"\n"),
        ),
        ("solver.start", appended("[solver]\nstart = \"?\"\n")),
        (
            "solver.structure",
            appended("[solver]\nstructure = \"?\"\n"),
        ),
    ]
}

/// The values the scene format accepts, from its own refusal of `?`.
fn accepted_values(scene: &str) -> BTreeSet<String> {
    let message = Scene::from_toml_str(scene)
        .expect_err("`?` is refused")
        .to_string();
    let expected = message
        .split("expected")
        .nth(1)
        .unwrap_or_else(|| panic!("no list in: {message}"));
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The values a field note lists: `a | b (why) | c: rule` gives a, b, c.
fn note_values(note: &str) -> BTreeSet<String> {
    let list = note.split(';').next().unwrap_or(note);
    list.split(['|'])
        .filter_map(|item| {
            item.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .find(|w| !w.is_empty())
        })
        .map(str::to_string)
        .collect()
}

#[test]
fn the_field_notes_list_every_value_of_each_kind() {
    let page = field_notes_markdown();
    for (field, scene) in enum_fields() {
        let row = format!("| `{field}` | ");
        let line = page
            .lines()
            .find(|l| l.starts_with(&row))
            .unwrap_or_else(|| panic!("no note for {field}"));
        // The note is the last column (a `\\|` inside it is no column break).
        let last = line
            .trim_end_matches(" |")
            .rsplit(" | ")
            .next()
            .unwrap_or("");
        let note = last.replace("\\|", "|");
        assert_eq!(
            note_values(&note),
            accepted_values(&scene),
            "the note of {field}"
        );
    }
}

/// The first-column values of the table after each kind-list marker.
fn marked_kind_lists(text: &str) -> Vec<(String, BTreeSet<String>)> {
    let mut lists = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let Some(field) = line.strip_prefix(KIND_LIST_MARKER) else {
            continue;
        };
        let field = field.trim_end_matches("-->").trim().to_string();
        let values = lines
            .by_ref()
            .take_while(|l| l.starts_with('|'))
            .skip(2)
            .filter_map(|row| row.split('`').nth(1).map(str::to_string))
            .collect();
        lists.push((field, values));
    }
    lists
}

#[test]
fn the_guides_kind_lists_match_the_scene_format() {
    let fields: HashMap<_, _> = enum_fields().into_iter().collect();
    let mut checked = 0;
    for page in guide_pages() {
        for (field, values) in marked_kind_lists(&read(&page)) {
            let scene = fields
                .get(field.as_str())
                .unwrap_or_else(|| panic!("{page}: no field {field}"));
            assert_eq!(
                values,
                accepted_values(scene),
                "{page}: the kind list of {field}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 2, "the guide's kind lists are marked");
}

#[test]
fn no_page_lists_some_body_kinds_but_not_all() {
    let kinds = accepted_values(&enum_fields()[0].1);
    for page in guide_pages() {
        for line in read(&page).lines() {
            let named: BTreeSet<_> = kinds
                .iter()
                .filter(|kind| {
                    line.contains(&format!("`{kind}`")) || line.contains(&format!("\"{kind}\""))
                })
                .collect();
            assert!(
                named.len() < 3 || named.len() == kinds.len(),
                "{page}: a list of body kinds without {:?}: {line}",
                kinds
                    .iter()
                    .filter(|k| !named.contains(k))
                    .collect::<Vec<_>>()
            );
        }
    }
}

/// `key = value` lines of `scenes --show` output that carry no note.
fn fields_without_note(shown: &str) -> Vec<String> {
    shown
        .lines()
        .filter(|line| {
            line.split(" = ").next().is_some_and(|key| {
                !key.is_empty() && key.chars().all(|c| c.is_ascii_lowercase() || c == '_')
            })
        })
        // A multi-line array carries its note after its closing bracket.
        .filter(|line| line.contains(" = ") && !line.contains("  # ") && !line.ends_with('['))
        .map(str::to_string)
        .collect()
}

#[test]
fn every_field_of_the_shipped_scenes_has_a_note() {
    let mut sources: Vec<String> = guideway::scene::builtins()
        .iter()
        .map(|(name, _)| name.to_string())
        .collect();
    for entry in std::fs::read_dir(root().join("scenes")).expect("scenes/ exists") {
        sources.push(
            entry
                .expect("a directory entry")
                .path()
                .to_string_lossy()
                .into_owned(),
        );
    }
    for source in sources {
        let bare = fields_without_note(&guideway(&["scenes", "--show", &source]));
        assert!(
            bare.is_empty(),
            "{source}: fields without a note in src/scene/annotate.rs: {bare:?}"
        );
    }
}

/// The ```toml blocks of a page that are whole scenes (a name and a beam,
/// nothing elided).
fn scene_blocks(text: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find("```toml\n") {
        let body = &rest[open + "```toml\n".len()..];
        let end = body.find("```").unwrap_or(body.len());
        let block = &body[..end];
        let first_field = block
            .lines()
            .find(|l| !l.starts_with('#') && !l.trim().is_empty());
        // A block that elides part of a scene (`# ... as in`) is an excerpt.
        let whole = block.contains("\n[beam]") && !block.contains("# ...");
        if whole && first_field.is_some_and(|l| l.starts_with("name = ")) {
            blocks.push(block.to_string());
        }
        rest = &body[end..];
    }
    blocks
}

#[test]
fn every_whole_scene_in_the_guide_is_valid() {
    let mut checked = 0;
    for page in guide_pages() {
        for block in scene_blocks(&read(&page)) {
            if let Err(error) = Scene::from_toml_str(&block) {
                panic!("{page}: a scene of the guide is refused: {error}\n{block}");
            }
            checked += 1;
        }
    }
    assert!(checked >= 3, "only {checked} whole scenes found");
}

/// Paths of tests and scripts the guide names in inline code
/// (`tests/x.rs`, `scripts/tests/y.py`, `scripts/z.sh`).
fn named_test_and_script_paths(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .flat_map(str::split_whitespace)
        .filter(|word| word.starts_with("tests/") || word.starts_with("scripts/"))
        .map(|word| word.trim_end_matches([',', ';', ':', ')']).to_string())
        .filter(|path| [".rs", ".py", ".sh"].iter().any(|ext| path.ends_with(ext)))
        .collect()
}

#[test]
fn every_test_and_script_the_guide_names_exists() {
    let mut missing = Vec::new();
    for page in guide_pages() {
        for path in named_test_and_script_paths(&read(&page)) {
            if !root().join(&path).exists() {
                missing.push(format!("{page}: {path}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "named but missing:\n{}",
        missing.join("\n")
    );
}
