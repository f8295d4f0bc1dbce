//! The report's charts, drawn by `plotters` into SVG (text stays SVG text, so no font files
//! are needed): per-frame series of each scene and the Pareto panels of every run.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::ReportError;
use crate::evaluate::{FrameRecord, RunSummary};

/// Font family of every chart label (resolved by the SVG viewer).
const FONT: &str = "sans-serif";

/// Size of a per-frame chart, pixels.
const SERIES_SIZE: (u32, u32) = (960, 480);

/// Size of a Pareto chart (2 x 2 panels), pixels.
const PARETO_SIZE: (u32, u32) = (1400, 1100);

/// Fraction of the PSNR points left out at the low end of the per-frame PSNR chart.
pub const PSNR_CLIP: f64 = 0.02;

/// The per-frame PSNR chart's y axis ends this many dB above the highest median PSNR of a
/// run: frames far above every run's median are near-black frames (the flash's troughs),
/// where PSNR spikes towards its 120 dB floor and would flatten every other line.
pub const PSNR_SPIKE_DB: f64 = 8.0;

/// Whether a run label names a swept setting (a default run's label is the model name).
#[inline]
#[must_use]
pub fn is_sweep(label: &str) -> bool {
    label.contains(' ')
}

/// The colour of a run: its model's colour, lighter for a swept setting.
#[must_use]
pub fn colour(label: &str) -> RGBColor {
    let [r, g, b]: [u8; 3] = match label.split(' ').next().unwrap_or("") {
        "fixed8" => [190, 190, 190],
        "fixed16" => [140, 140, 140],
        "fixed32" => [90, 90, 90],
        "fixed64" => [20, 20, 20],
        "as" => [214, 39, 40],
        "ccv" => [44, 160, 44],
        "ocv" => [31, 119, 180],
        "budget" => [255, 127, 14],
        _ => [148, 103, 189],
    };
    if is_sweep(label) {
        let light = |c: u8| ((u16::from(c) + 255) / 2) as u8;
        RGBColor(light(r), light(g), light(b))
    } else {
        RGBColor(r, g, b)
    }
}

/// A per-frame quantity that gets its own chart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Series {
    /// Mean samples per subsurface pixel (linear axis from 0).
    Spp,
    /// Single-frame PSNR, dB (axis from the [`PSNR_CLIP`] percentile to
    /// [`PSNR_SPIKE_DB`] above the highest run median).
    Psnr,
    /// Single-frame relative MSE (logarithmic axis).
    RelMse,
}

impl Series {
    /// Every series, in report order.
    pub const ALL: [Self; 3] = [Self::Spp, Self::Psnr, Self::RelMse];

    /// File-name part.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Spp => "spp",
            Self::Psnr => "psnr",
            Self::RelMse => "relmse",
        }
    }

    fn value(self, r: &FrameRecord) -> f64 {
        match self {
            Self::Spp => r.spp,
            Self::Psnr => r.psnr,
            Self::RelMse => r.relmse,
        }
    }

    fn title(self) -> &'static str {
        match self {
            Self::Spp => "mean spp per frame",
            Self::Psnr => "single-frame PSNR per frame",
            Self::RelMse => "single-frame relMSE per frame (log axis)",
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Self::Spp => "mean spp",
            Self::Psnr => "PSNR (dB)",
            Self::RelMse => "relMSE",
        }
    }
}

/// The value at quantile `q` of sorted `v` (nearest rank; NaN when empty).
fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let i = ((v.len() - 1) as f64 * q).round() as usize;
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// The y range of a series chart and how many points lie outside it.
fn y_range(series: Series, runs: &[(String, Vec<FrameRecord>)]) -> (f64, f64, usize) {
    let mut v: Vec<f64> = runs
        .iter()
        .flat_map(|(_, r)| r.iter().map(|r| series.value(r)))
        .filter(|v| v.is_finite() && (series != Series::RelMse || *v > 0.0))
        .collect();
    v.sort_by(f64::total_cmp);
    let (lo, hi) = match series {
        Series::Spp => (0.0, v.last().copied().unwrap_or(64.0).max(64.0) * 1.05),
        Series::Psnr => {
            let top_median = runs
                .iter()
                .map(|(_, r)| {
                    let mut m: Vec<f64> =
                        r.iter().map(|r| r.psnr).filter(|v| v.is_finite()).collect();
                    m.sort_by(f64::total_cmp);
                    quantile(&m, 0.5)
                })
                .filter(|m| m.is_finite())
                .fold(f64::NEG_INFINITY, f64::max);
            let a = quantile(&v, PSNR_CLIP);
            let b = v
                .last()
                .copied()
                .unwrap_or(f64::NAN)
                .min(top_median + PSNR_SPIKE_DB);
            let pad = ((b - a) * 0.05).max(0.5);
            (a - pad, b + pad)
        }
        Series::RelMse => {
            let (a, b) = (
                v.first().copied().unwrap_or(1e-6),
                v.last().copied().unwrap_or(1.0),
            );
            (a / 1.5, b * 1.5)
        }
    };
    let (lo, hi) = if lo.is_finite() && hi.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (0.0, 1.0)
    };
    let outside = v.iter().filter(|x| **x < lo || **x > hi).count();
    (lo, hi, outside)
}

