//! The AO renderer on the CPU: the twin of [`AoGpu`](super::AoGpu), frame by frame.

use spvg::SpvgConfig;
use spvg::reproject::Reprojection;

use super::gpu::{AoFrame, AoMode};
use super::{AoParams, twin};
use crate::adaptive::{AdaptiveError, AdaptiveTwin, Control, EstimateData, UpdateData};

/// The CPU twin of [`AoGpu`](super::AoGpu): [`twin::gbuffer`], the component's
/// [`AdaptiveTwin`] (or a fixed count), [`twin::sample`].
#[derive(Clone, Debug)]
pub struct AoCpu {
    mode: AoMode,
    adaptive: Option<AdaptiveTwin>,
    previous_depth: Option<Vec<f32>>,
}

impl AoCpu {
    /// The twin of [`AoGpu::new`](super::AoGpu::new).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::new`].
    pub fn new(
        width: u32,
        height: u32,
        mode: AoMode,
        config: SpvgConfig<f32>,
        reprojection: Reprojection<f32>,
    ) -> Result<Self, AdaptiveError> {
        let adaptive = match mode {
            AoMode::Fixed(_) => None,
            AoMode::Adaptive | AoMode::Identity => {
                let mut a = AdaptiveTwin::new(config, Control::As, width, height)?;
                a.set_reprojection(reprojection);
                Some(a)
            }
        };
        Ok(Self {
            mode,
            adaptive,
            previous_depth: None,
        })
    }

    /// The twin of [`AoGpu::set_count_dilation`](super::AoGpu::set_count_dilation).
    ///
    /// # Errors
    ///
    /// As `AdaptivePass::set_count_dilation`.
    pub fn set_count_dilation(&mut self, radius: u32) -> Result<(), AdaptiveError> {
        spvg::dilation::check_radius(radius)?;
        match &mut self.adaptive {
            Some(a) => a.set_count_dilation(radius),
            None => Ok(()),
        }
    }

    /// The twin of [`AoGpu::run_frame`](super::AoGpu::run_frame).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::estimate`] (frame size of `params` not the renderer's).
    pub fn run_frame(&mut self, params: &AoParams) -> Result<AoFrame, AdaptiveError> {
        let g = twin::gbuffer(params);
        let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
        let count = match (&mut self.adaptive, self.mode) {
            (Some(a), mode) => {
                let identity = mode == AoMode::Identity;
                let motion: Vec<[f32; 2]> = if identity {
                    vec![[0.0; 2]; g.len()]
                } else {
                    g.iter().map(|x| x.motion).collect()
                };
                // Frame 0 on the GPU reads a zeroed previous depth.
                let zero = vec![0.0; g.len()];
                let previous = if identity {
                    &depth
                } else {
                    self.previous_depth.as_ref().unwrap_or(&zero)
                };
                a.estimate(&EstimateData {
                    motion: &motion,
                    depth: &depth,
                    previous_depth: previous,
                    masks: None,
                    gamma: None,
                })?
                .to_vec()
            }
            (None, AoMode::Fixed(n)) => vec![n; g.len()],
            (None, _) => vec![0; g.len()],
        };
        let value = twin::sample(params, &g, &count);
        if let Some(a) = &mut self.adaptive {
            a.update(&UpdateData {
                value: &value,
                control: None,
            })?;
        }
        self.previous_depth = Some(depth);
        Ok(AoFrame { count, value })
    }
}
