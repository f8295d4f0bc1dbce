//! The focus-region scene run separable-only, AFIS adaptive-only (AS and CCV) and hybrid
//! (docs/algorithms.md §5.1), against the quadrature reference, with each run's work
//! ([`super::work`]) and, where asked, the timing rows at a larger size.
//!
//! The focus scene is the static scene (shadow edge, depth step, gently varying light) with
//! a disc in the middle tagged for Monte Carlo: its time, PSNR over the frame and over the
//! disc, and the seam (the error in a band along the disc's boundary against the error of
//! each technique away from it).

use half::f16;
use spvg::burley::{MaterialPreset, presets};

use super::work;
use crate::error::ReportError;
use crate::metrics::{psnr, rgb, rmse};
use crate::reference::static_reference;
use crate::scene::{Lighting, Scene, SceneKind};
use crate::wgpu_api::{
    FrameInputs, GpuDevice, HybridPass, HybridTimes, HybridTwin, Model, PassConfig,
    SeparableConfig, SeparableParams, SeparablePass, SeparableTwin, SssPass, SssTwin,
    technique_ids,
};

/// Half-width of the seam band, in pixels, on each side of the focus boundary.
pub const BAND_PX: f64 = 3.0;

/// What the focus scene runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FocusOptions {
    /// Frame width and height.
    pub size: [u32; 2],
    /// Frames per run; the metrics average the second half (after the adaptive models'
    /// warm-up).
    pub frames: u32,
    /// The material.
    pub material: MaterialPreset,
    /// The focus disc's centre, as fractions of the frame width and height.
    pub centre: [f64; 2],
    /// The focus disc's radius as a fraction of the frame height.
    pub radius: f64,
    /// The timing rows' frame size and measured frames (on a device only; `None` times
    /// the quality runs): at the quality runs' size a software adapter's frame time is
    /// mostly per-dispatch and per-submit overhead, not the pixels' work that the hybrid
    /// pass's tags decide.
    pub timing: Option<([u32; 2], u32)>,
}

impl Default for FocusOptions {
    fn default() -> Self {
        Self {
            size: [160, 120],
            frames: 16,
            material: presets::SKIN1,
            centre: [0.2, 0.3],
            radius: 0.16,
            timing: Some(([640, 480], TIMING_FRAMES)),
        }
    }
}

/// One run of the focus scene, averaged over the measured frames.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FocusRun {
    /// `separable`, `as`, `ccv` or `hybrid-ccv`.
    pub name: String,
    /// Mean frame time (ms).
    pub time_ms: f64,
    /// PSNR of the luminance over the subsurface pixels (dB).
    pub psnr_frame: f64,
    /// PSNR over the focus disc (dB).
    pub psnr_focus: f64,
    /// Luminance RMSE in the band of [`BAND_PX`] around the boundary (for the runs of one
    /// technique: that technique's error on the same pixels).
    pub rmse_band: f64,
    /// Luminance RMSE inside the disc, farther than the band from the boundary.
    pub rmse_inside: f64,
    /// Luminance RMSE outside the disc, farther than the band from the boundary.
    pub rmse_outside: f64,
    /// Mean samples per subsurface pixel.
    pub spp: f64,
}

/// Measured frames of the timing rows by default (after [`TIMING_WARMUP`]): on a software
/// adapter a frame's four runs take about a second at 640x480, and the median of the
/// per-frame slack needs enough frames to stand still against the machine's load.
pub const TIMING_FRAMES: u32 = 24;

/// Frames of the timing rows not measured: the hybrid pass's first step runs over the
/// whole frame for two frames after its tags are set, and the first frame of each pass
/// compiles its pipelines.
pub const TIMING_WARMUP: u32 = 3;

/// The timing rows: separable-only, CCV-only and hybrid (CCV in the disc) at a size where
/// the pixels' work dominates, interleaved frame by frame, medians; and the median of the
/// per-frame slack of the time bound, which the time check judges.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FocusTiming {
    /// Frame size.
    pub size: [u32; 2],
    /// Measured frames per run.
    pub frames: u32,
    /// Fraction of the subsurface pixels tagged at that size.
    pub focus_fraction: f64,
    /// Median frame time of the separable-only run (ms).
    pub separable_ms: f64,
    /// Median frame time of the CCV-only run (ms).
    pub ccv_ms: f64,
    /// Median frame time of the hybrid run, one submit per frame (ms).
    pub hybrid_ms: f64,
    /// The hybrid's steps, each submitted alone (medians, ms).
    pub steps: HybridTimes,
    /// Median over the frames of the per-frame slack of the time bound,
    /// `separable + 1.3 x focus_fraction x (CCV - separable) - hybrid` with the three runs
    /// of the same frame (ms; >= 0 where the bound holds). The runs of a frame are
    /// interleaved, so a change of the machine's load reaches them alike and mostly cancels
    /// here, where it would move the medians of the runs apart.
    pub slack_ms: f64,
}

