//! Scenes with motion, run through the second consumer (ambient occlusion,
//! `spvg_wgpu::ao`) and the adaptive component: camera pans at 1 to 8 px per frame, a
//! camera rotation, and a sphere moving across the surface (disocclusion by motion). Each
//! scene runs with a fixed count, AS with reprojection, and AS with the identity history
//! (zero motion vectors, no depth test: a renderer without reprojection), against a
//! converged quadrature reference of its own ([`reference()`]).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::ReportError;
use spvg::SpvgConfig;
use spvg::reproject::{BorderCount, Reprojection};
use spvg_wgpu::GpuDevice;
use spvg_wgpu::adaptive::AdaptiveError;
use spvg_wgpu::ao::{AoFrame, AoMode, AoParams, AoPass, AoScene, AoTwin, Motion, twin};

/// Settings of the motion report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionOptions {
    /// Frame size of the pans and their static camera (wide, so that the pixels entering
    /// at 8 px per frame are a small part of the frame, as at real resolutions).
    pub pan_size: [u32; 2],
    /// Frame size of the rotation, the moving sphere and their static camera.
    pub size: [u32; 2],
    /// Frames per run.
    pub frames: u32,
    /// The controller (AS).
    pub config: SpvgConfig<f32>,
    /// Directions per axis of the reference quadrature (`grid^2` per pixel).
    pub grid: u32,
    /// Count dilation radius of the AS runs (`spvg::dilation`); the report also runs
    /// radius 0 (`as-no-dilation`) on the static cameras, the fastest pan and the rotation.
    pub dilation: u32,
}

impl MotionOptions {
    /// The defaults: pans at 384x192, the rest at 128x96, 48 frames, `sigma0^2 = 1e-4`
    /// (the library's published default), budget [8, 64], a 32x32 reference grid, count
    /// dilation radius 1.
    ///
    /// # Errors
    ///
    /// Never with these constants; typed for a caller that changes them.
    pub fn new() -> Result<Self, spvg::Error> {
        Ok(Self {
            pan_size: [384, 192],
            size: [128, 96],
            frames: 48,
            config: SpvgConfig::builder().target_variance(1e-4).build()?,
            grid: 32,
            dilation: 1,
        })
    }
}

/// The pans (along `+x` at 1, 2, 4 and 8 px per frame), compared with a static camera at
/// the same size.
#[must_use]
pub fn pans() -> Vec<Motion> {
    [1.0, 2.0, 4.0, 8.0]
        .map(|speed| Motion::Pan { speed })
        .to_vec()
}

/// The other moving scenes: a rotation of 2 degrees per frame (about 2 px per frame at the
/// frame's corners) and a sphere crossing at 3 px per frame, compared with a static camera
/// at the same size.
#[must_use]
pub fn others() -> Vec<Motion> {
    vec![
        Motion::Rotate { degrees: 2.0 },
        Motion::MovingSphere { speed: 3.0 },
    ]
}

/// The converged reference of one frame: at each pixel's visible point, the fraction of
/// the cosine-weighted hemisphere that escapes, by the midpoint rule on a `grid x grid`
/// stratification of the same warp the renderer samples (exact directions in f64, the
/// twin's ray tests), on all cores.
#[must_use]
pub fn reference(params: &AoParams, grid: u32) -> Vec<f32> {
    let g = twin::gbuffer(params);
    reference_of(params, &g, grid, |_| true, &[])
}

/// [`reference`] at the pixels of `g` where `todo(i)` holds; elsewhere `base[i]`.
fn reference_of(
    params: &AoParams,
    g: &[twin::GPixel],
    grid: u32,
    todo: impl Fn(usize) -> bool + Sync,
    base: &[f32],
) -> Vec<f32> {
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = g.len().div_ceil(threads).max(1);
    let mut out = vec![0.0_f32; g.len()];
    let todo = &todo;
    std::thread::scope(|s| {
        for (k, (part, dst)) in g.chunks(chunk).zip(out.chunks_mut(chunk)).enumerate() {
            s.spawn(move || {
                for (j, (px, o)) in part.iter().zip(dst.iter_mut()).enumerate() {
                    let i = k * chunk + j;
                    *o = if todo(i) {
                        hemisphere_fraction(params, &px.surface, grid)
                    } else {
                        base.get(i).copied().unwrap_or(0.0)
                    };
                }
            });
        }
    });
    out
}

