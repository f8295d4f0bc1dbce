//! The motion section's charts, as data for [`crate::charts`]: the mean spp per frame of
//! each scene's runs, and on the moving-object scenes the PSNR of the uncovered pixels by
//! their age on screen.

use std::path::Path;

use super::data::MotionReport;
use super::scenes::{
    BORDER_TEXEL, NEAREST_ONLY, NO_DILATION, NO_PRIOR, NO_REPROJECTED_DEPTH, YOUNG,
};
use crate::charts::{self, Colour, Legend, Line, LineChart};
use crate::error::ReportError;

/// The colour of a run's line by its mode.
fn mode_colour(mode: &str) -> Colour {
    match mode {
        "as" => [31, 119, 180],
        "as-identity" => [214, 39, 40],
        NO_PRIOR => [255, 127, 14],
        NO_DILATION => [44, 160, 44],
        NEAREST_ONLY => [148, 103, 189],
        BORDER_TEXEL => [140, 86, 75],
        NO_REPROJECTED_DEPTH => [227, 119, 194],
        _ => [90, 90, 90],
    }
}

/// The last frame of `scene`'s runs (at least 1): the x range's end.
fn last_frame(rep: &MotionReport, scene: &str) -> f64 {
    rep.runs
        .iter()
        .find(|r| r.scene == scene)
        .map_or(2, |r| r.spp.len())
        .max(2) as f64
        - 1.0
}

/// Draws `motion_<scene>_spp.svg`: mean spp per frame of every mode of `scene`, and for the
/// moving objects the AS run's newly uncovered and steady pixels. Returns the file name.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_spp_chart(dir: &Path, rep: &MotionReport, scene: &str) -> Result<String, ReportError> {
    let file = format!("motion_{scene}_spp.svg");
    let mut lines = Vec::new();
    let line = |label: String, points, colour| Line {
        label,
        points,
        colour,
        dashed: false,
        width: 2,
    };
    for r in rep.runs.iter().filter(|r| r.scene == scene) {
        let pts = r
            .spp
            .iter()
            .enumerate()
            .map(|(t, v)| (t as f64, *v))
            .collect();
        lines.push(line(
            format!("{}: all pixels", r.mode),
            pts,
            mode_colour(&r.mode),
        ));
        if r.mode == "as" && !r.uncovered_spp.is_empty() {
            let pick = |v: &[Option<f64>]| {
                v.iter()
                    .enumerate()
                    .filter_map(|(t, x)| x.map(|x| (t as f64, x)))
                    .collect::<Vec<_>>()
            };
            lines.push(line(
                "as: newly uncovered".into(),
                pick(&r.uncovered_spp),
                [44, 160, 44],
            ));
            lines.push(line(
                "as: steady".into(),
                pick(&r.steady_spp),
                [148, 103, 189],
            ));
        }
    }
    let mut chart = LineChart::new(
        format!("{scene}: mean spp per frame"),
        (0.0, last_frame(rep, scene)),
        (0.0, 70.0),
        lines,
    );
    chart.y_desc = "mean spp".into();
    chart.legend = Legend::UpperRight;
    chart.size = (900, 420);
    charts::draw_lines(dir, &file, &chart)?;
    Ok(file)
}

/// Draws `motion_<scene>_uncovered.svg`: per frame, the PSNR of the steady pixels and of the
/// newly uncovered ones at their first, second and third frame on screen
/// ([`super::uncovered`]), for `as` (solid) and `as-young` (dashed, where it ran). Frames
/// without a reference, or without pixels of a class, are left out. Returns the file
/// name, or `None` where the scene has no such figures.
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file when drawing or writing fails.
pub fn write_uncovered_chart(
    dir: &Path,
    rep: &MotionReport,
    scene: &str,
) -> Result<Option<String>, ReportError> {
    let file = format!("motion_{scene}_uncovered.svg");
    let classes: [(&str, Colour); 4] = [
        ("steady", [90, 90, 90]),
        ("uncovered, 1st frame", [214, 39, 40]),
        ("uncovered, 2nd frame", [255, 127, 14]),
        ("uncovered, 3rd frame", [44, 160, 44]),
    ];
    let mut lines: Vec<Line> = Vec::new();
    for (mode, dashed) in [("as", false), (YOUNG, true)] {
        let Some(r) = rep
            .find(scene, mode)
            .filter(|r| !r.uncovered_errors.is_empty())
        else {
            continue;
        };
        for (k, (what, colour)) in classes.iter().enumerate() {
            lines.push(Line {
                label: format!("{mode}: {what}"),
                points: r
                    .uncovered_errors
                    .iter()
                    .enumerate()
                    .filter_map(|(t, e)| e.psnr(k).map(|p| (t as f64, p)))
                    .collect(),
                colour: *colour,
                dashed,
                width: if dashed { 1 } else { 2 },
            });
        }
    }
    let all = || lines.iter().flat_map(|l| l.points.iter().map(|p| p.1));
    let (Some(lo), Some(hi)) = (
        all().reduce(f64::min).map(|x| (x - 1.0).floor()),
        all().reduce(f64::max).map(|x| (x + 1.0).ceil()),
    ) else {
        return Ok(None);
    };
    let mut chart = LineChart::new(
        format!("{scene}: PSNR of uncovered pixels by frames on screen, and steady"),
        (0.0, last_frame(rep, scene)),
        (lo, hi),
        lines,
    );
    chart.y_desc = "PSNR (dB)".into();
    chart.legend = Legend::UpperLeft;
    chart.size = (900, 420);
    charts::draw_lines(dir, &file, &chart)?;
    Ok(Some(file))
}
