//! The subsurface pass on a wgpu device: textures, dispatch, readback. The adaptive
//! models are a consumer of the reusable component [`AdaptivePass`]: per frame
//! `sss_gamma` -> the component's estimate -> `sss_sample` -> the component's update.

use half::f16;

use crate::adaptive::{AdaptivePass, EstimateInputs, Masks, UpdateInputs};
use crate::device::GpuDevice;
use crate::error::PassError;
use crate::gpu::{
    bind_group, compute_pipeline, dispatch_8x8, map_buffer, read_texture, shader_module,
    texture_2d, view,
};
use crate::sss::params::ComponentSetup;
use crate::sss::{FrameInputs, FrameOutput, History, Model, PassParams, Timer, sss_source};

const FMT_RGBA16F: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Compute passes of a frame at most (the adaptive models: `sss_gamma`, the component's
/// estimate, `sss_sample`, the component's update), each timed by its own begin/end pair.
const MAX_PASSES: u32 = 4;
const TIMESTAMP_BYTES: u64 = 16 * MAX_PASSES as u64;

/// The fixed-count baseline: its entry point and the counts it writes.
#[derive(Debug)]
struct Fixed {
    /// `sss_fixed`.
    pipeline: wgpu::ComputePipeline,
    /// The counts of `sss_fixed` (also sampled: the budget reduction reads them).
    count: wgpu::Texture,
}

/// What the adaptive models add to the pass: their two entry points and the textures they
/// exchange with the component, and the component itself.
#[derive(Debug)]
struct Adaptive {
    passes: AdaptivePasses,
    /// Built at the first frame from that frame's block
    /// ([`PassParams::component_setup`]).
    component: Option<(ComponentSetup, AdaptivePass)>,
}

/// The adaptive models' entry points and the textures they exchange with the component.
#[derive(Debug)]
struct AdaptivePasses {
    gamma_pipeline: wgpu::ComputePipeline,
    sample_pipeline: wgpu::ComputePipeline,
    /// Zero motion (`Rg16Float`): the subsurface scenes have a static camera.
    motion: wgpu::Texture,
    /// The distant-energy ratio `sss_gamma` writes (`R32Float`).
    gamma: wgpu::Texture,
    /// The monitored and control luminances `sss_sample` writes (`R32Float`).
    value: wgpu::Texture,
    control: wgpu::Texture,
}

/// The model's own entry points and state: a model is one or the other for the pass's
/// whole life, so a frame never meets a pass without its pipelines.
#[derive(Debug)]
enum Kind {
    Fixed(Fixed),
    Adaptive(Box<Adaptive>),
}

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
    /// Index of the depth and mask of the last frame run.
    last: usize,
    result: wgpu::Texture,
    timestamps: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
}

