//! The component's configuration: the control model, the uniform blocks, the controller
//! block built from the core crate's configuration.

use spvg::SpvgConfig;
use spvg::controller::CountPolicy;
use spvg::cv::Ocv;
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Params, Storage, StoreRounding};

use super::AdaptiveError;
use crate::params::PassParams;

/// The control model of the monitored value (docs/algorithms.md §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Plain adaptive sampling: the history monitors the value itself (`S = fbar`). One
    /// history texel; the update needs no control value.
    As,
    /// Constant control variate: `S = fbar - G`. One history texel.
    Ccv,
    /// Online control variate: `S = fbar - alpha G` with a per-pixel `alpha` from a second
    /// history texel (the CV history). The model is used with
    /// [`Ocv::with_f16_inputs`]`(true)` whatever it was built with, because the CV history
    /// is stored in f16 (see that method for why).
    Ocv(Ocv<f32>),
}

impl Control {
    /// Short name (`as`, `ccv`, `ocv`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::As => "as",
            Self::Ccv => "ccv",
            Self::Ocv(_) => "ocv",
        }
    }

    /// Whether the update reads a control value `G`.
    #[must_use]
    pub fn needs_control(&self) -> bool {
        !matches!(self, Self::As)
    }

    /// Bytes of history per pixel kept between frames (8 per RGBA16F texel; the ping-pong
    /// copy not counted).
    #[must_use]
    pub fn history_bytes_per_pixel(&self) -> u32 {
        match self {
            Self::As | Self::Ccv => 8,
            Self::Ocv(_) => 16,
        }
    }

    /// The OCV model as the component runs it (f16 inputs), if this is OCV.
    #[must_use]
    pub(crate) fn ocv(&self) -> Option<Ocv<f32>> {
        match self {
            Self::Ocv(o) => Some(o.with_f16_inputs(true)),
            _ => None,
        }
    }
}

/// The component's own uniform block (binding 1 of both steps).
///
/// WGSL twin: `struct AdaptiveParams` in `shaders/adaptive/adaptive.wgsl`; same field order
/// and types.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AdaptiveParams {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Relative depth tolerance of the reprojection (`spvg::reproject::Reprojection`).
    pub depth_tolerance: f32,
    /// Bit 0 ([`FLAG_MASKS`]): masks bound; bit 1 ([`FLAG_GAMMA`]): distant-energy ratio
    /// bound; bit 2 ([`FLAG_CONTROL`]): the monitored value is `fbar - alpha G` with the
    /// constant `alpha` of CCV; bit 3 ([`FLAG_BORDER_PRIOR`]): pixels entering the frame
    /// estimate from a texel near the edge they crossed (`spvg::reproject::border_texel`);
    /// bit 4 ([`FLAG_FOOTPRINT`]): the footprint search
    /// (`spvg::reproject::footprint_texel` where the nearest texel fails); bit 5
    /// ([`FLAG_BORDER_MAXIMUM`]): pixels entering under the border prior take `beta_max`
    /// (`spvg::reproject::BorderCount::Maximum`).
    pub flags: u32,
    /// Radius of the count dilation (`spvg::dilation`); 0 = off.
    pub dilation: u32,
    /// Padding to the 16-byte multiple of a WGSL uniform struct; zero.
    pub pad: [u32; 3],
}

const _: () = assert!(
    size_of::<AdaptiveParams>() == 32,
    "AdaptiveParams must match the 32-byte WGSL struct"
);

/// [`AdaptiveParams::flags`] bit: the mask textures are bound.
pub const FLAG_MASKS: u32 = 1;
/// [`AdaptiveParams::flags`] bit: the distant-energy ratio texture is bound.
pub const FLAG_GAMMA: u32 = 2;
/// [`AdaptiveParams::flags`] bit: the update reads a control value (CCV).
pub const FLAG_CONTROL: u32 = 4;
/// [`AdaptiveParams::flags`] bit: the border prior of `spvg::reproject` is on
/// ([`spvg::reproject::Reprojection::border_prior`]).
pub const FLAG_BORDER_PRIOR: u32 = 8;
/// [`AdaptiveParams::flags`] bit: the footprint search of `spvg::reproject` is on
/// ([`spvg::reproject::Reprojection::footprint_search`]).
pub const FLAG_FOOTPRINT: u32 = 16;
/// [`AdaptiveParams::flags`] bit: pixels entering the frame under the border prior take
/// `beta_max` ([`spvg::reproject::BorderCount::Maximum`]).
pub const FLAG_BORDER_MAXIMUM: u32 = 32;

/// The controller's uniform block (binding 0, `spvg_Params` of the spvg-shaders library)
/// for `config` and `control`, inside the demo pass's [`PassParams`] so the CPU twin
/// ([`crate::twin::Twin`]) reads the same numbers; the subsurface fields are unused (the
/// Burley shapes are 1 so the twin's profile check passes). History in f16 texels, rounded
/// to nearest, the variance stored relative to the power of two nearest `encoding_target`
/// (the configuration's target at construction; kept when the target moves).
pub(crate) fn controller_block(
    config: &SpvgConfig<f32>,
    control: &Control,
    encoding_target: f32,
) -> Result<PassParams, AdaptiveError> {
    if config.policy() != CountPolicy::Spvg {
        return Err(AdaptiveError::UnsupportedPolicy(config.policy()));
    }
    let enc = TexelEncoding::new(encoding_target)?;
    let (encoding, model) = match control.ocv() {
        Some(o) => (enc.for_ocv(&o)?, spvg_shaders::Control::Ocv(o)),
        None if matches!(control, Control::Ccv) => (enc, spvg_shaders::Control::Ccv),
        None => (enc, spvg_shaders::Control::As),
    };
    let storage = Storage {
        encoding,
        layout: Layout::F16,
        rounding: StoreRounding::Nearest,
    };
    Ok(PassParams {
        spvg: Params::new(config, model, &storage),
        d_r: 1.0,
        d_g: 1.0,
        d_b: 1.0,
        d_s: 1.0,
        inv_d_r: 1.0,
        inv_d_g: 1.0,
        inv_d_b: 1.0,
        inv_d_s: 1.0,
        ..bytemuck::Zeroable::zeroed()
    })
}

/// The configuration with target `sigma0_sq`, for `set_target_variance` of the component
/// and its twin: refused between a frame's estimate and its update (`estimated`) and for a
/// target the controller rejects.
pub(crate) fn retargeted(
    config: &SpvgConfig<f32>,
    estimated: bool,
    sigma0_sq: f32,
) -> Result<SpvgConfig<f32>, AdaptiveError> {
    if estimated {
        return Err(AdaptiveError::TargetBetweenSteps);
    }
    Ok(config.to_builder().target_variance(sigma0_sq).build()?)
}
