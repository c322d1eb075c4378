//! `guideway release [--out dist] [--changelog CHANGELOG.md] [--replace]`.

use super::{Failure, ReleaseArgs};
use guideway::fmu::{self, release};

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
    let changelog = std::fs::read_to_string(&args.changelog).map_err(|e| {
        Failure::Run(format!(
            "cannot read the changelog {}: {e} (run from the repository root or pass --changelog)",
            args.changelog.display()
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