fn hemisphere_fraction(p: &AoParams, s: &twin::Surface, grid: u32) -> f32 {
    let n = s.normal.map(f64::from);
    let sgn = if n[2] >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sgn + n[2]);
    let b = n[0] * n[1] * a;
    let t = [1.0 + sgn * n[0] * n[0] * a, sgn * b, -sgn * n[0]];
    let bt = [b, sgn + n[1] * n[1] * a, -n[1]];
    let o: [f32; 3] = core::array::from_fn(|i| s.position[i] + s.normal[i] * 0.001);
    let mut open = 0_u64;
    for i in 0..grid {
        let u1 = (f64::from(i) + 0.5) / f64::from(grid);
        let (r, z) = (u1.sqrt(), (1.0 - u1).sqrt());
        for j in 0..grid {
            let phi = std::f64::consts::TAU * (f64::from(j) + 0.5) / f64::from(grid);
            let (dx, dy) = (r * phi.cos(), r * phi.sin());
            let d: [f32; 3] = core::array::from_fn(|k| (t[k] * dx + bt[k] * dy + n[k] * z) as f32);
            if !twin::occluded(p, o, d) {
                open += 1;
            }
        }
    }
    (open as f64 / f64::from(grid * grid)) as f32
}

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
    /// Moving-sphere scene: mean spp of the pixels uncovered this frame (`None` where no
    /// pixel was).
    pub uncovered_spp: Vec<Option<f64>>,
    /// Moving-sphere scene: mean spp of the steady pixels (surface in both frames).
    pub steady_spp: Vec<Option<f64>>,
    /// Moving-sphere scene: fraction of the uncovered pixels at the maximum count.
    pub uncovered_at_max: Vec<Option<f64>>,
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

    /// Mean over the frames after [`WARM_UP`] of the PSNR of the steady pixels.
    #[must_use]
    pub fn mean_psnr_steady(&self) -> f64 {
        mean(steady(&self.psnr_steady))
    }
}

