//! The run as a PNG in the manner of the paper's Fig. 10: nominal speed,
//! sensor deflections over the static midspan deflection, and the energy
//! balance's relative drift, against normalised time t·V0/L for the
//! paper's one body, seconds otherwise; with vehicles also the contacts'
//! normal forces (their flights shaded, as in any run with a lift-off) and
//! the vertical accelerations of the sprung bodies and of the unsprung
//! masses, each panel's many curves drawn as their envelope.

use super::curve_groups::{columns_of, grouped, is_unsprung};
use super::plot_style;
use super::trace::Trace;
use crate::outputs::{output_name, reports, QuantityKind};
use crate::scene::Scene;
use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

/// Where the plot's font is looked for, first found wins. Without one the
/// plot is drawn without any text.
pub const FONT_PATHS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// Environment variable naming a TTF file to use instead.
pub const FONT_ENV: &str = "GUIDEWAY_PLOT_FONT";

/// The plot's width, and the height of each panel.
const WIDTH: u32 = 1000;
const PANEL_HEIGHT: u32 = 240;
pub(crate) const FONT: &str = "sans-serif";
const COLOURS: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];

/// Whether text can be drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Text {
    /// Titles, axis labels and legends.
    Labelled,
    /// Lines and grid only (no font found).
    Omitted,
}

/// Register a font with plotters once per process; says whether one was
/// found.
pub fn load_font() -> Text {
    static LOADED: OnceLock<Text> = OnceLock::new();
    *LOADED.get_or_init(|| {
        let from_env = std::env::var(FONT_ENV).ok();
        let candidates = from_env.iter().map(String::as_str).chain(FONT_PATHS);
        for path in candidates {
            let Ok(bytes) = std::fs::read(path) else {
                continue;
            };
            // plotters keeps fonts for the life of the process.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            if plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok() {
                return Text::Labelled;
            }
        }
        Text::Omitted
    })
}

/// Write the plot, with text if a font can be found.
pub fn write_plot(scene: &Scene, trace: &Trace, path: &Path) -> Result<(), String> {
    draw(scene, trace, path, load_font())
}

/// One curve of a panel.
pub struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

struct Panel {
    title: String,
    y_label: String,
    /// Digits after the point on the y axis; scientific notation if `None`.
    y_decimals: Option<usize>,
    curves: Vec<Curve>,
    /// Spans of x in which a contact is open (in flight), shaded.
    flights: Vec<(f64, f64)>,
}

/// Write the plot, drawing text or not.
pub fn draw(scene: &Scene, trace: &Trace, path: &Path, text: Text) -> Result<(), String> {
    let (x, x_label) = normalised_time(scene, trace);
    let panels = panels(scene, trace, &x);
    let height = PANEL_HEIGHT * panels.len().max(1) as u32;
    let root = BitMapBackend::new(path, (WIDTH, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len(), 1));
    let x_range = padded_range(x.iter().copied());
    for (panel, area) in panels.iter().zip(&areas) {
        draw_panel(panel, area, x_range.clone(), &x_label, text).map_err(|e| e.to_string())?;
    }
    root.present()
        .map_err(|e| format!("cannot write the plot to {}: {e}", path.display()))
}

/// The x axis: t·V0/L for the paper's one body starting to move (its
/// Fig. 10), seconds for vehicles, trains and moving forces (their length,
/// not the span's, sets the time scale); and the axis label.
fn normalised_time(scene: &Scene, trace: &Trace) -> (Vec<f64>, String) {
    // Read only for one body: the first vehicle is the only one.
    let speed = scene.vehicles[0].initial_speed;
    let one_body = !has_vehicles(scene) && !crate::moving_load::is_moving_force_scene(scene);
    if speed > 0.0 && one_body {
        let scale = speed / scene.beam.length;
        (
            trace.time.iter().map(|t| t * scale).collect(),
            "t V0 / L".to_string(),
        )
    } else {
        (trace.time.clone(), "t (s)".to_string())
    }
}

/// P L³ / (48 EI): the static midspan deflection of the single simply
/// supported span under the paper's one body's load P = |force_y| (the
/// first vehicle's; a train's scale is `deflection_scale`'s envelope).
pub fn static_deflection(scene: &Scene) -> f64 {
    let beam = &scene.beam;
    scene.vehicles[0].force_y.abs() * beam.length.powi(3) / (48.0 * beam.bending_stiffness)
}

