//! The subsurface pass on the CPU: [`SssTwin`], the twin of
//! [`SssPass`](crate::sss::SssPass) frame by frame.

use half::f16;
use spvg::SpvgConfig;
use spvg::burley::MaterialPreset;
use spvg::texel::TexelEncoding;
use spvg_wgpu::adaptive::{AdaptiveTwin, EstimateData, Masks, UpdateData};

use super::BlockTwin;
use super::entry::{sss_fixed, sss_gamma, sss_sample};
use crate::error::PassError;
use crate::sss::pass::region_mask;
use crate::sss::{FrameInputs, FrameOutput, Guide, History, Model, PassConfig, PassParams, Timer};

/// The CPU twin of [`SssPass`](crate::sss::SssPass): a fixed count runs the twin of
/// `sss_fixed`; AS, CCV and OCV run the adaptive component's twin ([`AdaptiveTwin`],
/// built by the first [`frame_params`](Self::frame_params), which owns the history)
/// around the twins of `sss_gamma` and `sss_sample`.
#[derive(Clone, Debug)]
pub struct SssTwin {
    model: Model,
    size: [u32; 2],
    /// Boxed: the twin holds its uniform block, and an `SssRunner` should stay small.
    component: Option<Box<AdaptiveTwin>>,
    /// The controller and texel encoding of the last `frame_params`' block, and the
    /// block.
    controller: Option<Box<(SpvgConfig<f32>, TexelEncoding, spvg_shaders::Params)>>,
    /// The previous frame's depth and mask (the component's previous inputs).
    previous: Option<(Vec<f32>, Vec<u8>)>,
}

impl SssTwin {
    /// A CPU pass for `model` on `width x height` frames, with a cold (all-zero) history.
    #[must_use]
    pub fn new(model: Model, width: u32, height: u32) -> Self {
        Self {
            model,
            size: [width, height],
            component: None,
            controller: None,
            previous: None,
        }
    }

    /// The adaptive component's twin, once the first
    /// [`frame_params`](Self::frame_params) of an adaptive model has built it (the twin of
    /// [`SssPass::adaptive`](crate::sss::SssPass::adaptive)).
    #[must_use]
    pub fn adaptive(&self) -> Option<&AdaptiveTwin> {
        self.component.as_deref()
    }

    /// The controller and texel encoding of the last
    /// [`frame_params`](Self::frame_params) (`None` before the first).
    pub(crate) fn block_controller(&self) -> Option<(SpvgConfig<f32>, TexelEncoding)> {
        self.controller.as_deref().map(|&(c, e, _)| (c, e))
    }

    fn pixels(&self) -> usize {
        self.size[0] as usize * self.size[1] as usize
    }

