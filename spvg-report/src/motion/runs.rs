//! The runs of the motion report: one scene through one [`Variant`] on the GPU or the CPU
//! twin, measured frame by frame against its references, and the GPU against the twin.

use spvg::reproject::Reprojection;

use super::MotionOptions;
use super::acceptance::acceptance;
use super::baseline::{baseline_frames, static_at_heights};
use super::poses::{StillBaseline, still_at_poses, still_frames};
use super::reference::references;
use super::scenes::{DOLLY, GUIDED, OBJECTS, Variant, others, pans, variants};
use super::uncovered::{AgeErrors, since_uncovered};
use crate::acceptance::Check;
use crate::metrics::{Flicker, psnr_of_pairs, relmse_of_pairs};
use crate::progress::Progress;
use crate::taa::{Taa, TaaFrame};
use crate::wgpu_api::{
    AdaptiveError, AdaptiveSettings, AoFrame, AoGuide, AoMode, AoParams, AoPass, AoScene, AoTwin,
    GpuDevice, Motion, ao_twin as twin,
};

/// Per-frame results of one scene through one mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionRun {
    /// Scene name (`static`, `pan4`, ...).
    pub scene: String,
    /// Mode name (`fixed64`, `as`, `as-identity`).
    pub mode: String,
    /// Mean samples per pixel, per frame.
    pub spp: Vec<f64>,
    /// PSNR of the AO against the reference, per frame (dB, peak 1).
    pub psnr: Vec<f64>,
    /// PSNR over the pixels whose surface point was on screen in this and the two previous
    /// frames (the steady part of the frame; the pixels entering the frame have no history
    /// of their own for their first frames).
    pub psnr_steady: Vec<f64>,
    /// PSNR of the AO after the TAA resolve ([`crate::taa`]), per frame (dB; NaN where
    /// the frame is not scored).
    pub psnr_taa: Vec<f64>,
    /// Relative MSE of the AO after the TAA resolve, per frame.
    pub relmse_taa: Vec<f64>,
    /// Temporal instability of the resolved AO ([`Flicker`]), per frame (NaN on the first
    /// scored frame).
    pub flicker_taa: Vec<f64>,
    /// Moving-object scenes: mean spp of the pixels uncovered this frame (`None` where no
    /// pixel was).
    pub uncovered_spp: Vec<Option<f64>>,
    /// Moving-object scenes: mean spp of the steady pixels (no object in either frame).
    pub steady_spp: Vec<Option<f64>>,
    /// Moving-object scenes: fraction of the uncovered pixels at the maximum count.
    pub uncovered_at_max: Vec<Option<f64>>,
    /// Moving-object scenes: mean spp of the pixels showing a moving object now.
    pub object_spp: Vec<Option<f64>>,
    /// Moving-object scenes: per frame, the squared error of the steady pixels and of the
    /// uncovered ones by their age on screen ([`AgeErrors`]; all 0 on unscored frames).
    pub uncovered_errors: Vec<AgeErrors>,
}

/// Frames left out of the run means: the controller's warm-up from a cold history (every
/// mode and scene alike; the charts and `motion.csv` show every frame).
pub const WARM_UP: usize = 16;

impl MotionRun {
    /// Mean over the frames after [`WARM_UP`] (all frames of a shorter run) of the
    /// per-frame mean spp.
    #[must_use]
    pub fn mean_spp(&self) -> f64 {
        mean(steady(&self.spp))
    }

    /// Mean over the frames after [`WARM_UP`] of the per-frame PSNR.
    #[must_use]
    pub fn mean_psnr(&self) -> f64 {
        mean(steady(&self.psnr))
    }

    /// Mean over the frames after [`WARM_UP`] of the PSNR after TAA.
    #[must_use]
    pub fn mean_psnr_taa(&self) -> f64 {
        mean(steady(&self.psnr_taa))
    }

    /// Mean over the frames after [`WARM_UP`] of the relative MSE after TAA.
    #[must_use]
    pub fn mean_relmse_taa(&self) -> f64 {
        mean(steady(&self.relmse_taa))
    }

