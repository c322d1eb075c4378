//! The `guideway` command line (binary only; the library does the work).
//!
//! Exit codes: 0 success, 1 the run or an output file failed, 2 bad command
//! line or bad scene (every problem listed on stderr), 130 interrupted by
//! Ctrl-C.

mod check;
mod converge;
mod error;
mod export;
mod interrupt;
mod modes;
mod progress;
mod release;
mod run;
mod run_forces;
mod scenes;
mod sweep;
mod work_precision;

use clap::{Parser, Subcommand};
use guideway::report::DEFAULT_MAX_STEPS;
use guideway::scene::{SceneError, DEFAULT_SCENE};
use guideway::Scene;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "guideway",
    version,
    about = "Simulate vehicles and moving forces crossing flexible bridges and guideways (Lee 1994); export them as FMUs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scene until its last contact (or moving force) leaves the
    /// beam (or to `solver.end_time`); write CSV, summary, plot.
    Run(RunArgs),
    /// List the built-in scenes, or print one as a TOML scene file.
    Scenes(ScenesArgs),
    /// Print the beam's lowest natural frequencies; write the mode shapes
    /// as CSV with `--out`.
    Modes(ModesArgs),
    /// Export a scene as an FMI 2.0 co-simulation FMU.
    Export(ExportArgs),
    /// Run a moving-force scene (or every HSLM train), or a vehicle scene,
    /// at every speed of a range, in parallel; write the envelope (peak deck deflection and
    /// acceleration, DAF) as CSV and a plot.
    Sweep(SweepArgs),
    /// Dynamic check of a railway bridge (EN 1991-2 §6.4, EN 1990 A2)
    /// from a short description: every case run, a self-contained HTML
    /// report with the PASS/FAIL table, CSVs and JSON.
    Check(CheckArgs),
    /// Error against run time of every integrator on the paper's cases
    /// (CSV for `scripts/work_precision.py`).
    WorkPrecision(WorkPrecisionArgs),
    /// A scene's summary figures at a ladder of halved steps (or doubled
    /// elements): observed orders, errors against the extrapolated values,
    /// the cost of each run; a table, a CSV and a plot.
    Converge(ConvergeArgs),
    /// Build the release of this version: the FMUs of the paper's built-in
    /// scenes, cross-check files, release notes and checksums in
    /// `<out>/<version>/`.
    Release(ReleaseArgs),
}

#[derive(Debug, clap::Args)]
struct WorkPrecisionArgs {
    /// Where to write the points.
    #[arg(
        long,
        short,
        value_name = "CSV",
        default_value = "report/work_precision.csv"
    )]
    out: PathBuf,
    /// Runs per point; the wall time is their median.
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Fewer steps and a coarser reference (for tests).
    #[arg(long)]
    quick: bool,
    /// Only the modal structures' points (and the references they need).
    #[arg(long)]
    modal_only: bool,
}

#[derive(Debug, clap::Args)]
struct RunArgs {
    /// Scene file (TOML) or name of a built-in scene (see `guideway scenes`).
    #[arg(default_value = DEFAULT_SCENE)]
    scene: String,
    /// Write every output at every internal step to this CSV file.
    #[arg(long, short, value_name = "CSV")]
    out: Option<PathBuf>,
    /// Write the run's figures (exit time and speed, peaks, energy drift,
    /// steps, iterations, wall time) to this JSON file.
    #[arg(long, value_name = "JSON")]
    summary: Option<PathBuf>,
    /// Draw the run to this PNG: nominal speed, sensor deflection, contact
    /// forces and sprung accelerations (vehicles), track irregularity,
    /// energy drift; for moving forces deflection, acceleration and
    /// section moments against time.
    #[arg(long, value_name = "PNG")]
    plot: Option<PathBuf>,
    /// Write every node's deflection and acceleration at every internal
    /// step to this CSV file (refused beyond 5e7 rows × nodes).
    #[arg(long, value_name = "CSV")]
    nodes: Option<PathBuf>,
    /// Refuse, before running, a run that needs more internal steps than
    /// this (the time a step takes grows with beam.elements).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STEPS)]
    max_steps: u64,
    /// No progress bar, no summary on the terminal; errors only.
    #[arg(long, short)]
    quiet: bool,
    /// Estimate the discretisation error of every summary figure by
    /// companion runs at twice and half the step (`time`, the default) or
    /// half and twice the elements (`mesh`); printed as value ± error and
    /// written to the --summary JSON (docs/error-estimates.md).
    #[arg(long, value_name = "time|mesh", num_args = 0..=1, default_missing_value = "time")]
    error: Option<guideway::study::refine::Refinement>,
    /// Choose the step (with --error mesh: the elements) so that the
    /// estimated error of every summary figure is within this relative
    /// tolerance (overrides solver.tolerance).
    #[arg(long, value_name = "RTOL")]
    rtol: Option<f64>,
}