fn steady(v: &[f64]) -> &[f64] {
    if v.len() > 2 * WARM_UP {
        &v[WARM_UP..]
    } else {
        v
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn psnr(image: &[f32], reference: &[f32]) -> f64 {
    let mse = image
        .iter()
        .zip(reference)
        .map(|(a, b)| (f64::from(*a) - f64::from(*b)).powi(2))
        .sum::<f64>()
        / image.len().max(1) as f64;
    if mse > 0.0 {
        -10.0 * mse.log10()
    } else {
        f64::INFINITY
    }
}

enum Renderer {
    Gpu(Box<AoPass>),
    Cpu(Box<AoTwin>),
}

impl Renderer {
    fn frame(&mut self, p: &AoParams) -> Result<AoFrame, AdaptiveError> {
        match self {
            Self::Gpu(g) => g.run_frame(p),
            Self::Cpu(c) => c.run_frame(p),
        }
    }
}

/// The name of the AS run without the border prior (`spvg::reproject`): pixels entering
/// the frame start at `beta_min`, the papers' disocclusion rule.
pub const NO_PRIOR: &str = "as-beta-min";

/// The name of the AS run without count dilation (`spvg::dilation`, radius 0): each pixel
/// spends its own estimate, the papers' rule.
pub const NO_DILATION: &str = "as-no-dilation";

/// The name of the AS run without the footprint search (`spvg::reproject`): the nearest
/// texel only, rejected when it fails the mask or depth test.
pub const NEAREST_ONLY: &str = "as-nearest-only";

/// The name of the AS run whose entering pixels take the border texel's count
/// (`spvg::reproject::BorderCount::Texel`) instead of `beta_max`.
pub const BORDER_TEXEL: &str = "as-border-texel";

/// One way of running a scene: the renderer's mode, the reprojection rule and the count
/// dilation radius of the adaptive component.
#[derive(Clone, Copy, Debug)]
pub struct Variant {
    /// Fixed count, AS with reprojection, or AS with the identity history.
    pub mode: AoMode,
    /// The reprojection rule (depth tolerance, border prior).
    pub reprojection: Reprojection<f32>,
    /// The count dilation radius.
    pub dilation: u32,
}

impl Variant {
    /// The run's name: the mode's, or [`NO_PRIOR`] / [`NEAREST_ONLY`] / [`BORDER_TEXEL`] /
    /// [`NO_DILATION`] for AS with the border prior, the footprint search, the entering
    /// pixels' `beta_max` or the dilation of `opts` switched off.
    #[must_use]
    pub fn name(&self, opts: &MotionOptions) -> String {
        if self.mode != AoMode::Adaptive {
            self.mode.name()
        } else if !self.reprojection.border_prior() {
            NO_PRIOR.into()
        } else if !self.reprojection.footprint_search() {
            NEAREST_ONLY.into()
        } else if self.reprojection.border_count() == BorderCount::Texel {
            BORDER_TEXEL.into()
        } else if self.dilation == 0 && opts.dilation > 0 {
            NO_DILATION.into()
        } else {
            self.mode.name()
        }
    }
}

/// Runs `motion` through `variant` on the GPU (`Some`) or the CPU twin, with per-frame
/// references `refs`.
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
) -> Result<MotionRun, AdaptiveError> {
    let Variant {
        mode,
        reprojection: repro,
        dilation,
    } = variant;
    let [w, h] = size;
    let scene = AoScene {
        width: w,
        height: h,
        motion,
    };
    let mut r = match dev {
        Some(d) => Renderer::Gpu(Box::new(AoPass::new(
            &d.device,
            &d.queue,
            w,
            h,
            mode,
            opts.config,
            repro,
        )?)),
        None => Renderer::Cpu(Box::new(AoTwin::new(w, h, mode, opts.config, repro)?)),
    };
    match &mut r {
        Renderer::Gpu(g) => g.set_count_dilation(dilation)?,
        Renderer::Cpu(c) => c.set_count_dilation(dilation)?,
    }
    let mut run = MotionRun {
        scene: motion.name(),
        mode: variant.name(opts),
        ..MotionRun::default()
    };
    let max = opts.config.max_samples();
    let mut on_mover_before: Option<Vec<bool>> = None;
    // Frames the pixel's surface point has been on screen (capped at 3).
    let mut age = vec![0_u8; (w * h) as usize];
    for t in 0..opts.frames {
        let p = scene.params(t);
        let f = r.frame(&p)?;
        run.spp
            .push(f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len() as f64);
        run.psnr.push(psnr(&f.value, &refs[t as usize]));
        let g = twin::gbuffer(&p);
        age = g
            .iter()
            .enumerate()
            .map(|(i, gp)| {
                let q = spvg::reproject::previous_texel(
                    [(i % w as usize) as u32, (i / w as usize) as u32],
                    gp.motion,
                    [w, h],
                );
                match q {
                    Some(q) if t > 0 => age[(q[1] * w + q[0]) as usize].saturating_add(1).min(3),
                    _ => 1,
                }
            })
            .collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for (i, &k) in age.iter().enumerate() {
            if k >= 3 {
                a.push(f.value[i]);
                b.push(refs[t as usize][i]);
            }
        }
        run.psnr_steady
            .push(if a.is_empty() { f64::NAN } else { psnr(&a, &b) });
        if let Motion::MovingSphere { .. } = motion {
            let on_mover: Vec<bool> = twin::gbuffer(&p).iter().map(|g| g.surface.moving).collect();
            let before = on_mover_before.as_ref().unwrap_or(&on_mover);
            let (mut un, mut st) = (Vec::new(), Vec::new());
            for i in 0..f.count.len() {
                match (before[i], on_mover[i]) {
                    (true, false) => un.push(f.count[i]),
                    (false, false) => st.push(f.count[i]),
                    _ => {}
                }
            }
            let avg = |v: &[u32]| {
                (!v.is_empty())
                    .then(|| v.iter().map(|&n| f64::from(n)).sum::<f64>() / v.len() as f64)
            };
            run.uncovered_spp.push(avg(&un));
            run.steady_spp.push(avg(&st));
            run.uncovered_at_max.push(
                (!un.is_empty())
                    .then(|| un.iter().filter(|&&n| n >= max).count() as f64 / un.len() as f64),
            );
            on_mover_before = Some(on_mover);
        }
    }
    Ok(run)
}

/// The whole motion report: every scene with `fixed64`, `as` and `as-identity`, the GPU
/// against the CPU twin on the moving scenes when a device is given, the acceptance lines.
#[derive(Clone, Debug, Default)]
pub struct MotionReport {
    /// Every run.
    pub runs: Vec<MotionRun>,
    /// Per moving scene: the smallest per-frame fraction of pixels whose GPU count equals
    /// the twin's (GPU runs only).
    pub agreement: Vec<(String, f64)>,
    /// The acceptance lines: text and pass.
    pub lines: Vec<(String, bool)>,
}

/// Per-frame references of every scene of one group: the static camera and `moving`.
///
/// The pans reuse one reference of the world strip they cross (pixel centres stay on the
/// world's half-integer grid at integer speeds, so each frame is a window of it); the
/// moving sphere recomputes only the pixels within reach of the sphere (30 px) and takes
/// the static reference elsewhere; the rotation computes every frame.
pub fn references(opts: &MotionOptions, size: [u32; 2], motion: Motion) -> Vec<Vec<f32>> {
    let [w, h] = size;
    let scene = AoScene {
        width: w,
        height: h,
        motion,
    };
    let frames = opts.frames as usize;
    match motion {
        Motion::Static => vec![reference(&scene.params(0), opts.grid); frames],
        Motion::Pan { speed } => {
            let (strip, pitch) = pan_strip(opts, size);
            (0..opts.frames)
                .map(|t| {
                    let shift = (speed * t as f32) as usize;
                    (0..(w * h) as usize)
                        .map(|i| strip[(i / w as usize) * pitch + i % w as usize + shift])
                        .collect()
                })
                .collect()
        }
        Motion::MovingSphere { .. } => {
            let base = reference(
                &AoScene {
                    motion: Motion::Static,
                    ..scene
                }
                .params(0),
                opts.grid,
            );
            (0..opts.frames)
                .map(|t| {
                    let p = scene.params(t);
                    let g = twin::gbuffer(&p);
                    let m = p.mover;
                    let near = |i: usize| {
                        let s = g[i].surface.position;
                        (s[0] - m[0]).hypot(s[1] - m[1]) < m[3] + twin::RANGE + 2.0
                    };
                    reference_of(&p, &g, opts.grid, near, &base)
                })
                .collect()
        }
        Motion::Rotate { .. } => (0..opts.frames)
            .map(|t| reference(&scene.params(t), opts.grid))
            .collect(),
    }
}

/// The reference of the world strip every pan crosses (the fastest, 8 px per frame, goes
/// furthest): `size` plus `8 frames` columns, its column `k` the pan's column `k` at frame
/// 0. Cached per size and frame count.
fn pan_strip(opts: &MotionOptions, size: [u32; 2]) -> (std::sync::Arc<Vec<f32>>, usize) {
    type Key = ([u32; 2], u32, u32);
    static CACHE: std::sync::Mutex<Vec<(Key, std::sync::Arc<Vec<f32>>)>> =
        std::sync::Mutex::new(Vec::new());
    let [w, h] = size;
    let fastest = pans()
        .iter()
        .map(|m| match m {
            Motion::Pan { speed } => *speed,
            _ => 0.0,
        })
        .fold(0.0_f32, f32::max);
    let extra = (fastest * opts.frames as f32).ceil() as u32;
    let pitch = (w + extra) as usize;
    let key = (size, opts.frames, opts.grid);
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, s)) = cache.iter().find(|(k, _)| *k == key) {
        return (s.clone(), pitch);
    }
    let wide = AoScene {
        width: w + extra,
        height: h,
        motion: Motion::Static,
    };
    let mut p = wide.params(0);
    // Centre the strip so that its column k is the pan's column k at frame 0.
    p.camera[0] += 0.5 * extra as f32;
    let strip = std::sync::Arc::new(reference(&p, opts.grid));
    cache.push((key, strip.clone()));
    (strip, pitch)
}

