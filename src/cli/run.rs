//! `guideway run SCENE [--out CSV] [--summary JSON] [--plot PNG] [--nodes CSV] [--max-steps N]
//! [--quiet]`.
//!
//! The rows go to the CSV as they are computed (memory does not grow with
//! the run); the summary and the plot are built alongside, the plot from
//! a thinned copy of the rows. Every output is staged beside its path and
//! renamed onto it only when the run succeeded.

use super::progress::Progress;
use super::{check_outputs, error, interrupt, load_scene_with_inputs, Failure, Inputs, RunArgs};
use guideway::design::StaticEnvelope;
use guideway::output_file::Staged;
use guideway::report::csv::CsvWriter;
use guideway::report::exits::{self, ExitWatch, VehicleExit};
use guideway::report::nodes::{check_node_output, WithNodes};
use guideway::report::{
    check_run_length, drive_into, plot, Decimated, RowSink, RunSummary, StreamError, Streamed,
    SummaryBuilder, SummaryEvent, Trace,
};
use guideway::simulation::Simulation;
use guideway::study::refine::{Refinement, StepChoice, Study};
use guideway::Scene;
use std::fs::File;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

/// Values (rows × outputs) kept for the plot: between this and twice this,
/// so that 10 000 sensors do not take gigabytes. With the paper's 21
/// outputs that is about 50 000 rows, more than a plot has pixels.
const PLOT_VALUES: usize = 1_000_000;

/// The staged output files of a run, created before it starts.
pub(super) struct Outputs {
    pub csv: Option<Staged>,
    pub summary: Option<Staged>,
    pub plot: Option<Staged>,
    pub nodes: Option<Staged>,
}

impl Outputs {
    /// Each output file asked for, staged beside its path.
    pub fn stage(args: &RunArgs) -> Result<Outputs, Failure> {
        let stage = |path: &Option<PathBuf>| {
            let staged = path.as_deref().map(Staged::new).transpose();
            staged.map_err(Failure::Run)
        };
        Ok(Outputs {
            csv: stage(&args.out)?,
            summary: stage(&args.summary)?,
            plot: stage(&args.plot)?,
            nodes: stage(&args.nodes)?,
        })
    }
}

pub(super) fn run(args: RunArgs) -> Result<(), Failure> {
    let (mut scene, inputs) = load_scene_with_inputs(&args.scene)?;
    check_paths(&args, &inputs)?;
    if guideway::moving_load::is_moving_force_scene(&scene) {
        return super::run_forces::run(&args, &scene);
    }
    let choice = choose_step(&args, &mut scene)?;
    let interrupted = interrupt::install();
    let outputs = Outputs::stage(&args)?;

    let mut simulation = open_simulation(&scene, &args, &outputs)?;
    let pending = choice.or_else(|| {
        let choice = simulation.integrator_choice();
        let start = |r| error::start(&scene, r, choice, args.max_steps);
        args.error.map(start)
    });
    let mut sink = Sink::new(&scene, simulation.outputs(), &outputs)?;
    let vehicles = exits::vehicle_names(&scene);
    if outputs.csv.is_none() && outputs.plot.is_none() {
        let summary = !args.quiet || outputs.summary.is_some() || pending.is_some();
        read_only_what_is_read(&mut simulation, &sink, &scene, &vehicles, summary);
    }
    let mut progress = Progress::new(args.quiet);
    let on_step = progress.on_step(&interrupted);
    let (result, exits) = match &outputs.nodes {
        None => {
            let mut watch = ExitWatch::new(&mut simulation, &vehicles);
            let result = drive_into(&scene, &mut watch, &mut sink, on_step);
            (result, watch.finish())
        }
        Some(staged) => drive_with_nodes(&scene, &mut simulation, &mut sink, staged, on_step)?,
    };
    progress.finish();
    match result {
        Ok(streamed) => {
            let integrator = simulation.integrator_choice().to_string();
            let events = SummaryEvent::list(&simulation);
            let run = (integrator, events, exits);
            let envelope =
                |scene: &Scene| guideway::design::envelope_of_run(&simulation, scene).ok();
            let finished = (&streamed, run, envelope);
            let quiet = args.quiet;
            if let Some((summary, study)) = finish(sink, outputs, finished, &scene, quiet, pending)?
            {
                if !quiet {
                    println!("{summary}");
                    if let Some((study, choice)) = &study {
                        error::print(study, choice.as_ref());
                    }
                }
            }
            Ok(())
        }
        Err(error) => Err(failed(error, sink, outputs.csv, &scene)),
    }
}

