//! The envelope of a speed sweep as a PNG: peak deck acceleration and the
//! dynamic amplifications (deflection, moment, shear) against speed, one
//! curve per train, each panel's critical train and speed marked, with the
//! deck acceleration limit of EN 1990 Annex A2 (A2.4.4.2.1) for the track on the
//! deck: 3.5 m/s² on ballasted track, 5 m/s² on slab track.

use super::sweep::{EnvelopeRow, SpeedUnit};
use crate::report::plot::{load_font, Text, FONT};
use crate::report::plot_style::{colour, err, limit_line};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// EN 1990 A2.4.4.2.1(4): deck acceleration limits (m/s²).
pub const BALLASTED_LIMIT: f64 = 3.5;
pub const SLAB_TRACK_LIMIT: f64 = 5.0;

/// The track on the deck, which sets the deck acceleration limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Track {
    Ballasted,
    Slab,
}

impl Track {
    /// `ballasted` or `slab`.
    pub fn parse(text: &str) -> Result<Track, String> {
        match text {
            "ballasted" => Ok(Track::Ballasted),
            "slab" => Ok(Track::Slab),
            _ => Err(format!("--track {text:?}: want \"ballasted\" or \"slab\"")),
        }
    }

    /// The deck acceleration limit of EN 1990 A2.4.4.2.1(4) (m/s²).
    pub fn limit(self) -> f64 {
        match self {
            Track::Ballasted => BALLASTED_LIMIT,
            Track::Slab => SLAB_TRACK_LIMIT,
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            Track::Ballasted => "ballasted track",
            Track::Slab => "slab track",
        }
    }
}

const SIZE: (u32, u32) = (1000, 1340);
/// Pixels above the panels for the figure's title and the trains' key.
const TITLE_HEIGHT: u32 = 90;

/// One panel of the sweep plot: what it draws against speed.
struct Quantity<'a> {
    label: String,
    value: &'a dyn Fn(&EnvelopeRow) -> f64,
}

/// Write the envelope plot of the sweep `title` to `path`: the peak deck
/// acceleration with the limit of `track`, then the dynamic amplification
/// of each quantity the rows carry one for (deflection, moment, shear),
/// each panel's largest value marked with its train and speed.
pub fn write_sweep_plot(
    title: &str,
    rows: &[EnvelopeRow],
    unit: SpeedUnit,
    track: Track,
    path: &Path,
) -> Result<(), String> {
    let text = load_font();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (top, body) = root.split_vertically(TITLE_HEIGHT);
    if text == Text::Labelled {
        let key = top.titled(title, (FONT, 24)).map_err(|e| e.to_string())?;
        draw_key(&key, &trains(rows), track)?;
    }
    let acceleration = |r: &EnvelopeRow| r.peak_acceleration;
    let mut quantities = vec![Quantity {
        label: "peak deck acceleration (m/s²)".into(),
        value: &acceleration,
    }];
    let amplifications = amplification_quantities(rows);
    quantities.extend(amplifications.iter().map(|(label, value)| Quantity {
        label: label.clone(),
        value: value.as_ref(),
    }));
    let areas = body.split_evenly((quantities.len(), 1));
    for (i, (quantity, area)) in quantities.iter().zip(&areas).enumerate() {
        let limit = (i == 0).then_some(track);
        panel(rows, unit, area, text, quantity, limit)?;
    }
    root.present()
        .map_err(|e| format!("cannot write the plot to {}: {e}", path.display()))
}

/// A row's amplification of one quantity.
type Amplification = Box<dyn Fn(&EnvelopeRow) -> f64>;