#[derive(Debug, clap::Args)]
struct ConvergeArgs {
    /// Scene file (TOML) or name of a built-in scene.
    scene: String,
    /// Runs of the ladder: the scene's step, then halved each time.
    #[arg(long, default_value_t = 5)]
    rungs: usize,
    /// Double the elements in place of halving the step.
    #[arg(long)]
    mesh: bool,
    /// Every figure at every run.
    #[arg(long, short, value_name = "CSV", default_value = "converge.csv")]
    out: PathBuf,
    /// Error against step (and solve time) to this PNG.
    #[arg(long, value_name = "PNG")]
    plot: Option<PathBuf>,
    /// Threads (default: the machine's cores).
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Refuse, before running, a ladder whose finest run needs more steps.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STEPS)]
    max_steps: u64,
}

#[derive(Debug, clap::Args)]
struct ModesArgs {
    /// Scene file or built-in scene name.
    scene: String,
    /// How many of the lowest modes.
    #[arg(long, default_value_t = 6)]
    count: usize,
    /// Write the mode shapes (deflection at every node, largest 1) here.
    #[arg(long, short, value_name = "CSV")]
    out: Option<PathBuf>,
}

#[derive(Debug, clap::Args)]
struct SweepArgs {
    /// Scene file: moving forces (kind = "moving_force"), or vehicles, whose
    /// speeds the sweep sets (docs/vehicles.md).
    scene: String,
    /// Speeds START:STOP:STEP (inclusive), e.g. 100:400:5, or one speed.
    #[arg(long, value_name = "START:STOP:STEP", allow_hyphen_values = true)]
    speeds: String,
    /// Unit of --speeds: m/s or km/h.
    #[arg(long, default_value = "m/s")]
    unit: String,
    /// `hslm` (HSLM-A1 … A10 in place of the scene's forces) or a comma
    /// list of HSLM train names; the scene's own forces when left out.
    #[arg(long, value_name = "hslm|NAMES")]
    trains: Option<String>,
    /// The envelope, one row per train and speed.
    #[arg(long, short, value_name = "CSV", default_value = "sweep.csv")]
    out: PathBuf,
    /// Plot peak deck acceleration and DAF against speed to this PNG.
    #[arg(long, value_name = "PNG")]
    plot: Option<PathBuf>,
    /// Threads (default: the machine's cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(usize))]
    threads: Option<usize>,
    /// The track on the deck, which sets the deck acceleration limit of
    /// EN 1990 A2.4.4.2.1: ballasted (3.5 m/s²) or slab (5 m/s²).
    #[arg(long, value_name = "ballasted|slab", default_value = "ballasted")]
    track: String,
    /// Refuse, before running, a sweep of more steps than this in all.
    #[arg(long, value_name = "N", default_value_t = guideway::study::sweep::DEFAULT_MAX_SWEEP_STEPS)]
    max_steps: u64,
}

#[derive(Debug, clap::Args)]
struct CheckArgs {
    /// Bridge description (TOML), or `bridge20` for the built-in example.
    bridge: String,
    /// Directory for report.html, runs.csv, checks.csv, check.json and the
    /// plots.
    #[arg(long, short, value_name = "DIR", default_value = "check-report")]
    out: PathBuf,
    /// Threads (default: the machine's cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(usize))]
    threads: Option<usize>,
}

#[derive(Debug, clap::Args)]
struct ScenesArgs {
    /// Print this scene (built-in name or file) as TOML, ready to edit
    /// (the same as `--show NAME`, as `run` and `export` take their scene).
    #[arg(value_name = "NAME", conflicts_with = "show")]
    name: Option<String>,
    /// Print this scene (built-in name or file) as TOML, ready to edit.
    #[arg(long, value_name = "NAME")]
    show: Option<String>,
}

