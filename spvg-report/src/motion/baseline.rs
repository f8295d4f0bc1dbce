//! The static baseline of the dolly: a dolly with a zoom changes what the frame shows (at
//! its nearest the frame covers a third of the area, magnified), and the image content sets
//! the counts and the PSNR that AS reaches as much as the motion does (measured: AS on a
//! static camera reaches 41.5 dB at 31.8 spp at height 100, 40.6 dB at 35.1 spp at height
//! 80, 40.0 dB at 36.6 spp at height 61). So the dolly is judged against a static camera
//! that shows what it shows: per frame, AS on a camera held still at that frame's height
//! and zoom, after its warm-up.

use std::collections::HashMap;

use super::MotionOptions;
use super::reference::reference;
use super::runs::{MotionRun, Renderer, WARM_UP, mean, psnr};
use super::scenes::variants;
use crate::progress::Progress;
use crate::wgpu_api::{AdaptiveError, AoMode, AoScene, GpuDevice, Motion};

/// Frames each static camera of the baseline runs: the warm-up, then the frames averaged.
const STATIC_FRAMES: u32 = WARM_UP as u32 + 8;

/// The name of the baseline's scene for `motion` (`static-dolly3`).
#[must_use]
pub fn baseline_name(motion: Motion) -> String {
    format!("static-{}", motion.name())
}

/// The distinct lenses (camera heights) of `motion`'s frames, in order of first use; empty
/// for a scene whose camera does not dolly.
fn heights(opts: &MotionOptions, motion: Motion) -> Vec<[f32; 4]> {
    if !matches!(motion, Motion::Dolly { .. }) {
        return Vec::new();
    }
    let scene = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion,
    };
    let mut out: Vec<[f32; 4]> = Vec::new();
    for t in 0..opts.frames {
        let lens = scene.params(t).lens;
        if !out.contains(&lens) {
            out.push(lens);
        }
    }
    out
}

/// Frames [`static_at_heights`] renders for `motion` (for a progress bar).
#[must_use]
pub fn baseline_frames(opts: &MotionOptions, motion: Motion) -> u64 {
    heights(opts, motion).len() as u64 * u64::from(STATIC_FRAMES)
}

/// For a dolly, a run named [`baseline_name`] (mode `as`) whose frame `t` holds the mean
/// spp and PSNR of AS on a static camera at frame `t`'s height and zoom, over the frames
/// after its warm-up; `None` for other motions.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn static_at_heights(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    motion: Motion,
    progress: &Progress,
) -> Result<Option<MotionRun>, AdaptiveError> {
    let lenses = heights(opts, motion);
    if lenses.is_empty() {
        return Ok(None);
    }
    let Some(v) = variants(Motion::Static, opts)
        .into_iter()
        .find(|v| v.mode == AoMode::Adaptive)
    else {
        return Ok(None);
    };
    progress.stage(&format!(
        "motion: static cameras at the heights of {}",
        motion.name()
    ));
    let still = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion: Motion::Static,
    };
    let mut at: HashMap<[u32; 4], (f64, f64)> = HashMap::new();
    for lens in &lenses {
        let mut p0 = still.params(0);
        (p0.lens, p0.previous_lens) = (*lens, *lens);
        let r = reference(&p0, opts.grid);
        let mut renderer = Renderer::variant(dev, opts, opts.size, v)?;
        let (mut spp, mut db) = (Vec::new(), Vec::new());
        for t in 0..STATIC_FRAMES {
            let mut p = still.params(t);
            (p.lens, p.previous_lens) = (*lens, *lens);
            let f = renderer.frame(&p)?;
            if t >= WARM_UP as u32 {
                spp.push(f.count.iter().map(|&n| f64::from(n)).sum::<f64>() / f.count.len() as f64);
                db.push(psnr(&f.value, &r));
            }
            progress.inc(1);
        }
        at.insert(lens.map(f32::to_bits), (mean(&spp), mean(&db)));
    }
    let scene = AoScene {
        width: opts.size[0],
        height: opts.size[1],
        motion,
    };
    let mut run = MotionRun {
        scene: baseline_name(motion),
        mode: "as".into(),
        ..MotionRun::default()
    };
    for t in 0..opts.frames {
        let (spp, db) = at
            .get(&scene.params(t).lens.map(f32::to_bits))
            .copied()
            .unwrap_or((f64::NAN, f64::NAN));
        run.spp.push(spp);
        run.psnr.push(db);
        run.psnr_steady.push(db);
    }
    Ok(Some(run))
}
