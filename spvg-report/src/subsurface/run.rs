//! Runs a scene through a model and measures it against the converged reference.

use std::collections::BTreeMap;

use crate::error::ReportError;
use crate::metrics::{Flicker, mean_spp, psnr, psnr_of_pairs, relmse, relmse_of_pairs, rgb};
use crate::reference::{Quadrature, reference_bases};
use crate::scene::Scene;
use crate::taa::{Taa, TaaFrame};
use crate::wgpu_api::{
    Backend, FrameInputs, FrameOutput, FrameSums, History, Model, PassConfig, Reducer, Timer,
    luminance,
};
use spvg::budget::{BudgetConfig, Governor};
use spvg::burley::MaterialPreset;

/// Frames left out of the budget acceptance (the governor's warm-up from the initial
/// target).
pub const BUDGET_WARMUP: u32 = 10;

/// The band around the budget a frame's total must stay in (relative).
pub const BUDGET_BAND: f64 = 0.1;

/// The governor's default integral gain (`spvg::budget::BudgetConfig`'s default, free of
/// overshoot at one and two frames of feedback latency).
pub const DEFAULT_GAIN: f64 = 0.25;

/// References of a scene per state (one image per basis light), computed on demand.
#[derive(Debug)]
pub struct ReferenceCache {
    scene: Scene,
    material: MaterialPreset,
    cfg: PassConfig,
    quad: Quadrature,
    states: BTreeMap<u32, Vec<Vec<[f32; 3]>>>,
}

impl ReferenceCache {
    /// An empty cache for `scene`.
    #[must_use]
    pub fn new(scene: Scene, material: MaterialPreset, cfg: PassConfig, quad: Quadrature) -> Self {
        Self {
            scene,
            material,
            cfg,
            quad,
            states: BTreeMap::new(),
        }
    }

    /// The converged reference of frame `t`: `sum_k I_k(t) Ref_k(state(t))`.
    pub fn frame(&mut self, t: u32) -> Vec<[f32; 3]> {
        let lights = self.scene.lights(t);
        let scene = self.scene;
        let (material, cfg, quad) = (self.material, self.cfg, self.quad);
        let refs = self.states.entry(lights.state).or_insert_with(|| {
            let geo = scene.geometry(lights.state);
            let bases = scene.bases(lights.state);
            reference_bases(
                scene.width,
                scene.height,
                &geo,
                &bases,
                &material,
                &cfg,
                quad,
            )
        });
        let n = scene.width as usize * scene.height as usize;
        let mut out = vec![[0.0_f32; 3]; n];
        for (basis, k) in refs.iter().zip(&lights.intensities) {
            for (o, v) in out.iter_mut().zip(basis) {
                for c in 0..3 {
                    o[c] += k * v[c];
                }
            }
        }
        out
    }
}

/// Measurements of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRecord {
    /// Frame index.
    pub frame: u32,
    /// Mean distant samples per subsurface pixel.
    pub spp: f64,
    /// Pass time, ms.
    pub time_ms: f64,
    /// PSNR of the single-frame result, dB.
    pub psnr: f64,
    /// Relative MSE of the single-frame result ([`relmse`]).
    pub relmse: f64,
    /// PSNR of the luminance after the TAA resolve ([`crate::taa`]), dB.
    pub psnr_taa: f64,
    /// Relative MSE of the luminance after the TAA resolve.
    pub relmse_taa: f64,
    /// Temporal instability of the resolved luminance ([`Flicker`]; NaN on frame 0).
    pub flicker_taa: f64,
    /// Subsurface pixels that took no distant samples (the zero-sample rule).
    pub zero_pixels: u64,
    /// The count's step per subsurface pixel: the mean of `|n_t - n_(t-1)|` (NaN on frame
    /// 0 and without subsurface pixels).
    pub count_step: f64,
    /// Fractions of the subsurface pixels whose count is `beta_min` and `beta_max` (the
    /// per-pixel clamps; NaN without subsurface pixels).
    pub at_bounds: [f64; 2],
    /// Target variance `sigma0^2` the frame ran with (moved by the governor in a budget
    /// run, else the run's setting).
    pub target: f64,
    /// A budget run's feed-forward model of the frame's total at that target, in spp:
    /// the previous frame's clamped demand curve (`spvg::budget::DemandCurve::total_at`)
    /// over the subsurface pixels; NaN in other runs and in the first frame.
    pub planned_spp: f64,
}

