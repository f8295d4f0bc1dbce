//! One scene through one [`Variant`], measured frame by frame against its references: the
//! run itself and the fixed runs its ladder yields, each scored single-frame and after
//! the renderer's TAA resolve, with the moving objects' figures of the uncovered pixels.

use super::data::{MotionRun, TwinCheck, allocation_bounds, psnr, split_taa};
use super::options::MotionOptions;
use super::render::{Renderer, Setup};
use super::scenes::Variant;
use super::uncovered::{AgeErrors, since_uncovered};
use crate::error::ReportError;
use crate::metrics::{Flicker, relmse_of_pairs};
use crate::progress::Progress;
use crate::taa::{Taa, TaaFrame};
use crate::wgpu_api::{
    AoFrame, AoGuide, AoMode, AoParams, AoScene, GpuDevice, Motion, ao_twin as twin,
};

/// Frames each pixel's surface point has been on screen, capped at 3: a pixel whose
/// previous texel (along its motion vector) is inside the frame is one frame older than
/// that texel; every pixel is 1 on frame 0 or when its point just entered.
fn ages(motion: &[[f32; 2]], before: &[u8], t: u32, size: [u32; 2]) -> Vec<u8> {
    let w = size[0] as usize;
    motion
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let here = [(i % w) as u32, (i / w) as u32];
            match spvg::reproject::previous_texel(here, v, size) {
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
    /// Whether the stream's counts are fractional: a pixel of 0 samples skipped the frame
    /// and has no value for the resolve (ambient occlusion has no zero-sample rule).
    fractional: bool,
    /// The previous frame's counts (for [`MotionRun::count_step`]).
    previous_count: Option<Vec<u32>>,
    /// The last frame's resolved image (for the split against the second seed).
    resolved: Option<Vec<f32>>,
}

/// The weight the stream's TAA gave its last frame per pixel, for the next frame's
/// estimate (`None` before the first resolve, or for a stream without the
/// resolved-image rule: `rule` off).
fn resolve_weight(stream: Option<&Scored>, rule: bool) -> Option<Vec<f32>> {
    let w = stream?.taa.as_ref()?.resolve_weights();
    (rule && !w.is_empty()).then(|| w.to_vec())
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

impl FrameContext<'_> {
    fn taa_frame<'v>(&'v self, value: &'v [f32], skipped: Option<&'v [bool]>) -> TaaFrame<'v> {
        TaaFrame {
            value,
            motion: self.motion,
            depth: self.depth,
            mask: self.covered,
            skipped,
        }
    }
}

impl Scored {
    fn new(scene: String, mode: String, size: [u32; 2], fractional: bool) -> Self {
        Self {
            fractional,
            run: MotionRun::named(scene, mode),
            // The renderer's TAA after the consumer: its history runs through the unscored
            // warm-up frames too. It cannot fail at the frame's own size; if it did, the
            // frame's TAA figures would read NaN.
            taa: Taa::report(size[0], size[1]).ok(),
            flicker: Flicker::default(),
            previous_count: None,
            resolved: None,
        }
    }

    /// The pixels that skipped the frame (0 samples of a fractional count), `None` for a
    /// stream of integer counts.
    fn skipped(&self, count: &[u32]) -> Option<Vec<bool>> {
        self.fractional
            .then(|| count.iter().map(|&n| n == 0).collect())
    }

    /// Resolves one frame's `value` taken with `count` samples per pixel through the
    /// stream's TAA (`None` where it has none or the resolve fails).
    fn resolve(&mut self, value: &[f32], count: &[u32], c: &FrameContext<'_>) -> Option<Vec<f32>> {
        let skipped = self.skipped(count);
        let frame = c.taa_frame(value, skipped.as_deref());
        self.taa
            .as_mut()
            .and_then(|taa| taa.resolve(&frame).ok().map(<[f32]>::to_vec))
    }

    /// Scores one frame's `value` taken with `count` samples per pixel.
    fn push(&mut self, value: &[f32], count: &[u32], c: &FrameContext<'_>) {
        let resolved = self.resolve(value, count, c);
        self.score(value, resolved, count, c);
    }

