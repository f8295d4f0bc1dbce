//! The subsurface pass on a wgpu device: textures, dispatch, readback. The adaptive
//! models are a consumer of the reusable component [`AdaptivePass`]: per frame
//! `sss_gamma` -> the component's estimate -> `sss_sample` -> the component's update.

use half::f16;

use spvg::SpvgConfig;
use spvg::burley::MaterialPreset;
use spvg::texel::TexelEncoding;
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveTiles};
use spvg_wgpu::util::GpuDevice;

use super::record::{Adaptive, AdaptivePasses, Fixed, FrameTextures, Kind, OnePass, component_for};
use super::tiles::SssTiles;
use crate::error::PassError;
use crate::gpu::{
    compute_pipeline, read_buffer, read_texture, shader_module, texture_2d, write_scalar,
    write_texture_level,
};
use crate::sss::{
    FrameInputs, FrameOutput, Guide, History, Model, PassConfig, PassParams, Timer, sss_source,
};

const FMT_RGBA16F: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Compute passes of a frame at most (the adaptive models: `sss_gamma`, the component's
/// estimate, `sss_sample`, the component's update), each timed by its own begin/end pair.
pub(super) const MAX_PASSES: u32 = 4;
const TIMESTAMP_BYTES: u64 = 16 * MAX_PASSES as u64;

/// The subsurface pass bound to one device, image size and model. A fixed count keeps no
/// history; AS, CCV and OCV run the adaptive component ([`AdaptivePass`]), which owns the
/// history (one ping-pong pair of texels for AS and CCV, two for OCV).
#[derive(Debug)]
pub struct SssPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    model: Model,
    kind: Kind,
    params: wgpu::Buffer,
    lighting: wgpu::Texture,
    /// Depth and mask ping-pong: this frame's and the previous frame's (the component's
    /// `previous_depth` and previous mask).
    depth: [wgpu::Texture; 2],
    mask: [wgpu::Texture; 2],
    /// The adaptive component's mask ping-pong: the subsurface mask, or its part inside
    /// the sampling region of [`SssPass::run_frame_in`].
    count_mask: [wgpu::Texture; 2],
    /// Index of the depth and mask of the last frame run.
    last: usize,
    result: wgpu::Texture,
    timestamps: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    /// The adaptive steps over a tile list (the hybrid pass's first step), built at the
    /// first frame that asks for them.
    tiles: Option<SssTiles>,
    /// The controller and texel encoding of the last `frame_params`' block (the budget
    /// reduction's twin reads them).
    controller: Option<(SpvgConfig<f32>, TexelEncoding)>,
    /// Whether the adaptive models run their frames in one pass where they can
    /// ([`SssPass::set_one_pass`]).
    use_one_pass: bool,
}

