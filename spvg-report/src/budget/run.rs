//! The budget table's runs: the budgets, the sweep of targets per budget and floor, the
//! rule that picks a target from the counts alone, and each run's scores.

use spvg::burley::{MaterialPreset, presets};

use crate::error::ReportError;
use crate::metrics::{psnr, rgb, rmse};
use crate::reference::static_reference;
use crate::scene::{Scene, SceneKind};
use crate::wgpu_api::{GpuDevice, Model, PassConfig, SssPass, SssTwin};

/// The budgets of the table.
pub const BUDGETS: [u32; 3] = [64, 128, 512];

/// The published target variance (the SPVG paper's and the component's default), the
/// sweep's first point.
pub const PUBLISHED_TARGET: f32 = 1e-4;

/// The targets each budget sweeps: `1e-4 / 4^j`, `j = 0..6`, a factor 4 apart (one octave of
/// RMSE), from the published target to about 1e-7, where every pixel with a measured
/// variance already asks for the cap at budget 512.
pub const SWEEP: [f32; 6] = [1e-4, 2.5e-5, 6.25e-6, 1.5625e-6, 3.906_25e-7, 9.765_625e-8];

/// The rule's share: the picked target is the smallest swept one whose run uses at most
/// this share of the fixed run's samples (the acceptance's bound, so that the judged row
/// is the best the sweep reaches within it).
pub const SAMPLE_SHARE: f64 = 0.5;

/// `beta_max / beta_min` of the published budget `[8, 64]`, which the scaled interval keeps.
pub const INTERVAL_RATIO: u32 = 8;

/// The `beta_min` values a budget's adaptive runs sweep: the published 8, and
/// `budget / INTERVAL_RATIO` (the judged one) when that differs.
///
/// # Examples
///
/// ```
/// use spvg_report::budget::beta_mins;
/// assert_eq!(beta_mins(64), vec![8]);
/// assert_eq!(beta_mins(512), vec![8, 64]);
/// ```
#[must_use]
pub fn beta_mins(budget: u32) -> Vec<u32> {
    let scaled = (budget / INTERVAL_RATIO).max(1);
    if scaled == 8 {
        vec![8]
    } else {
        vec![8, scaled]
    }
}

/// What the table runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetOptions {
    /// Frame width and height.
    pub size: [u32; 2],
    /// Frames per run; metrics average the second half.
    pub frames: u32,
    /// The material.
    pub material: MaterialPreset,
}

impl Default for BudgetOptions {
    fn default() -> Self {
        Self {
            size: [96, 72],
            frames: 16,
            material: presets::SKIN1,
        }
    }
}

impl BudgetOptions {
    /// The table's options for a command: 96x72 (160x120 with `full`), 16 frames, `size`
    /// and `frames` where given.
    #[must_use]
    pub fn for_command(size: Option<[u32; 2]>, frames: Option<u32>, full: bool) -> Self {
        let mut o = Self::default();
        if full {
            o.size = [160, 120];
        }
        if let Some(s) = size {
            o.size = s;
        }
        if let Some(f) = frames {
            o.frames = f;
        }
        o
    }

    /// Runs the table renders (for a progress bar), each `frames` frames: per budget the
    /// fixed count and the sweep at every floor.
    #[must_use]
    pub fn runs(&self) -> u64 {
        BUDGETS
            .iter()
            .map(|&b| 1 + (SWEEP.len() * beta_mins(b).len()) as u64)
            .sum()
    }
}

/// One row: a budget, fixed or adaptive at one target.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BudgetRow {
    /// The budget (`beta_max`, or the fixed count).
    pub budget: u32,
    /// Whether the count is adaptive.
    pub adaptive: bool,
    /// The adaptive run's target variance `sigma0^2` (0 for the fixed count).
    pub sigma0_sq: f32,
    /// The adaptive run's `beta_min` (0 for the fixed count).
    pub beta_min: u32,
    /// Whether this adaptive row is the one [`pick`] chose for its budget and `beta_min`.
    pub picked: bool,
    /// Mean frame time (ms).
    pub time_ms: f64,
    /// PSNR over the subsurface pixels (dB).
    pub psnr: f64,
    /// RMSE over the pixels at `beta_min` in the adaptive run (the picked one for the
    /// fixed row).
    pub err1: f64,
    /// RMSE over the pixels above `beta_min` in that adaptive run.
    pub err2: f64,
    /// Total samples per frame (mean over the measured frames).
    pub samples: f64,
}