/// Runs the motion report.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn report(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    mut progress: impl FnMut(&str),
) -> Result<MotionReport, AdaptiveError> {
    let mut rep = MotionReport::default();
    for (group, size, moving) in [("pan", opts.pan_size, pans()), ("", opts.size, others())] {
        for motion in std::iter::once(Motion::Static).chain(moving) {
            progress(&format!(
                "reference {} {}x{}",
                motion.name(),
                size[0],
                size[1]
            ));
            let refs = references(opts, size, motion);
            let with = Reprojection::default();
            let variant = |mode, reprojection, dilation| Variant {
                mode,
                reprojection,
                dilation,
            };
            let d = opts.dilation;
            let mut variants = vec![
                variant(AoMode::Fixed(64), with, 0),
                variant(AoMode::Adaptive, with, d),
                variant(AoMode::Identity, with, d),
            ];
            // The border prior matters only where pixels enter the frame.
            if matches!(motion, Motion::Pan { .. } | Motion::Rotate { .. }) {
                variants.push(variant(AoMode::Adaptive, with.with_border_prior(false), d));
                variants.push(variant(
                    AoMode::Adaptive,
                    with.with_border_count(BorderCount::Texel),
                    d,
                ));
            }
            // What the dilation buys and costs: at rest, and under the fastest motions.
            let hardest = matches!(motion, Motion::Static | Motion::Rotate { .. })
                || motion == Motion::Pan { speed: 8.0 };
            if d > 0 && hardest {
                variants.push(variant(AoMode::Adaptive, with, 0));
            }
            // The footprint search matters only under sub-pixel motion.
            if matches!(motion, Motion::Rotate { .. }) {
                variants.push(variant(
                    AoMode::Adaptive,
                    with.with_footprint_search(false),
                    d,
                ));
            }
            for v in variants {
                progress(&format!("{} {}", motion.name(), v.name(opts)));
                let mut r = run(dev, opts, size, motion, v, &refs)?;
                if motion == Motion::Static && !group.is_empty() {
                    r.scene = format!("static-{group}");
                }
                rep.runs.push(r);
            }
        }
    }
    if dev.is_some() {
        for motion in [
            Motion::Pan { speed: 4.0 },
            Motion::Rotate { degrees: 2.0 },
            Motion::MovingSphere { speed: 3.0 },
        ] {
            progress(&format!("GPU vs twin {}", motion.name()));
            rep.agreement
                .push((motion.name(), agreement(dev, opts, motion)?));
        }
    }
    rep.lines = acceptance(&rep, opts);
    Ok(rep)
}

