//! The hybrid, importance-guided pass (docs/algorithms.md §5.1; the dissertation's
//! Fig. 5.9): Monte Carlo subsurface scattering with the adaptive count where the caller
//! tags the frame (its focus, a main character), the separable filter everywhere else, in
//! one frame.
//!
//! - Setup: the caller's region becomes a technique id per pixel ([`technique_ids`]: 1 =
//!   AFIS), optionally widened to whole 8 x 8 tiles so a workgroup samples all or nothing.
//!   The 8 x 8 tiles holding a tagged pixel become a tile list, rebuilt and uploaded only
//!   when the tags change (they are the caller's, known on the CPU).
//! - P1: the subsurface pass ([`SssPass`]) with its adaptive model controls the count under
//!   the subsurface mask times the tags: untagged pixels take 0 samples and keep no
//!   history; tagged ones sample the lighting of the whole surface (so the estimate at the
//!   region's edge is not cut off at it). Its four steps (the distant ratio, the
//!   component's estimate, the sampling, the component's update) run over the listed
//!   tiles only, so the work follows the tags; for two frames after the tags change they
//!   run over the whole frame, which writes the untagged pixels' zero counts and history
//!   into both halves of the history's ping-pong pair.
//! - P2 and P3: the separable passes ([`SeparablePass`]) with the P1 result as their input
//!   at the tagged pixels (written into their input texture on the device over the tagged
//!   tiles, in the same submit, so their taps read one texture): a separable pixel whose
//!   kernel reaches into the region reads light of the Monte Carlo brightness, so no dim
//!   border appears. They run over the 8 x 8 tiles holding an untagged pixel only (a
//!   second list, built with the first): the step that writes the P1 result into their
//!   input also writes it into the first pass's output, which the vertical taps read, and
//!   the second pass writes into P1's result texture. At a tagged pixel of a listed tile
//!   each pass is a copy; a wholly tagged tile costs neither. They read P1's lighting
//!   (mip 0, into which the AFIS result is written after P1's sampling), depth and mask
//!   textures: nothing is uploaded twice.
//! - P4: the tagged pixels keep the P1 result unchanged (it stays in its texture, which
//!   the frame reads back), and P1's update has already written the history of those
//!   pixels.
//!
//! The whole frame is one command buffer and one submit.
//!
//! [`HybridTwin`] is the same on the CPU twins.

use spvg::burley::MaterialPreset;
use spvg_wgpu::util::read_texture;

use super::separable_pass::SharedTextures;
use super::twin::{HybridSources, SeparableTwin};
use super::{
    FrameInputs, FrameOutput, History, Model, PassConfig, PassParams, SeparableParams,
    SeparablePass, SssPass, SssTwin, Timer,
};
use crate::error::PassError;

/// Technique id of a pixel that the hybrid pass samples (AFIS); 0 is separable.
pub const TECHNIQUE_AFIS: u8 = 1;

/// The technique id per pixel from the caller's region (nonzero = focus): `None` tags the
/// region's pixels themselves, `Some(t)` every pixel of each `t x t` tile that holds a
/// region pixel (a tile of the passes' 8 x 8 workgroups then samples all or nothing).
///
/// # Errors
///
/// [`PassError::InputSize`] when `region` is not `width * height` long;
/// [`PassError::Param`] naming `tile` when it is 0.
///
/// # Examples
///
/// ```
/// use spvg_effects::sss::technique_ids;
/// let mut region = vec![0_u8; 16 * 8];
/// region[3 * 16 + 9] = 1;
/// let per_pixel = technique_ids(&region, 16, 8, None).unwrap();
/// assert_eq!(per_pixel.iter().filter(|&&t| t == 1).count(), 1);
/// let per_tile = technique_ids(&region, 16, 8, Some(8)).unwrap();
/// // The pixel's tile is the right half: 64 pixels.
/// assert_eq!(per_tile.iter().filter(|&&t| t == 1).count(), 64);
/// assert_eq!(per_tile[15], 1);
/// assert_eq!(per_tile[0], 0);
/// ```
pub fn technique_ids(
    region: &[u8],
    width: u32,
    height: u32,
    tile: Option<u32>,
) -> Result<Vec<u8>, PassError> {
    let (w, h) = (width as usize, height as usize);
    if region.len() != w * h {
        return Err(PassError::InputSize {
            expected: w * h,
            got: region.len(),
        });
    }
    let tag = |r: u8| if r != 0 { TECHNIQUE_AFIS } else { 0 };
    let Some(t) = tile else {
        return Ok(region.iter().map(|&r| tag(r)).collect());
    };
    if t == 0 {
        return Err(PassError::Param(spvg::Error::invalid(
            "tile",
            0.0,
            "must be at least 1",
        )));
    }
    let t = t as usize;
    let (tw, th) = (w.div_ceil(t), h.div_ceil(t));
    let mut tiles = vec![0_u8; tw * th];
    for (i, &r) in region.iter().enumerate() {
        if r != 0 {
            tiles[(i / w / t) * tw + (i % w) / t] = TECHNIQUE_AFIS;
        }
    }
    Ok((0..w * h)
        .map(|i| tiles[(i / w / t) * tw + (i % w) / t])
        .collect())
}

