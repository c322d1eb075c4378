//! The plot styling the speed-sweep plot and the bridge check's plots
//! share: the train colours, the labelled axes, the dashed limit line and
//! the legend box, so that both kinds of figure look alike.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::plot::FONT;

/// Distinct colours for up to twelve trains (then they repeat): ten
/// HSLM-A trains and two real ones each get their own.
pub const COLOURS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 90, 60),
    RGBColor(120, 60, 0),
];

/// The colour of the `i`-th train.
pub fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

pub type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// A chart with f64 axes on any backend.
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Text of a drawing error.
pub fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// A chart on `area` over `x` × `y` with room for the axis labels.
pub fn labelled_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> Result<Chart<'a, DB>, String> {
    ChartBuilder::on(area)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(err)
}

/// The grid with the axis descriptions in the shared font.
pub fn labelled_mesh<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), String> {
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style((FONT, 16))
        .draw()
        .map_err(err)
}

/// A legend entry's short line in `style`.
pub fn legend_line(style: ShapeStyle) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style)
}

/// The dashed horizontal line of a limit across `low..high`, in the legend
/// as `label` when given.
pub fn limit_line<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    (low, high): (f64, f64),
    limit: f64,
    label: Option<String>,
) -> Result<(), String> {
    let style = BLACK.stroke_width(2);
    let series = chart
        .draw_series(DashedLineSeries::new(
            [(low, limit), (high, limit)],
            8,
            6,
            style,
        ))
        .map_err(err)?;
    if let Some(label) = label {
        series.label(label).legend(legend_line(style));
    }
    Ok(())
}

/// The legend box at `position`.
pub fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .draw()
        .map_err(err)
}