/// The acceptance's time bound on the hybrid: separable-only plus 1.3 x the tagged fraction
/// of what CCV-only costs over it (ms). [`FocusTiming::slack_ms`] is the median of this
/// minus the hybrid's time, frame by frame.
///
/// # Examples
///
/// ```
/// use spvg_report::separable::hybrid_time_bound;
/// // 100 + 1.3 x 0.05 x (200 - 100)
/// assert!((hybrid_time_bound(100.0, 200.0, 0.05) - 106.5).abs() < 1e-12);
/// ```
#[must_use]
pub fn hybrid_time_bound(separable_ms: f64, ccv_ms: f64, focus_fraction: f64) -> f64 {
    separable_ms + 1.3 * focus_fraction * (ccv_ms - separable_ms)
}

/// The work of the focus scene's runs ([`super::work`]): fetched texels per frame, the
/// mean over the measured frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FocusWork {
    /// Separable-only.
    pub separable: f64,
    /// CCV-only.
    pub ccv: f64,
    /// The hybrid (CCV in the disc).
    pub hybrid: f64,
}

/// The focus scene's result: the runs and the checks.
#[derive(Clone, Debug, PartialEq)]
pub struct FocusResult {
    /// Separable, AS, CCV, hybrid (CCV in the disc).
    pub runs: Vec<FocusRun>,
    /// Fraction of the subsurface pixels tagged for Monte Carlo.
    pub focus_fraction: f64,
    /// Whether the times are CPU time (software adapter or the twin).
    pub cpu_time: bool,
    /// Whether the times are GPU timestamps of a hardware adapter, so that the time line
    /// judges milliseconds (else it judges [`work`](Self::work)).
    pub judge_time: bool,
    /// The runs' work.
    pub work: FocusWork,
    /// The timing rows ([`FocusOptions::timing`]), which the time line judges on a
    /// hardware adapter with timestamps.
    pub timing: Option<FocusTiming>,
}

/// Which pixels belong to the disc, the band, and the two interiors.
struct Regions {
    focus: Vec<u8>,
    band: Vec<u8>,
    inside: Vec<u8>,
    outside: Vec<u8>,
}

fn regions(opts: &FocusOptions, mask: &[u8]) -> Regions {
    let [w, h] = opts.size;
    let (cx, cy) = (opts.centre[0] * f64::from(w), opts.centre[1] * f64::from(h));
    let radius = opts.radius * f64::from(h);
    let mut r = Regions {
        focus: Vec::new(),
        band: Vec::new(),
        inside: Vec::new(),
        outside: Vec::new(),
    };
    for (i, &m) in mask.iter().enumerate().take((w * h) as usize) {
        let (x, y) = ((i % w as usize) as f64 + 0.5, (i / w as usize) as f64 + 0.5);
        let dist = (x - cx).hypot(y - cy) - radius;
        let on = m != 0;
        r.focus.push(u8::from(dist < 0.0));
        r.band.push(u8::from(on && dist.abs() <= BAND_PX));
        r.inside.push(u8::from(on && dist < -BAND_PX));
        r.outside.push(u8::from(on && dist > BAND_PX));
    }
    r
}

/// The technique a focus run uses.
enum Runner {
    Separable(Option<Box<SeparablePass>>),
    Sampled(Box<Result<SssPass, SssTwin>>),
    Hybrid(Box<Result<HybridPass, HybridTwin>>),
}

