//! `guideway release [--out dist] [--changelog CHANGELOG.md] [--replace]`.

use super::{Failure, ReleaseArgs};
use guideway::fmu::{self, release};
use guideway::input_file::{read_text_bounded, MAX_CHANGELOG_BYTES};
use std::path::Path;

pub(super) fn release(args: ReleaseArgs) -> Result<(), Failure> {
    let dir = args.out.join(release::VERSION);
    if dir.exists() && !args.replace {
        // Refusing to overwrite an output is a command-line matter (exit
        // code 2), as for `run` and `export`.
        return Err(Failure::Usage(format!(
            "{} exists: remove it, or rebuild it with --replace",
            dir.display()
        )));
    }
    refuse_changelog_inside(&args.changelog, &dir)?;
    let changelog = read_text_bounded(&args.changelog, MAX_CHANGELOG_BYTES).map_err(|e| {
        Failure::Run(format!(
            "{e} (run from the repository root or pass --changelog)"
        ))
    })?;
    let cdylib = fmu::release_cdylib().map_err(Failure::Run)?;
    let built =
        release::build(&args.out, &cdylib, &changelog, args.replace).map_err(Failure::Run)?;
    for fmu in &built.fmus {
        println!("{}", fmu.display());
    }
    println!(
        "guideway {} released into {} (README.md, RELEASE_NOTES.md, SHA256SUMS, cross-check/)",
        release::VERSION,
        built.dir.display()
    );
    Ok(())
}

/// The changelog is an input: refused inside the release directory, which
/// `--replace` removes and rewrites (the rule of `check_outputs`).
fn refuse_changelog_inside(changelog: &Path, dir: &Path) -> Result<(), Failure> {
    let (Ok(file), Ok(dir)) = (changelog.canonicalize(), dir.canonicalize()) else {
        return Ok(());
    };
    if file.starts_with(&dir) {
        return Err(Failure::Usage(format!(
            "--changelog {} lies inside the release directory {}, which the release \
             replaces: it would be overwritten; choose another path",
            changelog.display(),
            dir.display()
        )));
    }
    Ok(())
}