    /// Mean over the frames after [`WARM_UP`] that have one of the instability after TAA
    /// (NaN when none has).
    #[must_use]
    pub fn mean_flicker_taa(&self) -> f64 {
        let v: Vec<f64> = steady(&self.flicker_taa)
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .collect();
        if v.is_empty() { f64::NAN } else { mean(&v) }
    }

    /// Mean over the frames after [`WARM_UP`] of the PSNR of the steady pixels.
    #[must_use]
    pub fn mean_psnr_steady(&self) -> f64 {
        mean(steady(&self.psnr_steady))
    }

    /// The squared errors by age since uncovered pooled over the frames after
    /// [`WARM_UP`] (all frames of a shorter run): every pixel-frame weighs the same.
    #[must_use]
    pub fn pooled_uncovered_errors(&self) -> AgeErrors {
        AgeErrors::pooled(steady(&self.uncovered_errors))
    }
}

fn steady<T>(v: &[T]) -> &[T] {
    if v.len() > 2 * WARM_UP {
        &v[WARM_UP..]
    } else {
        v
    }
}

/// The mean of `v` (0 when empty).
pub(crate) fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// PSNR of AO values against their reference ([`psnr_of_pairs`]: peak 1, the AO's range).
pub(super) fn psnr(image: &[f32], reference: &[f32]) -> f64 {
    psnr_of_pairs(
        image
            .iter()
            .zip(reference)
            .map(|(a, b)| (f64::from(*a), f64::from(*b))),
    )
}

/// The AO renderer on the GPU or the CPU twin.
pub(super) enum Renderer {
    Gpu(Box<AoPass>),
    Cpu(Box<AoTwin>),
}

impl Renderer {
    #[allow(clippy::too_many_arguments)]
    fn new(
        dev: Option<&GpuDevice>,
        config: spvg::SpvgConfig<f32>,
        size: [u32; 2],
        mode: AoMode,
        repro: Reprojection<f32>,
        dilation: u32,
        reprojected_depth: bool,
        neighbour_prior: bool,
    ) -> Result<Self, AdaptiveError> {
        let [w, h] = size;
        let settings = AdaptiveSettings {
            config,
            reprojection: repro,
            dilation,
            neighbour_prior,
            ..AdaptiveSettings::default()
        };
        Ok(match dev {
            Some(d) => {
                let mut g = AoPass::new(&d.device, &d.queue, w, h, mode, settings)?;
                g.set_reprojected_depth(reprojected_depth);
                Self::Gpu(Box::new(g))
            }
            None => {
                let mut c = AoTwin::new(w, h, mode, settings)?;
                c.set_reprojected_depth(reprojected_depth);
                Self::Cpu(Box::new(c))
            }
        })
    }

    pub(super) fn variant(
        dev: Option<&GpuDevice>,
        opts: &MotionOptions,
        size: [u32; 2],
        v: Variant,
    ) -> Result<Self, AdaptiveError> {
        let mut r = Self::new(
            dev,
            v.config(&opts.config)?,
            size,
            v.mode,
            v.reprojection,
            v.dilation,
            v.reprojected_depth,
            v.neighbour_prior,
        )?;
        match &mut r {
            Self::Gpu(g) => g.set_prefix_counts(v.prefixes),
            Self::Cpu(c) => c.set_prefix_counts(v.prefixes),
        }
        Ok(r)
    }

    pub(super) fn frame(&mut self, p: &AoParams) -> Result<AoFrame, AdaptiveError> {
        self.frame_guided(p, None)
    }

    fn frame_guided(
        &mut self,
        p: &AoParams,
        guide: Option<&mut AoGuide<'_>>,
    ) -> Result<AoFrame, AdaptiveError> {
        match self {
            Self::Gpu(g) => g.run_frame_guided(p, guide),
            Self::Cpu(c) => c.run_frame_guided(p, guide),
        }
    }
}