/// One hybrid frame's output: the final image and counts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HybridOutput {
    /// The final result and the counts (0 outside the tags); `time_ms` is the wall time of
    /// the frame's single submit (P1 to P4), or with [`HybridPass::run_frame_per_pass`]
    /// the sum of its steps.
    pub frame: FrameOutput,
}

/// The wall time of each step of a hybrid frame ([`HybridPass::run_frame_per_pass`]), in
/// ms: each step submitted and waited for on its own, so each pays a submit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HybridTimes {
    /// P1: `sss_gamma` and the component's estimate.
    pub estimate_ms: f64,
    /// P1: `sss_sample`.
    pub sampling_ms: f64,
    /// P1: the component's update.
    pub update_ms: f64,
    /// P2's input: `sep_compose` over P1's tiles (the AFIS result copied into the
    /// separable passes' input and first output at the tagged pixels) with the frame's
    /// separable block and, when they changed, technique ids uploaded.
    pub compose_ms: f64,
    /// P2: `sep_horizontal_tiles`.
    pub horizontal_ms: f64,
    /// P3 and P4: `sep_vertical_tiles`.
    pub vertical_ms: f64,
}

impl HybridTimes {
    /// The sum of the steps.
    #[must_use]
    pub fn total_ms(&self) -> f64 {
        self.estimate_ms
            + self.sampling_ms
            + self.update_ms
            + self.compose_ms
            + self.horizontal_ms
            + self.vertical_ms
    }
}

fn check_model(model: Model) -> Result<(), PassError> {
    if matches!(model, Model::Fixed(_)) {
        return Err(PassError::Param(spvg::Error::InconsistentParameters {
            names: "model",
            expected: "the hybrid pass needs an adaptive model (AS, CCV or OCV)",
        }));
    }
    Ok(())
}

fn check_block(sep: &SeparableParams) -> Result<(), PassError> {
    if sep.hybrid == 0 {
        return Err(PassError::Param(spvg::Error::InconsistentParameters {
            names: "SeparableParams::hybrid",
            expected: "a hybrid frame's separable block built with hybrid = true",
        }));
    }
    Ok(())
}

/// The hybrid pass on a wgpu device.
#[derive(Debug)]
pub struct HybridPass {
    sampled: SssPass,
    separable: SeparablePass,
}

