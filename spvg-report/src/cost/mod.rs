//! The component's cost (docs/algorithms.md §2.8): an adaptive frame's time against the
//! fixed-count line at its own mean count. Per effect (the subsurface pass and ambient
//! occlusion, each on its static scene) the runs at several fixed counts and the adaptive
//! runs (AS in two passes, the effects' default; in one pass; one pass without the
//! count order; two passes with the count-classified dispatch) render frame by frame in turn, so all see
//! the same machine load. The line `t(n) = t0 + k n` is fitted (least squares) through the
//! fixed runs' median frame times; an adaptive run's cost is its median time over
//! `t(nbar)` at its mean count `nbar`. 1 means the samples it saved became time one for
//! one; the excess is what the controller and the divergence of its counts cost.
//!
//! The default suite judges the effects' default form at a small frame (the line: at most
//! [`BOUND`]); `--full` also runs 1920x1080, shown, not judged (a timing study).
//!
//! Files: `cost.md`, `cost.csv`, `cost_<size>.svg` (time against spp per effect).

mod runs;

use std::fmt::Write as _;
use std::path::Path;

pub use runs::{Config, Effect, EffectRuns, Form, FrameCost, LANES, lanes_spp};

use crate::acceptance::Check;
use crate::charts::{Colour, Panel, ScatterChart, ScatterPoint, draw_scatter};
use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::{Group, Section};
use crate::timing::Timing;
use crate::wgpu_api::{Backend, GpuDevice, check_frame_size};

/// The judged bound on the default form's cost: its median time at most this many times
/// the fixed-count line at its mean count.
pub const BOUND: f64 = 1.10;

/// The fixed counts of the line.
pub const FIXED: [u32; 5] = [1, 8, 16, 32, 64];

const GREY: Colour = [120, 120, 120];
const BLUE: Colour = [31, 119, 180];
const ORANGE: Colour = [230, 120, 20];

/// One frame size of the section: judged or shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CostRun {
    /// Frame size.
    pub size: [u32; 2],
    /// Frames per configuration, the warm-up included.
    pub frames: u32,
    /// Frames left out first (shader compilation, first touch, the histories' first
    /// frames).
    pub warmup: u32,
    /// Whether its lines are judged.
    pub judged: bool,
}

/// What the section runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CostOptions {
    /// The frame sizes.
    pub runs: Vec<CostRun>,
    /// The effects.
    pub effects: Vec<Effect>,
}

impl CostOptions {
    /// The default suite's run (judged), with `--full` the 1920x1080 study too; `size` and
    /// `frames` replace the judged run's where given.
    #[must_use]
    pub fn for_command(size: Option<[u32; 2]>, frames: Option<u32>, full: bool) -> Self {
        let mut runs = vec![CostRun {
            size: size.unwrap_or([480, 270]),
            frames: frames.unwrap_or(14).max(4),
            warmup: 4,
            judged: true,
        }];
        if full && size.is_none() {
            runs.push(CostRun {
                size: [1920, 1080],
                frames: frames.unwrap_or(10).max(4),
                warmup: 3,
                judged: false,
            });
        }
        for r in &mut runs {
            r.warmup = r.warmup.min(r.frames - 2);
        }
        Self {
            runs,
            effects: vec![Effect::Subsurface, Effect::Ao],
        }
    }

    /// The configurations of every effect's run: the fixed counts, then each form.
    #[must_use]
    pub fn configs() -> Vec<Config> {
        FIXED
            .iter()
            .map(|&n| Config::Fixed(n))
            .chain(Form::ALL.iter().map(|&f| Config::Adaptive(f)))
            .collect()
    }

    /// Frames the section renders (for a progress bar).
    #[must_use]
    pub fn frames_to_render(&self) -> u64 {
        let per = (Self::configs().len() * self.effects.len()) as u64;
        self.runs.iter().map(|r| per * u64::from(r.frames)).sum()
    }
}