/// The textures of one frame's passes: this frame's depth and mask and the previous
/// frame's, the result, the lighting, the uniform block.
struct FrameTextures<'a> {
    device: &'a wgpu::Device,
    params: &'a wgpu::Buffer,
    lighting: &'a wgpu::Texture,
    depth: [&'a wgpu::Texture; 2],
    mask: [&'a wgpu::Texture; 2],
    result: &'a wgpu::Texture,
    size: [u32; 2],
}

impl SssPass {
    /// Builds the pipelines and textures for `model` on a `width x height` image. The
    /// adaptive component of AS, CCV and OCV is built at the first frame, from its block.
    /// Creates no adapter: the caller passes its device (see [`crate::acquire_device`]).
    /// wgpu panics on a frame beyond the device's limits: check sizes you did not choose
    /// with [`crate::check_frame_size`] first.
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
                    motion: tex("zero motion", wgpu::TextureFormat::Rg16Float, input),
                    gamma: tex("gamma", scalar, exchanged),
                    value: tex("monitored luminance", scalar, exchanged),
                    control: tex("control luminance", scalar, exchanged),
                },
                component: None,
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
            last: 1,
            result: tex("result", FMT_RGBA16F, output),
            timestamps: timestamps.then(|| timestamp_queries(device)),
        }
    }

    /// The pass on a device from [`crate::acquire_device`] (tests pass their own):
    /// [`SssPass::new`] with timestamps where they measure the pass. Check sizes you did
    /// not choose with [`GpuDevice::check_frame`] first ([`crate::Backend::pass`] does).
    ///
    /// Pass times are timestamp queries on a hardware adapter that has them, else wall
    /// time: a software rasterizer's (lavapipe's) timestamps did not bracket the work of
    /// the adaptive models' four passes (measured: 0.5 ms for a frame whose single-pass
    /// fixed baseline at the same count took 15 ms), while its wall time is the CPU time it
    /// spends.
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

    /// The adaptive component, once the first frame of an adaptive model has built it.
    #[must_use]
    pub fn adaptive(&self) -> Option<&AdaptivePass> {
        match &self.kind {
            Kind::Adaptive(ad) => ad.component.as_ref().map(|(_, a)| a),
            Kind::Fixed(_) => None,
        }
    }

    /// Runs one frame: uploads the inputs, records the model's passes (a fixed count:
    /// `sss_fixed`; the adaptive models: `sss_gamma`, the component's estimate,
    /// `sss_sample`, the component's update), reads back the result and the counts.
    ///
    /// The first frame of an adaptive model builds the component from its block; later
    /// frames may move the target variance (a budget governor), nothing else.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inputs of another size, [`PassError::Param`] for a block
    /// the controller rejects, [`PassError::ControllerChanged`] for a block whose
    /// controller differs from the first frame's in more than the target,
    /// [`PassError::Adaptive`] when the component refuses it, [`PassError::Device`] when
    /// the device is lost or a readback fails.
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        let n = self.width as usize * self.height as usize;
        if !inputs.is_consistent() || inputs.len() != n || inputs.width != self.width {
            return Err(PassError::InputSize {
                expected: n,
                got: inputs.lighting.len(),
            });
        }
        if n == 0 {
            return Ok(FrameOutput::default());
        }
        let mut p = *params;
        p.width = self.width;
        p.height = self.height;
        let (cur, prev) = (1 - self.last, self.last);
        let model = self.model;
        let frame = FrameTextures {
            device: &self.device,
            params: &self.params,
            lighting: &self.lighting,
            depth: [&self.depth[cur], &self.depth[prev]],
            mask: [&self.mask[cur], &self.mask[prev]],
            result: &self.result,
            size: [self.width, self.height],
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sss") });
        let stamps = self.timestamps.as_ref().map(|(set, _, _)| set);
        let (count, passes) = match &mut self.kind {
            Kind::Fixed(fixed) => {
                fixed.record(&mut encoder, &frame, stamps);
                (fixed.count.clone(), 1)
            }
            Kind::Adaptive(ad) => {
                // Decoded and checked before anything is uploaded: a refused block leaves
                // the pass as it was.
                let setup = p.component_setup(model)?;
                let component = prepare(&mut ad.component, &frame, setup, &p)?;
                ad.passes.record(&mut encoder, &frame, component, stamps)?;
                (component.count_texture().clone(), MAX_PASSES)
            }
        };
        upload(&self.queue, &frame, &p, inputs);
        let time = self.submit(encoder, passes)?;
        let result: Vec<[f16; 4]> = read_texture(&self.device, &self.queue, &self.result)?;
        let count: Vec<u32> = read_texture(&self.device, &self.queue, &count)?;
        self.last = cur;
        Ok(FrameOutput {
            result,
            count,
            time_ms: time.0,
            timer: time.1,
        })
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
        let ticks: Vec<u64> =
            map_buffer(&self.device, read, 16 * u64::from(passes)).map_err(PassError::Device)?;
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

impl Fixed {
    /// Records `sss_fixed`.
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        stamps: Option<&wgpu::QuerySet>,
    ) {
        let views = [
            (1, f.lighting.create_view(&Default::default())),
            (2, view(f.depth[0])),
            (3, view(f.mask[0])),
            (4, view(f.result)),
            (5, view(&self.count)),
        ];
        let group = sss_group(f, &self.pipeline, &views);
        let stamp = stamp(stamps, 0);
        dispatch_8x8(encoder, "sss_fixed", &self.pipeline, &group, stamp, f.size);
    }
}