impl SssPass {
    /// Builds the pipelines and textures for `model` on a `width x height` image. The
    /// adaptive component of AS, CCV and OCV is built by the first
    /// [`frame_params`](Self::frame_params), from its settings. Creates no adapter: the
    /// caller passes its device (see [`spvg_wgpu::util::acquire_device`]). wgpu panics on a
    /// frame beyond the device's limits: check sizes you did not choose with
    /// [`crate::check_frame_size`] first.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        model: Model,
        timestamps: bool,
    ) -> Self {
        let module = shader_module(device, "sss.wgsl", sss_source());
        let pipeline = |entry: &str| compute_pipeline(device, &module, entry, None);
        let size = [width.max(1), height.max(1)];
        let tex = |label: &str, format, usage| texture_2d(device, label, format, size, usage);
        let input = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let output = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let exchanged = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let scalar = wgpu::TextureFormat::R32Float;
        let kind = match model {
            Model::Fixed(_) => Kind::Fixed(Fixed {
                pipeline: pipeline("sss_fixed"),
                // Also sampled: the budget reduction (`crate::sss::reduce`) reads the counts.
                count: tex(
                    "count",
                    wgpu::TextureFormat::R32Uint,
                    output | wgpu::TextureUsages::TEXTURE_BINDING,
                ),
            }),
            Model::As | Model::Ccv | Model::Ocv => Kind::Adaptive(Box::new(Adaptive {
                passes: AdaptivePasses {
                    gamma_pipeline: pipeline("sss_gamma"),
                    sample_pipeline: pipeline("sss_sample"),
                    sample_classified_pipeline: pipeline("sss_sample_classified"),
                    motion: tex("zero motion", wgpu::TextureFormat::Rg16Float, input),
                    gamma: tex("gamma", scalar, exchanged),
                    // COPY_SRC: a guided frame reads it back for the renderer's guide.
                    value: tex(
                        "monitored luminance",
                        scalar,
                        exchanged | wgpu::TextureUsages::COPY_SRC,
                    ),
                    control: tex("control luminance", scalar, exchanged),
                    guide: tex("taa guide", scalar, input),
                },
                component: None,
                one_pass: None,
            })),
        };
        let depth = wgpu::TextureFormat::R32Float;
        let mask = wgpu::TextureFormat::R8Uint;
        Self {
            device: device.clone(),
            queue: queue.clone(),
            width,
            height,
            model,
            kind,
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("PassParams"),
                size: size_of::<PassParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            lighting: lighting_texture(device, size),
            depth: [tex("depth a", depth, input), tex("depth b", depth, input)],
            mask: [tex("mask a", mask, input), tex("mask b", mask, input)],
            count_mask: [
                tex("count mask a", mask, input),
                tex("count mask b", mask, input),
            ],
            last: 1,
            // Also sampled: the hybrid pass composes it into the separable passes' input.
            result: tex(
                "result",
                FMT_RGBA16F,
                output | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            timestamps: timestamps.then(|| timestamp_queries(device)),
            tiles: None,
            controller: None,
            use_one_pass: false,
        }
    }

    /// Whether the adaptive models run a frame in the component's one-pass form:
    /// `sss_gamma`, then the estimate, the distant samples and the update in one dispatch
    /// (`sss_sample_one_pass`). Off by default: on software Vulkan the two-pass form
    /// measured faster (BENCHMARKS.md, the component's cost), as the one-pass form's
    /// barriers are costly there. Off, or for a frame one pass cannot serve (the
    /// count-classified dispatch, which needs the counts before the sampling dispatch; a
    /// guided frame, whose guide is computed after the sampling; the hybrid pass's steps
    /// over a tile list), they run the two-pass form: `sss_gamma`, the component's
    /// estimate, `sss_sample`, the component's update. Both give the same counts, results
    /// and histories.
    pub fn set_one_pass(&mut self, on: bool) {
        self.use_one_pass = on;
    }

    /// The pass on a device from [`spvg_wgpu::util::acquire_device`] (tests pass their
    /// own): [`SssPass::new`] with timestamps where they measure the pass. Check sizes you
    /// did not choose with [`crate::check_frame_size`] first ([`crate::Backend::pass`]
    /// does).
    ///
    /// Pass times are timestamp queries on a hardware adapter that has them, else wall
    /// time: a software rasterizer's (lavapipe's) timestamps do not bracket the work of the
    /// adaptive models' four passes (they report a fraction of the single-pass fixed
    /// baseline's time at the same count), while its wall time is the CPU time it spends.
    #[must_use]
    pub fn for_device(device: &GpuDevice, model: Model, width: u32, height: u32) -> Self {
        Self::new(
            &device.device,
            &device.queue,
            width,
            height,
            model,
            device.timestamps && !device.is_software(),
        )
    }

    /// The model this pass runs.
    #[must_use]
    pub fn model(&self) -> Model {
        self.model
    }

    /// The device the pass runs on.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue the pass submits to.
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Depth, mask and counts of the last frame and the H history the next frame reads
    /// (for `crate::sss::reduce`); `None` without history (a fixed count, or before the
    /// first frame).
    pub(crate) fn reduce_textures(
        &self,
    ) -> Option<(
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
    )> {
        let a = self.adaptive()?;
        Some((
            &self.depth[self.last],
            &self.mask[self.last],
            a.count_texture(),
            a.history_texture(),
        ))
    }

    /// The adaptive component, once the first [`frame_params`](Self::frame_params) of an
    /// adaptive model has built it.
    #[must_use]
    pub fn adaptive(&self) -> Option<&AdaptivePass> {
        match &self.kind {
            Kind::Adaptive(ad) => ad.component.as_ref(),
            Kind::Fixed(_) => None,
        }
    }

    /// The adaptive component to change what its settings do not hold between frames
    /// (the one-pass form's switches, [`AdaptivePass::set_one_pass_order`]), once the first
    /// [`frame_params`](Self::frame_params) of an adaptive model has built it. Its settings
    /// come from each frame's [`PassConfig`] (`frame_params` hands them over); the
    /// one-pass switches stay as set here.
    #[must_use]
    pub fn adaptive_mut(&mut self) -> Option<&mut AdaptivePass> {
        match &mut self.kind {
            Kind::Adaptive(ad) => ad.component.as_mut(),
            Kind::Fixed(_) => None,
        }
    }

    /// The uniform block of frame `frame` of `material` under `config`, for
    /// [`run_frame`](Self::run_frame): an adaptive model's first call builds its component
    /// from `config.settings(model)` (the first target fixes the history's texel
    /// encoding), later calls hand it the new settings between frames (a budget governor's
    /// target); the block's controller is the component's
    /// ([`AdaptivePass::params_block`]), or for the fixed count
    /// [`PassConfig::fixed_block`].
    ///
    /// # Errors
    ///
    /// [`PassError::Adaptive`] for settings the component refuses (a control model other
    /// than the pass's model's cannot happen: the model sets it), [`PassError::Param`] for
    /// the pass's own fields.
    pub fn frame_params(
        &mut self,
        config: &PassConfig,
        material: &MaterialPreset,
        frame: u32,
    ) -> Result<PassParams, PassError> {
        let size = [self.width, self.height];
        let (block, enc) = match &mut self.kind {
            Kind::Fixed(_) => (
                config.fixed_block()?,
                TexelEncoding::new(config.spvg.target_variance())?,
            ),
            Kind::Adaptive(ad) => {
                let settings = config.settings(self.model);
                match &mut ad.component {
                    Some(a) => a.set_settings(settings)?,
                    None => {
                        let [w, h] = size;
                        let mut a = AdaptivePass::new(&self.device, settings, w, h)?;
                        // Every frame's counts are read back (`FrameOutput::count`) and
                        // the budget reduction reads them.
                        a.set_one_pass_counts(true);
                        ad.component = Some(a);
                    }
                }
                match &ad.component {
                    Some(a) => (*a.params_block(), a.encoding()),
                    None => (
                        config.fixed_block()?,
                        TexelEncoding::new(config.spvg.target_variance())?,
                    ),
                }
            }
        };
        self.controller = Some((config.spvg, enc));
        config.params(self.model, material, size, frame, block)
    }

    /// The controller and texel encoding of the last [`frame_params`](Self::frame_params)
    /// (`None` before the first).
    pub(crate) fn block_controller(&self) -> Option<(SpvgConfig<f32>, TexelEncoding)> {
        self.controller
    }

    /// Runs one frame: uploads the inputs, records the model's passes (a fixed count:
    /// `sss_fixed`; the adaptive models: `sss_gamma`, the component's estimate,
    /// `sss_sample`, the component's update), reads back the result and the counts.
    ///
    /// `params` comes from this pass's [`frame_params`](Self::frame_params).
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inputs of another size, [`PassError::Param`] naming
    /// `params.spvg` for a block not built by this pass's `frame_params`,
    /// [`PassError::Adaptive`] when the component refuses an input,
    /// [`PassError::Device`] when the device is lost or a readback fails.
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        self.run_frame_with(params, inputs, None, None)
    }

    /// [`SssPass::run_frame`] with the sampling restricted to `region` (nonzero = sample):
    /// the adaptive component controls the count under the subsurface mask times the
    /// region, so pixels outside it take 0 samples and keep no history (the first step of
    /// the hybrid pass), while the samples of the pixels inside still read the lighting
    /// of the whole surface (the estimator's mask is the subsurface mask). The work
    /// follows the region: a pixel with count 0 takes no sample.
    ///
    /// # Errors
    ///
    /// As [`SssPass::run_frame`]; [`PassError::InputSize`] for a region of another size,
    /// [`PassError::Param`] for a region with the fixed count (it has no controller).
    pub fn run_frame_in(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
    ) -> Result<FrameOutput, PassError> {
        self.run_frame_with(params, inputs, region, None)
    }

    /// [`run_frame`](Self::run_frame) with the renderer's TAA guide (docs/algorithms.md
    /// §8.5): an adaptive model submits its sampling, reads back the result and the
    /// monitored values, calls `guide` with them, uploads what it returns as the
    /// component's [`UpdateInputs::guide`](spvg_wgpu::adaptive::UpdateInputs::guide) and
    /// submits the update (the frame's time is the sampling's). A fixed count has no
    /// update and ignores `guide`; `None` is [`run_frame`](Self::run_frame).
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
        if self.check_frame(inputs, region)? {
            return Ok(FrameOutput::default());
        }
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sss") });
        let (count, passes) =
            self.record_frame(&mut encoder, params, inputs, region, false, guide.is_some())?;
        let time = self.submit(encoder, passes)?;
        let result: Vec<[f16; 4]> = read_texture(&self.device, &self.queue, &self.result)?;
        if let (Some(guide), Kind::Adaptive(ad)) = (guide, &mut self.kind)
            && let Some(component) = &mut ad.component
        {
            let n = result.len();
            let value: Vec<f32> = read_texture(&self.device, &self.queue, &ad.passes.value)?;
            let c = guide(&result, &value);
            if c.len() != n {
                return Err(PassError::InputSize {
                    expected: n,
                    got: c.len(),
                });
            }
            write_scalar(&self.queue, &ad.passes.guide, [self.width, self.height], &c);
            let mut encoder = self.device.create_command_encoder(&Default::default());
            ad.passes
                .record_update(&mut encoder, component, Some(&ad.passes.guide), None, None)?;
            self.queue.submit([encoder.finish()]);
        }
        let count: Vec<u32> = read_texture(&self.device, &self.queue, &count)?;
        Ok(FrameOutput {
            result,
            count,
            time_ms: time.0,
            timer: time.1,
        })
    }

    /// The result texture (`Rgba16Float`, `COPY_SRC`): the hybrid pass copies it into the
    /// separable passes' AFIS input on the device.
    pub(super) fn result_texture(&self) -> &wgpu::Texture {
        &self.result
    }

    /// The lighting, depth and mask textures of the frame last recorded (the hybrid pass's
    /// separable passes read them instead of uploading their own).
    pub(super) fn frame_textures(&self) -> [&wgpu::Texture; 3] {
        [
            &self.lighting,
            &self.depth[self.last],
            &self.mask[self.last],
        ]
    }

    /// The tile list of the adaptive steps over tiles, once a frame has asked for them.
    pub(super) fn tile_list(&self) -> Option<&AdaptiveTiles> {
        self.tiles.as_ref().map(|t| &t.list)
    }

    /// Checks a frame's inputs and region against the pass; `true` for an empty frame
    /// (nothing to run).
    pub(super) fn check_frame(
        &self,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
    ) -> Result<bool, PassError> {
        let n = self.width as usize * self.height as usize;
        if !inputs.is_consistent()
            || inputs.len() != n
            || inputs.width != self.width
            || region.is_some_and(|r| r.len() != n)
        {
            return Err(PassError::InputSize {
                expected: n,
                got: inputs.lighting.len(),
            });
        }
        if region.is_some() && matches!(self.model, Model::Fixed(_)) {
            return Err(PassError::Param(spvg::Error::InconsistentParameters {
                names: "model, region",
                expected: "a sampling region needs an adaptive model",
            }));
        }
        Ok(n == 0)
    }

    /// Records one checked frame ([`SssPass::check_frame`]) into `encoder` and queues its
    /// uploads; returns the count texture and the passes recorded. The pass moves on to
    /// the next frame: submit `encoder` before recording another.
    ///
    /// With `tiles` (and a region, for an adaptive model) the adaptive steps run over the
    /// tiles that hold a region pixel once the region has been the same for
    /// [`tiles::SETTLE_FRAMES`](super::tiles) frames ([`SssTiles`]): the counts and the
    /// history are those of the whole-frame steps, the result is written inside those
    /// tiles only. With `guided` an adaptive model records everything before the update
    /// and leaves the update to the caller (it waits for the renderer's guide).
    pub(super) fn record_frame(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        params: &PassParams,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
        tiles: bool,
        guided: bool,
    ) -> Result<(wgpu::Texture, u32), PassError> {
        let mut p = *params;
        p.width = self.width;
        p.height = self.height;
        let (cur, prev) = (1 - self.last, self.last);
        let frame = FrameTextures {
            device: &self.device,
            params: &self.params,
            lighting: &self.lighting,
            depth: [&self.depth[cur], &self.depth[prev]],
            mask: [&self.mask[cur], &self.mask[prev]],
            count_mask: [&self.count_mask[cur], &self.count_mask[prev]],
            result: &self.result,
            size: [self.width, self.height],
        };
        let stamps = self.timestamps.as_ref().map(|(set, _, _)| set);
        let (count, passes) = match &mut self.kind {
            Kind::Fixed(fixed) => {
                fixed.record(encoder, &frame, stamps);
                (fixed.count.clone(), 1)
            }
            Kind::Adaptive(ad) => {
                // Checked before anything is uploaded: a refused block leaves the pass as
                // it was.
                let component = component_for(&mut ad.component, &p)?;
                let listed = match region.filter(|_| tiles) {
                    Some(r) => {
                        let t = self
                            .tiles
                            .get_or_insert_with(|| SssTiles::new(frame.device, component));
                        t.frame(r)?.then_some(&*t)
                    }
                    None => None,
                };
                let one_pass = self.use_one_pass
                    && !guided
                    && listed.is_none()
                    && !component.settings().classified_dispatch;
                if one_pass {
                    // The one-pass frame counts as updated once its group exists: record
                    // it now, and the uploads below land before the submission.
                    let group = component.one_pass_group(&ad.passes.estimate_inputs(&frame))?;
                    let op = ad
                        .one_pass
                        .get_or_insert_with(|| OnePass::new(frame.device, component));
                    ad.passes.record_gamma(encoder, &frame, stamps, None);
                    op.record(encoder, &frame, &group, stamps);
                    (component.count_texture().clone(), 2)
                } else if guided {
                    // The update waits for the renderer's guide: a second submission.
                    ad.passes
                        .record_sampling(encoder, &frame, component, stamps, listed)?;
                    (component.count_texture().clone(), MAX_PASSES - 1)
                } else {
                    ad.passes
                        .record(encoder, &frame, component, stamps, listed)?;
                    (component.count_texture().clone(), MAX_PASSES)
                }
            }
        };
        upload(&self.queue, &frame, &p, inputs);
        let count_mask = region.map(|r| region_mask(&inputs.mask, r));
        write_mask(
            &self.queue,
            frame.count_mask[0],
            count_mask.as_deref().unwrap_or(&inputs.mask),
            frame.size,
        );
        self.last = cur;
        Ok((count, passes))
    }

    /// [`SssPass::run_frame`] with each step submitted and waited for on its own, and timed
    /// by its wall time (submit to the wait's return): the estimate (`sss_gamma` and the
    /// component's estimate), the sampling (`sss_sample`, or `sss_fixed` for the fixed
    /// count) and the update, with the uploads waited for before the first. For a
    /// breakdown, not for speed: each step pays a submit and a wait.
    ///
    /// # Errors
    ///
    /// As [`SssPass::run_frame`].
    pub fn run_frame_per_pass(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<(FrameOutput, PassTimes), PassError> {
        self.per_pass(params, inputs, None, false)
    }

    /// [`SssPass::run_frame_per_pass`] with the sampling restricted to `region` as in
    /// [`SssPass::run_frame_in`], over its tiles when `tiles` as in
    /// [`SssPass::record_frame`] (the breakdown of the hybrid pass's first step).
    pub(super) fn per_pass(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
        region: Option<&[u8]>,
        tiles: bool,
    ) -> Result<(FrameOutput, PassTimes), PassError> {
        let n = self.width as usize * self.height as usize;
        if !inputs.is_consistent()
            || inputs.len() != n
            || inputs.width != self.width
            || region.is_some_and(|r| r.len() != n)
        {
            return Err(PassError::InputSize {
                expected: n,
                got: inputs.lighting.len(),
            });
        }
        if region.is_some() && matches!(self.model, Model::Fixed(_)) {
            return Err(PassError::Param(spvg::Error::InconsistentParameters {
                names: "model, region",
                expected: "a sampling region needs an adaptive model",
            }));
        }
        if n == 0 {
            return Ok((FrameOutput::default(), PassTimes::default()));
        }
        let mut p = *params;
        p.width = self.width;
        p.height = self.height;
        let (cur, prev) = (1 - self.last, self.last);
        let frame = FrameTextures {
            device: &self.device,
            params: &self.params,
            lighting: &self.lighting,
            depth: [&self.depth[cur], &self.depth[prev]],
            mask: [&self.mask[cur], &self.mask[prev]],
            count_mask: [&self.count_mask[cur], &self.count_mask[prev]],
            result: &self.result,
            size: [self.width, self.height],
        };
        let (device, queue) = (&self.device, &self.queue);
        let encoder = || {
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sss step"),
            })
        };
        let mut times = PassTimes::default();
        let count = match &mut self.kind {
            Kind::Fixed(fixed) => {
                upload(queue, &frame, &p, inputs);
                write_mask(queue, frame.count_mask[0], &inputs.mask, frame.size);
                wait(device, queue, encoder())?;
                let mut e = encoder();
                fixed.record(&mut e, &frame, None);
                times.sampling_ms = wait(device, queue, e)?;
                fixed.count.clone()
            }
            Kind::Adaptive(ad) => {
                let component = component_for(&mut ad.component, &p)?;
                let listed = match region.filter(|_| tiles) {
                    Some(r) => {
                        let t = self
                            .tiles
                            .get_or_insert_with(|| SssTiles::new(frame.device, component));
                        t.frame(r)?.then_some(&*t)
                    }
                    None => None,
                };
                upload(queue, &frame, &p, inputs);
                let count_mask = region.map(|r| region_mask(&inputs.mask, r));
                let count_mask = count_mask.as_deref().unwrap_or(&inputs.mask);
                write_mask(queue, frame.count_mask[0], count_mask, frame.size);
                wait(device, queue, encoder())?;
                let mut e = encoder();
                ad.passes
                    .record_estimate(&mut e, &frame, component, None, listed)?;
                times.estimate_ms = wait(device, queue, e)?;
                let mut e = encoder();
                ad.passes
                    .record_sample(&mut e, &frame, component, None, listed)?;
                times.sampling_ms = wait(device, queue, e)?;
                let mut e = encoder();
                ad.passes
                    .record_update(&mut e, component, None, None, listed)?;
                times.update_ms = wait(device, queue, e)?;
                component.count_texture().clone()
            }
        };
        let result: Vec<[f16; 4]> = read_texture(&self.device, &self.queue, &self.result)?;
        let count: Vec<u32> = read_texture(&self.device, &self.queue, &count)?;
        self.last = cur;
        let total = times.estimate_ms + times.sampling_ms + times.update_ms;
        Ok((
            FrameOutput {
                result,
                count,
                time_ms: total,
                timer: Timer::WallClock,
            },
            times,
        ))
    }

    /// Submits the frame's passes, waits for them, and measures them: by their
    /// timestamps when the pass has queries and every pair is ordered (the pass time spans
    /// the first begin to the last end, barriers between the passes included), else by
    /// the wall time from submit to the wait's return.
    fn submit(
        &self,
        mut encoder: wgpu::CommandEncoder,
        passes: u32,
    ) -> Result<(f64, Timer), PassError> {
        if let Some((set, resolve, read)) = &self.timestamps {
            encoder.resolve_query_set(set, 0..2 * passes, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16 * u64::from(passes));
        }
        let start = std::time::Instant::now();
        self.queue.submit([encoder.finish()]);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| PassError::Device(e.to_string()))?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let Some((_, _, read)) = &self.timestamps else {
            return Ok((wall_ms, Timer::WallClock));
        };
        let ticks: Vec<u64> = read_buffer(&self.device, read, 16 * u64::from(passes))?;
        let period = f64::from(self.queue.get_timestamp_period());
        let ordered = ticks.windows(2).all(|w| w[0] <= w[1]);
        Ok(match (ticks.first(), ticks.last()) {
            (Some(t0), Some(t1)) if ordered && t1 > t0 => {
                ((t1 - t0) as f64 * period * 1e-6, Timer::GpuTimestamp)
            }
            _ => (wall_ms, Timer::WallClock),
        })
    }

    /// Reads back the history written by the last frame (the component's; zeroed before
    /// the first frame, empty for a fixed count).
    ///
    /// # Errors
    ///
    /// [`PassError::Device`] when a readback fails.
    pub fn history(&self) -> Result<History, PassError> {
        let n = self.width as usize * self.height as usize;
        let zero = || vec![[f16::ZERO; 4]; n];
        let mut h = History::default();
        match (self.adaptive(), self.model) {
            (_, Model::Fixed(_)) => {}
            (Some(a), _) => {
                h.h = read_texture(&self.device, &self.queue, a.history_texture())?;
                if let Some(cv) = a.cv_history_texture() {
                    h.j = read_texture(&self.device, &self.queue, cv)?;
                }
            }
            (None, model) => {
                h.h = zero();
                if model == Model::Ocv {
                    h.j = zero();
                }
            }
        }
        Ok(h)
    }
}