/// One configuration's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The configuration.
    pub config: Config,
    /// Mean samples per pixel over the measured frames.
    pub spp: f64,
    /// The per-pixel samples of [`LANES`]-lane SIMD groups over the measured frames, in
    /// pixel order and in count order ([`FrameCost::lanes_spp`]).
    pub lanes_spp: [f64; 2],
    /// Median frame time (ms).
    pub median_ms: f64,
    /// 10th and 90th percentile of the frame times (ms).
    pub p10_ms: f64,
    /// See `p10_ms`.
    pub p90_ms: f64,
}

/// One effect at one size: its rows and the fixed-count line.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectCost {
    /// The effect.
    pub effect: Effect,
    /// The rows, fixed counts first.
    pub rows: Vec<Row>,
    /// The line `t(n) = t0 + k n` through the fixed rows: `(t0, k)` in ms.
    pub line: (f64, f64),
}

impl EffectCost {
    /// The line at `n` samples per pixel.
    #[must_use]
    pub fn line_at(&self, n: f64) -> f64 {
        self.line.0 + self.line.1 * n
    }

    /// The cost of `row`: its median over the line at its mean count.
    #[must_use]
    pub fn ratio(&self, row: &Row) -> f64 {
        row.median_ms / self.line_at(row.spp)
    }

    /// The row of `config`.
    #[must_use]
    pub fn row(&self, config: Config) -> Option<&Row> {
        self.rows.iter().find(|r| r.config == config)
    }
}

/// The least-squares line through `points` (x, y): `(intercept, slope)`; a flat line at
/// the mean where the x values do not spread.
#[must_use]
pub fn fit_line(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len().max(1) as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx > 0.0 {
        let k = sxy / sxx;
        (my - k * mx, k)
    } else {
        (my, 0.0)
    }
}

/// The `q` quantile (0 to 1) of `v` by the nearest rank (its median at 0.5).
fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return f64::NAN;
    }
    let i = ((s.len() - 1) as f64 * q).round() as usize;
    s[i.min(s.len() - 1)]
}

/// Runs `effect` at `run`'s size on `device`: every configuration one frame in turn, the
/// first configuration of frame `t` rotating with `t`, so that none always follows the
/// same one.
///
/// # Errors
///
/// A pass error.
pub fn run_effect(
    device: &GpuDevice,
    effect: Effect,
    run: &CostRun,
    progress: &Progress,
) -> Result<EffectCost, ReportError> {
    let configs = CostOptions::configs();
    let mut runs = EffectRuns::new(device, effect, run.size, &configs)?;
    let mut frames: Vec<Vec<FrameCost>> = vec![Vec::new(); configs.len()];
    for t in 0..run.frames {
        for j in 0..configs.len() {
            let k = (j + t as usize) % configs.len();
            let f = runs.frame(k, t)?;
            if t >= run.warmup {
                frames[k].push(f);
            }
            progress.inc(1);
        }
    }
    let rows: Vec<Row> = configs
        .iter()
        .zip(&frames)
        .map(|(&config, f)| {
            let ms: Vec<f64> = f.iter().map(|c| c.ms).collect();
            let m = f.len().max(1) as f64;
            Row {
                config,
                spp: f.iter().map(|c| c.spp).sum::<f64>() / m,
                lanes_spp: [0, 1].map(|k| f.iter().map(|c| c.lanes_spp[k]).sum::<f64>() / m),
                median_ms: quantile(&ms, 0.5),
                p10_ms: quantile(&ms, 0.1),
                p90_ms: quantile(&ms, 0.9),
            }
        })
        .collect();
    let fixed: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| matches!(r.config, Config::Fixed(_)))
        .map(|r| (r.spp, r.median_ms))
        .collect();
    Ok(EffectCost {
        effect,
        line: fit_line(&fixed),
        rows,
    })
}

