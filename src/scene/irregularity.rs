//! Track irregularities in a scene (`[[track.irregularities]]`, each a
//! `structure::profile::IrregularitySpec`, summed into the profile r(x)):
//! their rules, and the reading of profile tables from CSV files beside the
//! scene.

use std::path::Path;

use super::error::Problem;
use super::{Scene, SceneError, MAX_MAGNITUDE, MAX_SCENE_BYTES};
use crate::profile::spectrum::{Grid, Spectrum, MAX_SAMPLES};
use crate::structure::profile::IrregularitySpec;

/// Most irregularities in a scene (the scene's list limit).
pub const MAX_IRREGULARITIES: usize = 10_000;

/// Most points of a profile table: a measured profile is long (100 km at
/// 1 m), so this is ten times the scene's list limit; the scene's byte
/// limit bounds the text either way.
pub const MAX_TABLE_POINTS: usize = 100_000;

/// Where a random profile's grid starts and how long the track is (m).
pub fn track_extent(scene: &Scene) -> (f64, f64) {
    let t = &scene.track;
    (-t.approach, t.approach + scene.beam.length + t.run_off)
}

/// Set this environment variable to `anywhere` to let table files lie
/// outside the scene file's folder (by default a scene from elsewhere
/// cannot make guideway read, and embed in an FMU, any file it names).
pub const TABLE_PATHS_VARIABLE: &str = "GUIDEWAY_TABLE_PATHS";

/// Read every table `file` relative to `base` into its `points`; all the
/// tables together hold at most `MAX_TABLE_POINTS` points. Returns the
/// files read (inputs of the run: no output may overwrite them).
pub(super) fn read_tables(
    scene: &mut Scene,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, SceneError> {
    let mut problems = Vec::new();
    let mut total = 0;
    let mut read_files = Vec::new();
    for (i, spec) in scene.track.irregularities.iter_mut().enumerate() {
        if let IrregularitySpec::Table { file, points } = spec {
            let Some(name) = file.clone() else { continue };
            let path = format!("track.irregularities[{i}].file");
            if !points.is_empty() {
                problems.push(Problem::new(
                    path,
                    format!("{name:?}"),
                    "give either file or points, not both",
                ));
                continue;
            }
            let file_path = base.join(&name);
            match confined(base, &file_path).and_then(|()| read_table(&file_path)) {
                Ok(read) if total + read.len() > MAX_TABLE_POINTS => {
                    problems.push(Problem::new(
                        path,
                        format!("{name:?}"),
                        format!("the tables together must hold at most {MAX_TABLE_POINTS} points"),
                    ));
                    break;
                }
                Ok(read) => {
                    total += read.len();
                    *points = read;
                    *file = None;
                    read_files.push(file_path);
                }
                Err(rule) => problems.push(Problem::new(path, format!("{name:?}"), rule)),
            }
        }
    }
    if problems.is_empty() {
        Ok(read_files)
    } else {
        Err(SceneError::Invalid { problems })
    }
}

/// Refuse a table file outside the scene's folder (after following every
/// symbolic link), unless `TABLE_PATHS_VARIABLE` is `anywhere`.
fn confined(base: &Path, file: &Path) -> Result<(), String> {
    if std::env::var(TABLE_PATHS_VARIABLE).is_ok_and(|v| v == "anywhere") {
        return Ok(());
    }
    let folder = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let (Ok(folder), Ok(real)) = (folder.canonicalize(), file.canonicalize()) else {
        return Err("cannot be read: no such file".into());
    };
    if real.starts_with(&folder) {
        Ok(())
    } else {
        Err(format!(
            "must lie in the scene file's folder or below it (a scene may come from anyone; \
             set {TABLE_PATHS_VARIABLE}=anywhere to read tables from elsewhere)"
        ))
    }
}

/// The (x, r) rows of a CSV file: two numbers a line, separated by a comma;
/// blank lines and lines starting with `#` skipped, and a first line that
/// is not numeric taken as a header. Bounded by `MAX_SCENE_BYTES` and
/// `MAX_TABLE_POINTS`; the first bad line is named.
pub fn read_table(path: &Path) -> Result<Vec<[f64; 2]>, String> {
    use std::io::Read;
    crate::input_file::check_regular(path).map_err(|e| format!("cannot be read: {e}"))?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot be read: {e}"))?;
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot be read: {e}"))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(format!("is larger than {MAX_SCENE_BYTES} bytes"));
    }
    let text = String::from_utf8(bytes).map_err(|e| format!("is not UTF-8 text: {e}"))?;
    parse_table(&text)
}

