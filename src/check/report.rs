//! The check's report: one self-contained HTML page (tables, the PASS/FAIL
//! table, every assumption, the input's SHA-256 and the software version,
//! plots embedded as base64 PNG, nothing fetched), the runs and checks as
//! CSV, everything as JSON, and the plots as PNG files beside them.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use base64::Engine as _;
use plotters::prelude::*;
use sha2::{Digest, Sha256};

use super::CheckResult;
use crate::report::plot::{load_font, FONT};
use crate::report::plot_style::{
    colour, err, labelled_chart, labelled_mesh, legend, legend_line, limit_line, Area, Chart,
};

/// The files written into `dir`, the HTML first.
pub fn write_report(result: &CheckResult, input: &str, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let _ = load_font();
    let plots = [
        (
            "acceleration_daf.png",
            plot_speeds as fn(&CheckResult, &Path) -> Result<(), String>,
        ),
        ("worst_history.png", plot_history),
        ("envelopes.png", plot_envelopes),
    ];
    let mut written = Vec::new();
    let mut images = Vec::new();
    for (name, draw) in plots {
        let path = dir.join(name);
        draw(result, &path).map_err(|e| format!("{}: {e}", path.display()))?;
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        images.push(base64::engine::general_purpose::STANDARD.encode(bytes));
        written.push(path);
    }
    let files = [
        ("runs.csv", runs_csv(result)),
        ("checks.csv", checks_csv(result)),
        ("worst_history.csv", history_csv(result)),
        ("check.json", json(result, input)?),
        ("report.html", html(result, input, &images)),
    ];
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    written.rotate_right(1);
    Ok(written)
}

/// SHA-256 of the input text, hex.
pub fn input_hash(input: &str) -> String {
    Sha256::digest(input.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn version() -> String {
    format!("guideway {}", env!("CARGO_PKG_VERSION"))
}

fn runs_csv(r: &CheckResult) -> String {
    let mut text = String::from(
        "mass_case,train,speed_kmh,peak_acceleration_m_s2,peak_acceleration_filtered_m_s2,daf_deflection,daf_moment,static_moment_midspan_n_m",
    );
    for s in &r.stations {
        let _ = write!(text, ",deflection_{}_m", s.name);
    }
    for s in &r.stations {
        let _ = write!(text, ",moment_{}_n_m", s.name);
    }
    text.push('\n');
    for run in &r.runs {
        let _ = write!(
            text,
            "{},{},{},{},{},{},{},{}",
            run.mass_case,
            run.train,
            run.speed_kmh,
            run.acceleration,
            run.acceleration_filtered,
            run.daf_deflection,
            run.daf_moment,
            run.static_moment
        );
        for v in run.deflections.iter().chain(&run.moments) {
            let _ = write!(text, ",{v}");
        }
        text.push('\n');
    }
    text
}

fn csv_field(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\""))
}