/// Writes the frame's block, lighting (and its mips for AFIS), depth and mask.
fn upload(queue: &wgpu::Queue, f: &FrameTextures<'_>, p: &PassParams, inputs: &FrameInputs) {
    queue.write_buffer(f.params, 0, bytemuck::bytes_of(p));
    let [width, height] = f.size;
    let level = |texture, mip_level, data: &[u8], texel_bytes: u32, size: [u32; 2]| {
        write_texture_level(queue, texture, mip_level, data, texel_bytes, size);
    };
    let size = [width, height];
    level(
        f.lighting,
        0,
        bytemuck::cast_slice(&inputs.lighting),
        8,
        size,
    );
    if p.afis != 0 {
        for (k, (mw, mh, texels)) in inputs.lighting_mips().iter().enumerate() {
            level(
                f.lighting,
                k as u32 + 1,
                bytemuck::cast_slice(texels),
                8,
                [*mw, *mh],
            );
        }
    }
    level(f.depth[0], 0, bytemuck::cast_slice(&inputs.depth), 4, size);
    level(f.mask[0], 0, &inputs.mask, 1, size);
}

/// The time of each step of a frame ([`SssPass::run_frame_per_pass`]), wall time in ms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// `sss_gamma` and the component's estimate (0 for the fixed count).
    pub estimate_ms: f64,
    /// `sss_sample`, or `sss_fixed`.
    pub sampling_ms: f64,
    /// The component's update (0 for the fixed count).
    pub update_ms: f64,
}

