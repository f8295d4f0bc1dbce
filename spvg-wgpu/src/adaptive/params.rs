//! The component's own uniform block and its flags (the controller's block is built in
//! `settings.rs`).

use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg_shaders::{Control, StoreRounding};

use super::AdaptiveError;

/// The OCV model as the component runs it (f16 inputs, whatever `control` was built
/// with, because the CV history is stored in f16; see [`Ocv::with_f16_inputs`]), if
/// `control` is OCV.
pub(crate) fn component_ocv(control: &Control) -> Option<Ocv<f32>> {
    match control {
        Control::Ocv(o) => Some(o.with_f16_inputs(true)),
        Control::As | Control::Ccv => None,
    }
}

/// The component's own uniform block (binding 1 of both steps).
///
/// WGSL twin: `struct AdaptiveParams` in `shaders/adaptive/adaptive.wgsl`; same field order
/// and types.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct AdaptiveParams {
    /// Frame width in pixels.
    pub(crate) width: u32,
    /// Frame height in pixels.
    pub(crate) height: u32,
    /// Relative depth tolerance of the reprojection (`spvg::reproject::Reprojection`).
    pub(crate) depth_tolerance: f32,
    /// Bit 0 ([`FLAG_MASKS`]): masks bound; bit 1 ([`FLAG_GAMMA`]): distant-energy ratio
    /// bound; bit 2 ([`FLAG_CONTROL`]): the monitored value is `fbar - alpha G` with the
    /// constant `alpha` of CCV; bit 3 ([`FLAG_BORDER_PRIOR`]): pixels entering the frame
    /// estimate from a texel near the edge they crossed (`spvg::reproject::border_texel`);
    /// bit 4 ([`FLAG_FOOTPRINT`]): the footprint search
    /// (`spvg::reproject::footprint_texel` where the nearest texel fails); bit 5
    /// ([`FLAG_BORDER_MAXIMUM`]): pixels entering under the border prior take `beta_max`
    /// (`spvg::reproject::BorderCount::Maximum`); bit 6 ([`FLAG_REPROJECTED_DEPTH`]): the
    /// reprojected depth is bound and the depth test compares it instead of the depth; bit
    /// 7 ([`FLAG_NEIGHBOUR_PRIOR`]): the dilation's depth-aware neighbour prior; bit 8
    /// ([`FLAG_GUIDE`]): the update's TAA guide is bound; bit 9 ([`FLAG_STORE_COUNTS`]): the
    /// one-pass form stores the counts; bit 11 ([`FLAG_MOMENT`]): the update's second moment is
    /// bound; bit 10 ([`FLAG_COUNT_ORDER`]): the one-pass form's
    /// count order.
    pub(crate) flags: u32,
    /// Radius of the count dilation (`spvg::dilation`); 0 = off.
    pub(crate) dilation: u32,
    /// Padding to the 16-byte multiple of a WGSL uniform struct; zero.
    pub(crate) pad: [u32; 3],
}

const _: () = assert!(
    size_of::<AdaptiveParams>() == 32,
    "AdaptiveParams must match the 32-byte WGSL struct"
);

/// [`AdaptiveParams::flags`] bit: the mask textures are bound.
pub(crate) const FLAG_MASKS: u32 = 1;
/// [`AdaptiveParams::flags`] bit: the distant-energy ratio texture is bound.
pub(crate) const FLAG_GAMMA: u32 = 2;
/// [`AdaptiveParams::flags`] bit: the update reads a control value (CCV).
pub(crate) const FLAG_CONTROL: u32 = 4;
/// [`AdaptiveParams::flags`] bit: the border prior of `spvg::reproject` is on
/// ([`spvg::reproject::Reprojection::border_prior`]).
pub(crate) const FLAG_BORDER_PRIOR: u32 = 8;
/// [`AdaptiveParams::flags`] bit: the footprint search of `spvg::reproject` is on
/// ([`spvg::reproject::Reprojection::footprint_search`]).
pub(crate) const FLAG_FOOTPRINT: u32 = 16;
/// [`AdaptiveParams::flags`] bit: pixels entering the frame under the border prior take
/// `beta_max` ([`spvg::reproject::BorderCount::Maximum`]).
pub(crate) const FLAG_BORDER_MAXIMUM: u32 = 32;
/// [`AdaptiveParams::flags`] bit: the reprojected depth texture is bound
/// ([`EstimateInputs::reprojected_depth`](super::EstimateInputs::reprojected_depth)).
pub(crate) const FLAG_REPROJECTED_DEPTH: u32 = 64;
/// [`AdaptiveParams::flags`] bit: the update's TAA guide is bound
/// ([`UpdateInputs::guide`](super::UpdateInputs::guide)).
pub(crate) const FLAG_GUIDE: u32 = 256;