/// The component for this frame: built at the first frame from its block's `setup`
/// (checked to store the history with the block's texel scales), compared with `setup` at
/// later ones, its target set to the frame's.
fn prepare<'a>(
    slot: &'a mut Option<(ComponentSetup, AdaptivePass)>,
    f: &FrameTextures<'_>,
    setup: ComponentSetup,
    p: &PassParams,
) -> Result<&'a mut AdaptivePass, PassError> {
    let entry = match slot.take() {
        Some((s, a)) if s.config == setup.config && s.control == setup.control => (s, a),
        Some(other) => {
            *slot = Some(other);
            return Err(PassError::ControllerChanged);
        }
        None => {
            let [width, height] = f.size;
            let a = AdaptivePass::new(f.device, setup.config, setup.control, width, height)?;
            check_encoding(&a, p)?;
            (setup, a)
        }
    };
    let component = &mut slot.insert(entry).1;
    component.set_target_variance(setup.target)?;
    Ok(component)
}

impl AdaptivePasses {
    /// Records `sss_gamma`, the component's estimate, `sss_sample` and the component's
    /// update, each with its timestamp pair.
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &mut AdaptivePass,
        stamps: Option<&wgpu::QuerySet>,
    ) -> Result<(), PassError> {
        let views = [(2, view(f.depth[0])), (7, view(&self.gamma))];
        let group = sss_group(f, &self.gamma_pipeline, &views);
        let gamma = &self.gamma_pipeline;
        dispatch_8x8(
            encoder,
            "sss_gamma",
            gamma,
            &group,
            stamp(stamps, 0),
            f.size,
        );
        let inputs = EstimateInputs {
            motion: &self.motion,
            depth: f.depth[0],
            previous_depth: f.depth[1],
            masks: Some(Masks {
                current: f.mask[0],
                previous: f.mask[1],
            }),
            gamma: Some(&self.gamma),
        };
        component.record_estimate_timed(encoder, &inputs, stamp(stamps, 1))?;
        let views = [
            (1, f.lighting.create_view(&Default::default())),
            (2, view(f.depth[0])),
            (3, view(f.mask[0])),
            (4, view(f.result)),
            (6, view(component.count_texture())),
            (8, view(&self.value)),
            (9, view(&self.control)),
        ];
        let group = sss_group(f, &self.sample_pipeline, &views);
        let sample = &self.sample_pipeline;
        dispatch_8x8(
            encoder,
            "sss_sample",
            sample,
            &group,
            stamp(stamps, 2),
            f.size,
        );
        let control = component.control().needs_control().then_some(&self.control);
        let inputs = UpdateInputs {
            value: &self.value,
            control,
        };
        component.record_update_timed(encoder, &inputs, stamp(stamps, 3))?;
        Ok(())
    }
}

/// The timestamp writes of pass `k` of a frame: its own begin/end pair.
fn stamp(set: Option<&wgpu::QuerySet>, k: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
    set.map(|query_set| wgpu::ComputePassTimestampWrites {
        query_set,
        beginning_of_pass_write_index: Some(2 * k),
        end_of_pass_write_index: Some(2 * k + 1),
    })
}

/// Writes the frame's block, lighting (and its mips for AFIS), depth and mask.
fn upload(queue: &wgpu::Queue, f: &FrameTextures<'_>, p: &PassParams, inputs: &FrameInputs) {
    queue.write_buffer(f.params, 0, bytemuck::bytes_of(p));
    let [width, height] = f.size;
    let level = |texture, mip_level, data: &[u8], texel_bytes: u32, [w, h]: [u32; 2]| {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            data,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * texel_bytes),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
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

/// The lighting texture with its whole mip chain (AFIS reads the levels below 0).
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
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
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

/// The bind group of one `sss.wgsl` entry point (its layout holds only the bindings it
/// uses): the uniform block at 0 and `views`.
fn sss_group(
    f: &FrameTextures<'_>,
    pipeline: &wgpu::ComputePipeline,
    views: &[(u32, wgpu::TextureView)],
) -> wgpu::BindGroup {
    let layout = pipeline.get_bind_group_layout(0);
    bind_group(f.device, Some("sss"), &layout, &[(0, f.params)], views)
}

/// The component stores the history with the block's texel scales (the variance scale
/// always, the CV scale for OCV), or the frame is refused.
fn check_encoding(a: &AdaptivePass, p: &PassParams) -> Result<(), PassError> {
    let enc = a.encoding();
    let cv_differs = a.cv_history_texture().is_some() && enc.cv_scale() != p.spvg.cv_scale;
    if enc.variance_scale() != p.spvg.var_scale || cv_differs {
        return Err(PassError::ControllerChanged);
    }
    Ok(())
}
