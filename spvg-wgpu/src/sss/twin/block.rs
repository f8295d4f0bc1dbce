//! What the subsurface twin derives from the uniform block once per frame: the
//! component's decoded controller ([`Controller`]) and the Burley profiles, built from the
//! same `f32` values the shader reads.

use spvg::Error;
use spvg::burley::BurleyProfile;

use crate::adaptive::Controller;
use crate::sss::PassParams;

/// The subsurface pass's block on the CPU: the library block decoded by the component
/// ([`Controller::new`]), and the pass's own fields and profiles.
#[derive(Clone, Copy, Debug)]
pub struct BlockTwin {
    /// The uniform block.
    pub params: PassParams,
    /// The controller, online CV and texel encoding of the block's `spvg` member.
    pub controller: Controller,
    /// Per-channel profiles (albedo 1: it cancels in the ratio estimator).
    pub profiles: [BurleyProfile<f32>; 3],
    /// Sampling profile (the widest channel).
    pub sampling: BurleyProfile<f32>,
}

impl BlockTwin {
    /// Builds the core-crate objects from the uniform block.
    ///
    /// # Errors
    ///
    /// A field that the core crate rejects.
    pub fn new(p: &PassParams) -> Result<Self, Error> {
        Ok(Self {
            params: *p,
            controller: Controller::new(&p.spvg)?,
            profiles: [
                BurleyProfile::from_shape(1.0, p.d_r)?,
                BurleyProfile::from_shape(1.0, p.d_g)?,
                BurleyProfile::from_shape(1.0, p.d_b)?,
            ],
            sampling: BurleyProfile::from_shape(1.0, p.d_s)?,
        })
    }
}