/// [`AdaptiveParams::flags`] bit: the one-pass form stores the counts in the count
/// texture ([`AdaptivePass::set_one_pass_counts`](super::AdaptivePass::set_one_pass_counts)).
pub(crate) const FLAG_STORE_COUNTS: u32 = 512;

/// [`AdaptiveParams::flags`] bit: the one-pass form's invocations take the pixels of their
/// tile by rank of count
/// ([`AdaptivePass::set_one_pass_order`](super::AdaptivePass::set_one_pass_order)).
pub(crate) const FLAG_COUNT_ORDER: u32 = 1024;

/// [`AdaptiveParams::flags`] bit: the update's second moment is bound
/// ([`AdaptivePass::record_update_with_moment`](super::AdaptivePass::record_update_with_moment),
/// docs/algorithms.md §8.8).
pub(crate) const FLAG_MOMENT: u32 = 2048;

/// [`AdaptiveParams::flags`] bit: the depth-aware neighbour prior of the dilation is on
/// ([`AdaptiveSettings::neighbour_prior`](super::AdaptiveSettings::neighbour_prior), applied
/// by [`AdaptivePass::set_settings`](super::AdaptivePass::set_settings)).
pub(crate) const FLAG_NEIGHBOUR_PRIOR: u32 = 128;

/// The number of uniform blocks: one per combination of the optional inputs.
pub(crate) const PARAMS_BLOCKS: usize = 32;

/// The index of the uniform block of a step with the optional inputs of `flags` bound
/// (masks, gamma, reprojected depth for the estimate; the guide and the second moment for
/// the update): one
/// block per combination, [`PARAMS_BLOCKS`] in all.
pub(crate) fn params_index(flags: u32) -> usize {
    let bit = |flag: u32, k: usize| if flags & flag != 0 { k } else { 0 };
    (flags & (FLAG_MASKS | FLAG_GAMMA)) as usize
        | bit(FLAG_REPROJECTED_DEPTH, 4)
        | bit(FLAG_GUIDE, 8)
        | bit(FLAG_MOMENT, 16)
}

/// The optional-input flags of uniform block `k` ([`params_index`] inverted).
pub(crate) fn params_flags(k: usize) -> u32 {
    let bit = |b: usize, flag: u32| if k & b != 0 { flag } else { 0 };
    (k as u32 & (FLAG_MASKS | FLAG_GAMMA))
        | bit(4, FLAG_REPROJECTED_DEPTH)
        | bit(8, FLAG_GUIDE)
        | bit(16, FLAG_MOMENT)
}

/// How the component rounds every `f16` history store: to nearest, ties to even
/// (`spvg::texel::Rounding::Nearest`), explicitly in the shader (`spvg_to_f16`), not by the
/// driver's store conversion (lavapipe's truncates). Public as
/// [`AdaptivePass::STORE_ROUNDING`](super::AdaptivePass::STORE_ROUNDING).
pub(crate) const STORE_ROUNDING: StoreRounding = StoreRounding::Nearest;

/// The configuration with target `sigma0_sq`, for `set_target_variance` of the component
/// and its twin (a target the controller rejects is an error).
pub(crate) fn retargeted(
    config: &SpvgConfig<f32>,
    sigma0_sq: f32,
) -> Result<SpvgConfig<f32>, AdaptiveError> {
    Ok(config.to_builder().target_variance(sigma0_sq).build()?)
}
