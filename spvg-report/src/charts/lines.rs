//! Line charts: series against the frame index (or any x).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{Colour, FONT, chart_error, rgb};
use crate::error::ReportError;

/// One series of a line chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// Its legend entry.
    pub label: String,
    /// Its points (x, y); non-finite ones are left out.
    pub points: Vec<(f64, f64)>,
    /// Its colour.
    pub colour: Colour,
    /// Dashed instead of solid.
    pub dashed: bool,
    /// Stroke width in pixels.
    pub width: u32,
}

/// Where a line chart's legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Legend {
    /// In a column of this many pixels right of the plot, so it never covers a line.
    Column(u32),
    /// Inside the plot, upper right.
    UpperRight,
    /// Inside the plot, upper left.
    UpperLeft,
}

/// A chart of lines.
#[derive(Clone, Debug, PartialEq)]
pub struct LineChart {
    /// The caption above the plot.
    pub caption: String,
    /// The x axis' name.
    pub x_desc: String,
    /// The y axis' name.
    pub y_desc: String,
    /// The x range.
    pub x: (f64, f64),
    /// The y range (of the values, also on a log axis); points outside are drawn at its
    /// edge.
    pub y: (f64, f64),
    /// A log10 y axis, labelled with the values (`plotters`' own log axis crowds its
    /// labels into the top decade).
    pub y_log: bool,
    /// The series.
    pub lines: Vec<Line>,
    /// Where the legend goes.
    pub legend: Legend,
    /// The chart's size in pixels.
    pub size: (u32, u32),
    /// An x range shaded grey (a warm-up).
    pub shade_x: Option<(f64, f64)>,
    /// y values drawn as dashed black levels (a bound and its band).
    pub levels: Vec<f64>,
}

impl LineChart {
    /// A chart of `lines` with a column legend, 960 x 480 pixels, nothing shaded and no
    /// levels.
    #[must_use]
    pub fn new(caption: String, x: (f64, f64), y: (f64, f64), lines: Vec<Line>) -> Self {
        Self {
            caption,
            x_desc: "frame".into(),
            y_desc: String::new(),
            x,
            y,
            y_log: false,
            lines,
            legend: Legend::Column(150),
            size: (960, 480),
            shade_x: None,
            levels: Vec::new(),
        }
    }
}

/// Draws `chart` into `dir/file`.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn draw_lines(dir: &Path, file: &str, chart: &LineChart) -> Result<(), ReportError> {
    let path = dir.join(file);
    draw_lines_at(&path, chart).map_err(chart_error(&path))
}

fn draw_lines_at(path: &Path, c: &LineChart) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, c.size).into_drawing_area();
    root.fill(&WHITE)?;
    let plot = match c.legend {
        Legend::Column(w) => {
            let (plot, key) = root.split_horizontally(c.size.0.saturating_sub(w));
            draw_key(&key, &c.lines)?;
            plot
        }
        Legend::UpperRight | Legend::UpperLeft => root.clone(),
    };
    let map = |v: f64| if c.y_log { v.log10() } else { v };
    let (lo, hi) = (map(c.y.0), map(c.y.1));
    let (lo, hi) = if lo.is_finite() && hi.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (0.0, 1.0)
    };
    let (x0, x1) = if c.x.1 > c.x.0 { c.x } else { (0.0, 1.0) };
    let mut chart = ChartBuilder::on(&plot)
        .caption(c.caption.as_str(), (FONT, 20))
        .margin(14)
        .x_label_area_size(46)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, lo..hi)?;
    let log_label = |v: &f64| format!("{:.1e}", 10f64.powf(*v));
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(c.x_desc.as_str())
        .y_desc(c.y_desc.as_str())
        .x_label_formatter(&|v| format!("{v:.0}"))
        .light_line_style(RGBColor(235, 235, 235))
        .label_style((FONT, 15));
    if c.y_log {
        mesh.y_label_formatter(&log_label);
    }
    mesh.draw()?;
    if let Some((a, b)) = c.shade_x {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(a, lo), (b, hi)],
            RGBColor(240, 240, 240).filled(),
        )))?;
    }
    for &y in &c.levels {
        let y = map(y);
        chart.draw_series(DashedLineSeries::new(
            [(x0, y), (x1, y)],
            6,
            4,
            BLACK.stroke_width(1),
        ))?;
    }
    let inside = !matches!(c.legend, Legend::Column(_));
    for line in &c.lines {
        let colour = rgb(line.colour);
        let style = colour.stroke_width(line.width);
        let points = line
            .points
            .iter()
            .map(|&(x, y)| (x, map(y)))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| (x, y.clamp(lo, hi)));
        let drawn = if line.dashed {
            chart.draw_series(DashedLineSeries::new(points, 6, 4, style))?
        } else {
            chart.draw_series(LineSeries::new(points, style))?
        };
        if inside {
            let w = line.width;
            drawn.label(line.label.as_str()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(w))
            });
        }
    }
    let corner = match c.legend {
        Legend::Column(_) => None,
        Legend::UpperRight => Some(SeriesLabelPosition::UpperRight),
        Legend::UpperLeft => Some(SeriesLabelPosition::UpperLeft),
    };
    if let Some(position) = corner {
        chart
            .configure_series_labels()
            .position(position)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 13))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The legend of a line chart in its own column.
fn draw_key(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>> {
    for (i, line) in lines.iter().enumerate() {
        let y = 60 + 24 * i as i32;
        let c = rgb(line.colour);
        area.draw(&PathElement::new(vec![(6, y), (34, y)], c.stroke_width(3)))?;
        area.draw(&Text::new(
            line.label.clone(),
            (42, y - 8),
            (FONT, 15).into_font(),
        ))?;
    }
    Ok(())
}
