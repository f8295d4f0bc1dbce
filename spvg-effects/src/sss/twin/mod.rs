//! The CPU twin of the subsurface pass: the test oracle and the `cpu` backend.
//!
//! [`SssTwin`] runs a frame as [`SssPass`](super::SssPass) records it; [`BlockTwin`] is
//! what it derives from a frame's uniform block; `entry` has one function per entry point
//! of `sss/shaders/sss.wgsl` (each calling the core crate and the crate's
//! `unit_dir` of `common/direction.wgsl`, the one function of the pass's WGSL the core
//! crate does not have), and [`reduce_demand`] the entry point of
//! `sss/shaders/reduce.wgsl`; [`sep_horizontal`] and [`sep_vertical`] those of
//! `sss/shaders/separable.wgsl`, [`SeparableTwin`] the two in a row.

mod block;
mod entry;
mod pass;
mod reduce;
mod separable;

pub use block::BlockTwin;
pub use entry::{
    Mip, PixelEstimate, SampleOutput, estimate_pixel, filtered_mip_index, pixel_gamma_s, sss_fixed,
    sss_gamma, sss_sample,
};
pub use pass::SssTwin;
pub use reduce::{REDUCE_TILE, reduce_demand};
pub(crate) use separable::check_sizes;
pub use separable::{HybridSources, SeparableTwin, sep_horizontal, sep_vertical};

/// WGSL twin: `spvg_to_f16` (nearest) on every channel, what every `rgba16float` store of
/// the pass receives (`spvg::texel::to_f16`: NaN to 0, clamped to the f16 range, rounded
/// to nearest even).
fn to_texel(t: [f32; 4]) -> [half::f16; 4] {
    t.map(|x| spvg::texel::to_f16(x, spvg::texel::Rounding::Nearest))
}
