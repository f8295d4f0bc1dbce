//! The converged references of the motion scenes: a quadrature of the cosine-weighted
//! hemisphere at each pixel's visible point, and the shortcuts that reuse it across frames
//! and runs (tests/motion.rs holds every shortcut equal to the direct quadrature):
//!
//! - a frame's reference depends only on what its pixels see (the camera, the lens, the
//!   frame size and the moving objects' places) and the quadrature: frames and runs that
//!   see the same thing share one ([`ReferenceKey`]; the dolly's frames repeat every 26
//!   frames, and the static cameras at its heights see what its frames see);
//! - the pans and their static camera are windows of one reference of the strip they
//!   cross (pixel centres stay on the world's half-integer grid at integer speeds);
//! - the moving objects change only the pixels within reach of an object: the rest is the
//!   static camera's.

use std::sync::{Arc, Mutex, PoisonError};

use super::frames::scored;
use super::options::MotionOptions;
use super::scenes::PAN_SPEEDS;
use crate::wgpu_api::{AoParams, AoScene, Motion, ao_twin as twin};

/// The converged reference of one frame: at each pixel's visible point, the fraction of
/// the cosine-weighted hemisphere that escapes, by the midpoint rule on a `grid x grid`
/// stratification of the same warp the renderer samples (exact directions in f64, the
/// twin's ray tests with the point's candidate spheres found once), on all cores.
#[must_use]
pub fn reference(params: &AoParams, grid: u32) -> Vec<f32> {
    let g = twin::gbuffer(params);
    reference_where(params, &g, grid, |_| true, &[])
}

/// Everything a frame's reference reads: the frame size, the camera and lens (which point
/// each pixel sees), the moving objects (what occludes the rays) and the quadrature. The
/// frame index, the previous camera and the objects' velocities only move motion vectors
/// and samples, not the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceKey {
    size: [u32; 2],
    grid: u32,
    /// The bits of the camera, lens, the three movers and the bar's corners.
    view: [u32; 28],
}

impl ReferenceKey {
    /// The key of frame `p`'s reference on a `grid x grid` quadrature.
    #[must_use]
    pub fn of(p: &AoParams, grid: u32) -> Self {
        let mut view = [0_u32; 28];
        let parts = [
            p.camera,
            p.lens,
            p.mover,
            p.extra_movers[0],
            p.extra_movers[1],
            p.bar_min,
            p.bar_max,
        ];
        for (k, v) in parts.iter().flatten().enumerate() {
            view[k] = v.to_bits();
        }
        Self {
            size: [p.width, p.height],
            grid,
            view,
        }
    }
}

/// The references computed so far in this process, by key.
type Memo = Mutex<Vec<(ReferenceKey, Arc<Vec<f32>>)>>;

static MEMO: Memo = Mutex::new(Vec::new());

/// [`reference()`] of frame `p`, computed once per [`ReferenceKey`] in a process (the
/// memo's entries are the direct quadrature's, by construction).
#[must_use]
pub fn shared_reference(p: &AoParams, grid: u32) -> Arc<Vec<f32>> {
    let key = ReferenceKey::of(p, grid);
    if let Some(r) = lookup(key) {
        return r;
    }
    let r = Arc::new(reference(p, grid));
    MEMO.lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push((key, Arc::clone(&r)));
    r
}

fn lookup(key: ReferenceKey) -> Option<Arc<Vec<f32>>> {
    MEMO.lock()
        .unwrap_or_else(PoisonError::into_inner)
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, r)| Arc::clone(r))
}

/// [`reference()`] at the pixels of `g` (the frame's [`twin::gbuffer`]) where `todo(i)`
/// holds; elsewhere `base[i]`: what lets a frame recompute only the pixels a moving object
/// can change.
#[must_use]
pub fn reference_where(
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

/// The `size` window of the pans' strip shifted by `shift` columns.
fn strip_window(opts: &MotionOptions, size: [u32; 2], shift: usize) -> Vec<f32> {
    let (strip, pitch) = pan_strip(opts, size);
    let w = size[0] as usize;
    (0..w * size[1] as usize)
        .map(|i| strip[(i / w) * pitch + i % w + shift])
        .collect()
}

/// The reference of frame `t` of `scene`: the pans and their static camera from the
/// strip ([`pan_strip`]), the moving objects from the static camera's with the pixels
/// within reach of an object ([`near_a_mover`]) recomputed, the rest through
/// [`shared_reference`].
fn frame_reference(opts: &MotionOptions, scene: AoScene, t: u32) -> Vec<f32> {
    let size = [scene.width, scene.height];
    match scene.motion {
        Motion::Static if size == opts.pan_size => strip_window(opts, size, 0),
        Motion::Pan { speed } => strip_window(opts, size, (speed * t as f32) as usize),
        Motion::MovingSphere { .. } | Motion::MovingObjects { .. } => {
            let still = AoScene {
                motion: Motion::Static,
                ..scene
            };
            let base = shared_reference(&still.params(0), opts.grid);
            let p = scene.params(t);
            let g = twin::gbuffer(&p);
            let near = |i: usize| near_a_mover(&p, g[i].surface.position);
            reference_where(&p, &g, opts.grid, near, &base)
        }
        Motion::Static | Motion::Rotate { .. } | Motion::Dolly { .. } => {
            shared_reference(&scene.params(t), opts.grid).to_vec()
        }
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
/// empty where the frame is not scored ([`scored`]).
#[must_use]
pub fn references(opts: &MotionOptions, size: [u32; 2], motion: Motion) -> Vec<Vec<f32>> {
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    (0..opts.frames)
        .map(|t| {
            if scored(opts, motion, t) {
                frame_reference(opts, scene, t)
            } else {
                Vec::new()
            }
        })
        .collect()
}

/// The columns the strip adds to a frame's width: as far as the fastest pan goes in a
/// run.
fn strip_extra(opts: &MotionOptions) -> u32 {
    let fastest = PAN_SPEEDS.iter().copied().fold(0.0_f32, f32::max);
    (fastest * opts.frames as f32).ceil() as u32
}

/// The static camera whose frame is the world strip every pan crosses (the fastest,
/// 8 px per frame, goes furthest): `size` plus as many columns as the fastest pan crosses in a run, its column `k`
/// the pan's column `k` at frame 0. The pans' references and the fastest pan's camera
/// held still at its poses ([`super::poses`]) are windows of it.
#[must_use]
pub fn strip_scene(opts: &MotionOptions, size: [u32; 2]) -> (AoScene, [f32; 4]) {
    let extra = strip_extra(opts);
    let wide = AoScene {
        width: size[0] + extra,
        height: size[1],
        motion: Motion::Static,
    };
    let mut camera = wide.params(0).camera;
    // Centre the strip so that its column k is the pan's column k at frame 0.
    camera[0] += 0.5 * extra as f32;
    (wide, camera)
}

/// The parameters of frame `t` of the strip's static camera ([`strip_scene`]).
#[must_use]
pub fn strip_params(opts: &MotionOptions, size: [u32; 2], t: u32) -> AoParams {
    let (wide, camera) = strip_scene(opts, size);
    let mut p = wide.params(t);
    (p.camera, p.previous_camera) = (camera, camera);
    p
}

/// The reference of the strip ([`strip_scene`]) and its row pitch.
fn pan_strip(opts: &MotionOptions, size: [u32; 2]) -> (Arc<Vec<f32>>, usize) {
    let pitch = (size[0] + strip_extra(opts)) as usize;
    (
        shared_reference(&strip_params(opts, size, 0), opts.grid),
        pitch,
    )
}