/// Frames each pixel's surface point has been on screen, capped at 3: a pixel whose
/// previous texel (along its motion vector) is inside the frame is one frame older than
/// that texel; every pixel is 1 on frame 0 or when its point just entered.
fn ages(g: &[twin::GPixel], before: &[u8], t: u32, size: [u32; 2]) -> Vec<u8> {
    let w = size[0] as usize;
    g.iter()
        .enumerate()
        .map(|(i, gp)| {
            let here = [(i % w) as u32, (i / w) as u32];
            match spvg::reproject::previous_texel(here, gp.motion, size) {
                Some(q) if t > 0 => before[q[1] as usize * w + q[0] as usize]
                    .saturating_add(1)
                    .min(3),
                _ => 1,
            }
        })
        .collect()
}

/// The PSNR over the pixels on screen for 3 frames (NaN when there are none).
fn steady_psnr(value: &[f32], reference: &[f32], age: &[u8]) -> f64 {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for ((v, r), &k) in value.iter().zip(reference).zip(age) {
        if k >= 3 {
            a.push(*v);
            b.push(*r);
        }
    }
    if a.is_empty() { f64::NAN } else { psnr(&a, &b) }
}

/// The moving objects' per-frame figures: the mean count of the pixels they uncovered this
/// frame, of the steady ones and of those showing an object, and the fraction of the
/// uncovered at `max` samples.
fn uncovered_figures(run: &mut MotionRun, count: &[u32], before: &[bool], now: &[bool], max: u32) {
    let (mut un, mut st, mut on) = (Vec::new(), Vec::new(), Vec::new());
    for ((&n, &b), &m) in count.iter().zip(before).zip(now) {
        match (b, m) {
            (true, false) => un.push(n),
            (false, false) => st.push(n),
            (_, true) => on.push(n),
        }
    }
    let avg = |v: &[u32]| {
        (!v.is_empty()).then(|| v.iter().map(|&n| f64::from(n)).sum::<f64>() / v.len() as f64)
    };
    run.uncovered_spp.push(avg(&un));
    run.steady_spp.push(avg(&st));
    run.object_spp.push(avg(&on));
    run.uncovered_at_max.push(
        (!un.is_empty()).then(|| un.iter().filter(|&&n| n >= max).count() as f64 / un.len() as f64),
    );
}

/// One image stream of a run scored frame by frame: its [`MotionRun`], its TAA resolve
/// and its instability measure.
struct Scored {
    run: MotionRun,
    taa: Option<Taa>,
    flicker: Flicker,
}

/// What every stream of a frame shares: the G-buffer's motion and depth, the pixels'
/// ages on screen, the reference.
struct FrameContext<'a> {
    motion: &'a [[f32; 2]],
    depth: &'a [f32],
    covered: &'a [u8],
    age: &'a [u8],
    /// Moving-object scenes: each pixel's frames since uncovered ([`since_uncovered`]).
    since: Option<&'a [u8]>,
    reference: &'a [f32],
    size: [u32; 2],
}

impl Scored {
    fn new(scene: String, mode: String, size: [u32; 2]) -> Self {
        Self {
            run: MotionRun {
                scene,
                mode,
                ..MotionRun::default()
            },
            // The renderer's TAA after the consumer: its history runs through the unscored
            // warm-up frames too. It cannot fail at the frame's own size; if it did, the
            // frame's TAA figures would read NaN.
            taa: Taa::report(size[0], size[1]).ok(),
            flicker: Flicker::default(),
        }
    }

    /// Resolves one frame's `value` through the stream's TAA (`None` where it has none
    /// or the resolve fails).
    fn resolve(&mut self, value: &[f32], c: &FrameContext<'_>) -> Option<Vec<f32>> {
        let frame = TaaFrame {
            value,
            motion: c.motion,
            depth: c.depth,
            mask: c.covered,
        };
        self.taa
            .as_mut()
            .and_then(|taa| taa.resolve(&frame).ok().map(<[f32]>::to_vec))
    }