/// The smallest per-frame fraction of equal counts between the GPU and the twin (AS with
/// reprojection).
fn agreement(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    motion: Motion,
) -> Result<f64, AdaptiveError> {
    let Some(d) = dev else { return Ok(1.0) };
    let [w, h] = opts.size;
    let scene = AoScene {
        width: w,
        height: h,
        motion,
    };
    let repro = Reprojection::default();
    let mut g = AoPass::new(
        &d.device,
        &d.queue,
        w,
        h,
        AoMode::Adaptive,
        opts.config,
        repro,
    )?;
    let mut c = AoTwin::new(w, h, AoMode::Adaptive, opts.config, repro)?;
    g.set_count_dilation(opts.dilation)?;
    c.set_count_dilation(opts.dilation)?;
    let mut worst = 1.0_f64;
    for t in 0..opts.frames.min(16) {
        let p = scene.params(t);
        let (a, b) = (g.run_frame(&p)?, c.run_frame(&p)?);
        let same = a.count.iter().zip(&b.count).filter(|(x, y)| x == y).count();
        worst = worst.min(same as f64 / a.count.len() as f64);
    }
    Ok(worst)
}

fn find<'a>(rep: &'a MotionReport, scene: &str, mode: &str) -> Option<&'a MotionRun> {
    rep.runs.iter().find(|r| r.scene == scene && r.mode == mode)
}

/// The `as-no-dilation` and `as-nearest-only` runs of `scene` in words, or nothing where
/// they were not run.
fn without_dilation(rep: &MotionReport, scene: &str) -> String {
    [
        (BORDER_TEXEL, "entering pixels at the border texel's count"),
        (NO_DILATION, "without count dilation"),
        (NEAREST_ONLY, "without the footprint search"),
    ]
    .iter()
    .filter_map(|(mode, what)| {
        find(rep, scene, mode)
            .map(|b| format!("; {what}: {:.1} spp, {:.2} dB", b.mean_spp(), b.mean_psnr()))
    })
    .collect()
}

