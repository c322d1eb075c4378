//! Scene fuzzing: random and mutated scene TOML either loads (and then
//! `Simulation::new` builds it or returns an error) or is refused with an
//! error that says where; never a panic, never an endless loop.
//!
//! Inputs: the built-in scenes (plain and annotated TOML) mutated by
//! deleting, duplicating and retyping fields, extreme numbers (0, -0,
//! 1e308, subnormals, NaN/inf, element counts up to the validator's limit),
//! unicode, line edits; and arbitrary text. Only parse + validate + build:
//! no simulation is run, so each case is bounded.
//!
//! `GUIDEWAY_SCENE_FUZZ_CASES` sets the number of cases (default 300);
//! `scripts/fuzz_scene.sh` is the long run.

use guideway::scene::{builtin, builtins, Scene, SceneError, MAX_ELEMENTS};
use guideway::simulation::Simulation;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc;
use std::time::Duration;
use toml_edit::{DocumentMut, Item, Value};

/// Longest a case may take (parse, validate, build) before it counts as an
/// endless loop. Generous: the largest valid mesh builds in well under this.
const CASE_TIME_LIMIT: Duration = Duration::from_secs(20);

fn seed_texts() -> Vec<String> {
    let mut texts = Vec::new();
    for (name, _) in builtins() {
        let scene = builtin(name).expect("listed built-in");
        texts.push(scene.to_toml_string());
        texts.push(scene.to_annotated_toml());
    }
    // one with the optional parts present: intermediate supports, two
    // sensors, an end time
    let mut rich = builtin("lee1994-glider-30").unwrap().to_toml_string();
    rich = rich.replace("intermediate = []", "intermediate = [8.0, 16.0]");
    rich.push_str("\n[[sensors]]\nname = \"quarter\"\nposition = 6.0\n");
    rich = rich.replace("[solver]\n", "[solver]\nend_time = 0.5\n");
    texts.push(rich);
    texts
}

