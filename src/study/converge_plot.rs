//! The plot of `guideway converge`: each summary figure's error against
//! the step (or elements), log–log, with its observed order in the legend,
//! and the solve time of each run below (work against precision).

use super::converge::{Ladder, Point};
use super::convergence::is_error_measure;
use crate::report::plot::{load_font, Text, FONT};
use plotters::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (1100, 1000);

/// Figures drawn at most (the legend must stay readable); the CSV has all.
const MAX_CURVES: usize = 12;

/// Write the plot of `ladder` to `path`; `mesh`: against elements.
pub fn write_converge_plot(ladder: &Ladder, mesh: bool, path: &Path) -> Result<(), String> {
    let text = load_font();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (top, bottom) = root.split_vertically(650);
    let x = |p: &Point| if mesh { p.elements as f64 } else { p.step };
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for point in &ladder.points {
        let scale = if is_error_measure(&point.figure) {
            1.0
        } else {
            point.value.abs()
        };
        let relative = point.error / scale;
        if !(relative > 0.0 && relative.is_finite()) {
            continue;
        }
        let full = curves.len() >= MAX_CURVES;
        match curves.iter_mut().find(|(name, _)| *name == point.figure) {
            Some((_, points)) => points.push((x(point), relative)),
            None if !full => curves.push((point.figure.clone(), vec![(x(point), relative)])),
            None => {}
        }
    }
    let orders = |name: &str| {
        let last = ladder.points.iter().rev().find(|p| p.figure == name);
        last.and_then(|p| p.order)
            .map_or("-".to_string(), |o| format!("{o:.2}"))
    };
    let labelled: Vec<(String, Vec<(f64, f64)>)> = curves
        .into_iter()
        .map(|(name, points)| (format!("{name} (order {})", orders(&name)), points))
        .collect();
    let xlabel = if mesh { "elements" } else { "step Δt (s)" };
    panel(
        &top,
        text,
        &labelled,
        (xlabel, "relative error (drift: absolute)"),
    )?;
    let costs: Vec<(f64, f64)> = ladder
        .levels
        .iter()
        .map(|l| {
            (
                if mesh { l.elements as f64 } else { l.step },
                l.cost_s.max(1e-9),
            )
        })
        .collect();
    panel(
        &bottom,
        text,
        &[("solve time of the run".to_string(), costs)],
        (xlabel, "solve time (s)"),
    )?;
    root.present()
        .map_err(|e| format!("cannot write the plot to {}: {e}", path.display()))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// The points' x and y ranges (x0, x1, y0, y1); `None` when there are no
/// points.
fn bounds(curves: &[(String, Vec<(f64, f64)>)]) -> Option<(f64, f64, f64, f64)> {
    let all = curves.iter().flat_map(|(_, p)| p);
    let (x0, x1, y0, y1) = all.fold(
        (f64::INFINITY, 0.0_f64, f64::INFINITY, 0.0_f64),
        |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
    );
    (x0.is_finite() && y0.is_finite()).then_some((x0, x1, y0, y1))
}

/// A log–log panel of `curves`.
fn panel(
    area: &Area,
    text: Text,
    curves: &[(String, Vec<(f64, f64)>)],
    (xlabel, ylabel): (&str, &str),
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let Some((x0, x1, y0, y1)) = bounds(curves) else {
        return Ok(());
    };
    let mut builder = ChartBuilder::on(area);
    builder.margin(15);
    if text == Text::Labelled {
        builder.x_label_area_size(45).y_label_area_size(80);
    }
    let mut chart = builder
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 3.0..y1 * 3.0).log_scale(),
        )
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    if text == Text::Labelled {
        mesh.x_labels(8)
            .y_labels(8)
            .x_desc(xlabel)
            .y_desc(ylabel)
            .label_style((FONT, 15))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .x_label_formatter(&|x| format!("{x:.1e}"));
    } else {
        mesh.disable_x_axis().disable_y_axis();
    }
    mesh.draw().map_err(err)?;
    for (i, (name, points)) in curves.iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))
            .map_err(err)?;
        let series = chart
            .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
            .map_err(err)?;
        if text == Text::Labelled {
            series.label(name.clone()).legend(move |(x, y)| {
                PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        }
    }
    if text == Text::Labelled {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 12))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}
