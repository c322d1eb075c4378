//! `guideway work-precision`: measure error against run time.

use super::{Failure, WorkPrecisionArgs};
use guideway::study::work_precision::{cases, measure, measure_modal, reference, to_csv};

pub fn work_precision(args: WorkPrecisionArgs) -> Result<(), Failure> {
    let mut points = Vec::new();
    for case in cases(args.quick) {
        eprintln!(
            "{}: reference from RK4 at {:.3e} s (or the largest stable half of it) and half that",
            case.name, case.reference_step
        );
        let reference =
            reference(&case).map_err(|e| Failure::Run(format!("{}: {e}", case.name)))?;
        eprintln!(
            "  exit V = {:.10} m/s (fine runs differ by {:.1e} m/s; deflection RMS by {:.1e} of static)",
            reference.exit_speed, reference.exit_speed_spread, reference.deflection_spread
        );
        let report = |p: &guideway::study::work_precision::Point| match &p.failure {
            None => eprintln!(
                "  {:8} dt {:.3e} tol {:.0e}: |ΔV| {:.2e}  rms {:.2e}  drift {:.2e}  {:.2e} s",
                p.scheme,
                p.step,
                p.velocity_tolerance,
                p.exit_speed_error,
                p.rms_deflection_error,
                p.max_energy_drift,
                p.wall_time_s
            ),
            Some(why) => eprintln!("  {:8} dt {:.3e}: {why}", p.scheme, p.step),
        };
        let modal = measure_modal(&case, &reference, args.repeats, report);
        if !args.modal_only {
            points.extend(measure(&case, &reference, args.repeats, report));
        }
        points.extend(modal);
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Run(format!("cannot create {}: {e}", dir.display())))?;
    }
    std::fs::write(&args.out, to_csv(&points))
        .map_err(|e| Failure::Run(format!("cannot write {}: {e}", args.out.display())))?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}
