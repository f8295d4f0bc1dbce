//! What the subsurface twin derives from a frame's uniform block: the Burley profiles,
//! built from the same `f32` values the shader reads, and the controller the block's
//! `spvg` member was built from.

use spvg::burley::BurleyProfile;
use spvg::texel::{Layout, TexelEncoding};
use spvg::{Error, SpvgConfig};

use crate::sss::PassParams;

/// The subsurface pass's block on the CPU: the block, the controller and texel encoding
/// its `spvg` member was built from, and the pass's profiles.
#[derive(Clone, Copy, Debug)]
pub struct BlockTwin {
    /// The uniform block.
    pub params: PassParams,
    /// The controller of the block's `spvg` member: the settings' controller with its
    /// target as the f16 texel stores it, as the component derives it.
    pub spvg: SpvgConfig<f32>,
    /// The history's texel encoding.
    pub enc: TexelEncoding,
    /// Per-channel profiles (albedo 1: it cancels in the ratio estimator).
    pub profiles: [BurleyProfile<f32>; 3],
    /// Sampling profile (the widest channel).
    pub sampling: BurleyProfile<f32>,
}

impl BlockTwin {
    /// The block `p` of a pass whose controller is `config` with the texel encoding `enc`
    /// (the component's [`encoding`](spvg_wgpu::adaptive::AdaptiveTwin::encoding)).
    ///
    /// # Errors
    ///
    /// A field that the core crate rejects.
    pub fn new(
        p: &PassParams,
        config: &SpvgConfig<f32>,
        enc: TexelEncoding,
    ) -> Result<Self, Error> {
        Ok(Self {
            params: *p,
            spvg: enc.storable_config(config, Layout::F16)?,
            enc,
            profiles: [
                BurleyProfile::from_shape(1.0, p.d_r)?,
                BurleyProfile::from_shape(1.0, p.d_g)?,
                BurleyProfile::from_shape(1.0, p.d_b)?,
            ],
            sampling: BurleyProfile::from_shape(1.0, p.d_s)?,
        })
    }
}
