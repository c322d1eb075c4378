//! `guideway run` of a moving-force scene: the crossing (`ForceRun`)
//! streamed to the same sinks as any run (CSV, summary, plot), to the last
//! axle's exit or on to `solver.end_time` (the free vibration); the summary
//! names each vehicle's first and last axle's entry and exit.

use super::progress::Progress;
use super::run::{failed, finish, frequencies_line, Outputs, Sink};
use super::{interrupt, Failure, RunArgs};
use guideway::moving_load::ForceRun;
use guideway::report::exits::VehicleExit;
use guideway::report::{check_run_length, drive_into, SummaryEvent};
use guideway::Scene;

/// What `guideway run` offers for vehicles but not for moving forces, and
/// why.
fn refuse_options(args: &RunArgs, scene: &Scene) -> Result<(), Failure> {
    let refused = |option: &str, why: &str| {
        Failure::Usage(format!(
            "{option} is not available for moving forces (body.kind = \"moving_force\"): {why}"
        ))
    };
    if args.nodes.is_some() {
        return Err(refused(
            "--nodes",
            "the node file is written for vehicle runs only",
        ));
    }
    if args.error.is_some() || args.rtol.is_some() || scene.solver.tolerance.is_some() {
        return Err(refused(
            "--error, --rtol and solver.tolerance",
            "the error estimate's companion runs are vehicle runs; halve solver.step and \
             compare (`guideway sweep` at one speed runs the same crossing)",
        ));
    }
    Ok(())
}

pub(super) fn run(args: &RunArgs, scene: &Scene) -> Result<(), Failure> {
    refuse_options(args, scene)?;
    let cannot_simulate =
        |m: String| Failure::Scene(format!("scene `{}` cannot be simulated: {m}", scene.name));
    check_run_length(scene, args.max_steps, " (--max-steps N raises it)")
        .map_err(cannot_simulate)?;
    let mut forces = ForceRun::new(scene).map_err(cannot_simulate)?;
    let interrupted = interrupt::install();
    let outputs = Outputs::stage(args)?;
    if !args.quiet {
        println!("{}", frequencies_line(forces.beam()));
    }
    let mut sink = Sink::new(
        scene,
        guideway::report::Steppable::outputs(&forces),
        &outputs,
    )?;
    let mut progress = Progress::new(args.quiet);
    let on_step = progress.on_step(&interrupted);
    let result = drive_into(scene, &mut forces, &mut sink, on_step);
    progress.finish();
    match result {
        Ok(streamed) => {
            let integrator = "newmark (average acceleration; prescribed moving forces)";
            let run = (integrator.to_string(), events(&forces), exits(&forces));
            let envelope = |scene: &Scene| guideway::design::static_envelope(scene).ok();
            let finished = (&streamed, run, envelope);
            if let Some((summary, _)) = finish(sink, outputs, finished, scene, args.quiet, None)? {
                if !args.quiet {
                    println!("{summary}");
                }
            }
            Ok(())
        }
        Err(error) => Err(failed(error, sink, outputs.csv, scene)),
    }
}

/// The first and last axles' entries and exits, as the summary's events.
fn events(forces: &ForceRun) -> Vec<SummaryEvent> {
    forces
        .events()
        .into_iter()
        .map(|e| SummaryEvent {
            contact: e.axle,
            kind: e.kind.to_string(),
            time: e.time,
        })
        .collect()
}

/// Per vehicle, when its leading and its trailing axle left the beam
/// during the run, at the vehicle's (constant) speed.
fn exits(forces: &ForceRun) -> Vec<VehicleExit> {
    let length = forces.beam().length;
    let now = guideway::report::Steppable::time(forces);
    forces
        .vehicles()
        .iter()
        .map(|v| {
            let exit = |k: Option<usize>| {
                let axle = v.axles[k?];
                let time = guideway::moving_load::crossing_times(axle, length).1?;
                (time <= now).then_some((time, axle.speed.abs()))
            };
            let first = exit(Some(0));
            let last = exit(v.axles.len().checked_sub(1));
            VehicleExit {
                vehicle: v.name.clone(),
                contacts: v.axles.len(),
                first_exit_time: first.map(|f| f.0),
                first_exit_speed: first.map(|f| f.1),
                last_exit_time: last.map(|l| l.0),
                last_exit_speed: last.map(|l| l.1),
            }
        })
        .collect()
}