fn draw_err(path: &Path) -> impl Fn(Box<dyn std::error::Error>) -> ReportError + '_ {
    move |e| ReportError::Chart {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Writes `<scene>_<series>.svg`: `series` of every run in `runs` against the frame index,
/// one line per run with a legend. Returns the file name and, for PSNR, the number of points
/// outside the clipped axis (drawn at its edge).
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_series(
    dir: &Path,
    scene: &str,
    series: Series,
    runs: &[(String, Vec<FrameRecord>)],
) -> Result<(String, usize), ReportError> {
    let file = format!("{scene}_{}.svg", series.name());
    let path = dir.join(&file);
    let (lo, hi, outside) = y_range(series, runs);
    let frames = runs.iter().map(|(_, r)| r.len()).max().unwrap_or(2).max(2) as f64 - 1.0;
    let caption = match series {
        Series::Psnr if outside > 0 => format!(
            "{scene}: {} ({outside} points off the axis, drawn at its edge)",
            series.title()
        ),
        _ => format!("{scene}: {}", series.title()),
    };
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, SERIES_SIZE).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot, key) = root.split_horizontally(SERIES_SIZE.0 - LEGEND_W);
        draw_key(&key, runs)?;
        let clamp = |v: f64| v.clamp(lo, hi);
        let mut builder = ChartBuilder::on(&plot);
        builder
            .caption(caption.as_str(), (FONT, 20))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(78);
        if series == Series::RelMse {
            // log10 of the value on a linear axis, labelled with the value: plotters' own
            // log axis crowds its labels into the top decade.
            let mut chart = builder.build_cartesian_2d(0.0..frames, lo.log10()..hi.log10())?;
            chart
                .configure_mesh()
                .x_desc("frame")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .light_line_style(RGBColor(235, 235, 235))
                .y_desc(series.axis())
                .x_label_formatter(&|v| format!("{v:.0}"))
                .light_line_style(RGBColor(235, 235, 235))
                .y_label_formatter(&|v| format!("{:.1e}", 10f64.powf(*v)))
                .label_style((FONT, 15))
                .draw()?;
            for (label, recs) in runs {
                let c = colour(label);
                chart.draw_series(LineSeries::new(
                    recs.iter()
                        .filter(|r| r.relmse > 0.0 && r.relmse.is_finite())
                        .map(|r| (f64::from(r.frame), clamp(r.relmse).log10())),
                    c.stroke_width(2),
                ))?;
            }
        } else {
            let mut chart = builder.build_cartesian_2d(0.0..frames, lo..hi)?;
            chart
                .configure_mesh()
                .x_desc("frame")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .light_line_style(RGBColor(235, 235, 235))
                .y_desc(series.axis())
                .label_style((FONT, 15))
                .draw()?;
            for (label, recs) in runs {
                let c = colour(label);
                chart.draw_series(LineSeries::new(
                    recs.iter()
                        .map(|r| (f64::from(r.frame), series.value(r)))
                        .filter(|(_, v)| v.is_finite())
                        .map(|(x, v)| (x, clamp(v))),
                    c.stroke_width(2),
                ))?;
            }
        }
        root.present()?;
        Ok(())
    };
    draw().map_err(draw_err(&path))?;
    Ok((file, if series == Series::Psnr { outside } else { 0 }))
}