impl HybridPass {
    /// The passes for an adaptive `model` on a `width x height` image (timestamps off: the
    /// steps are timed by submit and wait).
    ///
    /// # Errors
    ///
    /// [`PassError::Param`] for the fixed count.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        model: Model,
    ) -> Result<Self, PassError> {
        check_model(model)?;
        Ok(Self {
            sampled: SssPass::new(device, queue, width, height, model, false),
            separable: SeparablePass::new(device, queue, width, height),
        })
    }

    /// The block of one frame of the AFIS step under `config`
    /// ([`SssPass::frame_params`]).
    ///
    /// # Errors
    ///
    /// As [`SssPass::frame_params`].
    pub fn frame_params(
        &mut self,
        config: &PassConfig,
        material: &MaterialPreset,
        frame: u32,
    ) -> Result<PassParams, PassError> {
        self.sampled.frame_params(config, material, frame)
    }

    /// Runs one frame: P1 on the tagged pixels, then P2 to P4. `technique` holds one id
    /// per pixel ([`technique_ids`]).
    ///
    /// # Errors
    ///
    /// As [`SssPass::run_frame_in`] and [`SeparablePass::run_frame`];
    /// [`PassError::Param`] for a separable block not built for a hybrid frame.
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        sep: &SeparableParams,
        inputs: &FrameInputs,
        technique: &[u8],
    ) -> Result<HybridOutput, PassError> {
        check_block(sep)?;
        let tagged = afis_region(technique);
        if self.sampled.check_frame(inputs, Some(&tagged))? {
            return Ok(HybridOutput::default());
        }
        let device = self.sampled.device().clone();
        let queue = self.sampled.queue().clone();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("hybrid"),
        });
        let (count, _) =
            self.sampled
                .record_frame(&mut encoder, params, inputs, Some(&tagged), true, false)?;
        let shared = shared(&self.sampled);
        let tiles = self.sampled.tile_list().ok_or(PassError::Device(
            "the subsurface pass built no tile list for a region".into(),
        ))?;
        self.separable.record_hybrid_inputs(
            &mut encoder,
            sep,
            inputs,
            technique,
            &shared,
            tiles,
        )?;
        self.separable
            .record_horizontal(&mut encoder, Some(&shared));
        self.separable.record_vertical(&mut encoder, Some(&shared));
        let time_ms = super::pass::wait(&device, &queue, encoder)?;
        let result = read_texture(&device, &queue, shared.afis)?;
        let count = read_texture(&device, &queue, &count)?;
        Ok(HybridOutput {
            frame: FrameOutput {
                result,
                count,
                time_ms,
                timer: Timer::WallClock,
            },
        })
    }

    /// [`HybridPass::run_frame`] with each step submitted and waited for on its own and
    /// timed by its wall time ([`HybridTimes`]): where a frame's time goes. The same
    /// output as [`HybridPass::run_frame`]; not for speed.
    ///
    /// # Errors
    ///
    /// As [`HybridPass::run_frame`].
    pub fn run_frame_per_pass(
        &mut self,
        params: &PassParams,
        sep: &SeparableParams,
        inputs: &FrameInputs,
        technique: &[u8],
    ) -> Result<(HybridOutput, HybridTimes), PassError> {
        check_block(sep)?;
        let tagged = afis_region(technique);
        if self.sampled.check_frame(inputs, Some(&tagged))? {
            return Ok(Default::default());
        }
        let (sampled, steps) = self.sampled.per_pass(params, inputs, Some(&tagged), true)?;
        let device = self.sampled.device().clone();
        let queue = self.sampled.queue().clone();
        let encoder = || {
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hybrid step"),
            })
        };
        let mut e = encoder();
        let shared = shared(&self.sampled);
        let tiles = self.sampled.tile_list().ok_or(PassError::Device(
            "the subsurface pass built no tile list for a region".into(),
        ))?;
        self.separable
            .record_hybrid_inputs(&mut e, sep, inputs, technique, &shared, tiles)?;
        let compose_ms = super::pass::wait(&device, &queue, e)?;
        let mut e = encoder();
        self.separable.record_horizontal(&mut e, Some(&shared));
        let horizontal_ms = super::pass::wait(&device, &queue, e)?;
        let mut e = encoder();
        self.separable.record_vertical(&mut e, Some(&shared));
        let vertical_ms = super::pass::wait(&device, &queue, e)?;
        let times = HybridTimes {
            estimate_ms: steps.estimate_ms,
            sampling_ms: steps.sampling_ms,
            update_ms: steps.update_ms,
            compose_ms,
            horizontal_ms,
            vertical_ms,
        };
        let result = read_texture(&device, &queue, shared.afis)?;
        let frame = FrameOutput {
            result,
            count: sampled.count,
            time_ms: times.total_ms(),
            timer: Timer::WallClock,
        };
        Ok((HybridOutput { frame }, times))
    }

    /// The history written by the last frame (zero outside the tags).
    ///
    /// # Errors
    ///
    /// A failed readback.
    pub fn history(&self) -> Result<History, PassError> {
        self.sampled.history()
    }
}

/// The hybrid pass on the CPU twins.
#[derive(Clone, Debug)]
pub struct HybridTwin {
    sampled: SssTwin,
}

impl HybridTwin {
    /// The twin for an adaptive `model` on `width x height` frames.
    ///
    /// # Errors
    ///
    /// [`PassError::Param`] for the fixed count.
    pub fn new(model: Model, width: u32, height: u32) -> Result<Self, PassError> {
        check_model(model)?;
        Ok(Self {
            sampled: SssTwin::new(model, width, height),
        })
    }

    /// The twin of [`HybridPass::frame_params`].
    ///
    /// # Errors
    ///
    /// As [`SssTwin::frame_params`].
    pub fn frame_params(
        &mut self,
        config: &PassConfig,
        material: &MaterialPreset,
        frame: u32,
    ) -> Result<PassParams, PassError> {
        self.sampled.frame_params(config, material, frame)
    }

    /// Twin of [`HybridPass::run_frame`].
    ///
    /// # Errors
    ///
    /// As [`HybridPass::run_frame`].
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        sep: &SeparableParams,
        inputs: &FrameInputs,
        technique: &[u8],
    ) -> Result<HybridOutput, PassError> {
        check_block(sep)?;
        let tagged = afis_region(technique);
        let sampled = self.sampled.run_frame_in(params, inputs, Some(&tagged))?;
        let mut s = *sep;
        (s.width, s.height) = (inputs.width, inputs.height);
        let out = SeparableTwin.run_frame(
            &s,
            inputs,
            Some(HybridSources {
                technique,
                afis: &sampled.result,
            }),
        )?;
        Ok(HybridOutput {
            frame: FrameOutput {
                result: out.result,
                count: sampled.count,
                time_ms: sampled.time_ms + out.time_ms,
                timer: out.timer,
            },
        })
    }

    /// The history written by the last frame.
    #[must_use]
    pub fn history(&self) -> History {
        self.sampled.history()
    }
}

/// The subsurface pass's textures of the frame just recorded that the separable passes
/// share.
fn shared(sampled: &SssPass) -> SharedTextures<'_> {
    let [lighting, depth, mask] = sampled.frame_textures();
    SharedTextures {
        afis: sampled.result_texture(),
        lighting,
        depth,
        mask,
    }
}

fn afis_region(technique: &[u8]) -> Vec<u8> {
    technique
        .iter()
        .map(|&t| u8::from(t == TECHNIQUE_AFIS))
        .collect()
}
