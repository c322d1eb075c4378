//! `guideway sweep SCENE --speeds START:STOP:STEP [--unit km/h]
//! [--trains hslm|NAME,...] [--out CSV] [--plot PNG] [--threads N]
//! [--track ballasted|slab]`: the
//! scene's moving forces, or HSLM trains, or its vehicles, at every speed;
//! the envelope as CSV and a plot.

use std::time::Instant;

use super::{check_outputs, load_scene_with_inputs, Failure, SweepArgs};
use guideway::moving_load::{hslm, HSLM_TRAINS};
use guideway::study::sweep::{envelope_csv, parse_speeds, sweep, Loads, SpeedUnit};
use guideway::study::sweep_plot::{write_sweep_plot, Track};

pub(super) fn run_sweep(args: SweepArgs) -> Result<(), Failure> {
    let unit = SpeedUnit::parse(&args.unit).map_err(Failure::Usage)?;
    let track = Track::parse(&args.track).map_err(Failure::Usage)?;
    let speeds = parse_speeds(&args.speeds).map_err(Failure::Usage)?;
    let loads = parse_trains(args.trains.as_deref()).map_err(Failure::Usage)?;
    let (scene, inputs) = load_scene_with_inputs(&args.scene)?;
    let mut outputs = vec![("--out", args.out.as_path())];
    if let Some(plot) = &args.plot {
        outputs.push(("--plot", plot.as_path()));
    }
    check_outputs(&inputs, &outputs)?;
    let threads = args.threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let started = Instant::now();
    let rows =
        sweep(&scene, &loads, (&speeds, unit), threads, args.max_steps).map_err(Failure::Scene)?;
    let elapsed = started.elapsed().as_secs_f64();
    write_whole(&args.out, &envelope_csv(&rows, unit))?;
    if let Some(plot) = &args.plot {
        let title = format!("{}: speed sweep", scene.name);
        write_sweep_plot(&title, &rows, unit, track, plot).map_err(Failure::Run)?;
    }
    let worst = rows
        .iter()
        .max_by(|a, b| a.peak_acceleration.total_cmp(&b.peak_acceleration));
    println!(
        "{} runs ({} speeds) on {threads} threads in {elapsed:.2} s; envelope: {}",
        rows.len(),
        speeds.len(),
        args.out.display()
    );
    if let Some(w) = worst {
        println!(
            "largest deck acceleration {:.3} m/s² ({} at {} {}), DAF there {:.3}",
            w.peak_acceleration,
            w.train,
            w.speed,
            unit.label(),
            w.daf
        );
        let limit = track.limit();
        let above = rows.iter().filter(|r| r.peak_acceleration > limit).count();
        println!(
            "{above} of {} runs above the deck acceleration limit of {limit} m/s² ({}, EN 1990 A2)",
            rows.len(),
            track.label()
        );
    }
    if let Some(plot) = &args.plot {
        println!("plot: {}", plot.display());
    }
    Ok(())
}

/// `hslm` (all ten), a comma list of HSLM train names, or none (the scene's
/// own forces).
fn parse_trains(text: Option<&str>) -> Result<Loads, String> {
    match text {
        None => Ok(Loads::Scene),
        Some(t) if t.eq_ignore_ascii_case("hslm") => Ok(Loads::Trains(HSLM_TRAINS.to_vec())),
        Some(t) => t
            .split(',')
            .map(|name| {
                hslm(name.trim()).ok_or_else(|| {
                    format!("--trains: {name:?} is not a train; want hslm or HSLM-A1 … HSLM-A10")
                })
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Loads::Trains),
    }
}

/// Write `text` to `path` whole or not at all (a temporary file beside it,
/// renamed onto it).
fn write_whole(path: &std::path::Path, text: &str) -> Result<(), Failure> {
    use std::io::Write as _;
    let fail = |e: &dyn std::fmt::Display| Failure::Run(format!("{}: {e}", path.display()));
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    let mut file = tempfile::NamedTempFile::new_in(dir).map_err(|e| fail(&e))?;
    file.write_all(text.as_bytes()).map_err(|e| fail(&e))?;
    file.persist(path).map_err(|e| fail(&e))?;
    Ok(())
}