    /// Scores one frame's `value` at the mean count `spp`.
    fn push(&mut self, value: &[f32], spp: f64, c: &FrameContext<'_>) {
        let resolved = self.resolve(value, c);
        self.score(value, resolved, spp, c);
    }

    /// Scores one frame's `value` at the mean count `spp`, `resolved` by the stream's TAA
    /// (a guided run resolves between its sampling and its update).
    fn score(&mut self, value: &[f32], resolved: Option<Vec<f32>>, spp: f64, c: &FrameContext<'_>) {
        let run = &mut self.run;
        run.spp.push(spp);
        let frame = TaaFrame {
            value,
            motion: c.motion,
            depth: c.depth,
            mask: c.covered,
        };
        // Frames without a reference (the default suite's warm-up) are not scored.
        if c.reference.is_empty() {
            run.psnr.push(f64::NAN);
            run.psnr_steady.push(f64::NAN);
        } else {
            run.psnr.push(psnr(value, c.reference));
            run.psnr_steady.push(steady_psnr(value, c.reference, c.age));
        }
        if let Some(since) = c.since {
            run.uncovered_errors.push(if c.reference.is_empty() {
                AgeErrors::default()
            } else {
                AgeErrors::of_frame(value, c.reference, since)
            });
        }
        let (p_taa, r_taa, fl) = match &resolved {
            Some(x) if !c.reference.is_empty() => (
                psnr(x, c.reference),
                relmse_of_pairs(
                    x.iter()
                        .zip(c.reference)
                        .map(|(a, b)| (f64::from(*a), f64::from(*b))),
                ),
                self.flicker.push(x, c.reference, &frame, c.size),
            ),
            _ => {
                // An unscored frame restarts the instability measure.
                self.flicker.push(&[], &[], &frame, c.size);
                (f64::NAN, f64::NAN, f64::NAN)
            }
        };
        run.psnr_taa.push(p_taa);
        run.relmse_taa.push(r_taa);
        run.flicker_taa.push(fl);
    }
}

/// Runs `motion` through `variant` on the GPU (`Some`) or the CPU twin, with per-frame
/// references `refs` (an empty one leaves its frame unscored: NaN PSNR); `progress`
/// counts each frame. Returns the variant's run, preceded by one fixed-count run per
/// prefix count of the variant (`Variant::prefixes`, read from the same frames: what a
/// separate fixed run of that count gives, bit for bit).
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn run(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    size: [u32; 2],
    motion: Motion,
    variant: Variant,
    refs: &[Vec<f32>],
    progress: &Progress,
) -> Result<Vec<MotionRun>, AdaptiveError> {
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    let mut r = Renderer::variant(dev, opts, size, variant)?;
    let prefixes: Vec<(usize, u32)> = variant
        .prefixes
        .iter()
        .copied()
        .enumerate()
        .filter(|&(_, n)| n > 0)
        .collect();
    let mut streams: Vec<Scored> = prefixes
        .iter()
        .map(|&(_, n)| Scored::new(motion.name(), AoMode::Fixed(n).name(), size))
        .collect();
    streams.push(Scored::new(motion.name(), variant.name(opts), size));
    let mut on_mover_before: Option<Vec<bool>> = None;
    let objects = matches!(
        motion,
        Motion::MovingSphere { .. } | Motion::MovingObjects { .. }
    );
    let mut since = vec![0_u8; (size[0] * size[1]) as usize];
    let mut age = vec![0_u8; (size[0] * size[1]) as usize];
    let covered = vec![1_u8; (size[0] * size[1]) as usize];
    for (t, reference) in (0..opts.frames).zip(refs) {
        let p = scene.params(t);
        let g = twin::gbuffer(&p);
        age = ages(&g, &age, t, size);
        let on_mover: Vec<bool> = g.iter().map(|g| g.surface.moving).collect();
        if objects {
            since = since_uncovered(&since, &on_mover);
        }
        let motion_px: Vec<[f32; 2]> = g.iter().map(|g| g.motion).collect();
        let depth: Vec<f32> = g.iter().map(|g| g.depth).collect();
        let c = FrameContext {
            motion: &motion_px,
            depth: &depth,
            covered: &covered,
            age: &age,
            since: objects.then_some(since.as_slice()),
            reference,
            size,
        };
        // A guided run resolves the frame between its sampling and its update (the
        // renderer's order: sample, TAA, update) and is scored on that resolve.
        let mut early: Option<Option<Vec<f32>>> = None;
        let f = match (variant.guided, streams.last_mut()) {
            (true, Some(main)) => {
                let mut guide = |value: &[f32]| {
                    early = Some(main.resolve(value, &c));
                    main.taa.as_ref().map_or_else(
                        || vec![f32::NAN; value.len()],
                        |taa| taa.clamped_history().to_vec(),
                    )
                };
                r.frame_guided(&p, Some(&mut guide))?
            }
            _ => r.frame(&p)?,
        };
        for (s, &(j, n)) in streams.iter_mut().zip(&prefixes) {
            let value: Vec<f32> = f.prefixes.iter().map(|x| x[j]).collect();
            s.push(&value, f64::from(n), &c);
        }
        let spp = f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len() as f64;
        let main = streams.last_mut().map(|s| {
            match early.take() {
                Some(resolved) => s.score(&f.value, resolved, spp, &c),
                None => s.push(&f.value, spp, &c),
            }
            &mut s.run
        });
        if let (true, Some(run)) = (objects, main) {
            let before = on_mover_before.as_ref().unwrap_or(&on_mover);
            uncovered_figures(run, &f.count, before, &on_mover, opts.config.max_samples());
            on_mover_before = Some(on_mover);
        }
        progress.inc(1);
    }
    Ok(streams.into_iter().map(|s| s.run).collect())
}