/// The scene's simulation, refused with the reason when it cannot run or
/// its run would exceed the step bound; its frequencies and advice
/// printed unless quiet.
fn open_simulation(
    scene: &Scene,
    args: &RunArgs,
    outputs: &Outputs,
) -> Result<Simulation, Failure> {
    let cannot_simulate =
        |m: String| Failure::Scene(format!("scene `{}` cannot be simulated: {m}", scene.name));
    let simulation = Simulation::new(scene).map_err(cannot_simulate)?;
    let steps = check_run_length(scene, args.max_steps, " (--max-steps N raises it)")
        .map_err(cannot_simulate)?;
    if outputs.nodes.is_some() {
        let nodes = simulation.system().beam.node_x.len();
        check_node_output(steps + 1, nodes).map_err(Failure::Usage)?;
    }

    if !args.quiet {
        println!("{}", frequencies_line(&simulation.system().beam));
        for advice in guideway::scene::advisories(scene) {
            eprintln!("note: {advice}");
        }
    }
    Ok(simulation)
}

/// Evaluate only the columns the summary, the sink and the exit watch read
/// (a run with no CSV and no plot).
fn read_only_what_is_read(
    simulation: &mut Simulation,
    sink: &Sink,
    scene: &Scene,
    vehicles: &[String],
    summary: bool,
) {
    let mut read = read_columns(sink, simulation.outputs(), scene, summary);
    for k in exits::exit_columns(simulation, vehicles) {
        read[k] = true;
    }
    simulation.read_only(Some(&read));
}

/// `drive_into` with every node written to `staged` after each row (the
/// file is kept only when the run finishes).
fn drive_with_nodes(
    scene: &Scene,
    simulation: &mut Simulation,
    sink: &mut Sink,
    staged: &Staged,
    on_step: impl FnMut(guideway::report::StepProgress) -> ControlFlow<()>,
) -> Result<(Result<Streamed, StreamError>, Vec<VehicleExit>), Failure> {
    let cannot = |e: &dyn std::fmt::Display| {
        Failure::Run(format!("cannot write {}: {e}", staged.path().display()))
    };
    let file = staged.file().map_err(Failure::Run)?;
    let mut with_nodes = WithNodes::new(simulation, file).map_err(|e| cannot(&e))?;
    let mut watch = ExitWatch::new(&mut with_nodes, &exits::vehicle_names(scene));
    let result = drive_into(scene, &mut watch, sink, on_step);
    let exits = watch.finish();
    let file = with_nodes.finish().map_err(|e| cannot(&e))?;
    file.sync_all().map_err(|e| cannot(&e))?;
    Ok((result, exits))
}

/// Write what a finished run produced and move each file onto its path;
/// the summary to print, unless quiet.
pub(super) fn finish(
    mut sink: Sink,
    outputs: Outputs,
    (streamed, (integrator, events, exits), envelope): (
        &Streamed,
        (String, Vec<SummaryEvent>, Vec<VehicleExit>),
        impl FnOnce(&Scene) -> Option<StaticEnvelope>,
    ),
    scene: &Scene,
    quiet: bool,
    pending: Option<error::Pending>,
) -> Result<Option<Finished>, Failure> {
    if let Some(csv) = outputs.csv {
        sink.finish_csv()?;
        csv.commit().map_err(Failure::Run)?;
    }
    if let Some(nodes) = outputs.nodes {
        nodes.commit().map_err(Failure::Run)?;
    }
    // Not built when nobody reads it (its static envelope is not free).
    let summary = (!quiet || outputs.summary.is_some() || pending.is_some()).then(|| {
        let mut summary = sink.summary.finish_with(
            streamed.exit_time,
            streamed.solve_time.as_secs_f64(),
            envelope,
        );
        summary.integrator = Some(integrator);
        summary.events = events;
        summary.set_vehicles(exits);
        summary
    });
    let study = match (pending, &summary) {
        (Some(pending), Some(summary)) => Some(error::finish(pending, scene, summary)?),
        _ => None,
    };
    if let (Some(staged), Some(summary)) = (outputs.summary, &summary) {
        std::fs::write(
            staged.temp_path(),
            summary_json(summary, study.as_ref()) + "\n",
        )
        .map_err(|e| Failure::Run(format!("cannot write {}: {e}", staged.path().display())))?;
        staged.commit().map_err(Failure::Run)?;
    }
    if let (Some(staged), Some(trace)) = (outputs.plot, sink.plot.map(Decimated::finish)) {
        if plot::load_font() == plot::Text::Omitted && !quiet {
            eprintln!(
                "note: no font found ({} or ${}); the plot has no text",
                plot::FONT_PATHS[0],
                plot::FONT_ENV
            );
        }
        plot::write_plot(scene, &trace, staged.temp_path()).map_err(Failure::Run)?;
        staged.commit().map_err(Failure::Run)?;
    }
    Ok(summary.map(|summary| (summary, study)))
}