#[derive(Debug, clap::Args)]
struct ExportArgs {
    /// Scene file (TOML) or name of a built-in scene (see `guideway scenes`).
    #[arg(default_value = DEFAULT_SCENE)]
    scene: String,
    /// The FMU to write, e.g. `lee1994_wheel_10.fmu`.
    #[arg(long, short, value_name = "FMU")]
    out: PathBuf,
    /// The FMI standard the FMU follows: 2 (FMI 2.0) or 3 (FMI 3.0); both
    /// co-simulation, from the same scene and variables.
    #[arg(long, value_name = "VERSION", default_value = "2", value_parser = ["2", "3"])]
    fmi: String,
    /// Also write the FMI cross-check reference files (`<model>_ref.csv`,
    /// `<model>_ref.opt`) into this directory.
    #[arg(long, value_name = "DIR")]
    cross_check: Option<PathBuf>,
    /// Also write an SSP system of this FMU (component `guideway`) and the
    /// `--vehicle` FMU (component `vehicle`), wired by `--connect`.
    #[arg(long, value_name = "SSP", requires = "vehicle")]
    ssp: Option<PathBuf>,
    /// The SSP standard of the `--ssp` system: 1 (SSP 1.0, which every
    /// tested master reads) or 2 (SSP 2.0, `Float64` connectors for FMI 3.0).
    #[arg(long, value_name = "VERSION", default_value = "1", value_parser = ["1", "2"], requires = "ssp")]
    ssp_version: String,
    /// The vehicle FMU of the `--ssp` system.
    #[arg(long, value_name = "FMU", requires = "ssp")]
    vehicle: Option<PathBuf>,
    /// A connection of the `--ssp` system, from an output to an input:
    /// `vehicle.force=guideway.wheel.force_y` (repeatable).
    #[arg(long = "connect", value_name = "FROM=TO", requires = "ssp")]
    connect: Vec<guideway::fmu::ssp::Connection>,
}

#[derive(Debug, clap::Args)]
struct ReleaseArgs {
    /// Directory receiving `<version>/`.
    #[arg(long, short, value_name = "DIR", default_value = "dist")]
    out: PathBuf,
    /// The Keep-a-Changelog file whose section for this version becomes the
    /// release notes.
    #[arg(long, value_name = "FILE", default_value = "CHANGELOG.md")]
    changelog: PathBuf,
    /// Replace `<out>/<version>/` if it exists (otherwise refused).
    #[arg(long)]
    replace: bool,
}

/// How a command failed, deciding the exit code (docs/cli.md, exit codes).
enum Failure {
    /// The scene (or what it asks for) is wrong: exit code 2.
    Scene(String),
    /// The command line is wrong (e.g. an output that would overwrite an
    /// input): exit code 2.
    Usage(String),
    /// The run or writing its outputs failed: exit code 1.
    Run(String),
    /// Ctrl-C: exit code 130.
    Interrupted(String),
}

impl Failure {
    fn into_message(self) -> String {
        match self {
            Failure::Scene(m) | Failure::Usage(m) | Failure::Run(m) | Failure::Interrupted(m) => m,
        }
    }
}

/// Load a scene file or built-in; a scene file's problems are prefixed with
/// its name.
fn load_scene(file_or_builtin: &str) -> Result<Scene, Failure> {
    Scene::load(file_or_builtin).map_err(|error| match error {
        SceneError::Parse { .. } | SceneError::Invalid { .. } | SceneError::TooLarge { .. } => {
            Failure::Scene(format!("{file_or_builtin}: {error}"))
        }
        SceneError::Read { .. } | SceneError::NotFound { .. } => Failure::Scene(error.to_string()),
    })
}

/// `load_scene`, and the files it read (the scene file, its table files),
/// each named by what it is.
fn load_scene_with_inputs(file_or_builtin: &str) -> Result<(Scene, Inputs), Failure> {
    let (scene, files) = Scene::load_with_inputs(file_or_builtin).map_err(|error| match error {
        SceneError::Parse { .. } | SceneError::Invalid { .. } | SceneError::TooLarge { .. } => {
            Failure::Scene(format!("{file_or_builtin}: {error}"))
        }
        SceneError::Read { .. } | SceneError::NotFound { .. } => Failure::Scene(error.to_string()),
    })?;
    let inputs = files
        .into_iter()
        .enumerate()
        .map(|(k, path)| (if k == 0 { "scene file" } else { "table file" }, path))
        .collect();
    Ok((scene, inputs))
}

/// The input files of a command, each with what it is.
type Inputs = Vec<(&'static str, PathBuf)>;

/// The one rule for every command: no output may be one of the command's
/// input files (by file identity: device and inode, through links and
/// other spellings), nor another output.
fn check_outputs(inputs: &Inputs, outputs: &[(&str, &std::path::Path)]) -> Result<(), Failure> {
    let inputs: Vec<(&str, &std::path::Path)> = inputs
        .iter()
        .map(|(what, p)| (*what, p.as_path()))
        .collect();
    guideway::output_file::check_distinct(&inputs, outputs).map_err(Failure::Usage)
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::run(args),
        Command::Scenes(args) => scenes::scenes(args),
        Command::Modes(args) => modes::modes(args),
        Command::Export(args) => export::export(args),
        Command::Sweep(args) => sweep::run_sweep(args),
        Command::Check(args) => check::run_check(args),
        Command::WorkPrecision(args) => work_precision::work_precision(args),
        Command::Release(args) => release::release(args),
        Command::Converge(args) => converge::run_converge(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Scene(message) | Failure::Usage(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
        Err(Failure::Run(message)) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
        Err(Failure::Interrupted(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(interrupt::EXIT_INTERRUPTED)
        }
    }
}