/// The judged lines of one size: the default form's cost per effect, the others beside.
#[must_use]
pub fn checks(costs: &[EffectCost], size: [u32; 2]) -> Vec<Check> {
    costs
        .iter()
        .filter_map(|c| {
            let row = c.row(Config::Adaptive(Form::Split))?;
            let ratio = c.ratio(row);
            let other = |f: Form| {
                c.row(Config::Adaptive(f))
                    .map_or(f64::NAN, |r| c.ratio(r))
            };
            let (one, classified) = (other(Form::OnePass), other(Form::Classified));
            Some(Check::new(
                ratio <= BOUND,
                format!(
                    "Component cost, {} at {}x{}: AS (two passes, the default) {:.1} ms at {:.2} spp against the fixed-count line t({:.2}) = {:.1} + {:.3} x {:.2} = {:.1} ms: {:.3}x (need <= {BOUND:.2}); in one pass {:.3}x, classified {:.3}x",
                    c.effect.name(),
                    size[0],
                    size[1],
                    row.median_ms,
                    row.spp,
                    row.spp,
                    c.line.0,
                    c.line.1,
                    row.spp,
                    c.line_at(row.spp),
                    ratio,
                    one,
                    classified
                ),
            ))
        })
        .collect()
}

/// The table of one size.
#[must_use]
pub fn table(costs: &[EffectCost]) -> String {
    let mut s = String::from(
        "| effect | run | spp | 8-lane spp, pixel / count order | median (ms) | p10 to p90 (ms) | fixed-count line at its spp (ms) | cost |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for c in costs {
        for r in &c.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {:.2} | {:.2} / {:.2} | {:.1} | {:.1} to {:.1} | {:.1} | {:.3}x |",
                c.effect.name(),
                r.config.name(),
                r.spp,
                r.lanes_spp[0],
                r.lanes_spp[1],
                r.median_ms,
                r.p10_ms,
                r.p90_ms,
                c.line_at(r.spp),
                c.ratio(r)
            );
        }
    }
    s
}

/// `cost.csv`: one row per effect, size and configuration.
#[must_use]
pub fn csv(sizes: &[([u32; 2], Vec<EffectCost>)]) -> String {
    let mut s = String::from(
        "width,height,effect,run,spp,lanes_spp,lanes_spp_count_order,median_ms,p10_ms,p90_ms,line_t0_ms,line_k_ms,line_at_spp_ms,cost\n",
    );
    for (size, costs) in sizes {
        for c in costs {
            for r in &c.rows {
                let _ = writeln!(
                    s,
                    "{},{},{},{},{:.4},{:.4},{:.4},{:.3},{:.3},{:.3},{:.3},{:.4},{:.3},{:.4}",
                    size[0],
                    size[1],
                    c.effect.name(),
                    r.config.name(),
                    r.spp,
                    r.lanes_spp[0],
                    r.lanes_spp[1],
                    r.median_ms,
                    r.p10_ms,
                    r.p90_ms,
                    c.line.0,
                    c.line.1,
                    c.line_at(r.spp),
                    c.ratio(r)
                );
            }
        }
    }
    s
}

fn chart(dir: &Path, size: [u32; 2], costs: &[EffectCost]) -> Result<String, ReportError> {
    let file = format!("cost_{}x{}.svg", size[0], size[1]);
    let panels = costs
        .iter()
        .map(|c| Panel {
            caption: c.effect.name().into(),
            points: c
                .rows
                .iter()
                .map(|r| ScatterPoint {
                    x: r.spp,
                    y: r.median_ms,
                    label: r.config.name(),
                    colour: match r.config {
                        Config::Fixed(_) => GREY,
                        Config::Adaptive(Form::Split) => BLUE,
                        Config::Adaptive(_) => ORANGE,
                    },
                    filled: !matches!(r.config, Config::Fixed(_)),
                })
                .collect(),
        })
        .collect();
    let merge = |labels: &[&str]| labels.join(", ");
    let ink = |_: &str| -> Colour { [0, 0, 0] };
    draw_scatter(
        dir,
        &file,
        &ScatterChart {
            title: format!(
                "Frame time against samples per pixel at {}x{}: fixed counts (rings) and AS in each form",
                size[0], size[1]
            ),
            x_desc: "samples per pixel".into(),
            y_desc: "median frame time (ms)".into(),
            panels,
            size: (1100, 520),
            merge: &merge,
            ink: &ink,
        },
    )?;
    Ok(file)
}

