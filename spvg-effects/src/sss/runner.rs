//! One interface over the two implementations of the subsurface pass, and the backend's
//! constructor of it.

use spvg::burley::MaterialPreset;

use crate::device::Backend;
use crate::error::PassError;
use crate::sss::{
    FrameInputs, FrameOutput, Guide, History, Model, PassConfig, PassParams, SssPass, SssTwin,
};

/// The subsurface pass on either implementation, as [`Backend::pass`] resolves it.
#[derive(Debug)]
pub enum SssRunner {
    /// The wgpu pass.
    Gpu(Box<SssPass>),
    /// The CPU twin.
    Cpu(SssTwin),
}

impl SssRunner {
    /// The block of one frame under `config` ([`SssPass::frame_params`] /
    /// [`SssTwin::frame_params`]).
    ///
    /// # Errors
    ///
    /// As `frame_params`.
    pub fn frame_params(
        &mut self,
        config: &PassConfig,
        material: &MaterialPreset,
        frame: u32,
    ) -> Result<PassParams, PassError> {
        match self {
            Self::Gpu(g) => g.frame_params(config, material, frame),
            Self::Cpu(c) => c.frame_params(config, material, frame),
        }
    }

    /// Runs one frame.
    ///
    /// # Errors
    ///
    /// As [`SssPass::run_frame`] / [`SssTwin::run_frame`].
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        match self {
            Self::Gpu(g) => g.run_frame(params, inputs),
            Self::Cpu(c) => c.run_frame(params, inputs),
        }
    }

    /// Runs one frame with the renderer's TAA guide.
    ///
    /// # Errors
    ///
    /// As [`SssPass::run_frame_guided`] / [`SssTwin::run_frame_guided`].
    pub fn run_frame_guided(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        guide: Option<&mut Guide<'_>>,
    ) -> Result<FrameOutput, PassError> {
        match self {
            Self::Gpu(g) => g.run_frame_guided(params, inputs, guide),
            Self::Cpu(c) => c.run_frame_guided(params, inputs, guide),
        }
    }

    /// The history written by the last frame.
    ///
    /// # Errors
    ///
    /// A failed GPU readback.
    pub fn history(&self) -> Result<History, PassError> {
        match self {
            Self::Gpu(g) => g.history(),
            Self::Cpu(c) => Ok(c.history()),
        }
    }
}

impl Backend {
    /// A pass for `model` on this backend, after [`Backend::check_frame`].
    ///
    /// # Errors
    ///
    /// [`PassError::FrameTooLarge`] when the frame does not fit the device.
    pub fn pass(&self, model: Model, width: u32, height: u32) -> Result<SssRunner, PassError> {
        self.check_frame(width, height)?;
        Ok(match self {
            Self::Gpu(d) => SssRunner::Gpu(Box::new(SssPass::for_device(
                d.as_ref(),
                model,
                width,
                height,
            ))),
            Self::Cpu => SssRunner::Cpu(SssTwin::new(model, width, height)),
        })
    }
}
