//! The bytes each step moves per pixel: the texels of the frame-size textures it binds,
//! in the formats this run feeds it (the copy kernel moves as many).

use crate::wgpu_api::{COUNT_FORMAT, HISTORY_FORMAT};
use wgpu::TextureFormat as Tf;

/// The motion-vector format this run feeds the estimate (one of the accepted ones).
pub const MOTION_FORMAT: Tf = Tf::Rg32Float;
/// The format of the depths and the monitored value this run feeds the steps.
pub const SCALAR_FORMAT: Tf = Tf::R32Float;
/// The format of the component's link texture (estimate to update).
pub const LINK_FORMAT: Tf = Tf::R32Uint;

/// Bytes a step moves per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepBytes {
    /// Bytes read per pixel.
    pub read: u64,
    /// Bytes written per pixel.
    pub written: u64,
}

impl StepBytes {
    /// Read plus written.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.read + self.written
    }
}

pub(super) fn texel(format: Tf) -> u64 {
    u64::from(format.block_copy_size(None).unwrap_or(0))
}

/// The estimate's bytes per pixel: it reads the history, the motion, the depth and the
/// previous depth, and writes the count and the link; with a dilation (`dilated`) it
/// writes the count before dilation instead, and its second pass reads that and writes
/// the dilated count.
#[must_use]
pub fn estimate_bytes(dilated: bool) -> StepBytes {
    let read = texel(HISTORY_FORMAT) + texel(MOTION_FORMAT) + 2 * texel(SCALAR_FORMAT);
    let written = texel(COUNT_FORMAT) + texel(LINK_FORMAT);
    if dilated {
        StepBytes {
            read: read + texel(COUNT_FORMAT),
            written: written + texel(COUNT_FORMAT),
        }
    } else {
        StepBytes { read, written }
    }
}

/// The update's bytes per pixel (AS: no control value, no CV history): it reads the
/// history, the monitored value, the count and the link, and writes the other history.
#[must_use]
pub fn update_bytes() -> StepBytes {
    StepBytes {
        read: texel(HISTORY_FORMAT)
            + texel(SCALAR_FORMAT)
            + texel(COUNT_FORMAT)
            + texel(LINK_FORMAT),
        written: texel(HISTORY_FORMAT),
    }
}

/// The one-pass form's bytes per pixel that the component adds to the renderer's dispatch
/// (AS, the counts not stored): it reads the history, the motion, the depth and the
/// previous depth, and writes the other history; nothing between the two calls.
#[must_use]
pub fn one_pass_bytes() -> StepBytes {
    StepBytes {
        read: texel(HISTORY_FORMAT) + texel(MOTION_FORMAT) + 2 * texel(SCALAR_FORMAT),
        written: texel(HISTORY_FORMAT),
    }
}