/// Dotted paths of every value in a TOML document (array elements and
/// array-of-tables entries included), in document order.
fn leaf_paths(doc: &DocumentMut) -> Vec<Vec<String>> {
    fn walk(item: &Item, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
        match item {
            Item::Table(t) => {
                for (k, v) in t.iter() {
                    prefix.push(k.to_string());
                    out.push(prefix.clone());
                    walk(v, prefix, out);
                    prefix.pop();
                }
            }
            Item::ArrayOfTables(a) => {
                for (i, t) in a.iter().enumerate() {
                    for (k, v) in t.iter() {
                        prefix.push(format!("{i}"));
                        prefix.push(k.to_string());
                        out.push(prefix.clone());
                        walk(v, prefix, out);
                        prefix.pop();
                        prefix.pop();
                    }
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(doc.as_item(), &mut Vec::new(), &mut out);
    out
}

/// The parent table of `path` and the last key, if the path still exists.
fn parent_table<'a>(doc: &'a mut DocumentMut, path: &[String]) -> Option<&'a mut toml_edit::Table> {
    let (last, parents) = path.split_last()?;
    let mut item = doc.as_item_mut();
    let mut i = 0;
    while i < parents.len() {
        item = match item {
            Item::Table(t) => t.get_mut(&parents[i])?,
            Item::ArrayOfTables(a) => {
                let idx: usize = parents[i].parse().ok()?;
                let t = a.get_mut(idx)?;
                i += 1;
                t.get_mut(parents.get(i)?)?
            }
            _ => return None,
        };
        i += 1;
    }
    match item {
        Item::Table(t) => t.contains_key(last).then_some(t),
        _ => None,
    }
}

/// Replacement values: extreme numbers, other types, unicode.
fn hostile_value() -> impl Strategy<Value = Value> {
    let max = MAX_ELEMENTS as i64;
    prop_oneof![
        prop::sample::select(vec![
            0.0,
            -0.0,
            1e308,
            -1e308,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-300,
            -1.0,
            0.5,
        ])
        .prop_map(Value::from),
        prop::sample::select(vec![0, -1, 1, 2, max - 1, max, max + 1, i64::MAX, i64::MIN])
            .prop_map(Value::from),
        (1..=max).prop_map(Value::from),
        any::<f64>().prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        any::<bool>().prop_map(Value::from),
        prop::sample::select(vec![
            "nan",
            "inf",
            "-inf",
            "1e308",
            "",
            "pinned",
            "clamped",
            "free",
            "wheel",
            "glider",
            "rk4",
            "ü∂ƒ©",
            "a b",
            "😀",
            "\u{0}",
            "rk5",
        ])
        .prop_map(Value::from),
        ".{0,40}".prop_map(Value::from),
        prop::collection::vec(-1e3f64..1e3, 0..5)
            .prop_map(|xs| Value::Array(xs.into_iter().collect())),
        Just(Value::InlineTable(toml_edit::InlineTable::new())),
    ]
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Retype(usize, Value),
    DuplicateLine(usize),
    DeleteLine(usize),
    InsertText(usize, String),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let index = any::<usize>();
    prop_oneof![
        2 => index.prop_map(Mutation::Delete),
        6 => (index, hostile_value()).prop_map(|(i, v)| Mutation::Retype(i, v)),
        1 => index.prop_map(Mutation::DuplicateLine),
        1 => index.prop_map(Mutation::DeleteLine),
        1 => (index, "(.|\n){0,12}").prop_map(|(i, s)| Mutation::InsertText(i, s)),
        1 => index.prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let pick = |i: usize, n: usize| if n == 0 { 0 } else { i % n };
    match m {
        Mutation::Delete(i) | Mutation::Retype(i, _) => {
            let Ok(mut doc) = text.parse::<DocumentMut>() else {
                return text.to_string();
            };
            let paths = leaf_paths(&doc);
            if paths.is_empty() {
                return text.to_string();
            }
            let path = &paths[pick(*i, paths.len())];
            let Some(table) = parent_table(&mut doc, path) else {
                return text.to_string();
            };
            let key = path.last().unwrap();
            match m {
                Mutation::Delete(_) => {
                    table.remove(key);
                }
                Mutation::Retype(_, v) => {
                    table.insert(key, Item::Value(v.clone()));
                }
                _ => unreachable!(),
            }
            doc.to_string()
        }
        Mutation::DuplicateLine(i) => {
            let mut out = lines.clone();
            if !lines.is_empty() {
                let k = pick(*i, lines.len());
                out.insert(k, lines[k]);
            }
            out.join("\n")
        }
        Mutation::DeleteLine(i) => {
            let mut out = lines.clone();
            if !lines.is_empty() {
                out.remove(pick(*i, lines.len()));
            }
            out.join("\n")
        }
        Mutation::InsertText(i, s) => {
            let cut = char_boundary(text, pick(*i, text.len() + 1));
            format!("{}{s}{}", &text[..cut], &text[cut..])
        }
        Mutation::Truncate(i) => text[..char_boundary(text, pick(*i, text.len() + 1))].to_string(),
    }
}

fn char_boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// A scene text: a seed with 1 to 4 mutations, or arbitrary text.
fn scene_text() -> impl Strategy<Value = String> {
    let seeds = seed_texts();
    prop_oneof![
        9 => (prop::sample::select(seeds), prop::collection::vec(mutation(), 1..5))
            .prop_map(|(seed, ms)| ms.iter().fold(seed, |t, m| apply(&t, m))),
        1 => "(.|\n){0,200}",
    ]
}

#[derive(Debug, PartialEq)]
enum Outcome {
    Built,
    RefusedAtBuild,
    Refused,
}

static COUNTS: [AtomicUsize; 3] = [
    AtomicUsize::new(0),
    AtomicUsize::new(0),
    AtomicUsize::new(0),
];

/// Where an error points: a field path, or a line of the text.
fn error_says_where(e: &SceneError) -> Result<(), String> {
    match e {
        SceneError::Invalid { problems } => match problems.iter().find(|p| p.path.is_empty()) {
            None if !problems.is_empty() => Ok(()),
            _ => Err(format!("a problem without a field: {e}")),
        },
        SceneError::Parse { path, location, .. } if !path.is_empty() || location.is_some() => {
            Ok(())
        }
        _ => Err(format!("neither a field nor a line: {e:?}")),
    }
}

/// Parse, validate and build `text` on a watched thread.
fn check(text: &str) -> Result<Outcome, String> {
    let (tx, rx) = mpsc::channel();
    let owned = text.to_string();
    let worker = std::thread::spawn(move || {
        let outcome = match Scene::from_toml_str(&owned) {
            Ok(scene) => match Simulation::new(&scene) {
                Ok(_) => Ok(Outcome::Built),
                Err(e) if !e.is_empty() => Ok(Outcome::RefusedAtBuild),
                Err(_) => Err("Simulation::new refused with an empty message".to_string()),
            },
            Err(e) => error_says_where(&e).map(|()| Outcome::Refused),
        };
        let _ = tx.send(outcome);
    });
    match rx.recv_timeout(CASE_TIME_LIMIT) {
        Ok(outcome) => {
            worker.join().map_err(|_| "panicked".to_string())?;
            outcome
        }
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!(
            "no result after {CASE_TIME_LIMIT:?}: endless loop?"
        )),
        Err(mpsc::RecvTimeoutError::Disconnected) => match worker.join() {
            Err(payload) => Err(format!(
                "panicked: {}",
                payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default()
            )),
            Ok(()) => Err("the worker ended without a result".to_string()),
        },
    }
}

fn cases() -> u32 {
    std::env::var("GUIDEWAY_SCENE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300)
}

#[test]
fn fuzzed_scenes_load_or_are_refused_naming_where_and_never_panic_or_hang() {
    let config = Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let started = std::time::Instant::now();
    let result = runner.run(&scene_text(), |text| {
        let outcome =
            check(&text).map_err(|e| TestCaseError::fail(format!("{e}\n--- scene:\n{text}")))?;
        let k = match outcome {
            Outcome::Built => 0,
            Outcome::RefusedAtBuild => 1,
            Outcome::Refused => 2,
        };
        COUNTS[k].fetch_add(1, Relaxed);
        Ok(())
    });
    let [built, at_build, refused] = COUNTS.each_ref().map(|c| c.load(Relaxed));
    eprintln!(
        "scene fuzz: {} scenes ({} cases), {built} loaded and built, {at_build} loaded but \
         refused by Simulation::new, {refused} refused with a located error, 0 panics, \
         0 hangs, {:.1} s",
        built + at_build + refused,
        cases(),
        started.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    // the generator reaches both sides
    assert!(built > 0 && refused > 0, "built {built}, refused {refused}");
}

#[test]
fn an_error_that_names_neither_field_nor_line_is_caught() {
    let e = SceneError::Invalid { problems: vec![] };
    assert!(error_says_where(&e).is_err());
    let e = SceneError::Parse {
        path: String::new(),
        location: None,
        message: "x".into(),
    };
    assert!(error_says_where(&e).is_err());
}

#[test]
fn largest_valid_mesh_builds_within_the_time_limit() {
    let mut scene = builtin("lee1994-wheel-10").unwrap();
    scene.beam.elements = MAX_ELEMENTS;
    scene.solver.step = 1e-9; // within RK4's limit for the finest mesh
    let text = scene.to_toml_string();
    let started = std::time::Instant::now();
    let outcome = check(&text).unwrap();
    assert!(
        matches!(outcome, Outcome::Built | Outcome::RefusedAtBuild),
        "{outcome:?}"
    );
    assert!(started.elapsed() < CASE_TIME_LIMIT);
}
