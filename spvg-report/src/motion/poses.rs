//! The static camera at a moving camera's own poses: the baseline of the young-history
//! lines. A pan or a rotation changes what the frame shows (the pan moves 8 px per frame
//! over a field whose occluders are not uniform), so a camera held still at the first
//! pose measures the content as much as the motion. This baseline holds the camera still
//! at the poses of some of the moving camera's scored frames, runs AS there from a cold
//! history for the warm-up and scores the frames after it against that frame's reference:
//! AS's loss against it is what the motion costs. `fixed64` is held at the same poses for
//! the same frames: its loss there is the content's share, with no history involved.
//!
//! The fastest pan's poses are windows of one static camera over the strip the pan
//! crosses (its pixel centres on the same half-integer grid, so each window shows exactly
//! what the pan's frame shows and its reference is that frame's): one run of the strip
//! holds every pose. Its windows' pixels have neighbours beyond their edges where a camera
//! held at one pose would have the frame's border, which only the count dilation, the
//! neighbour prior and the spatial variance read (within 4 px of two of 384 columns).
//! The rotation's poses are not windows of one frame: each is held by its own camera.
//!
//! The dolly is judged against its poses too: a dolly with a zoom changes what the frame
//! shows (at its nearest the frame covers a third of the area, magnified), and the image
//! content sets the counts and the PSNR that AS reaches as much as the motion does
//! (measured: AS on a static camera reaches 41.5 dB at 31.8 spp at height 100, 40.6 dB at
//! 35.1 spp at height 80, 40.0 dB at 36.6 spp at height 61). Its poses repeat (a height
//! comes back every 26 frames), so each distinct one is held once.

use super::data::{StillBaseline, TwinCheck, WARM_UP, mean, psnr};
use super::frames::pose_frames;
use super::options::MotionOptions;
use super::reference::{strip_params, strip_scene};
use super::render::{Renderer, Setup};
use super::scenes::{Variant, variants};
use crate::error::ReportError;
use crate::progress::Progress;
use crate::wgpu_api::{AoMode, AoScene, GpuDevice, Motion, ao_twin as twin};

/// Frames each still camera runs: the warm-up, then the frames scored.
pub const STILL_FRAMES: u32 = WARM_UP as u32 + 8;

/// A camera's pose: its camera and lens blocks (`AoParams::camera`, `AoParams::lens`).
type Pose = ([f32; 4], [f32; 4]);

/// The poses held by cameras of their own (the rotation's and the dolly's): each distinct
/// pose of [`pose_frames`] once.
fn distinct_poses(
    opts: &MotionOptions,
    size: [u32; 2],
    motion: Motion,
) -> Vec<([f32; 4], [f32; 4])> {
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion,
    };
    let mut out: Vec<Pose> = Vec::new();
    for t in pose_frames(opts, motion) {
        let p = scene.params(t);
        if !out.contains(&(p.camera, p.lens)) {
            out.push((p.camera, p.lens));
        }
    }
    out
}

/// Frames [`still_at_poses`] renders for `motion` at `size` (for a progress bar).
#[must_use]
pub fn still_frames(opts: &MotionOptions, size: [u32; 2], motion: Motion) -> u64 {
    let per_pose = u64::from(STILL_FRAMES) + u64::from(STILL_FRAMES) - WARM_UP as u64;
    if pose_frames(opts, motion).is_empty() {
        0
    } else if matches!(motion, Motion::Pan { .. }) {
        per_pose
    } else {
        distinct_poses(opts, size, motion).len() as u64 * per_pose
    }
}

/// A still baseline and the checks of its GPU runs against the twin.
#[derive(Debug)]
pub struct Still {
    /// The baseline.
    pub baseline: StillBaseline,
    /// Its GPU runs' checks.
    pub twin_checks: Vec<TwinCheck>,
}

/// The AS run of the static camera (the variant the baseline holds still) and `fixed64`.
fn still_variants(opts: &MotionOptions) -> Option<(Variant, Variant)> {
    let v = variants(Motion::Static, opts);
    let adaptive = v.iter().find(|v| v.mode == AoMode::Adaptive).copied()?;
    let fixed = v
        .iter()
        .find(|v| v.mode == AoMode::Fixed(64))
        .map(|f| Variant {
            prefixes: [0; 4],
            ..*f
        })?;
    Some((adaptive, fixed))
}

/// The mean count over the pixels of `count` (row pitch `pitch`) in the `w x h` window
/// at column `x0`, and the window's values.
fn window(
    value: &[f32],
    count: &[u32],
    pitch: usize,
    x0: usize,
    [w, h]: [u32; 2],
) -> (f64, Vec<f32>) {
    let (w, h) = (w as usize, h as usize);
    let mut v = Vec::with_capacity(w * h);
    let mut n = 0.0;
    for y in 0..h {
        let row = y * pitch + x0;
        v.extend_from_slice(&value[row..row + w]);
        n += count[row..row + w]
            .iter()
            .map(|&c| f64::from(c))
            .sum::<f64>();
    }
    (n / (w * h).max(1) as f64, v)
}