/// The dynamic amplifications to draw: the deflection's (`daf`) always,
/// then the moment's and the shear's where the rows' design outputs have
/// one (the largest over the sections of that kind).
fn amplification_quantities(rows: &[EnvelopeRow]) -> Vec<(String, Amplification)> {
    let mut quantities: Vec<(String, Amplification)> = vec![(
        "dynamic amplification, deflection".into(),
        Box::new(|r: &EnvelopeRow| r.daf),
    )];
    for (suffix, name) in [(".moment", "moment"), (".shear", "shear")] {
        let largest = move |r: &EnvelopeRow| {
            r.design
                .iter()
                .filter(|d| d.name.ends_with(suffix))
                .filter_map(|d| d.daf)
                .fold(f64::NAN, f64::max)
        };
        if rows.iter().any(|r| largest(r).is_finite()) {
            quantities.push((format!("dynamic amplification, {name}"), Box::new(largest)));
        }
    }
    quantities
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn panel(
    rows: &[EnvelopeRow],
    unit: SpeedUnit,
    area: &Area,
    text: Text,
    quantity: &Quantity,
    limit: Option<Track>,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let value = quantity.value;
    let (low, high) = speed_range(rows);
    let mut top = rows
        .iter()
        .map(value)
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    if let Some(track) = limit {
        top = top.max(track.limit());
    }
    let top = if top > 0.0 { 1.12 * top } else { 1.0 };
    let mut builder = ChartBuilder::on(area);
    builder.margin(12);
    if text == Text::Labelled {
        builder.x_label_area_size(45).y_label_area_size(70);
    }
    let mut chart = builder
        .build_cartesian_2d(low..high, 0.0..top)
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    if text == Text::Labelled {
        mesh.x_desc(format!("speed ({})", unit.label()))
            .y_desc(&quantity.label)
            .label_style((FONT, 16))
            .x_label_formatter(&|x| speed_tick(*x))
            .y_label_formatter(&|y| speed_tick(*y))
            .x_labels(10);
    } else {
        mesh.disable_x_axis().disable_y_axis();
    }
    mesh.draw().map_err(err)?;
    for (i, train) in trains(rows).iter().enumerate() {
        let colour = colour(i);
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.train == *train)
            .map(|r| (r.speed, value(r)))
            .filter(|p| p.1.is_finite())
            .collect();
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(err)?;
    }
    if let Some(track) = limit {
        limit_line(&mut chart, (low, high), track.limit(), None)?;
    }
    mark_largest(&mut chart, rows, unit, value, text)?;
    Ok(())
}

/// The key under the title, for every panel at once (a legend box would
/// hide a panel's low speeds): each train's colour and name, then the
/// dashed deck acceleration limit, in rows as wide as the figure.
fn draw_key(area: &Area, trains: &[&str], track: Track) -> Result<(), String> {
    const ENTRY_GAP: i32 = 22;
    const LINE: i32 = 24;
    let style = TextStyle::from((FONT, 15).into_font()).color(&BLACK);
    let limit = format!("EN 1990 A2 limit, {} {} m/s²", track.label(), track.limit());
    let mut entries: Vec<(String, Option<RGBColor>)> = trains
        .iter()
        .enumerate()
        .map(|(i, t)| (t.to_string(), Some(colour(i))))
        .collect();
    entries.push((limit, None));
    let width = area.dim_in_pixel().0 as i32;
    let (mut x, mut y) = (80, 10);
    for (name, colour) in entries {
        let text_width = area.estimate_text_size(&name, &style).map_err(err)?.0 as i32;
        if x + LINE + 6 + text_width > width - 20 {
            (x, y) = (80, y + 22);
        }
        let line = [(x, y + 8), (x + LINE, y + 8)];
        match colour {
            Some(c) => area.draw(&PathElement::new(line, c.stroke_width(3))),
            None => {
                let half = [(x, y + 8), (x + 10, y + 8)];
                area.draw(&PathElement::new(half, BLACK.stroke_width(2)))
                    .and_then(|_| {
                        area.draw(&PathElement::new(
                            [(x + 14, y + 8), (x + LINE, y + 8)],
                            BLACK.stroke_width(2),
                        ))
                    })
            }
        }
        .map_err(err)?;
        area.draw_text(&name, &style, (x + LINE + 6, y))
            .map_err(err)?;
        x += LINE + 6 + text_width + ENTRY_GAP;
    }
    Ok(())
}

/// The speeds' range, widened where there is one speed only.
fn speed_range(rows: &[EnvelopeRow]) -> (f64, f64) {
    let (low, high) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
            (l.min(r.speed), h.max(r.speed))
        });
    if low < high {
        (low, high)
    } else {
        (low - 1.0, low + 1.0)
    }
}

/// The trains in the rows' order, each once.
fn trains(rows: &[EnvelopeRow]) -> Vec<&str> {
    let mut trains: Vec<&str> = Vec::new();
    for row in rows {
        if !trains.contains(&row.train.as_str()) {
            trains.push(&row.train);
        }
    }
    trains
}

/// The row with the largest finite `value`: the critical train and speed.
pub fn largest_row<'a>(
    rows: &'a [EnvelopeRow],
    value: &dyn Fn(&EnvelopeRow) -> f64,
) -> Option<&'a EnvelopeRow> {
    rows.iter()
        .filter(|r| value(r).is_finite())
        .max_by(|a, b| value(a).total_cmp(&value(b)))
}