    /// The twin of [`SssPass::frame_params`](crate::sss::SssPass::frame_params).
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
        let (block, enc) = match self.model {
            Model::Fixed(_) => (
                config.fixed_block()?,
                TexelEncoding::new(config.spvg.target_variance())?,
            ),
            Model::As | Model::Ccv | Model::Ocv => {
                let settings = config.settings(self.model);
                let [w, h] = self.size;
                let component = match &mut self.component {
                    Some(a) => {
                        a.set_settings(settings)?;
                        a
                    }
                    None => self
                        .component
                        .insert(Box::new(AdaptiveTwin::new(settings, w, h)?)),
                };
                (*component.params_block(), component.encoding())
            }
        };
        self.controller = Some(Box::new((config.spvg, enc, block)));
        config.params(self.model, material, self.size, frame, block)
    }

    /// Runs one frame through the twins of the model's entry points (and of the adaptive
    /// component's steps), as [`SssPass::run_frame`](crate::sss::SssPass::run_frame)
    /// records them.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inconsistent inputs or another frame size than
    /// `pixels` (or than the first frame's), else as
    /// [`SssPass::run_frame`](crate::sss::SssPass::run_frame).
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        self.run_frame_with(params, inputs, None, None)
    }

    /// Twin of [`SssPass::run_frame_in`](crate::sss::SssPass::run_frame_in): the count
    /// controlled under the subsurface mask times `region`.
    ///
    /// # Errors
    ///
    /// As [`SssTwin::run_frame`]; [`PassError::InputSize`] for a region of another size,
    /// [`PassError::Param`] for a region with the fixed count.
    pub fn run_frame_in(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
    ) -> Result<FrameOutput, PassError> {
        self.run_frame_with(params, inputs, region, None)
    }

    /// The twin of
    /// [`SssPass::run_frame_guided`](crate::sss::SssPass::run_frame_guided): `guide` is
    /// called between the sampling and the update.
    ///
    /// # Errors
    ///
    /// As [`run_frame`](Self::run_frame); [`PassError::InputSize`] for a guide that is not
    /// one value per pixel.
    pub fn run_frame_guided(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        guide: Option<&mut Guide<'_>>,
    ) -> Result<FrameOutput, PassError> {
        self.run_frame_with(params, inputs, None, guide)
    }

    /// One frame with an optional sampling region and an optional TAA guide.
    fn run_frame_with(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
        guide: Option<&mut Guide<'_>>,
    ) -> Result<FrameOutput, PassError> {
        if region.is_some_and(|r| r.len() != inputs.len()) {
            return Err(PassError::InputSize {
                expected: inputs.len(),
                got: region.map_or(0, <[u8]>::len),
            });
        }
        if region.is_some() && matches!(self.model, Model::Fixed(_)) {
            return Err(PassError::Param(spvg::Error::InconsistentParameters {
                names: "model, region",
                expected: "a sampling region needs an adaptive model",
            }));
        }
        let size_changed = [inputs.width, inputs.height] != self.size;
        if !inputs.is_consistent() || inputs.len() != self.pixels() || size_changed {
            return Err(PassError::InputSize {
                expected: self.pixels(),
                got: inputs.lighting.len(),
            });
        }
        let mut p = *params;
        p.width = inputs.width;
        p.height = inputs.height;
        let (config, enc) = match self.controller.as_deref() {
            Some((config, enc, block)) if *block == p.spvg => (*config, *enc),
            _ => {
                return Err(PassError::Param(spvg::Error::InconsistentParameters {
                    names: "params.spvg",
                    expected: "the block of this twin's frame_params (its component's controller)",
                }));
            }
        };
        let tw = BlockTwin::new(&p, &config, enc)?;
        let start = std::time::Instant::now();
        let (result, count) = match self.model {
            Model::Fixed(_) => sss_fixed(&tw, inputs),
            Model::As | Model::Ccv | Model::Ocv => {
                if inputs.is_empty() {
                    (Vec::new(), Vec::new())
                } else {
                    let count_mask = region
                        .map_or_else(|| inputs.mask.clone(), |r| region_mask(&inputs.mask, r));
                    self.adaptive_frame(&tw, inputs, count_mask, guide)?
                }
            }
        };
        Ok(FrameOutput {
            result,
            count,
            time_ms: start.elapsed().as_secs_f64() * 1e3,
            timer: Timer::WallClock,
        })
    }

    /// `sss_gamma` -> estimate -> `sss_sample` -> update, on the twins.
    fn adaptive_frame(
        &mut self,
        tw: &BlockTwin,
        inputs: &FrameInputs,
        count_mask: Vec<u8>,
        guide: Option<&mut Guide<'_>>,
    ) -> Result<(Vec<[f16; 4]>, Vec<u32>), PassError> {
        let Some(component) = self.component.as_deref_mut() else {
            return Err(PassError::Param(spvg::Error::InconsistentParameters {
                names: "params",
                expected: "a block from this twin's frame_params",
            }));
        };
        let gamma = sss_gamma(tw, inputs);
        let motion = vec![[0.0_f32; 2]; inputs.len()];
        // Before the first frame the history is cold: the previous inputs do not matter.
        let (prev_depth, prev_mask) = self
            .previous
            .as_ref()
            .map_or((&inputs.depth, &count_mask), |(d, m)| (d, m));
        let count = component
            .estimate(
                &EstimateData::new(&motion, &inputs.depth, prev_depth)
                    .with_masks(Some(Masks {
                        current: &count_mask,
                        previous: prev_mask,
                    }))
                    .with_gamma(Some(&gamma)),
            )?
            .to_vec();
        let sampled = sss_sample(tw, inputs, &count);
        let control = component
            .settings()
            .control
            .needs_control()
            .then_some(sampled.control.as_slice());
        let guide = guide.map(|g| g(&sampled.result, &sampled.value));
        if let Some(g) = &guide
            && g.len() != inputs.len()
        {
            return Err(PassError::InputSize {
                expected: inputs.len(),
                got: g.len(),
            });
        }
        component.update(
            &UpdateData::new(&sampled.value)
                .with_control(control)
                .with_guide(guide.as_deref()),
        )?;
        self.previous = Some((inputs.depth.clone(), count_mask));
        Ok((sampled.result, count))
    }

    /// The history written by the last frame (a copy of the component's texels; zero
    /// before the first frame, empty for a fixed count).
    #[must_use]
    pub fn history(&self) -> History {
        let zero = || vec![[f16::ZERO; 4]; self.pixels()];
        match (self.component.as_deref(), self.model) {
            (_, Model::Fixed(_)) => History::default(),
            (Some(a), _) => History {
                h: a.history().to_vec(),
                j: a.cv_history().map(<[_]>::to_vec).unwrap_or_default(),
            },
            (None, Model::Ocv) => History {
                h: zero(),
                j: zero(),
            },
            (None, _) => History {
                h: zero(),
                j: Vec::new(),
            },
        }
    }
}