/// The whole motion report: every scene with its [`variants`], the GPU against the CPU
/// twin on the moving scenes when a device is given, the acceptance lines.
#[derive(Clone, Debug, Default)]
pub struct MotionReport {
    /// Every run.
    pub runs: Vec<MotionRun>,
    /// Per moving scene: the smallest per-frame fraction of pixels whose GPU count equals
    /// the twin's (GPU runs only), and the frames compared.
    pub agreement: Vec<(String, f64, u32)>,
    /// The motion bound on the static camera ([`motion_bound`]), where the run was long
    /// enough.
    pub motion_bound: Option<MotionBound>,
    /// The motion bound of the young-history rows on the static camera, by run name.
    pub motion_bound_young: Vec<(String, MotionBound)>,
    /// The fastest pan's and the rotation's static cameras held at their own poses (the
    /// young-history lines' baseline).
    pub still: Vec<StillBaseline>,
    /// The acceptance lines.
    pub lines: Vec<Check>,
}

/// The scenes compared between the GPU and the twin, and the frames each runs.
fn agreement_scenes(opts: &MotionOptions) -> ([Motion; 5], u32) {
    (
        [
            Motion::Pan { speed: 4.0 },
            Motion::Rotate { degrees: 2.0 },
            OBJECTS[0],
            DOLLY,
            OBJECTS[1],
        ],
        opts.frames.min(16),
    )
}

/// One frame of broken motion vectors (every vector `1e30` pixels, far beyond the motion
/// bound of `spvg::reproject`) on the static camera, AS: the mean spp of the frames
/// around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBound {
    /// The frame whose motion vectors are broken.
    pub frame: u32,
    /// Mean spp of the frame before it.
    pub before: f64,
    /// Mean spp of the broken frame (every pixel disoccluded).
    pub broken: f64,
    /// Mean spp of the frame after it.
    pub after: f64,
}

/// The frame [`motion_bound`] breaks: after the warm-up (as late as the run allows, one
/// frame kept after it), `None` for a run shorter than 3 frames.
#[must_use]
pub fn motion_bound_frame(opts: &MotionOptions) -> Option<u32> {
    (opts.frames >= 3).then(|| (WARM_UP as u32 + 4).min(opts.frames - 2))
}

