//! The motion report's charts: mean samples per pixel per frame of each scene's runs, and
//! on the moving-object scenes the PSNR of the uncovered pixels by their age on screen.

use std::path::Path;

use super::runs::MotionReport;
use super::scenes::{
    BORDER_TEXEL, NEAREST_ONLY, NO_DILATION, NO_PRIOR, NO_REPROJECTED_DEPTH, YOUNG,
};
use crate::error::ReportError;

/// Draws `motion_<scene>_spp.svg`: mean spp per frame of every mode of `scene`, and for the
/// moving sphere the AS run's newly uncovered and steady pixels. Returns the file name.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_chart(dir: &Path, rep: &MotionReport, scene: &str) -> Result<String, ReportError> {
    use plotters::prelude::*;
    let file = format!("motion_{scene}_spp.svg");
    let path = dir.join(&file);
    type Line = (String, Vec<(f64, f64)>, RGBColor);
    let mut lines: Vec<Line> = Vec::new();
    let mode_colour = |mode: &str| match mode {
        "as" => RGBColor(31, 119, 180),
        "as-identity" => RGBColor(214, 39, 40),
        NO_PRIOR => RGBColor(255, 127, 14),
        NO_DILATION => RGBColor(44, 160, 44),
        NEAREST_ONLY => RGBColor(148, 103, 189),
        BORDER_TEXEL => RGBColor(140, 86, 75),
        NO_REPROJECTED_DEPTH => RGBColor(227, 119, 194),
        _ => RGBColor(90, 90, 90),
    };
    for r in rep.runs.iter().filter(|r| r.scene == scene) {
        let pts = r
            .spp
            .iter()
            .enumerate()
            .map(|(t, v)| (t as f64, *v))
            .collect();
        lines.push((format!("{}: all pixels", r.mode), pts, mode_colour(&r.mode)));
        if r.mode == "as" && !r.uncovered_spp.is_empty() {
            let pick = |v: &[Option<f64>]| {
                v.iter()
                    .enumerate()
                    .filter_map(|(t, x)| x.map(|x| (t as f64, x)))
                    .collect::<Vec<_>>()
            };
            let (green, purple) = (RGBColor(44, 160, 44), RGBColor(148, 103, 189));
            lines.push(("as: newly uncovered".into(), pick(&r.uncovered_spp), green));
            lines.push(("as: steady".into(), pick(&r.steady_spp), purple));
        }
    }
    let frames = rep.runs.first().map_or(2, |r| r.spp.len()).max(2) as f64 - 1.0;
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, (900, 420)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(format!("{scene}: mean spp per frame"), ("sans-serif", 20))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..frames, 0.0..70.0)?;
        chart
            .configure_mesh()
            .x_desc("frame")
            .y_desc("mean spp")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .label_style(("sans-serif", 15))
            .draw()?;
        for (label, pts, c) in &lines {
            let c = *c;
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?
                .label(label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| ReportError::Chart {
        path: path.clone(),
        message: e.to_string(),
    })?;
    Ok(file)
}

/// Draws `motion_<scene>_uncovered.svg`: per frame, the PSNR of the steady pixels and of the
/// newly uncovered ones at their first, second and third frame on screen
/// ([`crate::motion::uncovered`]), for `as` (solid) and `as-young` (dashed). Frames without
/// a reference, or without pixels of a class, are left out (the legend sits over the
/// unscored warm-up). Returns the file name, or
/// `None` where the scene has no such figures.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_uncovered_chart(
    dir: &Path,
    rep: &MotionReport,
    scene: &str,
) -> Result<Option<String>, ReportError> {
    use plotters::prelude::*;
    let file = format!("motion_{scene}_uncovered.svg");
    let path = dir.join(&file);
    let classes = [
        ("steady", RGBColor(90, 90, 90)),
        ("uncovered, 1st frame", RGBColor(214, 39, 40)),
        ("uncovered, 2nd frame", RGBColor(255, 127, 14)),
        ("uncovered, 3rd frame", RGBColor(44, 160, 44)),
    ];
    type Line = (String, Vec<(f64, f64)>, RGBColor, bool);
    let mut lines: Vec<Line> = Vec::new();
    for (mode, dashed) in [("as", false), (YOUNG, true)] {
        let Some(r) = rep
            .runs
            .iter()
            .find(|r| r.scene == scene && r.mode == mode && !r.uncovered_errors.is_empty())
        else {
            continue;
        };
        for (k, (what, colour)) in classes.iter().enumerate() {
            let pts: Vec<(f64, f64)> = r
                .uncovered_errors
                .iter()
                .enumerate()
                .filter_map(|(t, e)| e.psnr(k).map(|p| (t as f64, p)))
                .collect();
            lines.push((format!("{mode}: {what}"), pts, *colour, dashed));
        }
    }
    let all = || lines.iter().flat_map(|l| l.1.iter().map(|p| p.1));
    let (Some(lo), Some(hi)) = (
        all().reduce(f64::min).map(|x| (x - 1.0).floor()),
        all().reduce(f64::max).map(|x| (x + 1.0).ceil()),
    ) else {
        return Ok(None);
    };
    let frames = rep
        .runs
        .iter()
        .find(|r| r.scene == scene)
        .map_or(2, |r| r.spp.len())
        .max(2) as f64
        - 1.0;
    let draw = || -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(&path, (900, 420)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("{scene}: PSNR of uncovered pixels by frames on screen, and steady"),
                ("sans-serif", 20),
            )
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..frames, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("frame")
            .y_desc("PSNR (dB)")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .label_style(("sans-serif", 15))
            .draw()?;
        for (label, pts, c, dashed) in &lines {
            let (c, w) = (*c, if *dashed { 1 } else { 2 });
            let style = c.stroke_width(w);
            if *dashed {
                chart.draw_series(DashedLineSeries::new(pts.iter().copied(), 6, 4, style))?
            } else {
                chart.draw_series(LineSeries::new(pts.iter().copied(), style))?
            }
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(w)));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .draw()?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| ReportError::Chart {
        path: path.clone(),
        message: e.to_string(),
    })?;
    Ok(Some(file))
}