/// Writes `<scene>_budget.svg`: each run's frame total over the budget (its mean spp over
/// `budget_spp`, both per subsurface pixel) against the frame index, with the budget
/// (1) and the acceptance band (`1 +- BUDGET_BAND`) as dashed lines and the warm-up
/// shaded. Returns the file name.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_budget(
    dir: &Path,
    scene: &str,
    budget_spp: f64,
    runs: &[(String, Vec<FrameRecord>)],
) -> Result<String, ReportError> {
    use crate::evaluate::{BUDGET_BAND, BUDGET_WARMUP};
    let file = format!("{scene}_budget.svg");
    let path = dir.join(&file);
    let frames = runs.iter().map(|(_, r)| r.len()).max().unwrap_or(2).max(2) as f64 - 1.0;
    let hi = runs
        .iter()
        .flat_map(|(_, r)| r.iter().map(|r| r.spp / budget_spp))
        .filter(|v| v.is_finite())
        .fold(1.0 + 2.0 * BUDGET_BAND, f64::max)
        .min(64.0 / budget_spp);
    let caption = format!("{scene}: frame total / budget ({budget_spp} spp per pixel)");
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, SERIES_SIZE).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot, key) = root.split_horizontally(SERIES_SIZE.0 - LEGEND_W);
        draw_key(&key, runs)?;
        let mut chart = ChartBuilder::on(&plot)
            .caption(caption.as_str(), (FONT, 20))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(78)
            .build_cartesian_2d(0.0..frames, 0.0..hi)?;
        chart
            .configure_mesh()
            .x_desc("frame")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .light_line_style(RGBColor(235, 235, 235))
            .y_desc("total / budget")
            .label_style((FONT, 15))
            .draw()?;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(0.0, 0.0), (f64::from(BUDGET_WARMUP), hi)],
            RGBColor(240, 240, 240).filled(),
        )))?;
        for y in [1.0 - BUDGET_BAND, 1.0, 1.0 + BUDGET_BAND] {
            chart.draw_series(DashedLineSeries::new(
                [(0.0, y), (frames, y)],
                6,
                4,
                BLACK.stroke_width(1),
            ))?;
        }
        for (label, recs) in runs {
            chart.draw_series(LineSeries::new(
                recs.iter()
                    .map(|r| (f64::from(r.frame), r.spp / budget_spp))
                    .filter(|(_, v)| v.is_finite())
                    .map(|(x, v)| (x, v.min(hi))),
                colour(label).stroke_width(2),
            ))?;
        }
        root.present()?;
        Ok(())
    };
    draw().map_err(draw_err(&path))?;
    Ok(file)
}

/// Width of the legend column right of a per-frame chart, pixels.
const LEGEND_W: u32 = 150;

/// The legend of a per-frame chart, in its own column so it never covers a line.
fn draw_key(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    runs: &[(String, Vec<FrameRecord>)],
) -> Result<(), Box<dyn std::error::Error>> {
    for (i, (label, _)) in runs.iter().enumerate() {
        let y = 60 + 24 * i as i32;
        let c = colour(label);
        area.draw(&PathElement::new(vec![(6, y), (34, y)], c.stroke_width(3)))?;
        area.draw(&Text::new(
            label.clone(),
            (42, y - 8),
            (FONT, 15).into_font(),
        ))?;
    }
    Ok(())
}

/// The x quantity of a Pareto chart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParetoX {
    /// Mean samples per subsurface pixel.
    Spp,
    /// Median pass time, ms.
    Time,
}

impl ParetoX {
    /// File-name part.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Spp => "spp",
            Self::Time => "time",
        }
    }

    fn value(self, s: &RunSummary) -> f64 {
        match self {
            Self::Spp => s.mean_spp,
            Self::Time => s.p50_ms,
        }
    }
}

/// Writes `pareto_<x>.svg`: mean PSNR against mean spp or p50 pass time, one panel per
/// scene, every run a point labelled with its setting (filled: default setting, hollow:
/// swept). `timing` is appended to the time axis name (e.g. "CPU time").
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_pareto(
    dir: &Path,
    x: ParetoX,
    scenes: &[&str],
    all: &[RunSummary],
    timing: &str,
) -> Result<String, ReportError> {
    let file = format!("pareto_{}.svg", x.name());
    let path = dir.join(&file);
    let x_desc = match x {
        ParetoX::Spp => "mean spp".to_owned(),
        ParetoX::Time => format!("p50 pass time, ms ({timing})"),
    };
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, PARETO_SIZE).into_drawing_area();
        root.fill(&WHITE)?;
        let title = match x {
            ParetoX::Spp => "mean PSNR vs mean spp (filled: report setting, hollow: sweep)",
            ParetoX::Time => "mean PSNR vs p50 pass time (filled: report setting, hollow: sweep)",
        };
        let body = root.titled(title, (FONT, 22))?;
        let cols = if scenes.len() > 1 { 2 } else { 1 };
        let rows = scenes.len().div_ceil(cols).max(1);
        for (panel, scene) in body.split_evenly((rows, cols)).iter().zip(scenes) {
            pareto_panel(panel, scene, x, &x_desc, all)?;
        }
        root.present()?;
        Ok(())
    };
    draw().map_err(draw_err(&path))?;
    Ok(file)
}