/// What the sensor deflections are divided by, and the axis label: the
/// largest static deflection of the actual structure under the scene's
/// loads crossing it (`design::static_envelope`; P L³ / 48 EI for one load
/// on one simply supported span) when every sensor shares one, else mm.
pub fn deflection_scale(scene: &Scene) -> (f64, String) {
    let envelope = crate::design::static_envelope(scene).ok();
    let peaks: Vec<f64> = scene
        .sensors
        .iter()
        .filter_map(|s| {
            let name = output_name(QuantityKind::Sensor, &s.name);
            envelope.as_ref()?.peaks.get(&name).copied()
        })
        .collect();
    let single = peaks.first().copied().filter(|&first| {
        peaks.len() == scene.sensors.len()
            && first > 0.0
            && first.is_finite()
            && peaks.iter().all(|&p| (p - first).abs() <= 1e-9 * first)
    });
    match single {
        Some(peak) => (peak, format!("deflection / (static peak {peak:.4} m)")),
        None => (1e-3, "deflection (mm)".to_string()),
    }
}

/// A curve of `values` over `x` divided by `scale`, without the points
/// that are not finite.
fn scaled_curve(x: &[f64], label: String, values: &[f64], scale: f64) -> Curve {
    Curve {
        label,
        points: x
            .iter()
            .zip(values)
            .map(|(&x, &v)| (x, v / scale))
            .filter(|(_, y)| y.is_finite())
            .collect(),
    }
}

fn panels(scene: &Scene, trace: &Trace, x: &[f64]) -> Vec<Panel> {
    let curve = |label: String, values: &[f64], scale: f64| scaled_curve(x, label, values, scale);
    if crate::moving_load::is_moving_force_scene(scene) {
        return force_panels(scene, trace, &curve);
    }
    let (speed_title, speed_columns) = speed_columns(scene, trace);
    let speeds = grouped(x, &named_columns(trace, &speed_columns), 1.0, "vehicles");
    let mut panels = Vec::new();
    // Nothing to show (moving forces have no body): no empty frame.
    if !speed_columns.is_empty() {
        panels.push(speed_panel(speed_title, speeds));
    }
    panels.push(deflection_panel(scene, trace, x));
    let flights = flights(trace, x);
    if has_vehicles(scene) || !flights.is_empty() {
        panels.extend(body_panels(trace, x, flights));
    }
    if !scene.track.irregularities.is_empty() {
        let profiles = columns_of(trace, &[QuantityKind::Irregularity], &|_| true)
            .into_iter()
            .map(|(name, values)| curve(name, values, 1e-3))
            .collect();
        panels.push(plain_panel(
            "Track irregularity at the contacts",
            "r (mm)",
            Some(2),
            profiles,
        ));
    }
    let drift = drift_curve(trace, x).into_iter().collect();
    panels.push(plain_panel(
        "Energy balance, relative drift",
        "(E - E0) / E0",
        None,
        drift,
    ));
    panels
}

/// The columns of `names` the trace has, with their names.
fn named_columns<'t>(trace: &'t Trace, names: &[String]) -> Vec<(String, &'t [f64])> {
    names
        .iter()
        .filter_map(|name| Some((name.clone(), trace.column(name)?)))
        .collect()
}

/// A panel without flights.
fn plain_panel(title: &str, y_label: &str, y_decimals: Option<usize>, curves: Vec<Curve>) -> Panel {
    Panel {
        title: title.to_string(),
        y_label: y_label.to_string(),
        y_decimals,
        curves,
        flights: Vec::new(),
    }
}

/// The sensors' deflections, scaled by the static peak where one is known.
fn deflection_panel(scene: &Scene, trace: &Trace, x: &[f64]) -> Panel {
    let (scale, y_label) = deflection_scale(scene);
    let sensor_columns: Vec<String> = scene
        .sensors
        .iter()
        .map(|sensor| output_name(QuantityKind::Sensor, &sensor.name))
        .collect();
    let deflections = grouped(x, &named_columns(trace, &sensor_columns), scale, "sensors");
    plain_panel("Sensor deflection", &y_label, Some(2), deflections)
}