/// A ring on the panel's largest value, with its train, speed and value
/// written beside it (to its left past the middle of the axis).
fn mark_largest<'a>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    rows: &[EnvelopeRow],
    unit: SpeedUnit,
    value: &dyn Fn(&EnvelopeRow) -> f64,
    text: Text,
) -> Result<(), String> {
    let Some(row) = largest_row(rows, value) else {
        return Ok(());
    };
    let point = (row.speed, value(row));
    let ring = Circle::new(point, 7, BLACK.stroke_width(2));
    chart
        .draw_series(std::iter::once(ring))
        .map_err(|e| e.to_string())?;
    if text != Text::Labelled {
        return Ok(());
    }
    let words = format!(
        "{} at {} {}: {:.2}",
        row.train,
        speed_tick(row.speed),
        unit.label(),
        point.1
    );
    let (low, high) = speed_range(rows);
    let right_half = point.0 > 0.5 * (low + high);
    let style = TextStyle::from((FONT, 15).into_font()).color(&BLACK);
    let (anchor, dx) = if right_half {
        (Pos::new(HPos::Right, VPos::Center), -12)
    } else {
        (Pos::new(HPos::Left, VPos::Center), 12)
    };
    let label =
        EmptyElement::at(point) + plotters::element::Text::new(words, (dx, 0), style.pos(anchor));
    chart
        .draw_series(std::iter::once(label))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// A speed tick as a person writes it: `150`, not `150.0`; a fraction only
/// where the tick has one (`62.5`).
pub fn speed_tick(x: f64) -> String {
    let rounded = x.round();
    if (x - rounded).abs() <= 1e-9 * x.abs().max(1.0) {
        format!("{rounded:.0}")
    } else {
        let text = format!("{x:.3}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

#[cfg(test)]
mod tick_tests {
    use super::{amplification_quantities, largest_row, speed_tick};
    use crate::study::sweep::{DesignPeak, EnvelopeRow};

    fn row(train: &str, speed: f64, acceleration: f64, moment_daf: Option<f64>) -> EnvelopeRow {
        let design = moment_daf
            .map(|daf| DesignPeak {
                name: "section.midspan.moment".into(),
                peak: 1.0,
                is_static: true,
                daf: Some(daf),
            })
            .into_iter()
            .collect();
        EnvelopeRow {
            train: train.into(),
            speed,
            speed_m_s: speed / 3.6,
            peak_deflection: 1e-3,
            peak_acceleration: acceleration,
            peak_acceleration_filtered: acceleration,
            acceleration_cut_off: 30.0,
            daf: 1.0,
            design,
        }
    }

    #[test]
    fn the_marked_row_is_the_largest_and_moment_panels_come_with_moment_dafs() {
        let rows = [
            row("A", 200.0, 2.0, Some(1.2)),
            row("B", 200.0, f64::NAN, Some(3.0)),
            row("B", 210.0, 5.0, Some(1.1)),
        ];
        let acceleration = |r: &EnvelopeRow| r.peak_acceleration;
        let worst = largest_row(&rows, &acceleration).unwrap();
        assert_eq!((worst.train.as_str(), worst.speed), ("B", 210.0));
        let quantities = amplification_quantities(&rows);
        let labels: Vec<&str> = quantities.iter().map(|q| q.0.as_str()).collect();
        assert_eq!(
            labels,
            [
                "dynamic amplification, deflection",
                "dynamic amplification, moment"
            ]
        );
        let moment = &quantities[1].1;
        let critical = largest_row(&rows, moment.as_ref()).unwrap();
        assert_eq!((critical.train.as_str(), critical.speed), ("B", 200.0));
        let without: Vec<EnvelopeRow> = rows
            .iter()
            .map(|r| row(&r.train, r.speed, 1.0, None))
            .collect();
        assert_eq!(amplification_quantities(&without).len(), 1);
    }

    #[test]
    fn speed_ticks_are_whole_numbers_where_they_are_whole() {
        assert_eq!(speed_tick(150.0), "150");
        assert_eq!(speed_tick(149.999_999_999_99), "150");
        assert_eq!(speed_tick(0.0), "0");
        assert_eq!(speed_tick(62.5), "62.5");
        assert_eq!(speed_tick(27.777_777), "27.778");
    }
}
