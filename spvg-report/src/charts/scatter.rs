//! Panels of labelled points (the subsurface section's Pareto charts): every point drawn,
//! the labels of points drawn at the same place merged into one, and each label put in the
//! first free spot around its point so that no two overprint.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{Colour, FONT, chart_error, rgb};
use crate::error::ReportError;

/// One point.
#[derive(Clone, Debug, PartialEq)]
pub struct ScatterPoint {
    /// Position.
    pub x: f64,
    /// Position.
    pub y: f64,
    /// Its label.
    pub label: String,
    /// Its colour.
    pub colour: Colour,
    /// Filled (else a ring, drawn first so the filled points sit on top).
    pub filled: bool,
}

/// One panel.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Its caption.
    pub caption: String,
    /// Its points; non-finite ones are left out.
    pub points: Vec<ScatterPoint>,
}

/// A chart of panels, two per row.
pub struct ScatterChart<'a> {
    /// The title above the panels.
    pub title: String,
    /// The x axis' name.
    pub x_desc: String,
    /// The y axis' name.
    pub y_desc: String,
    /// The panels.
    pub panels: Vec<Panel>,
    /// The chart's size in pixels.
    pub size: (u32, u32),
    /// The one label of points drawn at the same place, from theirs.
    pub merge: &'a dyn Fn(&[&str]) -> String,
    /// The colour of a label's text, from its label.
    pub ink: &'a dyn Fn(&str) -> Colour,
}

impl core::fmt::Debug for ScatterChart<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ScatterChart")
            .field("title", &self.title)
            .field("panels", &self.panels)
            .finish_non_exhaustive()
    }
}

/// Draws `chart` into `dir/file`.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn draw_scatter(dir: &Path, file: &str, chart: &ScatterChart<'_>) -> Result<(), ReportError> {
    let path = dir.join(file);
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, chart.size).into_drawing_area();
        root.fill(&WHITE)?;
        let body = root.titled(&chart.title, (FONT, 22))?;
        let cols = if chart.panels.len() > 1 { 2 } else { 1 };
        let rows = chart.panels.len().div_ceil(cols).max(1);
        for (area, panel) in body.split_evenly((rows, cols)).iter().zip(&chart.panels) {
            draw_panel(area, panel, chart)?;
        }
        root.present()?;
        Ok(())
    };
    draw().map_err(chart_error(&path))
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    panel: &Panel,
    chart: &ScatterChart<'_>,
) -> Result<(), Box<dyn std::error::Error>> {
    let pts: Vec<&ScatterPoint> = panel
        .points
        .iter()
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect();
    let fold = |f: fn(&ScatterPoint) -> f64| {
        pts.iter()
            .map(|p| f(p))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let (_, x1) = fold(|p| p.x);
    let (y0, y1) = fold(|p| p.y);
    if !(x1.is_finite() && y0.is_finite()) {
        area.draw(&Text::new(
            format!("{}: no points", panel.caption),
            (20, 20),
            (FONT, 16).into_font(),
        ))?;
        return Ok(());
    }
    // Room on the right for the labels of the rightmost points.
    let x_hi = (x1 * 1.25).max(1e-3);
    let pad = ((y1 - y0) * 0.08).max(0.3);
    let mut c = ChartBuilder::on(area)
        .caption(panel.caption.as_str(), (FONT, 19))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..x_hi, (y0 - pad)..(y1 + pad))?;
    c.configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .x_desc(chart.x_desc.as_str())
        .y_desc(chart.y_desc.as_str())
        .label_style((FONT, 14))
        .draw()?;
    // Rings first, so the filled points sit on top.
    let mut order = pts.clone();
    order.sort_by_key(|p| p.filled);
    for p in &order {
        let colour = rgb(p.colour);
        let style = if p.filled {
            colour.filled()
        } else {
            colour.stroke_width(2)
        };
        c.draw_series(std::iter::once(Circle::new((p.x, p.y), 5, style)))?;
    }
    let at: Vec<(i32, i32)> = pts.iter().map(|p| c.backend_coord(&(p.x, p.y))).collect();
    draw_labels(area, &pts, &at, chart)
}

/// Labels the points of a panel (`at`: their pixel positions): points drawn at the same
/// place share one label; each label takes the first free spot around its point, so no
/// two labels overprint.
fn draw_labels(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    pts: &[&ScatterPoint],
    at: &[(i32, i32)],
    chart: &ScatterChart<'_>,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut groups: Vec<((i32, i32), Vec<&str>)> = Vec::new();
    for (&(x, y), p) in at.iter().zip(pts) {
        match groups
            .iter_mut()
            .find(|(q, _)| (q.0 - x).abs() <= 3 && (q.1 - y).abs() <= 3)
        {
            Some((_, labels)) => labels.push(&p.label),
            None => groups.push(((x, y), vec![&p.label])),
        }
    }
    let mut taken: Vec<(i32, i32, i32, i32)> = at
        .iter()
        .map(|&(x, y)| (x - 6, y - 6, x + 6, y + 6))
        .collect();
    let (left, right) = {
        let (xs, _) = area.get_pixel_range();
        (xs.start, xs.end)
    };
    for ((x, y), labels) in groups {
        let text = (chart.merge)(&labels);
        let w = (text.len() as i32 * 13) / 2 + 4;
        let h = 14;
        let spots = [
            (8, -7),
            (8, -20),
            (8, 6),
            (-w - 8, -7),
            (8, -33),
            (8, 19),
            (-w - 8, -20),
            (-w - 8, 6),
            (8, -46),
            (8, 32),
            (-w - 8, -33),
            (-w - 8, 19),
            (8, -59),
            (8, 45),
        ];
        // A spot is free when the label stays inside the panel and covers no point or label.
        let free = |dx: i32, dy: i32| {
            let r = (x + dx, y + dy, x + dx + w, y + dy + h);
            r.2 <= right
                && r.0 >= left
                && !taken
                    .iter()
                    .any(|t| r.0 < t.2 && t.0 < r.2 && r.1 < t.3 && t.1 < r.3)
        };
        let (dx, dy) = spots
            .iter()
            .copied()
            .find(|&(dx, dy)| free(dx, dy))
            .unwrap_or(spots[0]);
        taken.push((x + dx, y + dy, x + dx + w, y + dy + h));
        let ink = rgb((chart.ink)(labels.first().copied().unwrap_or("")));
        area.draw(&Text::new(
            text,
            (
                x + dx - area.get_base_pixel().0,
                y + dy - area.get_base_pixel().1,
            ),
            (FONT, 12).into_font().color(&ink),
        ))?;
    }
    Ok(())
}
