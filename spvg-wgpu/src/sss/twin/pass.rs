//! The subsurface pass on the CPU: [`SssTwin`], the twin of
//! [`SssPass`](crate::sss::SssPass) frame by frame.

use half::f16;

use super::BlockTwin;
use super::entry::{sss_fixed, sss_gamma, sss_sample};
use crate::adaptive::{AdaptiveTwin, Control, EstimateData, Masks, UpdateData};
use crate::error::PassError;
use crate::sss::params::ComponentSetup;
use crate::sss::pass::region_mask;
use crate::sss::{FrameInputs, FrameOutput, Guide, History, Model, PassParams, Timer};

/// The CPU twin of [`SssPass`](crate::sss::SssPass): a fixed count runs the twin of
/// `sss_fixed`; AS, CCV and OCV run the adaptive component's twin ([`AdaptiveTwin`],
/// built at the first frame from its block, which owns the history) around the twins of
/// `sss_gamma` and `sss_sample`.
#[derive(Clone, Debug)]
pub struct SssTwin {
    model: Model,
    pixels: usize,
    /// Boxed: the twin holds two uniform blocks, and an `SssRunner` should stay small.
    component: Option<Box<(ComponentSetup, AdaptiveTwin)>>,
    /// The previous frame's depth and mask (the component's previous inputs).
    previous: Option<(Vec<f32>, Vec<u8>)>,
}

impl SssTwin {
    /// A CPU pass for `model` on frames of `pixels` pixels, with a cold (all-zero)
    /// history.
    #[must_use]
    pub fn new(model: Model, pixels: usize) -> Self {
        Self {
            model,
            pixels,
            component: None,
            previous: None,
        }
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
        let size_changed = self
            .component
            .as_ref()
            .is_some_and(|c| c.1.size() != [inputs.width, inputs.height]);
        if !inputs.is_consistent() || inputs.len() != self.pixels || size_changed {
            return Err(PassError::InputSize {
                expected: self.pixels,
                got: inputs.lighting.len(),
            });
        }
        let mut p = *params;
        p.width = inputs.width;
        p.height = inputs.height;
        let tw = BlockTwin::new(&p)?;
        let start = std::time::Instant::now();
        let (result, count) = match self.model {
            Model::Fixed(_) => sss_fixed(&tw, inputs),
            Model::As | Model::Ccv | Model::Ocv => {
                let setup = p.component_setup(self.model)?;
                if inputs.is_empty() {
                    (Vec::new(), Vec::new())
                } else {
                    let count_mask = region
                        .map_or_else(|| inputs.mask.clone(), |r| region_mask(&inputs.mask, r));
                    self.adaptive_frame(&tw, &setup, inputs, count_mask, guide)?
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
        setup: &ComponentSetup,
        inputs: &FrameInputs,
        count_mask: Vec<u8>,
        guide: Option<&mut Guide<'_>>,
    ) -> Result<(Vec<[f16; 4]>, Vec<u32>), PassError> {
        let component = match self.component.as_deref_mut() {
            Some((s, a)) if s.config == setup.config && s.control == setup.control => a,
            Some(_) => return Err(PassError::ControllerChanged),
            None => {
                let a =
                    AdaptiveTwin::new(setup.config, setup.control, inputs.width, inputs.height)?;
                let enc = a.encoding();
                let ocv = matches!(setup.control, Control::Ocv(_));
                if enc.variance_scale() != tw.controller.enc.variance_scale()
                    || (ocv && enc.cv_scale() != tw.controller.enc.cv_scale())
                {
                    return Err(PassError::ControllerChanged);
                }
                &mut self.component.insert(Box::new((*setup, a))).1
            }
        };
        component.set_target_variance(setup.target)?;
        let gamma = sss_gamma(tw, inputs);
        let motion = vec![[0.0_f32; 2]; inputs.len()];
        // Before the first frame the history is cold: the previous inputs do not matter.
        let (prev_depth, prev_mask) = self
            .previous
            .as_ref()
            .map_or((&inputs.depth, &count_mask), |(d, m)| (d, m));
        let count = component
            .estimate(&EstimateData {
                motion: &motion,
                depth: &inputs.depth,
                previous_depth: prev_depth,
                reprojected_depth: None,
                masks: Some(Masks {
                    current: &count_mask,
                    previous: prev_mask,
                }),
                gamma: Some(&gamma),
            })?
            .to_vec();
        let sampled = sss_sample(tw, inputs, &count);
        let control = component
            .control()
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
        component.update(&UpdateData {
            value: &sampled.value,
            control,
            guide: guide.as_deref(),
        })?;
        self.previous = Some((inputs.depth.clone(), count_mask));
        Ok((sampled.result, count))
    }

    /// The history written by the last frame (a copy of the component's texels; zero
    /// before the first frame, empty for a fixed count).
    #[must_use]
    pub fn history(&self) -> History {
        let zero = || vec![[f16::ZERO; 4]; self.pixels];
        match (self.component.as_deref(), self.model) {
            (_, Model::Fixed(_)) => History::default(),
            (Some((_, a)), _) => History {
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