/// Runs the static camera at `opts.size` (AS) up to the frame after
/// [`motion_bound_frame`], with every motion vector of that frame at `1e30` (a broken
/// motion buffer), and returns the mean spp around it.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn motion_bound(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    progress: &Progress,
) -> Result<Option<MotionBound>, AdaptiveError> {
    let adaptive = variants(Motion::Static, opts)
        .into_iter()
        .find(|v| v.mode == AoMode::Adaptive);
    match adaptive {
        Some(v) => motion_bound_of(dev, opts, v, progress),
        None => Ok(None),
    }
}

/// [`motion_bound`] of the static camera's run `v`.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn motion_bound_of(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    v: Variant,
    progress: &Progress,
) -> Result<Option<MotionBound>, AdaptiveError> {
    let Some(k) = motion_bound_frame(opts) else {
        return Ok(None);
    };
    let scene = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion: Motion::Static,
    };
    let mut r = Renderer::variant(dev, opts, opts.size, v)?;
    let mut spp = Vec::new();
    for t in 0..=k + 1 {
        let mut p = scene.params(t);
        if t == k {
            p.motion_bias = [1e30, 1e30, 0.0, 0.0];
        }
        let f = r.frame(&p)?;
        spp.push(f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len() as f64);
        progress.inc(1);
    }
    let at = |t: u32| spp[t as usize];
    Ok(Some(MotionBound {
        frame: k,
        before: at(k - 1),
        broken: at(k),
        after: at(k + 1),
    }))
}

/// The static camera's young-history rows (the motion bound runs each).
fn young_variants(opts: &MotionOptions) -> Vec<Variant> {
    variants(Motion::Static, opts)
        .into_iter()
        .filter(|v| {
            v.mode == AoMode::Adaptive
                && (v.age_weight
                    || v.spatial_variance != opts.config.spatial_variance()
                    || !v.neighbour_prior)
        })
        .collect()
}

/// The scene groups: the pans with their static camera at `pan_size` (its runs named
/// `static-pan`), the other motions with theirs at `size`.
fn groups(opts: &MotionOptions) -> [(&'static str, [u32; 2], Vec<Motion>); 2] {
    [("pan", opts.pan_size, pans()), ("", opts.size, others())]
}

/// Frames the motion report renders (for a progress bar): every run's, and the GPU
/// against the twin (two renderers) with a device.
#[must_use]
pub fn frames_to_render(opts: &MotionOptions, gpu: bool) -> u64 {
    let runs: usize = groups(opts)
        .iter()
        .flat_map(|(_, _, moving)| std::iter::once(Motion::Static).chain(moving.iter().copied()))
        .map(|m| variants(m, opts).len())
        .sum();
    let (scenes, frames) = agreement_scenes(opts);
    // The scenes, and the guided update on the first of them.
    let twin = if gpu {
        2 * (scenes.len() as u64 + 1) * u64::from(frames)
    } else {
        0
    };
    let bounds = 1 + young_variants(opts).len() as u64;
    let bound = bounds * motion_bound_frame(opts).map_or(0, |k| u64::from(k) + 2);
    let baseline: u64 = others().into_iter().map(|m| baseline_frames(opts, m)).sum();
    let still: u64 = groups(opts)
        .iter()
        .flat_map(|(_, _, moving)| moving.iter().map(|&m| still_frames(opts, m)))
        .sum();
    runs as u64 * u64::from(opts.frames) + twin + bound + baseline + still
}

/// Runs the motion report; `progress` counts frames and names each stage.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn report(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    progress: &Progress,
) -> Result<MotionReport, AdaptiveError> {
    let mut rep = MotionReport::default();
    for (group, size, moving) in groups(opts) {
        for motion in std::iter::once(Motion::Static).chain(moving) {
            progress.stage(&format!(
                "motion: reference {} {}x{}",
                motion.name(),
                size[0],
                size[1]
            ));
            let refs = references(opts, size, motion);
            for v in variants(motion, opts) {
                progress.stage(&format!("motion: {} {}", motion.name(), v.name(opts)));
                for mut r in run(dev, opts, size, motion, v, &refs, progress)? {
                    if motion == Motion::Static && !group.is_empty() {
                        r.scene = format!("static-{group}");
                    }
                    rep.runs.push(r);
                }
            }
            if let Some(b) = still_at_poses(dev, opts, size, motion, &refs, progress)? {
                rep.still.push(b);
            }
        }
    }
    for motion in others() {
        if let Some(b) = static_at_heights(dev, opts, motion, progress)? {
            rep.runs.push(b);
        }
    }
    progress.stage("motion: the motion bound (one frame of 1e30 motion, static)");
    rep.motion_bound = motion_bound(dev, opts, progress)?;
    for v in young_variants(opts) {
        if let Some(b) = motion_bound_of(dev, opts, v, progress)? {
            rep.motion_bound_young.push((v.name(opts), b));
        }
    }
    if let Some(d) = dev {
        let (scenes, frames) = agreement_scenes(opts);
        for motion in scenes {
            progress.stage(&format!("motion: GPU vs twin {}", motion.name()));
            let worst = agreement(d, opts, motion, frames, false, progress)?;
            rep.agreement.push((motion.name(), worst, frames));
        }
        // The TAA-guided update on the pan: each renderer's update takes the guide of
        // its own TAA resolve.
        let motion = scenes[0];
        progress.stage(&format!("motion: GPU vs twin {} {GUIDED}", motion.name()));
        let worst = agreement(d, opts, motion, frames, true, progress)?;
        rep.agreement
            .push((format!("{} {GUIDED}", motion.name()), worst, frames));
    }
    rep.lines = acceptance(&rep);
    Ok(rep)
}

