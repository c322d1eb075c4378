//! The envelope of a speed sweep as a PNG: peak deck acceleration and the
//! dynamic amplification against speed, one curve per train, with the deck
//! acceleration limit of EN 1990 Annex A2 (A2.4.4.2.1) for the track on the
//! deck: 3.5 m/s² on ballasted track, 5 m/s² on slab track.

use super::plot::{load_font, Text, FONT};
use super::plot_style::{colour, legend, legend_line, limit_line};
use crate::study::sweep::{EnvelopeRow, SpeedUnit};
use plotters::prelude::*;
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

const SIZE: (u32, u32) = (1000, 900);

/// Write the envelope plot to `path`, with the deck acceleration limit of
/// `track`.
pub fn write_sweep_plot(
    rows: &[EnvelopeRow],
    unit: SpeedUnit,
    track: Track,
    path: &Path,
) -> Result<(), String> {
    let text = load_font();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((2, 1));
    let acceleration = |r: &EnvelopeRow| r.peak_acceleration;
    let daf = |r: &EnvelopeRow| r.daf;
    panel(
        rows,
        unit,
        &areas[0],
        text,
        ("peak deck acceleration (m/s²)", &acceleration),
        Some(track),
    )?;
    panel(
        rows,
        unit,
        &areas[1],
        text,
        ("dynamic amplification (deflection)", &daf),
        None,
    )?;
    root.present()
        .map_err(|e| format!("cannot write the plot to {}: {e}", path.display()))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn panel(
    rows: &[EnvelopeRow],
    unit: SpeedUnit,
    area: &Area,
    text: Text,
    (label, value): (&str, &dyn Fn(&EnvelopeRow) -> f64),
    limit: Option<Track>,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let (low, high) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
            (l.min(r.speed), h.max(r.speed))
        });
    let (low, high) = if low < high {
        (low, high)
    } else {
        (low - 1.0, low + 1.0)
    };
    let mut top = rows
        .iter()
        .map(value)
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    if let Some(track) = limit {
        top = top.max(track.limit());
    }
    let top = if top > 0.0 { 1.1 * top } else { 1.0 };
    let mut builder = ChartBuilder::on(area);
    builder.margin(15);
    if text == Text::Labelled {
        builder.x_label_area_size(45).y_label_area_size(70);
    }
    let mut chart = builder
        .build_cartesian_2d(low..high, 0.0..top)
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    if text == Text::Labelled {
        mesh.x_desc(format!("speed ({})", unit.label()))
            .y_desc(label)
            .label_style((FONT, 16))
            .x_label_formatter(&|x| speed_tick(*x))
            .x_labels(10);
    } else {
        mesh.disable_x_axis().disable_y_axis();
    }
    mesh.draw().map_err(err)?;
    let mut trains: Vec<&str> = rows.iter().map(|r| r.train.as_str()).collect();
    trains.dedup();
    for (i, train) in trains.iter().enumerate() {
        let colour = colour(i);
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.train == *train)
            .map(|r| (r.speed, value(r)))
            .filter(|p| p.1.is_finite())
            .collect();
        let series = chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(err)?;
        if text == Text::Labelled {
            series
                .label(*train)
                .legend(legend_line(colour.stroke_width(2)));
        }
    }
    if let Some(track) = limit {
        let limit = track.limit();
        let name = (text == Text::Labelled)
            .then(|| format!("EN 1990 A2 limit, {} {limit} m/s²", track.label()));
        limit_line(&mut chart, (low, high), limit, name)?;
    }
    if text == Text::Labelled {
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    }
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
    use super::speed_tick;

    #[test]
    fn speed_ticks_are_whole_numbers_where_they_are_whole() {
        assert_eq!(speed_tick(150.0), "150");
        assert_eq!(speed_tick(149.999_999_999_99), "150");
        assert_eq!(speed_tick(0.0), "0");
        assert_eq!(speed_tick(62.5), "62.5");
        assert_eq!(speed_tick(27.777_777), "27.778");
    }
}