fn pareto_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    scene: &str,
    x: ParetoX,
    x_desc: &str,
    all: &[RunSummary],
) -> Result<(), Box<dyn std::error::Error>> {
    let pts: Vec<(f64, f64, &str)> = all
        .iter()
        .filter(|s| s.scene == scene)
        .map(|s| (x.value(s), s.mean_psnr, s.label.as_str()))
        .filter(|(a, b, _)| a.is_finite() && b.is_finite())
        .collect();
    let fold = |f: fn(&(f64, f64, &str)) -> f64| {
        pts.iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let (_, x1) = fold(|p| p.0);
    let (y0, y1) = fold(|p| p.1);
    if !(x1.is_finite() && y0.is_finite()) {
        area.draw(&Text::new(
            format!("{scene}: no runs"),
            (20, 20),
            (FONT, 16).into_font(),
        ))?;
        return Ok(());
    }
    // Room on the right for the labels of the rightmost points.
    let x_hi = (x1 * 1.25).max(1e-3);
    let pad = ((y1 - y0) * 0.08).max(0.3);
    let mut chart = ChartBuilder::on(area)
        .caption(scene, (FONT, 19))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..x_hi, (y0 - pad)..(y1 + pad))?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .x_desc(x_desc)
        .y_desc("mean PSNR (dB)")
        .label_style((FONT, 14))
        .draw()?;
    // Sweeps first, so the default runs sit on top.
    let mut order: Vec<&(f64, f64, &str)> = pts.iter().collect();
    order.sort_by_key(|p| !is_sweep(p.2));
    for &&(px, py, label) in &order {
        let c = colour(label);
        let style = if is_sweep(label) {
            c.stroke_width(2)
        } else {
            c.filled()
        };
        chart.draw_series(std::iter::once(Circle::new((px, py), 5, style)))?;
    }
    let at: Vec<(i32, i32)> = pts
        .iter()
        .map(|p| chart.backend_coord(&(p.0, p.1)))
        .collect();
    draw_labels(area, &pts, &at)
}

/// Labels the points of a Pareto panel (`at`: their pixel positions): points drawn at the
/// same place share one label; each label takes the first free spot around its point, so
/// no two labels overprint.
fn draw_labels(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    pts: &[(f64, f64, &str)],
    at: &[(i32, i32)],
) -> Result<(), Box<dyn std::error::Error>> {
    let mut groups: Vec<((i32, i32), Vec<&str>)> = Vec::new();
    for (&(x, y), p) in at.iter().zip(pts) {
        match groups
            .iter_mut()
            .find(|(q, _)| (q.0 - x).abs() <= 3 && (q.1 - y).abs() <= 3)
        {
            Some((_, labels)) => labels.push(p.2),
            None => groups.push(((x, y), vec![p.2])),
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
        let text = group_label(&labels);
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
        let ink = text_colour(labels.first().copied().unwrap_or(""));
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

/// One label for runs drawn at the same place: the models joined by `/`, then the
/// setting, or the settings in parentheses when they differ (`report` for the report's):
/// `ccv/ocv kappa=1`, `as/ccv (report, kappa=0)`.
#[must_use]
pub fn group_label(labels: &[&str]) -> String {
    let mut models: Vec<&str> = Vec::new();
    let mut settings: Vec<&str> = Vec::new();
    for l in labels {
        let (m, set) = l.split_once(' ').unwrap_or((l, ""));
        if !models.contains(&m) {
            models.push(m);
        }
        if !settings.contains(&set) {
            settings.push(set);
        }
    }
    let models = models.join("/");
    match settings.as_slice() {
        [""] => models,
        [one] => format!("{models} {one}"),
        many => {
            let named: Vec<&str> = many
                .iter()
                .map(|s| if s.is_empty() { "report" } else { s })
                .collect();
            format!("{models} ({})", named.join(", "))
        }
    }
}

/// Text colour of a label: the model's colour, darkened so light greys stay readable.
fn text_colour(label: &str) -> RGBColor {
    let RGBColor(r, g, b) = colour(label.split(' ').next().unwrap_or(""));
    let dark = |c: u8| (u16::from(c) * 7 / 10) as u8;
    RGBColor(dark(r), dark(g), dark(b))
}