/// The measured frames of one run, before scoring.
#[derive(Clone, Debug, Default)]
pub struct Measured {
    /// The result image of each measured frame.
    pub images: Vec<Vec<[f32; 3]>>,
    /// Per measured frame and pixel: 0 outside the subsurface mask, 1 at `beta_min` or
    /// below, 2 above it.
    pub classes: Vec<Vec<u8>>,
    /// Mean frame time (ms).
    pub time_ms: f64,
    /// Mean total samples per frame.
    pub samples: f64,
}

/// The table's scene (static, at `opts.size`) and its converged reference.
#[must_use]
pub fn scene_and_reference(opts: &BudgetOptions) -> (Scene, Vec<[f32; 3]>) {
    let [w, h] = opts.size;
    let scene = Scene::new(SceneKind::Static, w, h);
    let reference = static_reference(&scene, &opts.material, &PassConfig::default());
    (scene, reference)
}

/// Runs `model` under `cfg` for `opts.frames` frames on `scene` and keeps the second
/// half.
///
/// # Errors
///
/// A pass error or a refused configuration.
pub fn run_model(
    device: Option<&GpuDevice>,
    scene: &Scene,
    opts: &BudgetOptions,
    model: Model,
    cfg: &PassConfig,
) -> Result<Measured, ReportError> {
    let (w, h) = (scene.width, scene.height);
    let mut pass = match device {
        Some(d) => Ok(SssPass::for_device(d, model, w, h)),
        None => Err(SssTwin::new(model, w, h)),
    };
    let mut m = Measured::default();
    let k = 1.0 / f64::from(opts.frames - opts.frames / 2);
    for t in 0..opts.frames {
        let inputs = scene.inputs(t);
        let out = match &mut pass {
            Ok(g) => {
                let p = g.frame_params(cfg, &opts.material, t)?;
                g.run_frame(&p, &inputs)?
            }
            Err(c) => {
                let p = c.frame_params(cfg, &opts.material, t)?;
                c.run_frame(&p, &inputs)?
            }
        };
        if t < opts.frames / 2 {
            continue;
        }
        m.classes.push(
            out.count
                .iter()
                .zip(&inputs.mask)
                .map(|(&n, &s)| match (s, n) {
                    (0, _) => 0,
                    (_, n) if n <= cfg.spvg.min_samples() => 1,
                    _ => 2,
                })
                .collect(),
        );
        m.images.push(out.result.iter().map(|&t| rgb(t)).collect());
        m.time_ms += k * out.time_ms;
        m.samples += k * out.count.iter().map(|&n| f64::from(n)).sum::<f64>();
    }
    Ok(m)
}

/// A run's scores against the reference, each the mean over the measured frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Scores {
    /// PSNR over the subsurface pixels (dB).
    pub psnr: f64,
    /// RMSE over the split's pixels at `beta_min`.
    pub err1: f64,
    /// RMSE over the split's pixels above `beta_min`.
    pub err2: f64,
}

/// Scores a run against `reference`: the PSNR over its subsurface pixels and `err1`/`err2`
/// over the classes of `split` (an adaptive run's [`Measured::classes`]).
#[must_use]
pub fn score(m: &Measured, reference: &[[f32; 3]], split: &[Vec<u8>]) -> Scores {
    let k = 1.0 / m.images.len().max(1) as f64;
    let mut s = Scores::default();
    for (image, (own, split)) in m.images.iter().zip(m.classes.iter().zip(split)) {
        let mask: Vec<u8> = own.iter().map(|&c| u8::from(c != 0)).collect();
        let at = |class: u8| -> Vec<u8> { split.iter().map(|&c| u8::from(c == class)).collect() };
        s.psnr += k * psnr(image, reference, &mask);
        s.err1 += k * rmse(image, reference, &at(1));
        s.err2 += k * rmse(image, reference, &at(2));
    }
    s
}

