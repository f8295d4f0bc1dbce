//! The subsurface pass's adaptive steps over a tile list (the hybrid pass's first step):
//! `sss_gamma_tiles` and `sss_sample_tiles`, and the component's estimate and update over
//! the same [`AdaptiveTiles`], so the work of a frame follows its tags.
//!
//! Pixels outside the listed tiles are not written. That gives what the whole-frame steps
//! give once those pixels hold the whole-frame steps' values for pixels outside the
//! sampling region (count 0, history 0, the exchanged values of a pixel without samples),
//! which do not depend on the frame: after the list changes, the next [`SETTLE_FRAMES`]
//! frames run over the whole frame (the history is a ping-pong pair, so both halves get
//! them), and the restricted steps run from then on.

use crate::error::PassError;
use crate::gpu::{compute_pipeline, shader_module};
use crate::sss::sss_source;
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveTiles};

/// Whole frames after a change of the list: one per half of the history's ping-pong pair.
pub(super) const SETTLE_FRAMES: u32 = 2;

/// The tile list, its entry points of `sss.wgsl`, and the frames left before it is used.
#[derive(Debug)]
pub(super) struct SssTiles {
    pub(super) list: AdaptiveTiles,
    pub(super) gamma: wgpu::ComputePipeline,
    pub(super) sample: wgpu::ComputePipeline,
    settle: u32,
}

impl SssTiles {
    /// The tile steps of `component`'s frame, with an empty list not yet settled.
    pub(super) fn new(device: &wgpu::Device, component: &AdaptivePass) -> Self {
        let module = shader_module(device, "sss.wgsl tiles", sss_source());
        Self {
            list: AdaptiveTiles::new(component),
            gamma: compute_pipeline(device, &module, "sss_gamma_tiles", None),
            sample: compute_pipeline(device, &module, "sss_sample_tiles", None),
            settle: SETTLE_FRAMES,
        }
    }

    /// Sets this frame's region; returns whether the frame may run over the tiles (the
    /// list unchanged for [`SETTLE_FRAMES`] frames before it).
    pub(super) fn frame(&mut self, region: &[u8]) -> Result<bool, PassError> {
        if self.list.set_region(region)? {
            self.settle = SETTLE_FRAMES;
        }
        if self.settle > 0 {
            self.settle -= 1;
            return Ok(false);
        }
        Ok(true)
    }
}
