//! Reference results following the FMI cross-check rules:
//! `<Model>_ref.opt` (StartTime, StopTime, StepSize, RelTol) and
//! `<Model>_ref.csv` (time, then every output, one row per step), computed by
//! the same model code the FMU runs.

use crate::model::experiment::default_stop_time;
use crate::model::{Dynamics, Model, StepOutcome, Value};
use crate::output_file::Staged;
use crate::report::DEFAULT_MAX_STEPS;
use crate::scene::Scene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Relative tolerance declared in the options file.
pub const REL_TOL: f64 = 1e-6;

/// Most rows of a reference result: the cross-check rules cap the CSV at
/// 1 MB, which a run past the exit at a fine step would pass (1.7 MB for
/// `lee1994-wheel-1`).
pub const MAX_REF_ROWS: f64 = 2000.0;

/// The reference's communication step: `solver.step`, or the smallest
/// multiple of it that keeps the rows within `MAX_REF_ROWS`.
pub fn ref_step(scene: &Scene) -> f64 {
    let h = scene.solver.step;
    let stride = (default_stop_time(scene) / h / MAX_REF_ROWS)
        .ceil()
        .max(1.0);
    if stride.is_finite() {
        stride * h
    } else {
        h
    }
}

/// The options file's text.
pub fn ref_opt(scene: &Scene) -> String {
    format!(
        "StartTime, {:?}\nStopTime, {:?}\nStepSize, {:?}\nRelTol, {:?}\n",
        0.0,
        default_stop_time(scene),
        ref_step(scene),
        REL_TOL
    )
}

/// Refuse a reference that would need more than `DEFAULT_MAX_STEPS` steps
/// to reach the default stop time.
pub fn check_length(scene: &Scene) -> Result<(), String> {
    let stop = default_stop_time(scene);
    let h = scene.solver.step;
    let steps = (stop / h).ceil();
    if steps.is_nan() || steps > DEFAULT_MAX_STEPS as f64 {
        return Err(format!(
            "the cross-check reference would need {steps:e} steps of solver.step = {h:e} s to \
             reach the default stop time {stop:e} s, more than the limit of {DEFAULT_MAX_STEPS}"
        ));
    }
    Ok(())
}

/// Simulate `scene` with communication steps of `solver.step` until the
/// default stop time or the exit, and return the CSV text.
pub fn ref_csv<D: Dynamics>(scene: &Scene) -> Result<String, String> {
    let mut model = Model::<D>::new(scene.clone()).map_err(|e| e.0)?;
    model.initialize().map_err(|e| e.0)?;
    let outputs: Vec<_> = model.table().outputs().cloned().collect();
    let mut csv = String::from("time");
    for v in &outputs {
        csv += ",";
        csv += &v.name;
    }
    csv += "\n";
    check_length(scene)?;
    let stop = default_stop_time(scene);
    let h = ref_step(scene);
    let mut row = |model: &mut Model<D>| -> Result<(), String> {
        write!(csv, "{:?}", model.time()).expect("write to String");
        for v in &outputs {
            let value = model.get(v.ty, &[v.value_reference]).map_err(|e| e.0)?[0];
            match value {
                Value::Real(x) => write!(csv, ",{x:?}"),
                Value::Integer(n) => write!(csv, ",{n}"),
                Value::Boolean(b) => write!(csv, ",{}", b as i32),
            }
            .expect("write to String");
        }
        csv += "\n";
        Ok(())
    };
    row(&mut model)?;
    let mut k = 0u64;
    loop {
        let t = k as f64 * h;
        if t >= stop - 1e-9 * h {
            break;
        }
        let step = (stop - t).min(h);
        match model.do_step(model.time(), step).map_err(|e| e.0)? {
            StepOutcome::Completed => row(&mut model)?,
            StepOutcome::Exited { .. } => {
                row(&mut model)?;
                break;
            }
            StepOutcome::Failed { message, .. } => return Err(message),
        }
        k += 1;
    }
    Ok(csv)
}

/// The paths of `<id>_ref.opt` and `<id>_ref.csv` in `dir`.
pub fn files(id: &str, dir: &Path) -> [PathBuf; 2] {
    [
        dir.join(format!("{id}_ref.opt")),
        dir.join(format!("{id}_ref.csv")),
    ]
}

/// Write `<id>_ref.opt` and `<id>_ref.csv` into `dir`, each whole or not
/// at all; returns their paths.
pub fn write<D: Dynamics>(scene: &Scene, id: &str, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let [opt, csv] = files(id, dir);
    let staged = [Staged::new(&opt)?, Staged::new(&csv)?];
    let texts = [ref_opt(scene), ref_csv::<D>(scene)?];
    let mut written = Vec::new();
    for (staged, text) in staged.into_iter().zip(texts) {
        std::fs::write(staged.temp_path(), text)
            .map_err(|e| format!("cannot write {}: {e}", staged.path().display()))?;
        written.push(staged.commit()?);
    }
    Ok(written)
}