/// The rows of a table's text (see `read_table`).
pub fn parse_table(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut points: Vec<[f64; 2]> = Vec::new();
    let mut first = true;
    for (number, line) in text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        let header = first && parsed.first().is_some_and(|p| p.is_none());
        first = false;
        if header {
            continue;
        }
        // The line itself is not shown: a table path may name a file that
        // is not the user's to see (a refusal must not echo it).
        let (x, r) = match (fields.len(), parsed.as_slice()) {
            (2, &[Some(x), Some(r)]) => (x, r),
            _ => {
                return Err(format!(
                    "line {number} must hold two numbers x, r separated by a comma (it holds {} field(s), {} of them numbers)", fields.len(), parsed.iter().flatten().count()
                ))
            }
        };
        if !(x.is_finite() && r.is_finite() && x.abs() <= MAX_MAGNITUDE && r.abs() <= MAX_MAGNITUDE)
        {
            return Err(format!(
                "line {number} must hold finite numbers within ±{MAX_MAGNITUDE:e}"
            ));
        }
        if let Some(last) = points.last() {
            if x <= last[0] {
                return Err(format!(
                    "line {number}: x must increase from row to row (previous x = {})",
                    last[0]
                ));
            }
        }
        if points.len() == MAX_TABLE_POINTS {
            return Err(format!("has more than {MAX_TABLE_POINTS} rows"));
        }
        points.push([x, r]);
    }
    if points.len() < 2 {
        return Err("must hold at least two rows x, r".into());
    }
    Ok(points)
}

/// Every rule the irregularities break.
pub(super) fn problems(scene: &Scene) -> Vec<Problem> {
    let list = &scene.track.irregularities;
    let mut problems = Vec::new();
    if list.len() > MAX_IRREGULARITIES {
        problems.push(Problem::new(
            "track.irregularities",
            format!("{} irregularities", list.len()),
            format!("must hold at most {MAX_IRREGULARITIES}"),
        ));
        return problems;
    }
    // Bounds on the whole: every table and random grid is held in memory.
    let (mut points, mut samples) = (0usize, 0usize);
    for spec in list {
        match spec {
            IrregularitySpec::Table { points: p, .. } => points += p.len(),
            IrregularitySpec::Random {
                shortest_wavelength,
                longest_wavelength,
                spacing,
                ..
            } => {
                let spacing = IrregularitySpec::random_spacing(*shortest_wavelength, *spacing);
                let band = (*shortest_wavelength, *longest_wavelength);
                samples += Grid::of_band(spacing, band).map_or(0, |g| g.samples);
            }
            _ => {}
        }
    }
    if points > MAX_TABLE_POINTS {
        problems.push(Problem::new(
            "track.irregularities",
            format!("{points} table points"),
            format!("the tables together must hold at most {MAX_TABLE_POINTS} points"),
        ));
    }
    if samples > MAX_SAMPLES {
        problems.push(Problem::new(
            "track.irregularities",
            format!("{samples} random-profile samples"),
            format!(
                "the random profiles together must have at most {MAX_SAMPLES} samples (raise \
                 their spacing)"
            ),
        ));
    }
    for (i, spec) in list.iter().enumerate() {
        let mut rules = Rules {
            prefix: format!("track.irregularities[{i}]"),
            problems: &mut problems,
        };
        rules.check(spec, scene);
    }
    problems
}

struct Rules<'a> {
    prefix: String,
    problems: &'a mut Vec<Problem>,
}