/// Runs the focus scene on `device` (the CPU twins without one).
///
/// # Errors
///
/// A pass error, or a configuration the passes refuse.
pub fn run_focus(
    device: Option<&GpuDevice>,
    opts: &FocusOptions,
) -> Result<FocusResult, ReportError> {
    let [w, h] = opts.size;
    let scene = Scene {
        lighting: Lighting::Gradient,
        ..Scene::new(SceneKind::Static, w, h)
    };
    let cfg = PassConfig {
        afis: true,
        ..PassConfig::default()
    };
    let inputs0 = scene.inputs(0);
    let reference = static_reference(&scene, &opts.material, &cfg);
    let reg = regions(opts, &inputs0.mask);
    let technique = technique_ids(&reg.focus, w, h, None)?;
    let focus_mask: Vec<u8> = reg
        .focus
        .iter()
        .zip(&inputs0.mask)
        .map(|(&f, &m)| u8::from(f != 0 && m != 0))
        .collect();
    let on = inputs0.mask.iter().filter(|&&m| m != 0).count().max(1);
    let focus_fraction = focus_mask.iter().filter(|&&m| m != 0).count() as f64 / on as f64;
    let sep_cfg = SeparableConfig::for_pass(&cfg);
    let sep_plain = sep_cfg.params(&opts.material, w, h, false)?;
    let sep_hybrid = sep_cfg.params(&opts.material, w, h, true)?;
    let work_of = |count: &[u32], hybrid: bool| {
        let f = work::Frame {
            size: opts.size,
            mask: &inputs0.mask,
            depth: &inputs0.depth,
            technique: &technique,
            sep: &sep_hybrid,
        };
        if hybrid {
            f.hybrid(count)
        } else {
            f.sampled(count)
        }
    };
    let mut work = FocusWork::default();
    let mut runs = Vec::new();
    for name in ["separable", "as", "ccv", "hybrid-ccv"] {
        let mut runner = match name {
            "separable" => Runner::Separable(
                device.map(|d| Box::new(SeparablePass::new(&d.device, &d.queue, w, h))),
            ),
            "as" | "ccv" => {
                let model = if name == "as" { Model::As } else { Model::Ccv };
                Runner::Sampled(Box::new(match device {
                    Some(d) => Ok(SssPass::for_device(d, model, w, h)),
                    None => Err(SssTwin::new(model, w, h)),
                }))
            }
            _ => Runner::Hybrid(Box::new(match device {
                Some(d) => Ok(HybridPass::new(&d.device, &d.queue, w, h, Model::Ccv)?),
                None => Err(HybridTwin::new(Model::Ccv, w, h)?),
            })),
        };
        let mut acc = FocusRun {
            name: name.into(),
            ..FocusRun::default()
        };
        let measured = opts.frames - opts.frames / 2;
        for t in 0..opts.frames {
            let inputs = scene.inputs(t);
            let (result, count, ms) = frame(
                &mut runner,
                (&cfg, &opts.material, t),
                &sep_plain,
                &sep_hybrid,
                &inputs,
                &technique,
            )?;
            if t < opts.frames / 2 {
                continue;
            }
            let image: Vec<[f32; 3]> = result.iter().map(|&t| rgb(t)).collect();
            let k = 1.0 / f64::from(measured);
            acc.time_ms += k * ms;
            acc.psnr_frame += k * psnr(&image, &reference, &inputs.mask);
            acc.psnr_focus += k * psnr(&image, &reference, &focus_mask);
            acc.rmse_band += k * rmse(&image, &reference, &reg.band);
            acc.rmse_inside += k * rmse(&image, &reference, &reg.inside);
            acc.rmse_outside += k * rmse(&image, &reference, &reg.outside);
            acc.spp += k * crate::metrics::mean_spp(&count, &inputs.mask);
            match name {
                "ccv" => work.ccv += k * work_of(&count, false) as f64,
                "hybrid-ccv" => work.hybrid += k * work_of(&count, true) as f64,
                _ => {}
            }
        }
        runs.push(acc);
    }
    work.separable = work::Frame {
        size: opts.size,
        mask: &inputs0.mask,
        depth: &inputs0.depth,
        technique: &technique,
        sep: &sep_plain,
    }
    .separable_only() as f64;
    let timing = match (device, opts.timing) {
        (Some(d), Some((size, frames))) => Some(run_timing(d, opts, size, frames)?),
        _ => None,
    };
    Ok(FocusResult {
        runs,
        focus_fraction,
        cpu_time: device.is_none_or(GpuDevice::is_software),
        judge_time: judges_time(device),
        work,
        timing,
    })
}

