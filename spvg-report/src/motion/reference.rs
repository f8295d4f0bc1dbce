//! The converged references of the motion scenes: a quadrature of the cosine-weighted
//! hemisphere at each pixel's visible point, and the shortcuts that reuse it across frames
//! (tests/motion.rs holds the shortcuts equal to the direct quadrature).

use super::MotionOptions;
use super::runs::WARM_UP;
use super::scenes::pans;
use crate::wgpu_api::{AoParams, AoScene, Motion, ao_twin as twin};

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
    let spheres = twin::candidates(p, o);
    let mut open = 0_u64;
    for i in 0..grid {
        let u1 = (f64::from(i) + 0.5) / f64::from(grid);
        let (r, z) = (u1.sqrt(), (1.0 - u1).sqrt());
        for j in 0..grid {
            let phi = std::f64::consts::TAU * (f64::from(j) + 0.5) / f64::from(grid);
            let (dx, dy) = (r * phi.cos(), r * phi.sin());
            let d: [f32; 3] = core::array::from_fn(|k| (t[k] * dx + bt[k] * dy + n[k] * z) as f32);
            if !twin::occluded_among(p, o, d, &spheres) {
                open += 1;
            }
        }
    }
    (open as f64 / f64::from(grid * grid)) as f32
}

/// The first frame whose reference the report computes: frame 0 with
/// [`MotionOptions::full`] or in runs too short to leave out the warm-up, else
/// [`WARM_UP`] (the run means leave the warm-up out, and the default suite does not score
/// it: its PSNR is NaN in `motion.csv`).
#[must_use]
pub fn first_scored(opts: &MotionOptions) -> u32 {
    let warm_up = WARM_UP as u32;
    if opts.full || opts.frames <= 2 * warm_up {
        0
    } else {
        warm_up
    }
}

/// The static camera's reference at `size`: the first window of the pans' strip at the
/// pans' size (the strip is computed for them anyway), else computed once per size and
/// grid.
fn static_reference(opts: &MotionOptions, size: [u32; 2]) -> std::sync::Arc<Vec<f32>> {
    type Key = ([u32; 2], u32);
    static CACHE: std::sync::Mutex<Vec<(Key, std::sync::Arc<Vec<f32>>)>> =
        std::sync::Mutex::new(Vec::new());
    if size == opts.pan_size {
        return std::sync::Arc::new(strip_window(opts, size, 0));
    }
    let key = (size, opts.grid);
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, r)) = cache.iter().find(|(k, _)| *k == key) {
        return r.clone();
    }
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion: Motion::Static,
    };
    let r = std::sync::Arc::new(reference(&scene.params(0), opts.grid));
    cache.push((key, r.clone()));
    r
}

/// The `size` window of the pans' strip shifted by `shift` columns.
fn strip_window(opts: &MotionOptions, size: [u32; 2], shift: usize) -> Vec<f32> {
    let (strip, pitch) = pan_strip(opts, size);
    let w = size[0] as usize;
    (0..w * size[1] as usize)
        .map(|i| strip[(i / w) * pitch + i % w + shift])
        .collect()
}

/// The reference of frame `t` of `scene`.
///
/// The static camera and the pans reuse one reference of the world strip the pans cross
/// (pixel centres stay on the world's half-integer grid at integer speeds, so each frame
/// is a window of it); the moving objects recompute only the pixels within reach of an
/// object ([`near_a_mover`]) and take the static reference elsewhere; the rotation and
/// the dolly compute every frame.
fn frame_reference(opts: &MotionOptions, scene: AoScene, t: u32) -> Vec<f32> {
    let size = [scene.width, scene.height];
    match scene.motion {
        Motion::Static => static_reference(opts, size).to_vec(),
        Motion::Pan { speed } => strip_window(opts, size, (speed * t as f32) as usize),
        Motion::MovingSphere { .. } | Motion::MovingObjects { .. } => {
            let base = static_reference(opts, size);
            let p = scene.params(t);
            let g = twin::gbuffer(&p);
            let near = |i: usize| near_a_mover(&p, g[i].surface.position);
            reference_of(&p, &g, opts.grid, near, &base)
        }
        Motion::Rotate { .. } | Motion::Dolly { .. } => reference(&scene.params(t), opts.grid),
    }
}

/// Whether a ray from surface point `s` can reach a moving object of `p` (its distance
/// from a moving sphere's surface or from the bar's box below the ray length, 0.5 px to
/// spare for the rays' 0.001 offset from the surface and f32 rounding), or `s` is on
/// one: elsewhere the static camera's reference holds. The distance is in 3D: the
/// objects float, and the ground under them is further from them than its horizontal
/// distance says.
fn near_a_mover(p: &AoParams, s: [f32; 3]) -> bool {
    let reach = twin::RANGE + 0.5;
    let spheres = [p.mover, p.extra_movers[0], p.extra_movers[1]];
    let sphere = spheres.iter().any(|m| {
        let d = [s[0] - m[0], s[1] - m[1], s[2] - m[2]];
        m[3] > 0.0 && (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < m[3] + reach
    });
    let (lo, hi) = (p.bar_min, p.bar_max);
    let bar = hi[0] > lo[0] && {
        let d: [f32; 3] = core::array::from_fn(|i| (lo[i] - s[i]).max(s[i] - hi[i]).max(0.0));
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < reach
    };
    sphere || bar
}

/// Per-frame references of `motion` at `size`, each equal to the direct quadrature
/// ([`reference()`] of the frame's parameters; tests/motion.rs holds the shortcuts to it);
/// empty before [`first_scored`].
#[must_use]
pub fn references(opts: &MotionOptions, size: [u32; 2], motion: Motion) -> Vec<Vec<f32>> {
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    let first = first_scored(opts);
    (0..opts.frames)
        .map(|t| {
            if t < first {
                Vec::new()
            } else {
                frame_reference(opts, scene, t)
            }
        })
        .collect()
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