/// For the fastest pan, the rotation and the dolly, AS (the `as` variant of the static
/// camera) and `fixed64` on a camera held still at the pose of each of [`pose_frames`],
/// scored against `refs` (the moving scene's per-frame references: the held camera shows
/// what that frame shows); `None` for other motions.
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
) -> Result<Option<Still>, ReportError> {
    let frames: Vec<u32> = pose_frames(opts, motion)
        .into_iter()
        .filter(|&t| refs.get(t as usize).is_some_and(|r| !r.is_empty()))
        .collect();
    let Some((adaptive, fixed)) = still_variants(opts) else {
        return Ok(None);
    };
    if frames.is_empty() {
        return Ok(None);
    }
    progress.stage(&format!(
        "motion: static cameras at the poses of {}",
        motion.name()
    ));
    let label = format!("{} (held still at its poses)", motion.name());
    let mut out = StillBaseline {
        scene: motion.name(),
        frames: frames.clone(),
        ..StillBaseline::default()
    };
    let mut checks = Vec::new();
    let scored = WARM_UP as u32..STILL_FRAMES;
    if let Motion::Pan { speed } = motion {
        // One static camera over the strip holds every pose: pose t is its window at
        // column speed * t.
        let (wide, _) = strip_scene(opts, size);
        let wide_size = [wide.width, wide.height];
        let pitch = wide.width as usize;
        let shift = |t: u32| (speed * t as f32) as usize;
        let mut spp = vec![Vec::new(); frames.len()];
        let mut db = vec![Vec::new(); frames.len()];
        let mut fixed_db = vec![Vec::new(); frames.len()];
        let mut a = Renderer::new(dev, &Setup::of(opts, &adaptive)?, wide_size, &label, "as")?;
        let mut f = Renderer::new(dev, &Setup::of(opts, &fixed)?, wide_size, &label, "fixed64")?;
        for k in 0..STILL_FRAMES {
            let p = strip_params(opts, size, k);
            let g = twin::gbuffer(&p);
            let frame = a.frame(&p, &g)?;
            progress.inc(1);
            if !scored.contains(&k) {
                continue;
            }
            let fixed_frame = f.frame(&p, &g)?;
            progress.inc(1);
            for (j, &t) in frames.iter().enumerate() {
                let r = &refs[t as usize];
                let (n, v) = window(&frame.value, &frame.count, pitch, shift(t), size);
                spp[j].push(n);
                db[j].push(psnr(&v, r));
                let (_, v) = window(
                    &fixed_frame.value,
                    &fixed_frame.count,
                    pitch,
                    shift(t),
                    size,
                );
                fixed_db[j].push(psnr(&v, r));
            }
        }
        out.spp = spp.iter().map(|v| mean(v)).collect();
        out.psnr = db.iter().map(|v| mean(v)).collect();
        out.fixed_psnr = fixed_db.iter().map(|v| mean(v)).collect();
        checks.extend(a.twin_check());
        checks.extend(f.twin_check());
    } else {
        let scene = AoScene {
            width: size[0],
            height: size[1],
            motion,
        };
        let still = AoScene {
            motion: Motion::Static,
            ..scene
        };
        let mut f = Renderer::new(dev, &Setup::of(opts, &fixed)?, size, &label, "fixed64")?;
        // Per distinct pose: AS's mean spp and PSNR, fixed64's PSNR, over the frames
        // after AS's warm-up, against the reference of the pose's first frame (every
        // frame with that pose sees the same points).
        let mut held_poses: Vec<(Pose, [f64; 3])> = Vec::new();
        for pose in distinct_poses(opts, size, motion) {
            let Some(&t) = frames.iter().find(|&&t| {
                let p = scene.params(t);
                (p.camera, p.lens) == pose
            }) else {
                continue;
            };
            let r = &refs[t as usize];
            let held = |k: u32| {
                let mut p = still.params(k);
                (p.camera, p.previous_camera) = (pose.0, pose.0);
                (p.lens, p.previous_lens) = (pose.1, pose.1);
                p
            };
            let mut a = Renderer::new(dev, &Setup::of(opts, &adaptive)?, size, &label, "as")?;
            let (mut spp, mut db, mut fixed_db) = (Vec::new(), Vec::new(), Vec::new());
            for k in 0..STILL_FRAMES {
                let p = held(k);
                let g = twin::gbuffer(&p);
                let frame = a.frame(&p, &g)?;
                progress.inc(1);
                if !scored.contains(&k) {
                    continue;
                }
                spp.push(
                    frame.count.iter().map(|&n| f64::from(n)).sum::<f64>()
                        / frame.count.len().max(1) as f64,
                );
                db.push(psnr(&frame.value, r));
                fixed_db.push(psnr(&f.frame(&p, &g)?.value, r));
                progress.inc(1);
            }
            checks.extend(a.twin_check());
            held_poses.push((pose, [mean(&spp), mean(&db), mean(&fixed_db)]));
        }
        for &t in &frames {
            let p = scene.params(t);
            let [spp, db, fixed_db] = held_poses
                .iter()
                .find(|(pose, _)| *pose == (p.camera, p.lens))
                .map_or([f64::NAN; 3], |(_, v)| *v);
            out.spp.push(spp);
            out.psnr.push(db);
            out.fixed_psnr.push(fixed_db);
        }
        checks.extend(f.twin_check());
    }
    Ok(Some(Still {
        baseline: out,
        twin_checks: checks,
    }))
}