/// The energy balance's drift relative to its start, where the start is
/// a finite non-zero energy.
fn drift_curve(trace: &Trace, x: &[f64]) -> Option<Curve> {
    let energy = trace.column(&output_name(QuantityKind::Balance, ""))?;
    let initial = *energy.first()?;
    (initial != 0.0 && initial.is_finite()).then(|| {
        let relative: Vec<f64> = energy.iter().map(|e| (e - initial) / initial).collect();
        scaled_curve(x, "(E - E0) / E0".to_string(), &relative, 1.0)
    })
}

/// The speeds in m/s; or, where they stay within 1e-4 of their start (a
/// train at a constant 300 km/h), their departure from it in mm/s, so that
/// the ticks do not repeat "83.3333".
fn speed_panel(title: &str, mut curves: Vec<Curve>) -> Panel {
    let values = || curves.iter().flat_map(|c| c.points.iter().map(|p| p.1));
    let (low, high) = values().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
        (l.min(v), h.max(v))
    });
    let start = curves.first().and_then(|c| c.points.first()).map(|p| p.1);
    let mut y_label = "V (m/s)".to_string();
    if let Some(v0) = start.filter(|v0| *v0 != 0.0 && high - low < 1e-4 * v0.abs()) {
        for point in curves.iter_mut().flat_map(|c| c.points.iter_mut()) {
            point.1 = (point.1 - v0) * 1e3;
        }
        y_label = format!("V - {v0:.4} m/s (mm/s)");
    }
    plain_panel(title, &y_label, Some(2), curves)
}

/// Every contact's normal force (its flights shaded), then the vertical
/// accelerations of the sprung bodies and of the unsprung masses apart:
/// a car body's is the ride-comfort figure, a wheelset's is dominated by
/// the contact's stiffness.
fn body_panels(trace: &Trace, x: &[f64], flights: Vec<(f64, f64)>) -> Vec<Panel> {
    let forces = columns_of(trace, &[QuantityKind::NormalForce], &|_| true);
    let sprung = columns_of(trace, &[QuantityKind::Ay], &|b| !is_unsprung(trace, b));
    let unsprung = columns_of(trace, &[QuantityKind::Ay], &|b| is_unsprung(trace, b));
    let panel = |title: &str, y_label: &str, curves, flights| Panel {
        title: title.to_string(),
        y_label: y_label.to_string(),
        y_decimals: Some(0),
        curves,
        flights,
    };
    let mut panels = vec![Panel {
        y_decimals: Some(1),
        ..panel(
            "Contact forces",
            "normal force (kN)",
            grouped(x, &forces, 1e3, "contacts"),
            flights,
        )
    }];
    for (columns, title, what) in [
        (
            sprung,
            "Vertical acceleration of the sprung bodies",
            "sprung bodies",
        ),
        (
            unsprung,
            "Vertical acceleration of the unsprung masses",
            "unsprung masses",
        ),
    ] {
        if !columns.is_empty() {
            let curves = grouped(x, &columns, 1.0, what);
            panels.push(panel(title, "ay (m/s^2)", curves, Vec::new()));
        }
    }
    panels
}

/// The speed panel's title and its columns, one per vehicle: the nominal
/// speed (eq. 24) of a vehicle that is one rolling or gliding body (the
/// paper's wheel, a sprung mass on a follower), else its main body's
/// horizontal velocity `<name>.vx` (the car body of a bogie or maglev
/// vehicle, the sprung body: their wheelsets, magnets and followers each
/// have a nominal speed of their own, not one for the vehicle). Columns
/// the trace lacks are left out.
fn speed_columns(scene: &Scene, trace: &Trace) -> (&'static str, Vec<String>) {
    let vehicles = scene.vehicles.iter();
    let columns: Vec<String> = vehicles
        .filter_map(|vehicle| {
            let nominal = output_name(QuantityKind::NominalSpeed, &vehicle.name);
            let vx = format!("{}.vx", vehicle.name);
            [nominal, vx]
                .into_iter()
                .find(|name| trace.column(name).is_some())
        })
        .collect();
    let nominal = columns
        .iter()
        .all(|c| reports(c, QuantityKind::NominalSpeed));
    let title = if nominal {
        "Nominal speed"
    } else {
        "Speed of each vehicle"
    };
    (title, columns)
}

/// The spans of `x` in which any contact is open (its `.state` is 0).
fn flights(trace: &Trace, x: &[f64]) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    let contact_states = trace
        .names
        .iter()
        .filter(|n| reports(n, QuantityKind::ContactClosed));
    for name in contact_states {
        let Some(state) = trace.column(name) else {
            continue;
        };
        let mut start = None;
        for (&x, &closed) in x.iter().zip(state) {
            match (start, closed == 0.0) {
                (None, true) => start = Some(x),
                (Some(from), false) => {
                    spans.push((from, x));
                    start = None;
                }
                _ => {}
            }
        }
        if let (Some(from), Some(&end)) = (start, x.last()) {
            spans.push((from, end));
        }
    }
    spans
}

