//! `guideway release`: versioned, reproducible, with notes and checksums.

use crate::common;
use common::model_description;
use guideway::fmu::{self, release};
use guideway::scene::{builtin, fmu_builtins};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const CHANGELOG: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/CHANGELOG.md");

fn release_into(out: &Path, extra: &[&str]) -> Output {
    // `cargo test` builds the cdylib next to the test binaries, in deps/.
    let cdylib = fmu::default_cdylib().expect("the cdylib is built with the tests");
    Command::new(env!("CARGO_BIN_EXE_guideway"))
        .args([
            "release",
            "--out",
            out.to_str().unwrap(),
            "--changelog",
            CHANGELOG,
        ])
        .args(extra)
        .env("GUIDEWAY_CDYLIB", cdylib)
        .output()
        .expect("the guideway binary runs")
}

/// Every file under `dir`, relative paths sorted, with its bytes.
fn files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<(PathBuf, Vec<u8>)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let rel = path.strip_prefix(root).unwrap().to_path_buf();
                out.push((rel, std::fs::read(&path).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// An attribute of the `fmiModelDescription` element.
fn attribute<'a>(xml: &'a str, name: &str) -> &'a str {
    let xml = &xml[xml.find("<fmiModelDescription").unwrap()..];
    let start = xml.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
    let len = xml[start..].find('"').unwrap();
    &xml[start..start + len]
}

#[test]
fn releasing_twice_gives_byte_identical_files() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    for out in [a.path(), b.path()] {
        let output = release_into(out, &[]);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let version = env!("CARGO_PKG_VERSION");
    let (fa, fb) = (
        files(&a.path().join(version)),
        files(&b.path().join(version)),
    );
    let names: Vec<_> = fa.iter().map(|(p, _)| p.clone()).collect();
    assert_eq!(names, fb.iter().map(|(p, _)| p.clone()).collect::<Vec<_>>());
    for ((path, x), (_, y)) in fa.iter().zip(&fb) {
        assert!(x == y, "{} differs between the two builds", path.display());
    }
    // one FMU per built-in scene a release ships, at the top and in the
    // cross-check tree
    for (name, _) in fmu_builtins() {
        let id = name.replace('-', "_");
        assert!(
            names.contains(&PathBuf::from(format!("{id}.fmu"))),
            "{id}.fmu"
        );
        let model = release::cross_check_models_dir().join(&id);
        for file in [
            format!("{id}.fmu"),
            format!("{id}_ref.csv"),
            format!("{id}_ref.opt"),
            "ReadMe.txt".into(),
        ] {
            assert!(
                names.contains(&model.join(&file)),
                "{}",
                model.join(&file).display()
            );
        }
    }
    for file in ["README.md", "RELEASE_NOTES.md", "SHA256SUMS"] {
        assert!(names.contains(&PathBuf::from(file)), "{file}");
    }
}

#[test]
fn a_release_states_its_version_notes_and_checksums() {
    let out = tempfile::tempdir().unwrap();
    let output = release_into(out.path(), &[]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let version = env!("CARGO_PKG_VERSION");
    let dir = out.path().join(version);

    let xml = model_description(&dir.join("lee1994_wheel_10.fmu"));
    assert_eq!(attribute(&xml, "version"), version);
    assert_eq!(
        attribute(&xml, "generationTool"),
        format!("guideway {version}")
    );

    // archives: entries in name order, all stamped 1980-01-01 00:00
    let mut zip =
        zip::ZipArchive::new(std::fs::File::open(dir.join("lee1994_wheel_10.fmu")).unwrap())
            .unwrap();
    let mut names = Vec::new();
    for i in 0..zip.len() {
        let f = zip.by_index(i).unwrap();
        let name = f.name().unwrap().into_owned();
        let t = f.last_modified().unwrap();
        assert_eq!(
            (t.year(), t.month(), t.day(), t.hour(), t.minute()),
            (1980, 1, 1, 0, 0),
            "{name}"
        );
        names.push(name);
    }
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted, "entries in name order");

    let notes = std::fs::read_to_string(dir.join("RELEASE_NOTES.md")).unwrap();
    assert!(notes.contains(&format!("## [{version}]")), "{notes}");
    // The notes carry the body of the version's CHANGELOG section: its
    // first entry, as the changelog words it.
    let changelog = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/CHANGELOG.md"))
        .expect("the changelog");
    let section = &changelog[changelog
        .find(&format!("## [{version}]"))
        .expect("a section for this version")..];
    let first_entry = section.lines().find(|l| l.starts_with("- ")).unwrap();
    assert!(notes.contains(first_entry), "{first_entry} not in {notes}");
    assert!(!notes.contains("[Unreleased]"), "{notes}");

    // SHA256SUMS covers every other file, with the right digests
    let sums = std::fs::read_to_string(dir.join("SHA256SUMS")).unwrap();
    let listed: Vec<(&str, &str)> = sums
        .lines()
        .map(|l| l.split_once("  ").expect("`<hex>  <path>`"))
        .collect();
    let on_disk: Vec<_> = files(&dir)
        .into_iter()
        .filter(|(p, _)| p != Path::new("SHA256SUMS"))
        .collect();
    assert_eq!(listed.len(), on_disk.len());
    for ((hex, path), (p, bytes)) in listed.iter().zip(&on_disk) {
        assert_eq!(Path::new(path), p);
        let digest: String = Sha256::digest(bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(*hex, digest, "{path}");
    }
}

#[test]
fn an_existing_release_is_kept_unless_replace() {
    let out = tempfile::tempdir().unwrap();
    let version = env!("CARGO_PKG_VERSION");
    let marker = out.path().join(version).join("keep-me");
    std::fs::create_dir_all(marker.parent().unwrap()).unwrap();
    std::fs::write(&marker, "x").unwrap();
    let output = release_into(out.path(), &[]);
    // one exit-code convention (issue 13): an output refused is exit code 2
    assert_eq!(output.status.code(), Some(2));
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(err.contains("exists") && err.contains("--replace"), "{err}");
    assert!(marker.exists());
    let output = release_into(out.path(), &["--replace"]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(!marker.exists());
}

#[test]
fn the_guid_follows_the_model_description_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let (lib_a, lib_b) = (dir.path().join("a.so"), dir.path().join("b.so"));
    std::fs::write(&lib_a, b"one binary").unwrap();
    std::fs::write(&lib_b, b"another binary").unwrap();
    let scene = builtin("lee1994-wheel-10").unwrap();
    let guid = |scene: &guideway::Scene, lib: &Path, name: &str| {
        fmu::export(scene, &dir.path().join(name), lib)
            .unwrap()
            .guid
    };
    let g = guid(&scene, &lib_a, "a.fmu");
    // same description: same GUID, whatever the binary or the file name
    assert_eq!(guid(&scene, &lib_a, "again.fmu"), g);
    assert_eq!(guid(&scene, &lib_b, "b.fmu"), g);
    // any change of the description changes it
    let mut described = scene.clone();
    described.description.push_str(" (edited)");
    assert_ne!(guid(&described, &lib_a, "c.fmu"), g);
    let mut stiffer = scene.clone();
    stiffer.beam.bending_stiffness *= 2.0;
    assert_ne!(guid(&stiffer, &lib_a, "d.fmu"), g);
    let mut renamed = scene;
    renamed.sensors[0].name = "middle".into();
    assert_ne!(guid(&renamed, &lib_a, "e.fmu"), g);
}