fn checks_csv(r: &CheckResult) -> String {
    let mut text = String::from("clause,check,value,limit,status\n");
    for v in &r.verdicts {
        let fields = [&v.clause, &v.check, &v.value, &v.limit, &v.status].map(|f| csv_field(f));
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

fn history_csv(r: &CheckResult) -> String {
    let mut text = String::from("time_s,acceleration_m_s2,acceleration_filtered_m_s2\n");
    for (t, a, b) in &r.worst_history {
        let _ = writeln!(text, "{t},{a},{b}");
    }
    text
}

fn json(r: &CheckResult, input: &str) -> Result<String, String> {
    let value = serde_json::json!({
        "software": version(),
        "input_sha256": input_hash(input),
        "result": r,
    });
    serde_json::to_string_pretty(&value).map_err(|e| e.to_string())
}

/// HTML-escape `text`.
fn esc(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn html(r: &CheckResult, input: &str, images: &[String]) -> String {
    let mut h = html_head(r, input);
    h.push_str(&bridge_table(r));
    h.push_str(&checks_table(r));
    h.push_str("<h2>Assumptions</h2>\n<ul>\n");
    for a in &r.assumptions {
        let _ = writeln!(h, "<li>{}</li>", esc(a));
    }
    h.push_str("</ul>\n");
    h.push_str(&figures(r, images));
    let _ = writeln!(h, "<h2>Input</h2>\n<pre>{}</pre>\n<p>Files beside this page: runs.csv ({} runs), checks.csv, worst_history.csv, check.json.</p>\n</body></html>", esc(input), r.runs.len());
    h
}

/// The page's head, title, overall verdict, version and input hash.
fn html_head(r: &CheckResult, input: &str) -> String {
    let overall = if r.verdicts.iter().any(|v| v.status == "FAIL") {
        "FAIL"
    } else {
        "PASS"
    };
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Dynamic check: {name}</title>\
         <style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}table{{border-collapse:collapse}}\
         td,th{{border:1px solid #999;padding:.3em .6em;text-align:left}}.PASS{{background:#cfc}}.FAIL{{background:#fcc}}\
         .INFO{{background:#eef}}img{{max-width:100%}}</style></head><body>\n\
         <h1>Dynamic check of railway bridge “{name}”</h1>\n\
         <p>EN 1991-2:2003 §6.4 and EN 1990:2002 Annex A2. Overall: <b id=\"overall\" class=\"{overall}\">{overall}</b></p>\n\
         <p>Software: {ver}. Input SHA-256: <code>{hash}</code>.</p>\n",
        name = esc(&r.spec.name),
        ver = version(),
        hash = input_hash(input),
    )
}

/// The bridge's description and its mass cases.
fn bridge_table(r: &CheckResult) -> String {
    let spec = &r.spec;
    let mut h = String::from("<h2>Bridge</h2>\n<table>\n");
    let rows: [(&str, String); 6] = [
        ("spans", spec.span_description()),
        (
            "mass per length",
            format!(
                "{} kg/m (lower {}, upper {})",
                spec.mass_per_length,
                spec.mass_lower.unwrap_or(spec.mass_per_length),
                spec.mass_upper.unwrap_or(spec.mass_per_length)
            ),
        ),
        ("EI", format!("{:.4e} N m²", r.bending_stiffness)),
        ("bridge type", spec.bridge_type.label().to_string()),
        ("track", super::track_label(spec.track).to_string()),
        (
            "maximum line speed",
            format!(
                "{} km/h; design speed 1.2 × = {} km/h",
                spec.line_speed, r.design_speed
            ),
        ),
    ];
    for (k, v) in rows {
        let _ = writeln!(h, "<tr><th>{}</th><td>{}</td></tr>", esc(k), esc(&v));
    }
    for c in &r.mass_cases {
        let _ = writeln!(
            h,
            "<tr><th>mass case {}</th><td>{} kg/m: f1 = {:.3} Hz, f3 = {:.3} Hz, acceleration cut-off {:.2} Hz</td></tr>",
            esc(&c.name), c.mass_per_length, c.f1, c.f3, c.cut_off
        );
    }
    h.push_str("</table>\n");
    h
}

/// The PASS/FAIL table.
fn checks_table(r: &CheckResult) -> String {
    let mut h = String::from("<h2>Checks</h2>\n<table id=\"verdicts\">\n<tr><th>clause</th><th>check</th><th>value</th><th>limit</th><th>status</th></tr>\n");
    for v in &r.verdicts {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"{s}\">{s}</td></tr>",
            esc(&v.clause),
            esc(&v.check),
            esc(&v.value),
            esc(&v.limit),
            s = esc(&v.status)
        );
    }
    h.push_str("</table>\n");
    h
}

/// The three plots with their captions, and the worst run.
fn figures(r: &CheckResult, images: &[String]) -> String {
    let mut h = String::from("<h2>Plots</h2>\n");
    let captions = [
        "Peak deck acceleration (filtered: solid; raw: thin) and DAF of the midspan deflection against speed, per train; the limit dashed, per train the highest resonant speed f1·D/i (i = 1, 2, 3) in the range as a tick.",
        "Midspan acceleration of the worst run against time, raw and low-passed.",
        "Envelopes of |deflection| and |moment| along the bridge over every run.",
    ];
    for (img, caption) in images.iter().zip(captions) {
        let _ = writeln!(h, "<figure><img alt=\"{c}\" src=\"data:image/png;base64,{img}\"><figcaption>{c}</figcaption></figure>", c = esc(caption));
    }
    if let Some(w) = &r.worst {
        let _ = writeln!(
            h,
            "<p>Worst run: {} at {:.1} km/h ({} mass): {:.3} m/s² filtered, {:.3} m/s² raw.</p>",
            esc(&w.train),
            w.speed_kmh,
            esc(&w.mass_case),
            w.acceleration_filtered,
            w.acceleration
        );
    }
    h
}

/// Peak acceleration and DAF against speed per train (first mass case).
fn plot_speeds(r: &CheckResult, path: &Path) -> Result<(), String> {
    let root = BitMapBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let areas = root.split_evenly((2, 1));
    let case = &r.mass_cases[0].name;
    let runs: Vec<&super::Run> = r.runs.iter().filter(|x| &x.mass_case == case).collect();
    speed_panel(r, &runs, &areas[0], true)?;
    speed_panel(r, &runs, &areas[1], false)?;
    root.present().map_err(err)
}

/// One panel against speed: the peak deck acceleration (filtered solid,
/// raw thin, the limit dashed) when `acceleration`, else the DAF; the
/// highest resonant speed of each train in the range as a tick.
fn speed_panel(
    r: &CheckResult,
    runs: &[&super::Run],
    area: &Area,
    acceleration: bool,
) -> Result<(), String> {
    let low = runs
        .iter()
        .map(|x| x.speed_kmh)
        .fold(f64::INFINITY, f64::min);
    let high = runs
        .iter()
        .map(|x| x.speed_kmh)
        .fold(0.0, f64::max)
        .max(low + 1.0);
    let (label, top) = if acceleration {
        let top = runs
            .iter()
            .map(|x| x.acceleration.max(x.acceleration_filtered))
            .fold(r.acceleration_limit, f64::max);
        ("peak deck acceleration (m/s²)", 1.1 * top)
    } else {
        let top = runs.iter().map(|x| x.daf_deflection).fold(1.0, f64::max);
        ("DAF, midspan deflection", 1.1 * top)
    };
    let mut chart = labelled_chart(area, low..high, 0.0..top)?;
    labelled_mesh(&mut chart, "speed (km/h)", label)?;
    let mut trains: Vec<&str> = runs.iter().map(|x| x.train.as_str()).collect();
    trains.dedup();
    for (i, train) in trains.iter().enumerate() {
        let of_train: Vec<&super::Run> =
            runs.iter().copied().filter(|x| x.train == *train).collect();
        draw_train(&mut chart, (i, train), &of_train, acceleration)?;
        let tick = r
            .resonances
            .iter()
            .find(|(n, v)| n == train && *v >= low && *v <= high);
        if let Some(&(_, v)) = tick {
            let line = [(v, 0.0), (v, 0.04 * top)];
            let style = colour(i).stroke_width(3);
            chart
                .draw_series(LineSeries::new(line, style))
                .map_err(err)?;
        }
    }
    if acceleration {
        let limit = r.acceleration_limit;
        let name = format!("EN 1990 A2 limit {limit} m/s²");
        limit_line(&mut chart, (low, high), limit, Some(name))?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft)
}

/// One train's curve against speed (the filtered acceleration, with the
/// raw one thin beside it, or the deflection's DAF), in its colour `i`.
fn draw_train<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    (i, train): (usize, &str),
    runs: &[&super::Run],
    acceleration: bool,
) -> Result<(), String> {
    let of = |f: &dyn Fn(&super::Run) -> f64| -> Vec<(f64, f64)> {
        runs.iter().map(|x| (x.speed_kmh, f(x))).collect()
    };
    let style = colour(i).stroke_width(2);
    let main = if acceleration {
        of(&|x| x.acceleration_filtered)
    } else {
        of(&|x| x.daf_deflection)
    };
    chart
        .draw_series(LineSeries::new(main, style))
        .map_err(err)?
        .label(train)
        .legend(legend_line(style));
    if acceleration {
        let raw = of(&|x| x.acceleration);
        let thin = colour(i).mix(0.5).stroke_width(1);
        chart.draw_series(LineSeries::new(raw, thin)).map_err(err)?;
    }
    Ok(())
}

/// The worst run's midspan acceleration, raw and filtered.
fn plot_history(r: &CheckResult, path: &Path) -> Result<(), String> {
    let root = BitMapBackend::new(path, (1000, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let end = r.worst_history.last().map_or(1.0, |p| p.0);
    let top = r
        .worst_history
        .iter()
        .map(|p| p.1.abs().max(p.2.abs()))
        .fold(r.acceleration_limit, f64::max)
        * 1.1;
    let title = r.worst.as_ref().map_or(String::new(), |w| {
        format!("{} at {:.1} km/h, midspan", w.train, w.speed_kmh)
    });
    let titled = root.titled(&title, (FONT, 18)).map_err(err)?;
    let mut chart = labelled_chart(&titled, 0.0..end, -top..top)?;
    labelled_mesh(&mut chart, "time (s)", "deck acceleration (m/s²)")?;
    let raw = RGBColor(170, 170, 170).stroke_width(1);
    chart
        .draw_series(LineSeries::new(
            r.worst_history.iter().map(|p| (p.0, p.1)),
            raw,
        ))
        .map_err(err)?
        .label("raw")
        .legend(legend_line(raw));
    let filtered = colour(0).stroke_width(2);
    chart
        .draw_series(LineSeries::new(
            r.worst_history.iter().map(|p| (p.0, p.2)),
            filtered,
        ))
        .map_err(err)?
        .label("low-passed (§6.4.6.5(4))")
        .legend(legend_line(filtered));
    for limit in [r.acceleration_limit, -r.acceleration_limit] {
        limit_line(&mut chart, (0.0, end), limit, None)?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(err)
}

/// The envelopes of |deflection| (mm) and |moment| (MN m) along the span.
fn plot_envelopes(r: &CheckResult, path: &Path) -> Result<(), String> {
    let root = BitMapBackend::new(path, (1000, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let areas = root.split_evenly((2, 1));
    let l = r.spec.length();
    let envelope = |pick: &dyn Fn(&super::Run) -> &Vec<f64>, scale: f64| -> Vec<(f64, f64)> {
        let mut points = vec![(0.0, 0.0)];
        for (i, s) in r.stations.iter().enumerate() {
            let peak = r.runs.iter().map(|x| pick(x)[i]).fold(0.0, f64::max);
            points.push((s.position, peak * scale));
        }
        points.push((l, 0.0));
        points
    };
    let panels = [
        ("|deflection| (mm)", envelope(&|x| &x.deflections, 1e3)),
        ("|moment| (MN m)", envelope(&|x| &x.moments, 1e-6)),
    ];
    for (area, (label, points)) in areas.iter().zip(panels) {
        draw_envelope(area, label, &points, l)?;
    }
    root.present().map_err(err)
}

fn draw_envelope(area: &Area, label: &str, points: &[(f64, f64)], l: f64) -> Result<(), String> {
    let top = points.iter().map(|p| p.1).fold(0.0, f64::max).max(1e-9) * 1.1;
    let mut chart = labelled_chart(area, 0.0..l, 0.0..top)?;
    labelled_mesh(&mut chart, "x along the bridge (m)", label)?;
    let style = colour(0).stroke_width(2);
    chart
        .draw_series(LineSeries::new(points.iter().copied(), style))
        .map_err(err)?;
    chart
        .draw_series(
            points
                .iter()
                .map(|&p| Circle::new(p, 4, colour(0).filled())),
        )
        .map_err(err)?;
    Ok(())
}
