//! The static camera at a moving camera's own poses: the baseline of the young-history
//! lines. A pan or a rotation changes what the frame shows (the pan moves 8 px per frame
//! over a field whose occluders are not uniform), so a camera held still at the first
//! pose measures the content as much as the motion: `fixed64`, which has no history,
//! loses 0.6 to 0.7 dB on `pan8` and `rotate2` against their static cameras. This
//! baseline holds the camera still at the poses of some of the moving camera's scored
//! frames, runs AS there from a cold history for the warm-up and scores the frames after
//! it against that frame's reference: AS's loss against it is what the motion costs.

use super::MotionOptions;
use super::runs::{MotionRun, Renderer, WARM_UP, mean, psnr};
use super::scenes::variants;
use crate::progress::Progress;
use crate::wgpu_api::{AdaptiveError, AoMode, AoScene, GpuDevice, Motion};

/// Frames each still camera runs: the warm-up, then the frames scored.
const STILL_FRAMES: u32 = WARM_UP as u32 + 8;

/// Every how many scored frames a pose is held still.
const POSE_STRIDE: u32 = 4;

/// The moving scenes that get a still baseline: the young-history lines' (the fastest pan
/// and the rotation).
#[must_use]
pub fn has_still_baseline(motion: Motion) -> bool {
    motion == Motion::Pan { speed: 8.0 } || matches!(motion, Motion::Rotate { .. })
}

/// The frames of `motion` whose poses [`still_at_poses`] holds: every 4th
/// frame after the warm-up; none for a scene without a still baseline.
#[must_use]
pub fn pose_frames(opts: &MotionOptions, motion: Motion) -> Vec<u32> {
    if !has_still_baseline(motion) {
        return Vec::new();
    }
    (WARM_UP as u32..opts.frames)
        .step_by(POSE_STRIDE as usize)
        .collect()
}

/// Frames [`still_at_poses`] renders for `motion` (for a progress bar).
#[must_use]
pub fn still_frames(opts: &MotionOptions, motion: Motion) -> u64 {
    pose_frames(opts, motion).len() as u64 * u64::from(STILL_FRAMES)
}

/// AS on a camera held still at some poses of a moving camera, frame by frame.
#[derive(Clone, Debug, Default)]
pub struct StillBaseline {
    /// The moving scene's name (`pan8`).
    pub scene: String,
    /// The moving scene's frames whose poses were held.
    pub frames: Vec<u32>,
    /// Per held pose: AS's mean spp over the frames after its warm-up.
    pub spp: Vec<f64>,
    /// Per held pose: AS's mean PSNR over the same frames, against the moving scene's
    /// reference of that frame (the same view).
    pub psnr: Vec<f64>,
}

impl StillBaseline {
    /// `run`'s mean spp and PSNR over the frames whose poses were held (NaN where `run`
    /// is shorter), beside this baseline's means: `((run spp, run PSNR), (spp, PSNR))`.
    #[must_use]
    pub fn compare(&self, run: &MotionRun) -> ((f64, f64), (f64, f64)) {
        let at = |v: &[f64]| -> Vec<f64> {
            self.frames
                .iter()
                .map(|&t| v.get(t as usize).copied().unwrap_or(f64::NAN))
                .collect()
        };
        (
            (mean(&at(&run.spp)), mean(&at(&run.psnr))),
            (mean(&self.spp), mean(&self.psnr)),
        )
    }
}

/// For the fastest pan and the rotation, AS (the `as` variant of the static camera) on a
/// camera held still at the pose of each of [`pose_frames`], scored against `refs` (the
/// moving scene's per-frame references: the held camera shows what that frame shows);
/// `None` for other motions.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn still_at_poses(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    size: [u32; 2],
    motion: Motion,
    refs: &[Vec<f32>],
    progress: &Progress,
) -> Result<Option<StillBaseline>, AdaptiveError> {
    let frames = pose_frames(opts, motion);
    let Some(v) = variants(Motion::Static, opts)
        .into_iter()
        .find(|v| v.mode == AoMode::Adaptive)
    else {
        return Ok(None);
    };
    if frames.is_empty() {
        return Ok(None);
    }
    progress.stage(&format!(
        "motion: static cameras at the poses of {}",
        motion.name()
    ));
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    let still = AoScene {
        width: size[0],
        height: size[1],
        motion: Motion::Static,
    };
    let mut out = StillBaseline {
        scene: motion.name(),
        ..StillBaseline::default()
    };
    for &t in &frames {
        let Some(r) = refs.get(t as usize) else {
            continue;
        };
        let pose = scene.params(t);
        let mut renderer = Renderer::variant(dev, opts, size, v)?;
        let (mut spp, mut db) = (Vec::new(), Vec::new());
        for k in 0..STILL_FRAMES {
            let mut p = still.params(k);
            (p.camera, p.previous_camera) = (pose.camera, pose.camera);
            (p.lens, p.previous_lens) = (pose.lens, pose.lens);
            let f = renderer.frame(&p)?;
            if k >= WARM_UP as u32 {
                spp.push(f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len() as f64);
                db.push(psnr(&f.value, r));
            }
            progress.inc(1);
        }
        out.frames.push(t);
        out.spp.push(mean(&spp));
        out.psnr.push(mean(&db));
    }
    Ok(Some(out))
}