fn acceptance(rep: &MotionReport, opts: &MotionOptions) -> Vec<(String, bool)> {
    let mut lines = Vec::new();
    // Second consumer, static camera, at both sizes.
    for st_name in ["static", "static-pan"] {
        let (Some(st), Some(fixed)) = (find(rep, st_name, "as"), find(rep, st_name, "fixed64"))
        else {
            continue;
        };
        let ok = st.mean_psnr() >= fixed.mean_psnr() - 1.0 && st.mean_spp() <= 32.0;
        lines.push((
            format!(
                "Second consumer (AO), {st_name} camera: AS {:.2} dB at {:.1} spp vs fixed 64 \
                 {:.2} dB (within 1 dB at <= 32 spp){}",
                st.mean_psnr(),
                st.mean_spp(),
                fixed.mean_psnr(),
                without_dilation(rep, st_name)
            ),
            ok,
        ));
    }
    // Pans and the rotation, each against the static camera of its size.
    let moving = pans()
        .into_iter()
        .map(|m| (m, "static-pan"))
        .chain([(Motion::Rotate { degrees: 2.0 }, "static")]);
    for (scene, st_name) in moving {
        let name = scene.name();
        let (Some(a), Some(id), Some(st)) = (
            find(rep, &name, "as"),
            find(rep, &name, "as-identity"),
            find(rep, st_name, "as"),
        ) else {
            continue;
        };
        let without = find(rep, &name, NO_PRIOR).map_or(String::new(), |b| {
            format!(
                "; without the border prior (beta_min for entering pixels): {:.1} spp, {:.2} dB",
                b.mean_spp(),
                b.mean_psnr()
            )
        });
        let ratio = a.mean_spp() / st.mean_spp();
        let loss = st.mean_psnr() - a.mean_psnr();
        lines.push((
            format!(
                "Pan criterion, {name}: AS {:.1} spp = {ratio:.2}x {st_name} (<= 1.25x), {:.2} dB \
                 = {loss:+.2} dB below {st_name} (<= 1 dB); on the pixels on screen for 3 \
                 frames {:.2} dB ({:+.2} dB); identity history: {:.1} spp ({:.2}x), {:.2} dB\
                 {without}{}",
                a.mean_spp(),
                a.mean_psnr(),
                a.mean_psnr_steady(),
                st.mean_psnr() - a.mean_psnr_steady(),
                id.mean_spp(),
                id.mean_spp() / st.mean_spp(),
                id.mean_psnr(),
                without_dilation(rep, &name)
            ),
            ratio <= 1.25 && loss <= 1.0,
        ));
    }
    // Disocclusion by motion.
    for r in rep
        .runs
        .iter()
        .filter(|r| r.mode == "as" && r.scene.starts_with("object"))
    {
        let worst = r
            .uncovered_at_max
            .iter()
            .flatten()
            .fold(0.0_f64, |m, &x| m.max(x));
        let un = mean(
            &r.uncovered_spp
                .iter()
                .flatten()
                .copied()
                .collect::<Vec<_>>(),
        );
        let st = mean(&r.steady_spp.iter().flatten().copied().collect::<Vec<_>>());
        lines.push((
            format!(
                "Disocclusion by motion, {}: newly uncovered pixels {un:.1} spp vs steady {st:.1} \
                 spp on average; at most {:.1}% of the uncovered pixels at the maximum count in \
                 any frame (<= 10%)",
                r.scene,
                100.0 * worst
            ),
            worst <= 0.10,
        ));
    }
    for (scene, worst) in &rep.agreement {
        lines.push((
            format!(
                "GPU vs twin, {scene}: counts equal on {:.2}% of pixels in the worst of {} frames \
                 (>= 99%)",
                100.0 * worst,
                opts.frames
            ),
            *worst >= 0.99,
        ));
    }
    lines
}