/// Summary of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// Scene name.
    pub scene: &'static str,
    /// Configuration label (model and swept parameters).
    pub label: String,
    /// Model.
    pub model: Model,
    /// Mean over frames of the mean spp.
    pub mean_spp: f64,
    /// Largest per-frame mean spp.
    pub worst_spp: f64,
    /// Median pass time, ms (first frame excluded: shader JIT; NaN with fewer than two
    /// frames).
    pub p50_ms: f64,
    /// 95th percentile pass time, ms.
    pub p95_ms: f64,
    /// Largest pass time, ms.
    pub max_ms: f64,
    /// Mean single-frame PSNR, dB.
    pub mean_psnr: f64,
    /// Lowest single-frame PSNR, dB.
    pub worst_psnr: f64,
    /// Mean single-frame relative MSE.
    pub mean_relmse: f64,
    /// Mean PSNR after the TAA resolve, dB.
    pub mean_psnr_taa: f64,
    /// Lowest PSNR after the TAA resolve, dB.
    pub worst_psnr_taa: f64,
    /// Mean relative MSE after the TAA resolve.
    pub mean_relmse_taa: f64,
    /// Mean temporal instability after the TAA resolve (frames that have one).
    pub flicker_taa: f64,
    /// History bytes per pixel.
    pub history_bytes: u32,
    /// How times were measured.
    pub timer: Timer,
    /// The run's budget in samples per subsurface pixel (a `budget` run), else `None`.
    pub budget_spp: Option<f64>,
    /// Of a budget run, the fraction of the frames from [`BUDGET_WARMUP`] on whose total
    /// lies within [`BUDGET_BAND`] of the budget; NaN otherwise.
    pub in_band: f64,
    /// Mean over the second half of the frames of the count's step per pixel
    /// ([`FrameRecord::count_step`]).
    pub count_step: f64,
    /// Of a run of fractional counts ([`RunSpec::fractional`]), the longest run of
    /// consecutive frames without a sample of any subsurface pixel after its first
    /// sample, the last one counted to the end of the run (pixels that never sample, the
    /// zero-sample rule's, have none); `None` in other runs.
    pub longest_skip: Option<u32>,
}

/// Per pixel, the frames since its last sample (`None` before its first): the revisit
/// bound's measure ([`RunSummary::longest_skip`]).
#[derive(Debug, Default)]
struct SkipRuns {
    since: Vec<Option<u32>>,
    longest: u32,
}

impl SkipRuns {
    /// Counts one frame's `count` over the subsurface pixels of `mask`.
    fn push(&mut self, count: &[u32], mask: &[u8]) {
        self.since.resize(count.len(), None);
        for ((s, &n), &m) in self.since.iter_mut().zip(count).zip(mask) {
            if m == 0 {
                continue;
            }
            *s = if n > 0 { Some(0) } else { s.map(|k| k + 1) };
            self.longest = self.longest.max(s.unwrap_or(0));
        }
    }
}

/// The mean over the subsurface pixels of `|n - n_before|` (NaN without subsurface
/// pixels or a previous frame of the same size).
fn count_step(count: &[u32], before: Option<&[u32]>, mask: &[u8]) -> f64 {
    let Some(before) = before.filter(|b| b.len() == count.len()) else {
        return f64::NAN;
    };
    let (mut sum, mut n) = (0_u64, 0_u64);
    for ((&a, &b), &m) in count.iter().zip(before).zip(mask) {
        if m != 0 {
            sum += u64::from(a.abs_diff(b));
            n += 1;
        }
    }
    if n == 0 {
        f64::NAN
    } else {
        sum as f64 / n as f64
    }
}