/// `row` (its budget, count and target) completed with a run's time, samples and scores.
fn scored(row: BudgetRow, m: &Measured, s: Scores) -> BudgetRow {
    BudgetRow {
        time_ms: m.time_ms,
        samples: m.samples,
        psnr: s.psnr,
        err1: s.err1,
        err2: s.err2,
        ..row
    }
}

/// The rule that picks a budget's target from its sweep: among `samples` (the swept runs'
/// mean total samples, in [`SWEEP`] order, largest target first), the index of the smallest
/// target whose run uses at most [`SAMPLE_SHARE`] of `fixed_samples`; the first (the
/// published target) when none does. It reads no image, only the counts the runs took.
///
/// # Examples
///
/// ```
/// use spvg_report::budget::pick;
/// // Counts grow as the target shrinks; the last one within half of 1000 is picked.
/// assert_eq!(pick(&[100.0, 300.0, 480.0, 700.0], 1000.0), 2);
/// // A sweep that saturates below the share takes its smallest target.
/// assert_eq!(pick(&[100.0, 200.0, 200.0], 1000.0), 2);
/// // None within the share: the published target.
/// assert_eq!(pick(&[600.0, 900.0], 1000.0), 0);
/// ```
#[must_use]
pub fn pick(samples: &[f64], fixed_samples: f64) -> usize {
    samples
        .iter()
        .rposition(|&s| s <= SAMPLE_SHARE * fixed_samples)
        .unwrap_or(0)
}

/// Runs the table on `device` (the CPU twin without one): per budget the fixed count, then
/// AS at every target of [`SWEEP`] for each of [`beta_mins`]; the fixed row's `err1`/`err2`
/// use the judged picked run's split (the last `beta_min`).
///
/// # Errors
///
/// A pass error or a refused configuration.
pub fn run_budgets(
    device: Option<&GpuDevice>,
    opts: &BudgetOptions,
) -> Result<Vec<BudgetRow>, ReportError> {
    run_budgets_with(device, opts, &BUDGETS, &SWEEP)
}

/// [`run_budgets`] over chosen `budgets` and `targets` (the sweep, largest first).
///
/// # Errors
///
/// A pass error or a refused configuration.
pub fn run_budgets_with(
    device: Option<&GpuDevice>,
    opts: &BudgetOptions,
    budgets: &[u32],
    targets: &[f32],
) -> Result<Vec<BudgetRow>, ReportError> {
    let (scene, reference) = scene_and_reference(opts);
    let mut rows = Vec::new();
    for &budget in budgets {
        let base_cfg = PassConfig::default();
        let cfg = PassConfig {
            spvg: base_cfg
                .spvg
                .to_builder()
                .budget(base_cfg.spvg.min_samples().min(budget), budget)
                .build()?,
            ..base_cfg
        };
        let fixed = run_model(device, &scene, opts, Model::Fixed(budget), &cfg)?;
        let base = BudgetRow {
            budget,
            ..BudgetRow::default()
        };
        let mut split = fixed.classes.clone();
        for beta_min in beta_mins(budget) {
            let mut swept = Vec::new();
            for &sigma0_sq in targets {
                let cfg = PassConfig {
                    spvg: cfg
                        .spvg
                        .to_builder()
                        .target_variance(sigma0_sq)
                        .budget(beta_min, budget)
                        .build()?,
                    ..cfg
                };
                swept.push((sigma0_sq, run_model(device, &scene, opts, Model::As, &cfg)?));
            }
            let counts: Vec<f64> = swept.iter().map(|(_, m)| m.samples).collect();
            let chosen = pick(&counts, fixed.samples);
            for (i, (sigma0_sq, m)) in swept.iter().enumerate() {
                let row = BudgetRow {
                    adaptive: true,
                    sigma0_sq: *sigma0_sq,
                    beta_min,
                    picked: i == chosen,
                    ..base.clone()
                };
                rows.push(scored(row, m, score(m, &reference, &m.classes)));
            }
            if let Some((_, m)) = swept.get(chosen) {
                split.clone_from(&m.classes);
            }
        }
        rows.push(scored(base, &fixed, score(&fixed, &reference, &split)));
    }
    Ok(rows)
}