/// The smallest per-frame fraction of equal counts between the GPU and the twin (AS with
/// reprojection, with the TAA guide of each one's own resolve where `guided`) over
/// `frames` frames.
fn agreement(
    d: &GpuDevice,
    opts: &MotionOptions,
    motion: Motion,
    frames: u32,
    guided: bool,
    progress: &Progress,
) -> Result<f64, AdaptiveError> {
    let scene = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion,
    };
    let repro = Reprojection::default();
    let mut g = Renderer::new(
        Some(d),
        opts.config,
        opts.size,
        AoMode::Adaptive,
        repro,
        opts.dilation,
        true,
        false,
    )?;
    let mut c = Renderer::new(
        None,
        opts.config,
        opts.size,
        AoMode::Adaptive,
        repro,
        opts.dilation,
        true,
        false,
    )?;
    let mut worst = 1.0_f64;
    let [w, h] = opts.size;
    let mut taa = [Taa::report(w, h).ok(), Taa::report(w, h).ok()];
    let covered = vec![1_u8; (w * h) as usize];
    for t in 0..frames {
        let p = scene.params(t);
        let gb = twin::gbuffer(&p);
        let motion_px: Vec<[f32; 2]> = gb.iter().map(|g| g.motion).collect();
        let depth: Vec<f32> = gb.iter().map(|g| g.depth).collect();
        let frame = |r: &mut Renderer, taa: &mut Option<Taa>| {
            if !guided {
                return r.frame(&p);
            }
            let mut guide = |value: &[f32]| {
                let f = TaaFrame {
                    value,
                    motion: &motion_px,
                    depth: &depth,
                    mask: &covered,
                };
                match taa.as_mut().map(|taa| taa.resolve(&f).is_ok()) {
                    Some(true) => taa
                        .as_ref()
                        .map_or_else(Vec::new, |taa| taa.clamped_history().to_vec()),
                    _ => vec![f32::NAN; value.len()],
                }
            };
            r.frame_guided(&p, Some(&mut guide))
        };
        let [ta, tb] = &mut taa;
        let (a, b) = (frame(&mut g, ta)?, frame(&mut c, tb)?);
        let same = a.count.iter().zip(&b.count).filter(|(x, y)| x == y).count();
        worst = worst.min(same as f64 / a.count.len() as f64);
        progress.inc(2);
    }
    Ok(worst)
}