/// Nearest-rank percentile of sorted values; NaN when there are none (a run of one frame
/// has no timed frame), so tables print "n/a" rather than a time of zero.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted.get(i).copied().unwrap_or(f64::NAN)
}

/// The fractional floor of the [`RunSpec::resolved`] run: 0, the floor that wins on the
/// static scene after TAA (equal quality after TAA 3.12x against 2.82x at 0.125 and 2.63x
/// at 0.25, in one default run at this head); the revisit count
/// (`spvg::controller::fractional::REVISIT_COUNT`) keeps a converged pixel sampling.
/// Ambient occlusion takes its own (`crate::motion::scenes::RESOLVED_FLOOR`).
pub const RESOLVED_FLOOR: f32 = 0.0;

/// A run's description.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// The model.
    pub model: Model,
    /// Controller settings.
    pub cfg: PassConfig,
    /// Label for tables: the model name, then the swept setting after a space.
    pub label: String,
    /// A frame budget in samples per subsurface pixel: the run's `sigma0^2` is then only
    /// the initial target (and fixes the texel encoding), and `spvg::budget::Governor`
    /// sets each frame's target from the demand reduction of the pass
    /// (`spvg_effects::sss::reduce`).
    pub budget_spp: Option<f64>,
    /// The governor's integral gain in a budget run (`spvg::budget::BudgetConfig::gain`).
    pub budget_gain: f64,
    /// The TAA-guided update (docs/algorithms.md §8.5): each frame's update takes the
    /// report's TAA history `C_t` (reprojected and clamped against this frame, before the
    /// blend) as its guide, converted to the monitored space.
    pub guided: bool,
}

impl RunSpec {
    /// Whether this run is at a swept setting rather than the report's.
    #[must_use]
    pub fn is_sweep(&self) -> bool {
        self.label.contains(' ')
    }

    /// The runs of `models` at `settings` (label suffix, configuration; the first is the
    /// report setting): each fixed-count model once at the first setting, each adaptive
    /// model at every setting.
    #[must_use]
    pub fn for_models(models: &[Model], settings: &[(String, PassConfig)]) -> Vec<Self> {
        let base = settings.first().map_or_else(PassConfig::default, |s| s.1);
        let mut v: Vec<Self> = models
            .iter()
            .filter(|m| matches!(m, Model::Fixed(_)))
            .map(|&model| Self {
                model,
                cfg: base,
                label: model.name(),
                budget_spp: None,
                budget_gain: DEFAULT_GAIN,
                guided: false,
            })
            .collect();
        for (suffix, cfg) in settings {
            for &model in models.iter().filter(|m| !matches!(m, Model::Fixed(_))) {
                v.push(Self {
                    model,
                    cfg: *cfg,
                    label: format!("{}{suffix}", model.name()),
                    budget_spp: None,
                    budget_gain: DEFAULT_GAIN,
                    guided: false,
                });
            }
        }
        v
    }

    /// The `budget` run: CCV under the frame budget governor with a budget of
    /// `budget_spp` samples per subsurface pixel and integral gain `gain`, starting from
    /// (and encoding the history at) `cfg`'s target.
    #[must_use]
    pub fn budget(cfg: PassConfig, budget_spp: f64, gain: f64) -> Self {
        Self {
            model: Model::Ccv,
            cfg,
            label: "budget".into(),
            budget_spp: Some(budget_spp),
            budget_gain: gain,
            guided: false,
        }
    }

    /// The label of AS with the resolved-image count rule.
    pub const RESOLVED: &'static str = "as-resolved";