/// The summary and, when estimated, its errors.
pub(super) type Finished = (RunSummary, Option<(Study, Option<StepChoice>)>);

/// The summary JSON, with `error_estimate` when the error was estimated
/// (added after the summary's own entries, which stay as they were).
fn summary_json(summary: &RunSummary, study: Option<&(Study, Option<StepChoice>)>) -> String {
    let Some((study, choice)) = study else {
        return summary.to_json();
    };
    let mut json = serde_json::to_value(summary).expect("a summary always serialises to JSON");
    json["error_estimate"] = error::to_json(study, choice.as_ref());
    serde_json::to_string_pretty(&json).expect("JSON values serialise")
}

/// With a tolerance, the step (with `--error mesh` the elements) chosen for
/// it (set in `scene`) and its study.
fn choose_step(args: &RunArgs, scene: &mut Scene) -> Result<Option<error::Pending>, Failure> {
    let Some(rtol) = tolerance(args, scene)? else {
        return Ok(None);
    };
    let refinement = args.error.unwrap_or(Refinement::Time);
    let choice = error::choose(scene, refinement, rtol, args.max_steps, args.quiet)?;
    scene.solver.step = choice.step;
    scene.beam.elements = choice.elements;
    Ok(Some(error::Pending::Chosen(Box::new(choice))))
}

/// The relative tolerance asked for: --rtol, else solver.tolerance;
/// refused unless in (0, 1).
fn tolerance(args: &RunArgs, scene: &Scene) -> Result<Option<f64>, Failure> {
    match args.rtol {
        Some(rtol) if !(rtol > 0.0 && rtol < 1.0) => Err(Failure::Usage(format!(
            "--rtol {rtol}: must be a relative error in (0, 1)"
        ))),
        Some(rtol) => Ok(Some(rtol)),
        None => Ok(scene.solver.tolerance),
    }
}

/// Natural frequencies printed before a run.
const FREQUENCIES_SHOWN: usize = 5;

/// The beam's first natural frequencies in one line, or where to get them:
/// beyond `MAX_MODE_DOFS` free DOFs the subspace iteration would add a
/// noticeable wait before every run.
pub(super) fn frequencies_line(beam: &guideway::beam::Beam) -> String {
    let shown = if beam.free_dofs() <= guideway::beam::MAX_MODE_DOFS {
        beam.modes(FREQUENCIES_SHOWN)
    } else {
        Err(format!("the beam has {} free DOFs", beam.free_dofs()))
    };
    match shown {
        Ok(modes) => {
            let hz: Vec<String> = modes
                .omega
                .iter()
                .map(|w| format!("{:.4}", w / std::f64::consts::TAU))
                .collect();
            format!(
                "frequencies (Hz)   {} (guideway modes for more)",
                hz.join(", ")
            )
        }
        Err(why) => format!("frequencies        - ({why}; guideway modes SCENE computes them)"),
    }
}

/// Refuse outputs that would overwrite an input file or each other.
fn check_paths(args: &RunArgs, inputs: &Inputs) -> Result<(), Failure> {
    let outputs: Vec<(&str, &Path)> = [
        ("--out", &args.out),
        ("--summary", &args.summary),
        ("--plot", &args.plot),
        ("--nodes", &args.nodes),
    ]
    .into_iter()
    .filter_map(|(what, path)| Some((what, path.as_deref()?)))
    .collect();
    check_outputs(inputs, &outputs)
}

