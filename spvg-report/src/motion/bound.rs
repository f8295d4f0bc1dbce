//! The motion bound: one frame of broken motion vectors (every vector `1e30` pixels, far
//! beyond the motion bound of `spvg::reproject`) on the static camera, and the mean spp
//! of the frames around it.

use super::data::{MotionBound, TwinCheck, WARM_UP};
use super::options::MotionOptions;
use super::render::{Renderer, Setup};
use super::scenes::{Variant, variants};
use crate::error::ReportError;
use crate::progress::Progress;
use crate::wgpu_api::{AoMode, AoScene, GpuDevice, Motion, ao_twin as twin};

/// The frame [`motion_bound_of`] breaks: after the warm-up (as late as the run allows, one
/// frame kept after it), `None` for a run shorter than 3 frames.
#[must_use]
pub fn motion_bound_frame(opts: &MotionOptions) -> Option<u32> {
    (opts.frames >= 3).then(|| (WARM_UP as u32 + 4).min(opts.frames - 2))
}

/// The static camera's young-history rows (the full suite's; the motion bound runs each).
#[must_use]
pub fn young_variants(opts: &MotionOptions) -> Vec<Variant> {
    variants(Motion::Static, opts)
        .into_iter()
        .filter(|v| {
            v.mode == AoMode::Adaptive
                && !v.guided
                && v.dilation == opts.dilation
                && (v.age_weight
                    || v.spatial_variance != opts.config.spatial_variance()
                    || !v.neighbour_prior)
        })
        .collect()
}

/// The static camera's AS run and its young-history rows ([`young_variants`]): the runs
/// the motion bound breaks.
#[must_use]
pub fn bound_variants(opts: &MotionOptions) -> Vec<Variant> {
    let mut v: Vec<Variant> = variants(Motion::Static, opts)
        .into_iter()
        .filter(|v| v.mode == AoMode::Adaptive)
        .take(1)
        .collect();
    v.extend(young_variants(opts));
    v
}

/// Runs the static camera at `opts.size` in variant `v` up to the frame after
/// [`motion_bound_frame`], with every motion vector of that frame at `1e30` (a broken
/// motion buffer), and returns the mean spp around it and the GPU run's check against
/// the twin.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn motion_bound_of(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    v: Variant,
    progress: &Progress,
) -> Result<Option<(MotionBound, Option<TwinCheck>)>, ReportError> {
    let Some(k) = motion_bound_frame(opts) else {
        return Ok(None);
    };
    let scene = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion: Motion::Static,
    };
    let mut r = Renderer::new(
        dev,
        &Setup::of(opts, &v)?,
        opts.size,
        "static (motion bound)",
        &v.name(opts),
    )?;
    let mut spp = Vec::new();
    for t in 0..=k + 1 {
        let mut p = scene.params(t);
        if t == k {
            p.motion_bias = [1e30, 1e30, 0.0, 0.0];
        }
        let g = twin::gbuffer(&p);
        let f = r.frame(&p, &g)?;
        spp.push(f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len().max(1) as f64);
        progress.inc(1);
    }
    let at = |t: u32| spp.get(t as usize).copied().unwrap_or(f64::NAN);
    Ok(Some((
        MotionBound {
            frame: k,
            before: at(k - 1),
            broken: at(k),
            after: at(k + 1),
        },
        r.twin_check(),
    )))
}

/// Frames the motion bound renders (for a progress bar).
#[must_use]
pub fn bound_frames(opts: &MotionOptions) -> u64 {
    bound_variants(opts).len() as u64 * motion_bound_frame(opts).map_or(0, |k| u64::from(k) + 2)
}