    /// AS with the resolved-image count rule (docs/algorithms.md §8.7) at `cfg`: fractional
    /// counts with the floor [`RESOLVED_FLOOR`] under a count that aims at the image after
    /// the report's TAA (`SpvgConfig::resolve_weight` of its weight `crate::taa::WEIGHT`),
    /// at the resolved-image target `a / (2 - a)` times `cfg`'s, the variance that resolve
    /// leaves of a frame aimed at `cfg`'s target: both runs aim at the same resolved image.
    ///
    /// # Errors
    ///
    /// A configuration the core rejects (not with the report's).
    pub fn resolved(cfg: PassConfig) -> Result<Self, spvg::Error> {
        let target = cfg.spvg.target_variance()
            * spvg::controller::fractional::resolved_factor(crate::taa::WEIGHT);
        let spvg = cfg
            .spvg
            .to_builder()
            .target_variance(target)
            .fractional_floor(Some(RESOLVED_FLOOR))
            .resolve_weight(Some(crate::taa::WEIGHT))
            .build()?;
        Ok(Self {
            model: Model::As,
            cfg: PassConfig { spvg, ..cfg },
            label: Self::RESOLVED.into(),
            budget_spp: None,
            budget_gain: DEFAULT_GAIN,
            guided: false,
        })
    }

    /// Whether the run's counts are fractional: a pixel of 0 samples may have skipped the
    /// frame.
    #[must_use]
    pub fn fractional(&self) -> bool {
        !matches!(self.model, Model::Fixed(_)) && self.cfg.spvg.fractional_floor().is_some()
    }

    /// The label of the TAA-guided AS run.
    pub const GUIDED: &'static str = "as-guided";

    /// The TAA-guided AS run ([`guided`](Self::guided)) at `cfg`.
    #[must_use]
    pub fn guided(cfg: PassConfig) -> Self {
        Self {
            model: Model::As,
            cfg,
            label: Self::GUIDED.into(),
            budget_spp: None,
            budget_gain: DEFAULT_GAIN,
            guided: true,
        }
    }
}

/// The governor of a budget run: `budget_spp` samples for each of the `pixels`
/// subsurface pixels, integral gain `gain`, from the target `initial`.
fn governor(
    budget_spp: f64,
    gain: f64,
    pixels: usize,
    initial: f32,
) -> Result<Governor<f64>, ReportError> {
    let config = BudgetConfig::builder(budget_spp * pixels.max(1) as f64)
        .gain(gain)
        .build()?;
    Ok(Governor::new(config, f64::from(initial))?)
}