/// Submits `encoder`, waits for the device, and returns the wall time in ms.
pub(super) fn wait(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: wgpu::CommandEncoder,
) -> Result<f64, PassError> {
    let start = std::time::Instant::now();
    queue.submit([encoder.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| PassError::Device(e.to_string()))?;
    Ok(start.elapsed().as_secs_f64() * 1e3)
}

/// The subsurface mask inside the sampling region (1 where both are nonzero).
pub(crate) fn region_mask(mask: &[u8], region: &[u8]) -> Vec<u8> {
    mask.iter()
        .zip(region)
        .map(|(&m, &r)| u8::from(m != 0 && r != 0))
        .collect()
}

/// Writes an r8uint mask of the frame's size.
fn write_mask(queue: &wgpu::Queue, texture: &wgpu::Texture, data: &[u8], size: [u32; 2]) {
    write_texture_level(queue, texture, 0, data, 1, size);
}

/// The lighting texture with its whole mip chain (AFIS reads the levels below 0). Also a
/// storage texture: after a hybrid frame's sampling, the hybrid pass writes the AFIS result
/// into mip 0 at the tagged pixels, making it its separable passes' input (the next frame
/// uploads the lighting again).
fn lighting_texture(device: &wgpu::Device, [width, height]: [u32; 2]) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("lighting B"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 32 - width.max(height).leading_zeros(),
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FMT_RGBA16F,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::STORAGE_BINDING,
        view_formats: &[],
    })
}

/// The query set of a frame's pass pairs, its resolve buffer and its readback buffer.
fn timestamp_queries(device: &wgpu::Device) -> (wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer) {
    let set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("pass time"),
        ty: wgpu::QueryType::Timestamp,
        count: 2 * MAX_PASSES,
    });
    let buffer = |label, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: TIMESTAMP_BYTES,
            usage,
            mapped_at_creation: false,
        })
    };
    let resolve = buffer(
        "timestamps",
        wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
    );
    let read = buffer(
        "timestamps readback",
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    (set, resolve, read)
}