/// The message and exit code of a run that did not finish; the CSV rows
/// written so far are kept as `<out>.incomplete`.
pub(super) fn failed(
    error: StreamError,
    mut sink: Sink,
    csv: Option<Staged>,
    scene: &Scene,
) -> Failure {
    type Exit = fn(String) -> Failure;
    let (mut message, steps, exit): (String, u64, Exit) = match error {
        StreamError::Refused(m) => {
            return Failure::Scene(format!("scene `{}` cannot be simulated: {m}", scene.name))
        }
        StreamError::Output { message, .. } => return Failure::Run(message),
        StreamError::Solver { error, steps } => {
            (format!("the solver failed {error}"), steps, Failure::Run)
        }
        StreamError::Interrupted { time, steps } => (
            format!("interrupted (Ctrl-C) at t = {time} s"),
            steps,
            Failure::Interrupted,
        ),
    };
    if let Some(csv) = csv {
        let out = csv.path().to_path_buf();
        let kept = sink
            .finish_csv()
            .map_err(Failure::into_message)
            .and_then(|()| csv.commit_as(&incomplete_path(&out)));
        match kept {
            Ok(path) => message.push_str(&format!(
                "\n(the initial state and the {steps} steps before it are in {}, marked \
                 incomplete by its name; {} was left as it was)",
                path.display(),
                out.display()
            )),
            Err(e) => message.push_str(&format!("\n{e}")),
        }
    }
    exit(message)
}

/// `<out>.incomplete`: where the rows of a run that did not finish go.
fn incomplete_path(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".incomplete");
    PathBuf::from(name)
}

/// The columns read when no file takes every row: the summary's (if it is
/// built) and the travel position the progress bar follows.
fn read_columns(
    sink: &Sink,
    outputs: &[guideway::simulation::OutputInfo],
    scene: &Scene,
    summary: bool,
) -> Vec<bool> {
    let names: Vec<String> = outputs.iter().map(|o| o.name.clone()).collect();
    let mut read = vec![false; names.len()];
    let position = guideway::report::progress_column(scene, &names);
    let summary_columns = if summary {
        sink.summary.columns()
    } else {
        Vec::new()
    };
    for k in position.into_iter().chain(summary_columns) {
        read[k] = true;
    }
    read
}

/// Every row goes to the CSV (if asked), the summary and the plot's
/// thinned copy (if asked).
pub(super) struct Sink {
    csv: Option<(CsvWriter<File>, PathBuf)>,
    summary: SummaryBuilder,
    plot: Option<Decimated>,
}

impl Sink {
    pub fn new(
        scene: &Scene,
        names: &[guideway::simulation::OutputInfo],
        outputs: &Outputs,
    ) -> Result<Sink, Failure> {
        let trace = Trace::for_outputs(names);
        let csv = match &outputs.csv {
            None => None,
            Some(staged) => {
                let cannot = |e: String| {
                    Failure::Run(format!("cannot write {}: {e}", staged.path().display()))
                };
                let file = staged.file().map_err(Failure::Run)?;
                let writer = CsvWriter::new(file, &trace.names, &trace.kinds)
                    .map_err(|e| cannot(e.to_string()))?;
                Some((writer, staged.path().to_path_buf()))
            }
        };
        Ok(Sink {
            csv,
            summary: SummaryBuilder::new(scene, &trace.names),
            plot: outputs.plot.as_ref().map(|_| {
                let rows = PLOT_VALUES / (trace.names.len() + 1);
                Decimated::new(trace, rows)
            }),
        })
    }

    /// Flush the CSV to its staged file.
    fn finish_csv(&mut self) -> Result<(), Failure> {
        match self.csv.take() {
            None => Ok(()),
            Some((writer, path)) => writer
                .finish()
                .and_then(|file| file.sync_all())
                .map_err(|e| Failure::Run(format!("cannot write {}: {e}", path.display()))),
        }
    }
}

impl RowSink for Sink {
    fn row(&mut self, time: f64, values: &[f64]) -> Result<(), String> {
        if let Some((writer, path)) = &mut self.csv {
            writer
                .row(time, values)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        self.summary.push(time, values);
        if let Some(plot) = &mut self.plot {
            plot.push(time, values);
        }
        Ok(())
    }
}