/// Runs `frames` frames of `scene` with `spec` on `backend`; calls `on_frame` with each
/// frame's output and reference (for images). Without `refs` (timing runs at resolutions
/// where the quadrature reference would dominate the run time) the PSNR figures are NaN
/// and `on_frame` gets an empty reference.
///
/// # Errors
///
/// Parameter validation or device errors.
pub fn run_scene(
    backend: &Backend,
    scene: Scene,
    material: &MaterialPreset,
    spec: &RunSpec,
    frames: u32,
    mut refs: Option<&mut ReferenceCache>,
    mut on_frame: impl FnMut(u32, &FrameOutput, &[[f32; 3]], &[u8]),
) -> Result<(Vec<FrameRecord>, RunSummary), ReportError> {
    let mut pass = backend.pass(spec.model, scene.width, scene.height)?;
    let mut resolve = Resolve::new(scene)?;
    let mut records = Vec::with_capacity(frames as usize);
    let mut timer = Timer::WallClock;
    // A budget run: the governor, and the reduction of the pass that feeds it.
    let mut budget = match spec.budget_spp {
        Some(b) => {
            let pixels = scene.inputs(0).mask.iter().filter(|m| **m != 0).count();
            let reducer = Reducer::for_runner(&pass, scene.width, scene.height);
            Some((
                governor(b, spec.budget_gain, pixels, spec.cfg.spvg.target_variance())?,
                reducer,
            ))
        }
        None => None,
    };
    // The clamped demand curve the last plan came from (the feed-forward's model of the
    // next frame's total).
    let mut last_curve = None;
    let mut previous_count: Option<Vec<u32>> = None;
    let mut skips = spec.fractional().then(SkipRuns::default);
    for t in 0..frames {
        let inputs = scene.inputs(t);
        // Under the governor the target moves each frame while the texel encoding stays
        // at the run's initial target (the component keeps it; docs/algorithms.md §8.2).
        let cfg = match &budget {
            Some((g, _)) => PassConfig {
                spvg: spec
                    .cfg
                    .spvg
                    .to_builder()
                    .target_variance(g.target() as f32)
                    .build()?,
                ..spec.cfg
            },
            None => spec.cfg,
        };
        let params = pass.frame_params(&cfg, material, t)?;
        // A guided run resolves the frame inside the pass, between its sampling and its
        // update (the renderer's order: sample, TAA, update), and keeps the resolved image.
        let mut resolved = None;
        let out = if spec.guided {
            let mut guide = |result: &[[half::f16; 4]], value: &[f32]| {
                let (image, guide) = resolve.guided(result, value, &inputs);
                resolved = image;
                guide
            };
            pass.run_frame_guided(&params, &inputs, Some(&mut guide))?
        } else {
            pass.run_frame(&params, &inputs)?
        };
        let planned_spp = last_curve.map_or(f64::NAN, |c: spvg::budget::DemandCurve<f64>| {
            c.total_at(f64::from(cfg.spvg.target_variance()))
                / inputs.mask.iter().filter(|m| **m != 0).count().max(1) as f64
        });
        if let Some((g, reducer)) = &mut budget {
            // Frame t's total and the clamped demand curve of the history frame t + 1
            // reads, at candidates around the governor's feed-forward target: the target
            // of frame t + 1 is planned before it is submitted (spvg_effects::sss::reduce).
            let targets = g.curve_targets().map(|c| c as f32);
            let partials = reducer.partials(&pass, &params, &targets, &inputs, &out)?;
            let sums = FrameSums::from_partials(&partials, &targets);
            g.observe(sums.total as f64);
            g.plan_curve(&sums.curve);
            last_curve = Some(sums.curve);
        }
        timer = out.timer;
        let reference = refs.as_mut().map(|r| r.frame(t)).unwrap_or_default();
        // A fractional run's pixels of 0 samples show their distant part's history mean.
        let history = if spec.fractional() && !reference.is_empty() {
            Some(pass.history()?)
        } else {
            None
        };
        let a = accuracy(
            &out,
            &reference,
            &inputs,
            &mut resolve,
            resolved,
            history.as_ref(),
        )?;
        records.push(FrameRecord {
            frame: t,
            spp: mean_spp(&out.count, &inputs.mask),
            time_ms: out.time_ms,
            psnr: a.psnr,
            relmse: a.relmse,
            psnr_taa: a.psnr_taa,
            relmse_taa: a.relmse_taa,
            flicker_taa: a.flicker_taa,
            zero_pixels: zero_pixels(&out.count, &inputs.mask),
            count_step: count_step(&out.count, previous_count.as_deref(), &inputs.mask),
            at_bounds: at_bounds(
                &out.count,
                &inputs.mask,
                [spec.cfg.spvg.min_samples(), spec.cfg.spvg.max_samples()],
            ),
            target: f64::from(cfg.spvg.target_variance()),
            planned_spp,
        });
        if let Some(s) = &mut skips {
            s.push(&out.count, &inputs.mask);
        }
        previous_count = Some(out.count.clone());
        on_frame(t, &out, &reference, &inputs.mask);
    }
    let mut summary = summarize(scene, spec, &records, timer);
    summary.longest_skip = skips.map(|s| s.longest);
    Ok((records, summary))
}

/// The TAA resolve of a run's luminance and the stability measure of the resolved image.
struct Resolve {
    taa: Taa,
    flicker: Flicker,
    size: [u32; 2],
    /// The scenes' camera is fixed: zero motion everywhere (the occluders scene's disc
    /// moves, but it is not subsurface: what it uncovers fails the mask and depth tests).
    motion: Vec<[f32; 2]>,
}