/// The section's markdown before its tables.
fn preamble(timing: &Timing) -> String {
    format!(
        "## The component's cost: adaptive frames against the fixed-count line\n\n\
         Per effect, on its static scene, the fixed counts {} and AS in each form render \
         frame by frame in turn; the line `t(n) = t0 + k n` is fitted through the fixed \
         runs' median frame times, and a run's cost is its median over the line at its own \
         mean count (docs/algorithms.md §2.8): 1 when the samples the controller saved became \
         time one for one. `as` is the two-pass form (the effects' default), `as one-pass` \
         the one-pass form with the count order, `as one-pass unordered` the same without \
         the order, `as classified` the two-pass form with the count-classified dispatch. Times: {}\n\n",
        FIXED
            .iter()
            .map(|n| n.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        timing.sentence()
    )
}

/// Runs the section on `backend` (the CPU twin has no passes to time: the section says so
/// and judges nothing), writes its files into `dir` and returns it.
///
/// # Errors
///
/// A pass error, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    backend: &Backend,
    opts: &CostOptions,
    progress: &Progress,
) -> Result<Section, ReportError> {
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let timing = Timing::of(backend);
    let mut md = preamble(&timing);
    let mut groups = Vec::new();
    let Backend::Gpu(device) = backend else {
        md.push_str("Not run: the CPU twin has no passes to time.\n");
        progress.inc(opts.frames_to_render());
        return Ok(Section {
            name: "cost",
            markdown: md,
            groups,
        });
    };
    let mut all = Vec::new();
    for run in &opts.runs {
        check_frame_size(&device.device, run.size[0], run.size[1])?;
        let mut costs = Vec::new();
        for &effect in &opts.effects {
            progress.stage(&format!(
                "cost: {} at {}x{}, {} configurations interleaved",
                effect.name(),
                run.size[0],
                run.size[1],
                CostOptions::configs().len()
            ));
            costs.push(run_effect(device, effect, run, progress)?);
        }
        let file = chart(dir, run.size, &costs)?;
        let _ = write!(
            md,
            "### {}x{}, {} frames after {} of warm-up{}\n\n{}\n![frame time against spp]({file})\n\n",
            run.size[0],
            run.size[1],
            run.frames - run.warmup,
            run.warmup,
            if run.judged {
                ""
            } else {
                " (shown, not judged)"
            },
            table(&costs)
        );
        if run.judged {
            groups.push(Group::judged(
                format!("The component's cost at {}x{}", run.size[0], run.size[1]),
                checks(&costs, run.size),
            ));
        }
        all.push((run.size, costs));
    }
    for g in &groups {
        md.push_str(&g.markdown());
    }
    let path = dir.join("cost.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    let path = dir.join("cost.csv");
    std::fs::write(&path, csv(&all)).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "cost",
        markdown: md,
        groups,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit recovers a line exactly, and a flat set of points is its mean.
    #[test]
    fn fit_recovers_a_line() {
        let pts: Vec<(f64, f64)> = FIXED
            .iter()
            .map(|&n| (f64::from(n), 12.5 + 3.25 * f64::from(n)))
            .collect();
        let (t0, k) = fit_line(&pts);
        assert!(
            (t0 - 12.5).abs() < 1e-9 && (k - 3.25).abs() < 1e-12,
            "{t0} {k}"
        );
        assert_eq!(fit_line(&[(2.0, 1.0), (2.0, 3.0)]), (2.0, 0.0));
    }

    /// Quantiles by nearest rank, whatever the order.
    #[test]
    fn quantiles_by_rank() {
        let v = [5.0, 1.0, 4.0, 2.0, 3.0];
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert!(quantile(&[], 0.5).is_nan());
    }
}