/// Whether the scene has more than the paper's one body: then the plot
/// shows every contact's force and the sprung bodies' accelerations.
/// Moving forces have no body, contact or energy balance to draw: the
/// deck's deflection, acceleration and section moments.
fn force_panels(
    scene: &Scene,
    trace: &Trace,
    curve: &dyn Fn(String, &[f64], f64) -> Curve,
) -> Vec<Panel> {
    let columns = |kinds: &[QuantityKind], scale: f64| -> Vec<Curve> {
        columns_of(trace, kinds, &|_| true)
            .into_iter()
            .map(|(name, values)| curve(name, values, scale))
            .collect()
    };
    let (scale, y_label) = deflection_scale(scene);
    let panel =
        |title: &str, y_label: String, curves| plain_panel(title, &y_label, Some(2), curves);
    let mut panels = vec![
        panel(
            "Sensor deflection",
            y_label,
            columns(&[QuantityKind::Sensor], scale),
        ),
        panel(
            "Sensor acceleration",
            "acceleration (m/s^2)".into(),
            columns(&[QuantityKind::SensorAcceleration], 1.0),
        ),
    ];
    // A support's moment too (the name's `.moment`, as before the
    // catalogue was asked): the clamps' moments share the panel.
    let moments = columns(
        &[QuantityKind::SectionMoment, QuantityKind::ReactionMoment],
        1e3,
    );
    if !moments.is_empty() {
        panels.push(panel(
            "Section bending moment",
            "moment (kN m)".into(),
            moments,
        ));
    }
    panels
}

fn has_vehicles(scene: &Scene) -> bool {
    scene.vehicles.len() > 1
        || !matches!(
            scene.vehicles[0].kind,
            crate::scene::BodyKind::Wheel | crate::scene::BodyKind::Glider
        )
}

/// The chart of one panel, with x and y in data units.
type Chart<'a, 'b> = plot_style::Chart<'a, BitMapBackend<'b>>;
type DrawResult =
    Result<(), DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