impl Resolve {
    /// Resolves a guided frame's luminance (its `result` texels) and returns the resolved
    /// image (`None` if the resolve refused the frame) and the guide in the monitored
    /// space: the TAA history `C` of the result's luminance less the frame's near part
    /// `lum(result) - value` (the unified result is the near part plus the monitored
    /// distant part, and luminance is linear), NaN where the resolve had no history.
    fn guided(
        &mut self,
        result: &[[half::f16; 4]],
        value: &[f32],
        inputs: &FrameInputs,
    ) -> (Option<Vec<f32>>, Vec<f32>) {
        let lum: Vec<f32> = result.iter().map(|v| luminance(rgb(*v))).collect();
        let frame = TaaFrame {
            value: &lum,
            motion: &self.motion,
            depth: &inputs.depth,
            mask: &inputs.mask,
            skipped: None,
        };
        let Ok(resolved) = self.taa.resolve(&frame).map(<[f32]>::to_vec) else {
            return (None, vec![f32::NAN; value.len()]);
        };
        let guide = self
            .taa
            .clamped_history()
            .iter()
            .zip(&lum)
            .zip(value)
            .map(|((c, l), v)| c - (l - v))
            .collect();
        (Some(resolved), guide)
    }

    fn new(scene: Scene) -> Result<Self, ReportError> {
        let n = scene.width as usize * scene.height as usize;
        Ok(Self {
            taa: Taa::report(scene.width, scene.height)?,
            flicker: Flicker::default(),
            size: [scene.width, scene.height],
            motion: vec![[0.0; 2]; n],
        })
    }
}

/// A frame's accuracy figures (the fields of [`FrameRecord`] of the same names).
struct Accuracy {
    psnr: f64,
    relmse: f64,
    psnr_taa: f64,
    relmse_taa: f64,
    flicker_taa: f64,
}

/// A frame's single-frame PSNR and relMSE, and after the TAA resolve its PSNR, relMSE and
/// instability, against `reference` (NaN without one); resolves the frame's luminance
/// unless a guided frame already did (`resolved`).
///
/// With `history` (a fractional run's history after the frame), a subsurface pixel of 0
/// samples skipped the frame, or the zero-sample rule left it without distant samples:
/// its luminance shows the near part plus its history's mean monitored value (the
/// distant part's luminance; a skipped frame keeps the mean, and the zero-sample rule's
/// distant part is about 0), and the resolve keeps its own history there
/// ([`TaaFrame::skipped`]). Its single-frame RGB has no distant part: the single-frame
/// figures of such a run measure what it did not sample.
fn accuracy(
    out: &FrameOutput,
    reference: &[[f32; 3]],
    inputs: &FrameInputs,
    resolve: &mut Resolve,
    resolved: Option<Vec<f32>>,
    history: Option<&History>,
) -> Result<Accuracy, ReportError> {
    if reference.is_empty() {
        return Ok(Accuracy {
            psnr: f64::NAN,
            relmse: f64::NAN,
            psnr_taa: f64::NAN,
            relmse_taa: f64::NAN,
            flicker_taa: f64::NAN,
        });
    }
    let mask = &inputs.mask;
    let result: Vec<[f32; 3]> = out.result.iter().map(|v| rgb(*v)).collect();
    let single = psnr(&result, reference, mask);
    let rel = relmse(&result, reference, mask);
    let mut lum: Vec<f32> = result.iter().map(|v| luminance(*v)).collect();
    let skipped: Option<Vec<bool>> = history.map(|_| {
        out.count
            .iter()
            .zip(mask)
            .map(|(&n, &m)| n == 0 && m != 0)
            .collect()
    });
    if let (Some(h), Some(skipped)) = (history, &skipped) {
        for ((l, texel), &s) in lum.iter_mut().zip(&h.h).zip(skipped) {
            if s {
                *l += texel[0].to_f32();
            }
        }
    }
    let ref_lum: Vec<f32> = reference.iter().map(|v| luminance(*v)).collect();
    let frame = TaaFrame {
        value: &lum,
        motion: &resolve.motion,
        depth: &inputs.depth,
        mask,
        skipped: skipped.as_deref(),
    };
    let resolved = match resolved {
        Some(r) => r,
        None => resolve.taa.resolve(&frame)?.to_vec(),
    };
    let flicker = resolve
        .flicker
        .push(&resolved, &ref_lum, &frame, resolve.size);
    let pairs = || {
        resolved
            .iter()
            .zip(&ref_lum)
            .zip(mask)
            .filter(|(_, m)| **m != 0)
            .map(|((a, b), _)| (f64::from(*a), f64::from(*b)))
    };
    Ok(Accuracy {
        psnr: single,
        relmse: rel,
        psnr_taa: psnr_of_pairs(pairs()),
        relmse_taa: relmse_of_pairs(pairs()),
        flicker_taa: flicker,
    })
}

