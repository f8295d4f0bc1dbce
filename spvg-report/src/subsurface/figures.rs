//! The subsurface section's charts, as data for [`crate::charts`]: per scene the
//! per-frame series of the report-setting runs (spp, PSNR, relMSE, and the budget runs'
//! totals), and the Pareto panels of every run; and the charts section of its markdown.

use std::fmt::Write as _;
use std::path::Path;

use super::data::Report;
use super::run::{BUDGET_BAND, BUDGET_WARMUP, FrameRecord, RunSummary};
use super::scene_runs::SceneRuns;
use crate::charts::{self, Colour, Line, LineChart, Panel, ScatterChart, ScatterPoint};
use crate::error::ReportError;

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
pub fn colour(label: &str) -> Colour {
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
        [light(r), light(g), light(b)]
    } else {
        [r, g, b]
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

/// The last frame of `runs` (at least 1): the x range's end.
fn last_frame(runs: &[(String, Vec<FrameRecord>)]) -> f64 {
    runs.iter().map(|(_, r)| r.len()).max().unwrap_or(2).max(2) as f64 - 1.0
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
    let (lo, hi, outside) = y_range(series, runs);
    let caption = match series {
        Series::Psnr if outside > 0 => format!(
            "{scene}: {} ({outside} points off the axis, drawn at its edge)",
            series.title()
        ),
        _ => format!("{scene}: {}", series.title()),
    };
    let lines = runs
        .iter()
        .map(|(label, recs)| Line {
            label: label.clone(),
            points: recs
                .iter()
                .map(|r| (f64::from(r.frame), series.value(r)))
                .filter(|(_, v)| series != Series::RelMse || *v > 0.0)
                .collect(),
            colour: colour(label),
            dashed: false,
            width: 2,
        })
        .collect();
    let mut chart = LineChart::new(caption, (0.0, last_frame(runs)), (lo, hi), lines);
    chart.y_desc = series.axis().into();
    chart.y_log = series == Series::RelMse;
    charts::draw_lines(dir, &file, &chart)?;
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
    let file = format!("{scene}_budget.svg");
    let hi = runs
        .iter()
        .flat_map(|(_, r)| r.iter().map(|r| r.spp / budget_spp))
        .filter(|v| v.is_finite())
        .fold(1.0 + 2.0 * BUDGET_BAND, f64::max)
        .min(64.0 / budget_spp);
    let lines = runs
        .iter()
        .map(|(label, recs)| Line {
            label: label.clone(),
            points: recs
                .iter()
                .map(|r| (f64::from(r.frame), r.spp / budget_spp))
                .collect(),
            colour: colour(label),
            dashed: false,
            width: 2,
        })
        .collect();
    let mut chart = LineChart::new(
        format!("{scene}: frame total / budget ({budget_spp} spp per pixel)"),
        (0.0, last_frame(runs)),
        (0.0, hi),
        lines,
    );
    chart.y_desc = "total / budget".into();
    chart.shade_x = Some((0.0, f64::from(BUDGET_WARMUP)));
    chart.levels = vec![1.0 - BUDGET_BAND, 1.0, 1.0 + BUDGET_BAND];
    charts::draw_lines(dir, &file, &chart)?;
    Ok(file)
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
fn text_colour(label: &str) -> Colour {
    colour(label.split(' ').next().unwrap_or("")).map(|c| (u16::from(c) * 7 / 10) as u8)
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
    let panels = scenes
        .iter()
        .map(|&scene| Panel {
            caption: scene.to_owned(),
            points: all
                .iter()
                .filter(|s| s.scene == scene)
                .map(|s| ScatterPoint {
                    x: x.value(s),
                    y: s.mean_psnr,
                    label: s.label.clone(),
                    colour: colour(&s.label),
                    filled: !is_sweep(&s.label),
                })
                .collect(),
        })
        .collect();
    let chart = ScatterChart {
        title: match x {
            ParetoX::Spp => "mean PSNR vs mean spp (filled: report setting, hollow: sweep)",
            ParetoX::Time => "mean PSNR vs p50 pass time (filled: report setting, hollow: sweep)",
        }
        .into(),
        x_desc: match x {
            ParetoX::Spp => "mean spp".to_owned(),
            ParetoX::Time => format!("p50 pass time, ms ({timing})"),
        },
        y_desc: "mean PSNR (dB)".into(),
        panels,
        size: PARETO_SIZE,
        merge: &group_label,
        ink: &text_colour,
    };
    charts::draw_scatter(dir, &file, &chart)?;
    Ok(file)
}

/// The charts section drawn into `dir`, as markdown, and each PSNR chart with its number
/// of points off the axis (for the notes).
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file.
pub(crate) fn charts_section(
    r: &Report,
    dir: &Path,
) -> Result<(String, Vec<(String, usize)>), ReportError> {
    let i = &r.inputs;
    let mut clipped = Vec::new();
    let mut md = String::new();
    if !i.reference {
        md.push_str("(no charts: --no-reference)\n");
        return Ok((md, clipped));
    }
    for s in &r.scenes {
        let mut links = Vec::new();
        for series in Series::ALL {
            let (file, outside) = write_series(dir, s.kind.name(), series, &s.per_frame)?;
            if series == Series::Psnr {
                clipped.push((file.clone(), outside));
            }
            links.push(format!("![{} {}]({file})", s.kind.name(), series.name()));
        }
        if let Some(b) = i.budget_spp {
            let file = write_budget(dir, s.kind.name(), b, &s.per_frame)?;
            links.push(format!("![{} budget]({file})", s.kind.name()));
        }
        let _ = writeln!(md, "### {}\n\n{}\n", s.kind.name(), links.join("\n"));
    }
    let names: Vec<&str> = r.scenes.iter().map(|s| s.kind.name()).collect();
    let all: Vec<RunSummary> = r
        .scenes
        .iter()
        .flat_map(|s: &SceneRuns| s.summaries.clone())
        .collect();
    for x in [ParetoX::Spp, ParetoX::Time] {
        let file = write_pareto(dir, x, &names, &all, i.timing.short())?;
        let _ = writeln!(md, "![pareto {}]({file})\n", x.name());
    }
    Ok((md, clipped))
}