    /// Scores one frame's `value` taken with `count` samples per pixel, `resolved` by the
    /// stream's TAA (a guided run resolves between its sampling and its update).
    fn score(
        &mut self,
        value: &[f32],
        resolved: Option<Vec<f32>>,
        count: &[u32],
        c: &FrameContext<'_>,
    ) {
        let skipped = self.skipped(count);
        let run = &mut self.run;
        run.spp
            .push(count.iter().map(|&n| f64::from(n)).sum::<f64>() / count.len().max(1) as f64);
        run.count_step.push(match &self.previous_count {
            Some(before) if before.len() == count.len() && !count.is_empty() => {
                let steps: u64 = before
                    .iter()
                    .zip(count)
                    .map(|(&a, &b)| u64::from(a.abs_diff(b)))
                    .sum();
                steps as f64 / count.len() as f64
            }
            _ => f64::NAN,
        });
        self.previous_count = Some(count.to_vec());
        let frame = c.taa_frame(value, skipped.as_deref());
        let scored = !c.reference.is_empty();
        self.resolved.clone_from(&resolved);
        // Frames without a reference (the default suite's warm-up) are not scored.
        if scored {
            run.psnr.push(psnr(value, c.reference));
            run.psnr_steady.push(steady_psnr(value, c.reference, c.age));
            run.allocation_bounds.push(allocation_bounds(c.reference));
        } else {
            run.psnr.push(f64::NAN);
            run.psnr_steady.push(f64::NAN);
            run.allocation_bounds.push([f64::NAN; 2]);
        }
        if let Some(since) = c.since {
            let by_age = |image: Option<&[f32]>| match image {
                Some(x) if scored => AgeErrors::of_frame(x, c.reference, since, count),
                _ => AgeErrors::default(),
            };
            run.uncovered_errors.push(by_age(Some(value)));
            run.uncovered_errors_taa.push(by_age(resolved.as_deref()));
        }
        let (p_taa, r_taa, fl) = match &resolved {
            Some(x) if scored => (
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

/// A run's scored streams (its ladder's fixed runs first, then the run itself) and its
/// check against the twin (GPU runs).
#[derive(Debug)]
pub struct RunResult {
    /// The streams.
    pub runs: Vec<MotionRun>,
    /// The GPU run's check against the twin (`None` on the CPU twin).
    pub twin_check: Option<TwinCheck>,
}

/// One frame's geometry as a run scores it: per pixel the motion vector, the depth and
/// whether it shows a moving object.
pub(crate) struct Geometry {
    pub(crate) motion: Vec<[f32; 2]>,
    pub(crate) depth: Vec<f32>,
    pub(crate) moving: Vec<bool>,
}

/// The images of a frame's fixed-count ladder: per `(index, count)` of `prefixes`, the
/// prefix estimate of that index at every pixel.
fn ladder_values(f: &AoFrame, prefixes: &[(usize, u32)]) -> Vec<Vec<f32>> {
    prefixes
        .iter()
        .map(|&(j, _)| f.prefixes.iter().map(|x| x[j]).collect())
        .collect()
}

/// What a run's second seed adds to the index that seeds a frame's samples: its samples
/// are independent of the first seed's (the frame index seeds the sample sequence and
/// nothing else; the geometry and the component's fractional dither follow the frame's
/// own number).
pub(crate) const SECOND_SEED: u32 = 1 << 20;

/// A scene rendered frame by frame through one run's renderer: the procedural AO scenes
/// ([`Procedural`]) and the mesh scene (`crate::mesh`).
pub(crate) trait Frames {
    /// Frame `t`'s geometry (asked before [`render`](Self::render) of the same frame).
    fn geometry(&mut self, t: u32) -> Geometry;
    /// Renders frame `t`; a guided run's update takes what `guide` returns, and the
    /// estimate takes `resolve_weight` (the weight the run's TAA gave the previous frame,
    /// [`Taa::resolve_weights`]; `None`: none) as the resolved-image rule's per-pixel
    /// weight.
    fn render(
        &mut self,
        t: u32,
        guide: Option<&mut AoGuide<'_>>,
        resolve_weight: Option<&[f32]>,
    ) -> Result<AoFrame, ReportError>;
    /// The GPU run's check against the twin (`None` on the CPU twin).
    fn twin_check(&self) -> Option<TwinCheck>;
}

/// A procedural AO scene ([`AoScene`]) through its [`Renderer`].
struct Procedural {
    scene: AoScene,
    /// Added to the frame index that seeds the samples ([`SECOND_SEED`] on a run's
    /// second seed).
    seed: u32,
    renderer: Renderer,
    /// The frame whose geometry was asked last: its parameters and G-buffer.
    frame: Option<(AoParams, Vec<twin::GPixel>)>,
}

impl Frames for Procedural {
    fn geometry(&mut self, t: u32) -> Geometry {
        let p = self.scene.params(t);
        let g = twin::gbuffer(&p);
        let geometry = Geometry {
            motion: g.iter().map(|g| g.motion).collect(),
            depth: g.iter().map(|g| g.depth).collect(),
            moving: g.iter().map(|g| g.surface.moving).collect(),
        };
        self.frame = Some((p, g));
        geometry
    }

    fn render(
        &mut self,
        t: u32,
        guide: Option<&mut AoGuide<'_>>,
        resolve_weight: Option<&[f32]>,
    ) -> Result<AoFrame, ReportError> {
        let (p, g) = match self.frame.take() {
            Some(f) if f.0.frame == t => f,
            _ => {
                let p = self.scene.params(t);
                (p, twin::gbuffer(&p))
            }
        };
        let p = AoParams {
            frame: p.frame.wrapping_add(self.seed),
            ..p
        };
        self.renderer.frame_guided(&p, &g, guide, resolve_weight)
    }

    fn twin_check(&self) -> Option<TwinCheck> {
        self.renderer.twin_check()
    }
}

/// Runs `motion` at `size` through `variant` on the GPU (`Some`) or the CPU twin, with
/// per-frame references `refs` (an empty one leaves its frame unscored: NaN PSNR); the
/// runs are named after `scene`; `progress` counts each frame. The variant's run comes
/// last, preceded by one fixed-count run per prefix count of the variant
/// (`Variant::prefixes`, read from the same frames: what a separate fixed run of that
/// count gives, bit for bit).
///
/// # Errors
///
/// A device failure or a rejected configuration.
#[allow(
    clippy::too_many_arguments,
    reason = "one scene's run: its place, its references and the progress bar"
)]
pub fn run(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    size: [u32; 2],
    motion: Motion,
    scene_name: &str,
    variant: Variant,
    refs: &[Vec<f32>],
    progress: &Progress,
) -> Result<RunResult, ReportError> {
    let name = variant.name(opts);
    let setup = Setup::of(opts, &variant)?;
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    let mut source = Procedural {
        scene,
        seed: 0,
        renderer: Renderer::new(dev, &setup, size, scene_name, &name)?,
        frame: None,
    };
    let mut second = match opts.split && !variant.guided {
        true => Some(Procedural {
            scene,
            seed: SECOND_SEED,
            renderer: Renderer::new(dev, &setup, size, scene_name, &name)?,
            frame: None,
        }),
        false => None,
    };
    let objects = matches!(
        motion,
        Motion::MovingSphere { .. } | Motion::MovingObjects { .. }
    );
    run_frames(
        &mut source,
        second.as_mut().map(|s| s as &mut dyn Frames),
        opts,
        size,
        scene_name,
        variant,
        refs,
        objects,
        progress,
    )
}

/// [`run`] on any scene's frames (`objects`: the scene's moving objects get the
/// uncovered pixels' figures); `second`, the same run on a second seed, rendered in
/// lockstep and only resolved, splits each stream's error after TAA
/// ([`MotionRun::var_taa`]; a guided run takes none).
///
/// # Errors
///
/// As [`run`].
#[allow(
    clippy::too_many_arguments,
    reason = "one scene's run: its place, its references and the progress bar"
)]
pub(crate) fn run_frames(
    source: &mut dyn Frames,
    mut second: Option<&mut dyn Frames>,
    opts: &MotionOptions,
    size: [u32; 2],
    scene_name: &str,
    variant: Variant,
    refs: &[Vec<f32>],
    objects: bool,
    progress: &Progress,
) -> Result<RunResult, ReportError> {
    let name = variant.name(opts);
    let prefixes: Vec<(usize, u32)> = variant
        .prefixes
        .iter()
        .copied()
        .enumerate()
        .filter(|&(_, n)| n > 0)
        .collect();
    let mut streams: Vec<Scored> = prefixes
        .iter()
        .map(|&(_, n)| Scored::new(scene_name.into(), AoMode::Fixed(n).name(), size, false))
        .collect();
    let fractional = variant.mode == AoMode::Adaptive && variant.resolved;
    streams.push(Scored::new(scene_name.into(), name, size, fractional));
    let mut seconds: Vec<Scored> = streams
        .iter()
        .map(|s| Scored::new(String::new(), String::new(), size, s.fractional))
        .collect();
    let pixels = (size[0] * size[1]) as usize;
    let fixed_counts: Vec<Vec<u32>> = prefixes.iter().map(|&(_, n)| vec![n; pixels]).collect();
    let mut on_mover_before: Option<Vec<bool>> = None;
    let mut since = vec![0_u8; pixels];
    let mut age = vec![0_u8; pixels];
    let covered = vec![1_u8; pixels];
    for (t, reference) in (0..opts.frames).zip(refs) {
        let Geometry {
            motion,
            depth,
            moving: on_mover,
        } = source.geometry(t);
        age = ages(&motion, &age, t, size);
        if objects {
            since = since_uncovered(&since, &on_mover);
        }
        let c = FrameContext {
            motion: &motion,
            depth: &depth,
            covered: &covered,
            age: &age,
            since: objects.then_some(since.as_slice()),
            reference,
            size,
        };
        // The resolved-image rule's per-pixel weight: what the run's TAA gave the previous
        // frame (the estimate runs before this frame's resolve).
        let weight = resolve_weight(streams.last(), variant.resolved);
        let weight2 = resolve_weight(seconds.last(), variant.resolved);
        // A guided run resolves the frame between its sampling and its update (the
        // renderer's order: sample, TAA, update) and is scored on that resolve.
        let mut early: Option<Option<Vec<f32>>> = None;
        let f = match (variant.guided, streams.last_mut()) {
            (true, Some(main)) => {
                // A guided run's counts are integers: no pixel skips.
                let mut guide = |value: &[f32]| {
                    early = Some(main.resolve(value, &[], &c));
                    main.taa.as_ref().map_or_else(
                        || vec![f32::NAN; value.len()],
                        |taa| taa.clamped_history().to_vec(),
                    )
                };
                source.render(t, Some(&mut guide), weight.as_deref())?
            }
            _ => source.render(t, None, weight.as_deref())?,
        };
        for ((s, value), counts) in streams
            .iter_mut()
            .zip(ladder_values(&f, &prefixes))
            .zip(&fixed_counts)
        {
            s.push(&value, counts, &c);
        }
        let main = streams.last_mut().map(|s| {
            match early.take() {
                Some(resolved) => s.score(&f.value, resolved, &f.count, &c),
                None => s.push(&f.value, &f.count, &c),
            }
            &mut s.run
        });
        if let (true, Some(run)) = (objects, main) {
            let before = on_mover_before.as_ref().unwrap_or(&on_mover);
            uncovered_figures(run, &f.count, before, &on_mover, opts.config.max_samples());
            on_mover_before = Some(on_mover);
        }
        if let Some(r2) = second.as_deref_mut() {
            // The second source renders its frame from its own G-buffer (`render` builds
            // it where `geometry` was not asked).
            let f2 = r2.render(t, None, weight2.as_deref())?;
            let counts = fixed_counts
                .iter()
                .map(Vec::as_slice)
                .chain([&f2.count[..]]);
            let values = ladder_values(&f2, &prefixes)
                .into_iter()
                .chain([f2.value.clone()]);
            for ((s2, s), (value, count)) in
                seconds.iter_mut().zip(&mut streams).zip(values.zip(counts))
            {
                let split = match (&s.resolved, s2.resolve(&value, count, &c)) {
                    (Some(a), Some(b)) if !reference.is_empty() => split_taa(a, &b, reference),
                    _ => [f64::NAN; 2],
                };
                s.run.var_taa.push(split[0]);
                s.run.bias2_taa.push(split[1]);
            }
        }
        progress.inc(1);
    }
    Ok(RunResult {
        runs: streams.into_iter().map(|s| s.run).collect(),
        twin_check: source.twin_check(),
    })
}