fn draw_panel(
    panel: &Panel,
    area: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    x_range: Range<f64>,
    x_label: &str,
    text: Text,
) -> DrawResult {
    let y_range = padded_range(
        panel
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(|&(_, y)| y)),
    );
    let labelled = text == Text::Labelled;
    let box_height = legend_height(panel.curves.len(), area.dim_in_pixel().1);
    let (legend, y_range) = legend_place(&panel.curves, &x_range, y_range, box_height);
    let mut builder = ChartBuilder::on(area);
    builder.margin(15);
    if labelled {
        builder
            .caption(&panel.title, (FONT, 22))
            .x_label_area_size(40)
            .y_label_area_size(90);
    }
    let mut chart = builder.build_cartesian_2d(x_range.clone(), y_range.clone())?;
    if labelled {
        draw_mesh(&mut chart, panel, &y_range, x_label)?;
    } else {
        // Without a font the mesh cannot be labelled: frame the panel.
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x_range.start, y_range.start), (x_range.end, y_range.end)],
            BLACK.stroke_width(1),
        )))?;
    }
    chart.draw_series(panel.flights.iter().map(|&(from, to)| {
        Rectangle::new(
            [(from, y_range.start), (to, y_range.end)],
            BLACK.mix(0.12).filled(),
        )
    }))?;
    draw_curves(&mut chart, panel, &y_range, labelled)?;
    if labelled && !panel.curves.is_empty() {
        chart
            .configure_series_labels()
            .position(legend)
            .label_font((FONT, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
    }
    Ok(())
}

/// The labelled axes and grid.
fn draw_mesh(chart: &mut Chart, panel: &Panel, y_range: &Range<f64>, x_label: &str) -> DrawResult {
    let span = y_range.end - y_range.start;
    let decimals = panel.y_decimals.map(|d| d.max(tick_decimals(span)));
    let format_y = |y: &f64| tick_label(*y, span, decimals);
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(&panel.y_label)
        .label_style((FONT, 15))
        .y_label_formatter(&format_y)
        .draw()
}

/// The curves, each with its legend entry where the panel is labelled.
fn draw_curves(
    chart: &mut Chart,
    panel: &Panel,
    y_range: &Range<f64>,
    labelled: bool,
) -> DrawResult {
    // Two one-pixel lines a pixel apart, not one two-pixel line: plotters
    // joins wide segments with unlimited miters, so a spike (a landing's
    // force) drew a needle far out of its panel.
    let pixels = chart.plotting_area().dim_in_pixel().1.max(1);
    let one_pixel = (y_range.end - y_range.start) / f64::from(pixels);
    for (i, curve) in panel.curves.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let lifted = curve.points.iter().map(|&(x, y)| (x, y + one_pixel));
        chart.draw_series(LineSeries::new(lifted, colour.stroke_width(1)))?;
        let series = chart.draw_series(LineSeries::new(
            curve.points.iter().copied(),
            colour.stroke_width(1),
        ))?;
        if labelled {
            series.label(&curve.label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        }
    }
    Ok(())
}

/// Digits after the point that tell apart ticks of an axis spanning
/// `span`: about ten ticks, one digit more than their spacing needs (a
/// speed between 9.998 and 10.003 m/s gets 4, not the "10.00" repeated).
pub fn tick_decimals(span: f64) -> usize {
    if !(span > 0.0 && span.is_finite()) {
        return 2;
    }
    let spacing = span / 10.0;
    ((-libm::log10(spacing)).ceil() + 1.0).clamp(0.0, 15.0) as usize
}

/// A tick's label: fixed `decimals`, or scientific when `None`; a value
/// within round-off of zero on an axis spanning `span` is "0" (not
/// "-4.1e-25").
pub fn tick_label(y: f64, span: f64, decimals: Option<usize>) -> String {
    if y == 0.0 || y.abs() <= 1e-9 * span {
        return "0".to_string();
    }
    match decimals {
        Some(decimals) => format!("{y:.decimals$}"),
        None => format!("{y:.1e}"),
    }
}

/// The legend box's height as a fraction of the plotting area of a panel
/// `panel_pixels` high: a row of 15-px text per curve and its frame,
/// against the panel less its caption, axis labels and margins.
fn legend_height(curves: usize, panel_pixels: u32) -> f64 {
    let plot_pixels = f64::from(panel_pixels.saturating_sub(100).max(60));
    ((22 * curves.max(1) + 14) as f64 / plot_pixels).min(0.5)
}

/// The legend's corner and the y range to draw: the least crowded corner;
/// when even that one would hide part of a curve (a force that fills its
/// panel), the range grows upward so that the legend sits above them all.
pub fn legend_place(
    curves: &[Curve],
    x: &Range<f64>,
    y: Range<f64>,
    box_height: f64,
) -> (SeriesLabelPosition, Range<f64>) {
    let (corner, covered) = least_crowded_corner(curves, x, &y, box_height);
    if covered == 0 {
        return (corner, y);
    }
    let top = y.start + (y.end - y.start) / (1.0 - box_height);
    (SeriesLabelPosition::UpperRight, y.start..top)
}

/// The corner of the chart whose legend box (a third of the width,
/// `box_height` of the height) covers the fewest points of the curves,
/// and how many it covers.
pub fn least_crowded_corner(
    curves: &[Curve],
    x: &Range<f64>,
    y: &Range<f64>,
    box_height: f64,
) -> (SeriesLabelPosition, usize) {
    let (width, height) = (x.end - x.start, y.end - y.start);
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let covered = |right: bool, upper: bool| {
        curves
            .iter()
            .flat_map(|c| &c.points)
            .filter(|&&(px, py)| {
                let fx = (px - x.start) / width;
                let fy = (py - y.start) / height;
                let in_x = if right {
                    fx >= 2.0 / 3.0
                } else {
                    fx <= 1.0 / 3.0
                };
                let in_y = if upper {
                    fy >= 1.0 - box_height
                } else {
                    fy <= box_height
                };
                in_x && in_y
            })
            .count()
    };
    corners
        .into_iter()
        .map(|(corner, right, upper)| (corner, covered(right, upper)))
        .min_by_key(|&(_, count)| count)
        .unwrap_or((SeriesLabelPosition::UpperRight, 0))
}

/// The range of the finite values, widened by 5 % (or by 1 when they are
/// all equal, or [0, 1] when there are none).
fn padded_range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (low, high) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if low > high {
        return 0.0..1.0;
    }
    let span = high - low;
    if span <= f64::EPSILON * high.abs().max(low.abs()) {
        let pad = if high == 0.0 { 1.0 } else { high.abs() * 0.05 };
        return (low - pad)..(high + pad);
    }
    (low - 0.05 * span)..(high + 0.05 * span)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin;
    use crate::simulation::Simulation;

    /// The trace of `steps` grid steps of a built-in scene, and its x axis.
    fn run(name: &str, steps: usize) -> (Scene, Trace, Vec<f64>) {
        let scene = builtin(name).expect(name);
        let mut sim = Simulation::new(&scene).expect("builds");
        let mut trace = Trace::for_outputs(sim.outputs());
        let mut values = vec![0.0; trace.names.len()];
        for k in 0..=steps {
            sim.advance_to(k as f64 * scene.solver.step).expect("steps");
            sim.output_values(&mut values);
            trace.push(sim.time(), &values);
        }
        let (x, _) = normalised_time(&scene, &trace);
        (scene, trace, x)
    }

    #[test]
    fn bogie_vehicles_plot_each_vehicles_speed() {
        let (scene, trace, x) = run("train-2-coaches-2x40-100", 4);
        let panels = panels(&scene, &trace, &x);
        let speed = &panels[0];
        assert_eq!(speed.title, "Speed of each vehicle");
        let labels: Vec<&str> = speed.curves.iter().map(|c| c.label.as_str()).collect();
        assert_eq!(labels, ["coach1.vx", "coach2.vx"]);
        // A constant speed is drawn as its departure from the start, mm/s.
        let v0 = scene.vehicles[0].initial_speed;
        assert_eq!(speed.y_label, format!("V - {v0:.4} m/s (mm/s)"));
        for curve in &speed.curves {
            assert_eq!(curve.points.len(), 5, "{}", curve.label);
            assert_eq!(curve.points[0].1, 0.0);
            for &(_, dv) in &curve.points {
                assert!(dv.abs() < 1.0, "{dv} mm/s");
            }
        }
    }

    #[test]
    fn a_train_plots_in_seconds_with_sprung_bodies_and_wheelsets_apart() {
        let (scene, trace, x) = run("train-2-coaches-2x40-100", 4);
        assert_eq!(x, trace.time);
        let panels = panels(&scene, &trace, &x);
        let panel = |title: &str| panels.iter().find(|p| p.title == title).expect(title);
        let labels = |title: &str| -> Vec<String> {
            panel(title)
                .curves
                .iter()
                .map(|c| c.label.clone())
                .collect()
        };
        // Two car bodies and their four bogies, one by one.
        let sprung = labels("Vertical acceleration of the sprung bodies");
        assert_eq!(sprung.len(), 6, "{sprung:?}");
        assert!(sprung.iter().all(|l| !l.contains("wheelset")), "{sprung:?}");
        // Eight wheelsets: their envelope.
        assert_eq!(
            labels("Vertical acceleration of the unsprung masses"),
            ["largest of 8 unsprung masses", "least of 8 unsprung masses"]
        );
        assert_eq!(
            labels("Contact forces"),
            ["largest of 8 contacts", "least of 8 contacts"]
        );
    }

    #[test]
    fn the_paper_wheel_plots_its_nominal_speed() {
        let (scene, trace, x) = run(crate::scene::DEFAULT_SCENE, 2);
        let panels = panels(&scene, &trace, &x);
        assert_eq!(panels[0].title, "Nominal speed");
        assert_eq!(panels[0].curves.len(), 1);
        assert_eq!(panels[0].curves[0].label, "wheel.nominal_speed");
        assert_eq!(panels[0].curves[0].points.len(), 3);
    }

    #[test]
    fn without_any_speed_output_there_is_no_speed_panel() {
        let mut trace = Trace::with_names(["sensor.midspan.deflection", "energy.balance"]);
        trace.push(0.0, &[0.0, 1.0]);
        trace.push(0.01, &[-0.1, 1.0]);
        let scene = builtin(crate::scene::DEFAULT_SCENE).unwrap();
        let (x, _) = normalised_time(&scene, &trace);
        let titles: Vec<String> = panels(&scene, &trace, &x)
            .into_iter()
            .map(|p| p.title)
            .collect();
        assert_eq!(
            titles,
            ["Sensor deflection", "Energy balance, relative drift"]
        );
    }
}