impl Rules<'_> {
    fn fail(&mut self, field: &str, value: String, rule: impl Into<String>) {
        let path = format!("{}.{field}", self.prefix);
        self.problems.push(Problem::new(path, value, rule));
    }
    fn finite(&mut self, field: &str, x: f64) -> bool {
        let ok = x.is_finite() && x.abs() <= MAX_MAGNITUDE;
        if !ok {
            self.fail(
                field,
                format!("{x:?}"),
                format!("must be a finite number within ±{MAX_MAGNITUDE:e}"),
            );
        }
        ok
    }
    fn positive(&mut self, field: &str, x: f64) -> bool {
        if !self.finite(field, x) {
            return false;
        }
        let ok = x >= super::MIN_MAGNITUDE;
        if !ok {
            self.fail(field, format!("{x:?}"), "must be > 0");
        }
        ok
    }

    fn check(&mut self, spec: &IrregularitySpec, scene: &Scene) {
        match spec {
            IrregularitySpec::Step {
                position,
                height,
                smoothing,
            } => {
                self.finite("position", *position);
                self.finite("height", *height);
                self.smoothing(*smoothing);
            }
            IrregularitySpec::Ramp {
                start,
                length,
                height,
                smoothing,
            } => {
                self.finite("start", *start);
                self.positive("length", *length);
                self.finite("height", *height);
                self.smoothing(*smoothing);
            }
            IrregularitySpec::CosineDip {
                position,
                wavelength,
                depth,
            } => {
                self.finite("position", *position);
                self.positive("wavelength", *wavelength);
                self.finite("depth", *depth);
            }
            IrregularitySpec::Sine {
                amplitude,
                wavelength,
                phase,
            } => {
                self.finite("amplitude", *amplitude);
                self.positive("wavelength", *wavelength);
                self.finite("phase", *phase);
            }
            IrregularitySpec::Table { file, points } => self.table(file.as_deref(), points),
            IrregularitySpec::Random {
                spectrum,
                class,
                shortest_wavelength,
                longest_wavelength,
                spacing,
                ..
            } => {
                if let Err(rule) = Spectrum::from_name(spectrum, class.as_deref()) {
                    self.fail("spectrum", format!("{spectrum:?}"), rule);
                }
                let band = (*shortest_wavelength, *longest_wavelength);
                self.band(band, *spacing, scene);
            }
        }
    }

    /// A kink needs an impulse the bilateral contact cannot give.
    fn smoothing(&mut self, smoothing: f64) {
        if self.finite("smoothing", smoothing) && smoothing < super::MIN_MAGNITUDE {
            self.fail(
                "smoothing",
                format!("{smoothing:?}"),
                "must be > 0: a contact that stays closed cannot follow a kink (it would \
                 need an impulse)",
            );
        }
    }

    fn table(&mut self, file: Option<&str>, points: &[[f64; 2]]) {
        if let Some(file) = file {
            self.fail(
                "file",
                format!("{file:?}"),
                "can only be read when the scene is loaded from its own file (the path is \
                 relative to it); the points are then kept in the scene",
            );
            return;
        }
        if points.len() < 2 || points.len() > MAX_TABLE_POINTS {
            self.fail(
                "points",
                format!("{} points", points.len()),
                format!("must hold between 2 and {MAX_TABLE_POINTS} points [x, r]"),
            );
            return;
        }
        for (k, p) in points.iter().enumerate() {
            let ok = self.finite(&format!("points[{k}][0]"), p[0])
                & self.finite(&format!("points[{k}][1]"), p[1]);
            if ok && k > 0 && p[0] <= points[k - 1][0] {
                self.fail(
                    &format!("points[{k}][0]"),
                    format!("{:?}", p[0]),
                    format!(
                        "must be greater than the previous x = {:?}",
                        points[k - 1][0]
                    ),
                );
            }
        }
    }

    fn band(&mut self, (shortest, longest): (f64, f64), spacing: Option<f64>, scene: &Scene) {
        let ok = self.positive("shortest_wavelength", shortest)
            & self.positive("longest_wavelength", longest);
        if !ok {
            return;
        }
        if longest <= shortest {
            self.fail(
                "longest_wavelength",
                format!("{longest:?}"),
                format!("must be greater than shortest_wavelength = {shortest:?}"),
            );
            return;
        }
        let spacing = IrregularitySpec::random_spacing(shortest, spacing);
        if !self.positive("spacing", spacing) {
            return;
        }
        if spacing > shortest / 4.0 {
            self.fail(
                "spacing",
                format!("{spacing:?}"),
                format!(
                    "must be at most shortest_wavelength / 4 = {:?} (four samples a \
                     wavelength for the spline)",
                    shortest / 4.0
                ),
            );
            return;
        }
        let (_, length) = track_extent(scene);
        let Some(grid) = Grid::of_band(spacing, (shortest, longest)) else {
            self.fail(
                "spacing",
                format!("{spacing:?}"),
                format!(
                    "gives more than {MAX_SAMPLES} samples over two longest wavelengths: raise \
                     spacing or shortest_wavelength"
                ),
            );
            return;
        };
        // The profile repeats after its period: a longer track would see
        // the same stretch twice.
        if length > grid.period() {
            self.fail(
                "spacing",
                format!("{spacing:?}"),
                format!(
                    "gives a profile repeating every {} m, shorter than the track \
                     (track.approach + beam.length + track.run_off = {length:?} m): raise \
                     spacing or shortest_wavelength, or shorten the track",
                    grid.period()
                ),
            );
        }
    }
}
