//! `guideway run SCENE [--out CSV] [--summary JSON] [--plot PNG] [--quiet]`.

use super::progress::Progress;
use super::{load_scene, Failure, RunArgs};
use guideway::report::{csv, plot, run_scene, Run, RunError};
use std::fs::File;
use std::path::Path;

pub(super) fn run(args: RunArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    for path in [&args.out, &args.summary, &args.plot].into_iter().flatten() {
        check_writable(path)?;
    }
    let mut progress = Progress::new(args.quiet);
    let outcome = run_scene(&scene, |step| progress.update(step));
    progress.finish();

    let run = match outcome {
        Ok(run) => run,
        Err(RunError::Setup(message)) => {
            return Err(Failure::Scene(format!(
                "scene `{}` cannot be simulated: {message}",
                scene.name
            )))
        }
        Err(RunError::Solver { error, partial }) => {
            let mut message = format!("the solver failed {error}");
            if let Some(path) = &args.out {
                match write_csv(&partial, path) {
                    Ok(()) => message.push_str(&format!(
                        "\n(the {} steps before the failure are in {})",
                        partial.trace.len().saturating_sub(1),
                        path.display()
                    )),
                    Err(Failure::Run(e) | Failure::Scene(e)) => message.push_str(&format!("\n{e}")),
                }
            }
            return Err(Failure::Run(message));
        }
    };

    let summary = run.summary(&scene);
    if let Some(path) = &args.out {
        write_csv(&run, path)?;
    }
    if let Some(path) = &args.summary {
        std::fs::write(path, summary.to_json() + "\n")
            .map_err(|e| Failure::Run(format!("cannot write {}: {e}", path.display())))?;
    }
    if let Some(path) = &args.plot {
        if plot::load_font() == plot::Text::Omitted && !args.quiet {
            eprintln!(
                "note: no font found ({} or ${}); the plot has no text",
                plot::FONT_PATHS[0],
                plot::FONT_ENV
            );
        }
        plot::write_plot(&scene, &run.trace, path).map_err(Failure::Run)?;
    }
    if !args.quiet {
        println!("{summary}");
    }
    Ok(())
}

/// Fail before the run, not after it, when an output cannot be written.
fn check_writable(path: &Path) -> Result<(), Failure> {
    let parent = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let cannot = |why: String| {
        Err(Failure::Run(format!(
            "cannot write {}: {why}",
            path.display()
        )))
    };
    if path.is_dir() {
        cannot("it is a directory".to_string())
    } else if !parent.is_dir() {
        cannot(format!("{} is not a directory", parent.display()))
    } else {
        Ok(())
    }
}

fn write_csv(run: &Run, path: &Path) -> Result<(), Failure> {
    let cannot = |e: std::io::Error| Failure::Run(format!("cannot write {}: {e}", path.display()));
    let file = File::create(path).map_err(cannot)?;
    csv::write_csv(&run.trace, file).map_err(cannot)
}
