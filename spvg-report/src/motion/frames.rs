//! Which frames of a run are scored, and which poses of a moving camera are held still
//! for its baseline ([`super::poses`]).
//!
//! The default suite scores every frame after the warm-up, except on the rotation and the
//! dolly, whose frames each need a reference of their own (the rotation's never repeat):
//! there it scores the frames whose poses their still baselines hold, every 4th frame
//! after the warm-up. The full suite scores every frame from frame 0.

use super::data::WARM_UP;
use super::options::MotionOptions;
use super::scenes::FASTEST_PAN;
use crate::wgpu_api::Motion;

/// Every how many frames a pose is held still.
pub const POSE_STRIDE: u32 = 4;

/// The first frame whose reference the report computes: frame 0 with
/// [`MotionOptions::full`] or in runs too short to leave out the warm-up, else
/// [`WARM_UP`] (the run means leave the warm-up out).
#[must_use]
pub fn first_scored(opts: &MotionOptions) -> u32 {
    if opts.full || opts.frames as usize <= 2 * WARM_UP {
        0
    } else {
        WARM_UP as u32
    }
}

/// The moving scenes that get a still baseline: the young-history lines' (the fastest pan
/// and the rotation) and the dolly's pan criterion.
#[must_use]
pub fn has_still_baseline(motion: Motion) -> bool {
    motion == FASTEST_PAN || matches!(motion, Motion::Rotate { .. } | Motion::Dolly { .. })
}

/// The frames of `motion` whose poses are held still: every 4th frame of those the run
/// means pool (after the warm-up where the run is long enough to leave it out); none for
/// a scene without a still baseline.
#[must_use]
pub fn pose_frames(opts: &MotionOptions, motion: Motion) -> Vec<u32> {
    if !has_still_baseline(motion) {
        return Vec::new();
    }
    let first = if opts.frames as usize > 2 * WARM_UP {
        WARM_UP as u32
    } else {
        0
    };
    (first..opts.frames).step_by(POSE_STRIDE as usize).collect()
}

/// Whether frame `t` of `motion` is scored (its reference computed).
#[must_use]
pub fn scored(opts: &MotionOptions, motion: Motion, t: u32) -> bool {
    if t < first_scored(opts) {
        return false;
    }
    opts.full
        || !matches!(motion, Motion::Rotate { .. } | Motion::Dolly { .. })
        || (t - first_scored(opts)).is_multiple_of(POSE_STRIDE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rotation_and_the_dolly_score_their_poses_and_the_rest_every_frame() {
        let default = MotionOptions::new().expect("defaults");
        let full = MotionOptions::full().expect("defaults");
        let rotate = Motion::Rotate { degrees: 2.0 };
        let all = |o: &MotionOptions, m: Motion| -> Vec<u32> {
            (0..o.frames).filter(|&t| scored(o, m, t)).collect()
        };
        assert_eq!(all(&default, rotate), pose_frames(&default, rotate));
        assert_eq!(
            all(&default, FASTEST_PAN),
            (16..48).collect::<Vec<u32>>(),
            "a pan's references cost nothing"
        );
        assert_eq!(all(&full, rotate), (0..48).collect::<Vec<u32>>());
        assert_eq!(pose_frames(&full, rotate), pose_frames(&default, rotate));
        assert_eq!(
            pose_frames(&default, rotate),
            vec![16, 20, 24, 28, 32, 36, 40, 44]
        );
        assert!(pose_frames(&default, Motion::Static).is_empty());
    }
}