/// Whether the hybrid time line judges milliseconds on `device`: a hardware adapter with
/// timestamp queries. Elsewhere (a software rasterizer, whose times are CPU time that
/// moves between runs by more than the bound's slack, or the CPU twin) it judges work.
#[must_use]
pub fn judges_time(device: Option<&GpuDevice>) -> bool {
    device.is_some_and(|d| d.timestamps && !d.is_software())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The timing rows on `device` at `size`: each frame runs separable-only, CCV-only, the
/// hybrid and the hybrid step by step one after the other (in a rotating order, so a
/// change of the machine's load reaches all four alike); medians over `frames` frames after
/// [`TIMING_WARMUP`], and the median of the per-frame slack of the time bound.
fn run_timing(
    device: &GpuDevice,
    opts: &FocusOptions,
    size: [u32; 2],
    frames: u32,
) -> Result<FocusTiming, ReportError> {
    let [w, h] = size;
    let scene = Scene {
        lighting: Lighting::Gradient,
        ..Scene::new(SceneKind::Static, w, h)
    };
    let cfg = PassConfig {
        afis: true,
        ..PassConfig::default()
    };
    let sized = FocusOptions { size, ..*opts };
    let mask = scene.inputs(0).mask;
    let focus = regions(&sized, &mask).focus;
    let technique = technique_ids(&focus, w, h, None)?;
    let on = mask.iter().filter(|&&m| m != 0).count().max(1);
    let tagged = focus
        .iter()
        .zip(&mask)
        .filter(|(f, m)| **f != 0 && **m != 0);
    let focus_fraction = tagged.count() as f64 / on as f64;
    let sep_cfg = SeparableConfig::for_pass(&cfg);
    let sep_plain = sep_cfg.params(&opts.material, w, h, false)?;
    let sep_hybrid = sep_cfg.params(&opts.material, w, h, true)?;
    let mut separable = SeparablePass::new(&device.device, &device.queue, w, h);
    let mut ccv = SssPass::for_device(device, Model::Ccv, w, h);
    let mut hybrid = HybridPass::new(&device.device, &device.queue, w, h, Model::Ccv)?;
    let mut steps = HybridPass::new(&device.device, &device.queue, w, h, Model::Ccv)?;
    let mut times: [Vec<f64>; 9] = Default::default();
    for t in 0..TIMING_WARMUP + frames {
        let inputs = scene.inputs(t);
        let mut row = [0.0; 9];
        for k in 0..4 {
            match (k + t) % 4 {
                0 => row[0] = separable.run_frame(&sep_plain, &inputs, None)?.time_ms,
                1 => {
                    let p = ccv.frame_params(&cfg, &opts.material, t)?;
                    row[1] = ccv.run_frame(&p, &inputs)?.time_ms;
                }
                2 => {
                    let p = hybrid.frame_params(&cfg, &opts.material, t)?;
                    let o = hybrid.run_frame(&p, &sep_hybrid, &inputs, &technique)?;
                    row[2] = o.frame.time_ms;
                }
                _ => {
                    let p = steps.frame_params(&cfg, &opts.material, t)?;
                    let (_, s) = steps.run_frame_per_pass(&p, &sep_hybrid, &inputs, &technique)?;
                    row[3..].copy_from_slice(&[
                        s.estimate_ms,
                        s.sampling_ms,
                        s.update_ms,
                        s.compose_ms,
                        s.horizontal_ms,
                        s.vertical_ms,
                    ]);
                }
            }
        }
        if t >= TIMING_WARMUP {
            for (v, x) in times.iter_mut().zip(row) {
                v.push(x);
            }
        }
    }
    let slack: Vec<f64> = (0..times[0].len())
        .map(|i| hybrid_time_bound(times[0][i], times[1][i], focus_fraction) - times[2][i])
        .collect();
    let slack_ms = median(slack);
    let [s, c, hy, e, sa, u, co, ph, pv] = times.map(median);
    Ok(FocusTiming {
        size,
        frames,
        focus_fraction,
        separable_ms: s,
        ccv_ms: c,
        hybrid_ms: hy,
        steps: HybridTimes {
            estimate_ms: e,
            sampling_ms: sa,
            update_ms: u,
            compose_ms: co,
            horizontal_ms: ph,
            vertical_ms: pv,
        },
        slack_ms,
    })
}

type FrameResult = (Vec<[f16; 4]>, Vec<u32>, f64);

fn frame(
    runner: &mut Runner,
    (cfg, material, t): (&PassConfig, &MaterialPreset, u32),
    sep_plain: &SeparableParams,
    sep_hybrid: &SeparableParams,
    inputs: &FrameInputs,
    technique: &[u8],
) -> Result<FrameResult, ReportError> {
    Ok(match runner {
        Runner::Sampled(r) => match r.as_mut() {
            Ok(g) => {
                let p = g.frame_params(cfg, material, t)?;
                let o = g.run_frame(&p, inputs)?;
                (o.result, o.count, o.time_ms)
            }
            Err(c) => {
                let p = c.frame_params(cfg, material, t)?;
                let o = c.run_frame(&p, inputs)?;
                (o.result, o.count, o.time_ms)
            }
        },
        Runner::Hybrid(r) => {
            let o = match r.as_mut() {
                Ok(g) => {
                    let p = g.frame_params(cfg, material, t)?;
                    g.run_frame(&p, sep_hybrid, inputs, technique)?
                }
                Err(c) => {
                    let p = c.frame_params(cfg, material, t)?;
                    c.run_frame(&p, sep_hybrid, inputs, technique)?
                }
            };
            (o.frame.result, o.frame.count, o.frame.time_ms)
        }
        Runner::Separable(Some(g)) => {
            let o = g.run_frame(sep_plain, inputs, None)?;
            (o.result, o.count, o.time_ms)
        }
        Runner::Separable(None) => {
            let o = SeparableTwin.run_frame(sep_plain, inputs, None)?;
            (o.result, o.count, o.time_ms)
        }
    })
}