/// The report section (markdown) and the per-frame CSV.
#[must_use]
pub fn markdown(rep: &MotionReport, opts: &MotionOptions, backend: &str) -> (String, String) {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Motion: the adaptive component on a second consumer (ambient occlusion)\n\n\
         Stochastic ambient occlusion (16 px rays, cosine-weighted) on a procedural height \
         field (a plane with one sphere per 64 px cell); pans and their static camera \
         (`static-pan`) at {}x{}, the rotation, the moving sphere and their static camera at \
         {}x{}; {} frames, sigma0^2 = {}, budget [{}, {}], backend: {backend}. Reference: \
         midpoint rule on {}x{} directions per pixel. Motion vectors in pixels (current minus \
         previous position), history read at the nearest texel, valid when inside the frame \
         with the previous depth within 2% (where that texel fails, the first of the other \
         texels of its 2x2 footprint that passes). `as-identity` is today's behaviour for contrast: \
         the history read at the same pixel, no rejection. AS spends the largest count \
         within {} px (count dilation, docs/algorithms.md §2.5); `{NO_DILATION}` is AS with \
         each pixel's own count, `{NO_PRIOR}` AS without the border prior (entering pixels at \
         beta_min), `{BORDER_TEXEL}` AS with entering pixels at the border texel's count \
         instead of beta_max, `{NEAREST_ONLY}` AS \
         without the footprint search (the nearest texel only). Means over frames \
         {}..{} (the first {} are the warm-up from a cold history).\n",
        opts.pan_size[0],
        opts.pan_size[1],
        opts.size[0],
        opts.size[1],
        opts.frames,
        opts.config.target_variance(),
        opts.config.min_samples(),
        opts.config.max_samples(),
        opts.grid,
        opts.grid,
        opts.dilation,
        WARM_UP,
        opts.frames - 1,
        WARM_UP
    );
    let _ = writeln!(
        md,
        "| scene | mode | mean spp | mean PSNR (dB) | PSNR on steady pixels (dB) |\n| --- | --- | --- | --- | --- |"
    );
    for r in &rep.runs {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.2} | {:.2} |",
            r.scene,
            r.mode,
            r.mean_spp(),
            r.mean_psnr(),
            r.mean_psnr_steady()
        );
    }
    let _ = writeln!(md, "\n### Acceptance (motion)\n");
    for (line, ok) in &rep.lines {
        let _ = writeln!(md, "- {}: {line}", if *ok { "PASS" } else { "FAIL" });
    }
    let mut csv =
        String::from("scene,mode,frame,spp,psnr_db,uncovered_spp,steady_spp,uncovered_at_max\n");
    let opt = |v: Option<&Option<f64>>| {
        v.copied()
            .flatten()
            .map_or(String::new(), |x| format!("{x:.4}"))
    };
    for r in &rep.runs {
        for (t, (spp, p)) in r.spp.iter().zip(&r.psnr).enumerate() {
            let ps = r.psnr_steady.get(t).copied().unwrap_or(f64::NAN);
            let _ = writeln!(
                csv,
                "{},{},{t},{spp:.4},{p:.4},{ps:.4},{},{},{}",
                r.scene,
                r.mode,
                opt(r.uncovered_spp.get(t)),
                opt(r.steady_spp.get(t)),
                opt(r.uncovered_at_max.get(t))
            );
        }
    }
    (md, csv)
}

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

/// Runs the motion report and writes `motion.md`, `motion.csv` and the charts into `dir`;
/// returns the markdown (with the charts linked) and whether every line passed.
///
/// # Errors
///
/// A device failure, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    backend: &str,
    progress: impl FnMut(&str),
) -> Result<(String, bool), ReportError> {
    let rep = report(dev, opts, progress)
        .map_err(|e| ReportError::Usage(format!("motion report: {e}")))?;
    let (mut md, csv) = markdown(&rep, opts, backend);
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let _ = writeln!(md, "\nPer-frame values: [motion.csv](motion.csv).\n");
    let mut charts: Vec<String> = vec!["static-pan".into(), "static".into()];
    charts.extend(pans().iter().chain(&others()).map(Motion::name));
    for scene in charts {
        let file = write_chart(dir, &rep, &scene)?;
        let _ = writeln!(md, "![{scene}]({file})\n");
    }
    let csv_path = dir.join("motion.csv");
    std::fs::write(&csv_path, csv).map_err(|e| ReportError::io(&csv_path, e))?;
    let md_path = dir.join("motion.md");
    std::fs::write(&md_path, &md).map_err(|e| ReportError::io(&md_path, e))?;
    Ok((md, rep.lines.iter().all(|(_, ok)| *ok)))
}