/// Subsurface pixels that took no samples.
fn zero_pixels(count: &[u32], mask: &[u8]) -> u64 {
    count
        .iter()
        .zip(mask)
        .filter(|(c, m)| **c == 0 && **m != 0)
        .count() as u64
}

/// The fractions of the subsurface pixels whose count equals each of `bounds`.
fn at_bounds(count: &[u32], mask: &[u8], bounds: [u32; 2]) -> [f64; 2] {
    bounds.map(|b| {
        let (mut hit, mut all) = (0_usize, 0_usize);
        for (c, m) in count.iter().zip(mask) {
            if *m != 0 {
                all += 1;
                hit += usize::from(*c == b);
            }
        }
        hit as f64 / all as f64
    })
}

/// The summary of a run's frame records.
fn summarize(scene: Scene, spec: &RunSpec, records: &[FrameRecord], timer: Timer) -> RunSummary {
    let n = records.len().max(1) as f64;
    let mean = |f: fn(&FrameRecord) -> f64| records.iter().map(f).sum::<f64>() / n;
    let max = |f: fn(&FrameRecord) -> f64| records.iter().map(f).fold(f64::NAN, f64::max);
    let min = |f: fn(&FrameRecord) -> f64| records.iter().map(f).fold(f64::NAN, f64::min);
    let mut times: Vec<f64> = records.iter().skip(1).map(|r| r.time_ms).collect();
    times.sort_by(f64::total_cmp);
    RunSummary {
        scene: scene.kind.name(),
        label: spec.label.clone(),
        model: spec.model,
        mean_spp: mean(|r| r.spp),
        worst_spp: max(|r| r.spp),
        p50_ms: percentile(&times, 0.5),
        p95_ms: percentile(&times, 0.95),
        max_ms: times.last().copied().unwrap_or(f64::NAN),
        mean_psnr: mean(|r| r.psnr),
        worst_psnr: min(|r| r.psnr),
        mean_relmse: mean(|r| r.relmse),
        mean_psnr_taa: mean(|r| r.psnr_taa),
        worst_psnr_taa: min(|r| r.psnr_taa),
        mean_relmse_taa: mean(|r| r.relmse_taa),
        flicker_taa: finite_mean(records.iter().map(|r| r.flicker_taa)),
        history_bytes: spec.model.history_bytes_per_pixel(),
        timer,
        budget_spp: spec.budget_spp,
        in_band: spec.budget_spp.map_or(f64::NAN, |b| in_band(records, b)),
        count_step: finite_mean(records.iter().skip(records.len() / 2).map(|r| r.count_step)),
        longest_skip: None,
    }
}

/// The mean of the finite values (NaN when there are none).
fn finite_mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v
        .filter(|x| x.is_finite())
        .fold((0.0, 0_usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

/// The fraction of the frames from [`BUDGET_WARMUP`] on whose mean spp (the frame's total
/// over its subsurface pixels) lies within [`BUDGET_BAND`] of `budget_spp`; NaN when the
/// run is no longer than the warm-up.
#[must_use]
pub fn in_band(records: &[FrameRecord], budget_spp: f64) -> f64 {
    let judged: Vec<&FrameRecord> = records
        .iter()
        .filter(|r| r.frame >= BUDGET_WARMUP)
        .collect();
    if judged.is_empty() {
        return f64::NAN;
    }
    let inside = judged
        .iter()
        .filter(|r| (r.spp / budget_spp - 1.0).abs() <= BUDGET_BAND)
        .count();
    inside as f64 / judged.len() as f64
}
