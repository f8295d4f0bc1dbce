//! The subsurface pass on a wgpu device: textures, dispatch, readback. The adaptive
//! models are a consumer of the reusable component [`AdaptivePass`]: per frame
//! `sss_gamma` -> the component's estimate -> `sss_sample` -> the component's update.

use half::f16;

use crate::adaptive::{AdaptivePass, EstimateInputs, Masks, UpdateInputs};
use crate::error::PassError;
use crate::frame::{FrameInputs, FrameOutput, History, Timer};
use crate::params::{ComponentSetup, Model, PassParams};
use crate::resources::texture_2d;
use crate::shaders;

const FMT_RGBA16F: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Compute passes of a frame at most (the adaptive models: `sss_gamma`, the component's
/// estimate, `sss_sample`, the component's update), each timed by its own begin/end pair.
const MAX_PASSES: u32 = 4;
const TIMESTAMP_BYTES: u64 = 16 * MAX_PASSES as u64;

/// What the adaptive models add to the pass: their two entry points, the textures they
/// exchange with the component, and the component itself (built at the first frame from
/// that frame's block, [`PassParams::component_setup`]).
#[derive(Debug)]
struct Adaptive {
    gamma_pipeline: wgpu::ComputePipeline,
    sample_pipeline: wgpu::ComputePipeline,
    /// Zero motion (`Rg16Float`): the subsurface scenes have a static camera.
    motion: wgpu::Texture,
    /// The distant-energy ratio `sss_gamma` writes (`R32Float`).
    gamma: wgpu::Texture,
    /// The monitored and control luminances `sss_sample` writes (`R32Float`).
    value: wgpu::Texture,
    control: wgpu::Texture,
    component: Option<(ComponentSetup, AdaptivePass)>,
}

/// The subsurface pass bound to one device, image size and model. A fixed count keeps no
/// history; AS, CCV and OCV run the adaptive component ([`AdaptivePass`]), which owns the
/// history (one ping-pong pair of texels for AS and CCV, two for OCV).
#[derive(Debug)]
pub struct GpuPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    model: Model,
    /// `sss_fixed` (fixed count only).
    fixed: Option<wgpu::ComputePipeline>,
    adaptive: Option<Adaptive>,
    params: wgpu::Buffer,
    lighting: wgpu::Texture,
    /// Depth and mask ping-pong: this frame's and the previous frame's (the component's
    /// `previous_depth` and previous mask).
    depth: [wgpu::Texture; 2],
    mask: [wgpu::Texture; 2],
    /// Index of the depth and mask of the last frame run.
    last: usize,
    result: wgpu::Texture,
    /// The counts of `sss_fixed` (the adaptive models read the component's).
    count: wgpu::Texture,
    readback: wgpu::Buffer,
    timestamps: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
}

fn padded_row(width: u32, bytes_per_texel: u32) -> u32 {
    (width * bytes_per_texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

impl GpuPass {
    /// Builds the pipelines and textures for `model` on a `width x height` image. The
    /// adaptive component of AS, CCV and OCV is built at the first frame, from its block.
    /// Creates no adapter: the caller passes its device (see [`crate::acquire_device`]).
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        model: Model,
        timestamps: bool,
    ) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sss.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shaders::sss_source().into()),
        });
        let pipeline = |entry: &str| crate::resources::compute_pipeline(device, &module, entry);
        let size = [width.max(1), height.max(1)];
        let tex = |label: &str, format, usage| texture_2d(device, label, format, size, usage);
        let input = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let output = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let exchanged = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let scalar = wgpu::TextureFormat::R32Float;
        let (fixed, adaptive) = match model {
            Model::Fixed(_) => (Some(pipeline("sss_fixed")), None),
            Model::As | Model::Ccv | Model::Ocv => (
                None,
                Some(Adaptive {
                    gamma_pipeline: pipeline("sss_gamma"),
                    sample_pipeline: pipeline("sss_sample"),
                    motion: tex("zero motion", wgpu::TextureFormat::Rg16Float, input),
                    gamma: tex("gamma", scalar, exchanged),
                    value: tex("monitored luminance", scalar, exchanged),
                    control: tex("control luminance", scalar, exchanged),
                    component: None,
                }),
            ),
        };
        let levels = 32 - width.max(height).max(1).leading_zeros();
        let lighting = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("lighting B"),
            size: wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FMT_RGBA16F,
            usage: input,
            view_formats: &[],
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("PassParams"),
            size: size_of::<PassParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row(width.max(1), 8)) * u64::from(height.max(1)),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let timestamps = timestamps.then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_PASSES,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: TIMESTAMP_BYTES,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size: TIMESTAMP_BYTES,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (set, resolve, read)
        });
        let depth = wgpu::TextureFormat::R32Float;
        let mask = wgpu::TextureFormat::R8Uint;
        Self {
            device: device.clone(),
            queue: queue.clone(),
            width,
            height,
            model,
            fixed,
            adaptive,
            params,
            lighting,
            depth: [tex("depth a", depth, input), tex("depth b", depth, input)],
            mask: [tex("mask a", mask, input), tex("mask b", mask, input)],
            last: 1,
            result: tex("result", FMT_RGBA16F, output),
            // Also sampled: the budget reduction (`crate::reduce`) reads the counts.
            count: tex(
                "count",
                wgpu::TextureFormat::R32Uint,
                output | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            readback,
            timestamps,
        }
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
    /// (for `crate::reduce`); `None` without history (a fixed count, or before the first
    /// frame).
    pub(crate) fn reduce_textures(
        &self,
    ) -> Option<(
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
    )> {
        let (_, a) = self.adaptive.as_ref()?.component.as_ref()?;
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
        self.adaptive.as_ref()?.component.as_ref().map(|(_, a)| a)
    }

    fn upload<T: bytemuck::Pod>(&self, texture: &wgpu::Texture, data: &[T], texel_bytes: u32) {
        self.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(self.width * texel_bytes),
                rows_per_image: Some(self.height),
            },
            self.extent(),
        );
    }

    fn extent(&self) -> wgpu::Extent3d {
        wgpu::Extent3d {
            width: self.width,
            height: self.height,
            depth_or_array_layers: 1,
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
        let setup = p.component_setup(self.model)?;
        self.prepare_component(setup.as_ref(), &p)?;
        let (cur, prev) = (1 - self.last, self.last);
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        self.upload(&self.lighting, &inputs.lighting, 8);
        if p.afis != 0 {
            for (k, (mw, mh, texels)) in inputs.lighting_mips().iter().enumerate() {
                self.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &self.lighting,
                        mip_level: k as u32 + 1,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    bytemuck::cast_slice(texels),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(mw * 8),
                        rows_per_image: Some(*mh),
                    },
                    wgpu::Extent3d {
                        width: *mw,
                        height: *mh,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        self.upload(&self.depth[cur], &inputs.depth, 4);
        self.upload(&self.mask[cur], &inputs.mask, 1);

        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sss") });
        // Every pass writes its own begin/end pair; the pass time spans the first begin to
        // the last end (barriers between the passes included) when every pair is ordered.
        let stamp = |k: u32| {
            self.timestamps
                .as_ref()
                .map(|(set, _, _)| wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: Some(2 * k),
                    end_of_pass_write_index: Some(2 * k + 1),
                })
        };
        let passes = if self.fixed.is_some() { 1 } else { MAX_PASSES };
        let count = match (&self.fixed, &mut self.adaptive) {
            (Some(fixed), _) => {
                let views = [
                    (1, self.lighting.create_view(&Default::default())),
                    (2, view(&self.depth[cur])),
                    (3, view(&self.mask[cur])),
                    (4, view(&self.result)),
                    (5, view(&self.count)),
                ];
                let group = sss_group(&self.device, &self.params, fixed, &views);
                dispatch(
                    &mut encoder,
                    "sss_fixed",
                    fixed,
                    &group,
                    stamp(0),
                    [self.width, self.height],
                );
                self.count.clone()
            }
            (None, Some(ad)) => {
                let Some((_, component)) = ad.component.as_mut() else {
                    return Err(PassError::ControllerChanged);
                };
                let size = [self.width, self.height];
                let views = [(2, view(&self.depth[cur])), (7, view(&ad.gamma))];
                let group = sss_group(&self.device, &self.params, &ad.gamma_pipeline, &views);
                dispatch(
                    &mut encoder,
                    "sss_gamma",
                    &ad.gamma_pipeline,
                    &group,
                    stamp(0),
                    size,
                );
                component.record_estimate_timed(
                    &mut encoder,
                    &EstimateInputs {
                        motion: &ad.motion,
                        depth: &self.depth[cur],
                        previous_depth: &self.depth[prev],
                        masks: Some(Masks {
                            current: &self.mask[cur],
                            previous: &self.mask[prev],
                        }),
                        gamma: Some(&ad.gamma),
                    },
                    stamp(1),
                )?;
                let views = [
                    (1, self.lighting.create_view(&Default::default())),
                    (2, view(&self.depth[cur])),
                    (3, view(&self.mask[cur])),
                    (4, view(&self.result)),
                    (6, view(component.count_texture())),
                    (8, view(&ad.value)),
                    (9, view(&ad.control)),
                ];
                let group = sss_group(&self.device, &self.params, &ad.sample_pipeline, &views);
                dispatch(
                    &mut encoder,
                    "sss_sample",
                    &ad.sample_pipeline,
                    &group,
                    stamp(2),
                    size,
                );
                let control = component.control().needs_control().then_some(&ad.control);
                component.record_update_timed(
                    &mut encoder,
                    &UpdateInputs {
                        value: &ad.value,
                        control,
                    },
                    stamp(3),
                )?;
                component.count_texture().clone()
            }
            (None, None) => return Err(PassError::ControllerChanged),
        };
        if let Some((set, resolve, read)) = &self.timestamps {
            encoder.resolve_query_set(set, 0..2 * passes, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16 * u64::from(passes));
        }
        let start = std::time::Instant::now();
        self.queue.submit([encoder.finish()]);
        self.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;

        let (time_ms, timer) = match &self.timestamps {
            Some((_, _, read)) => {
                let ticks: Vec<u64> = self.map_read(read, 16 * u64::from(passes))?;
                let period = f64::from(self.queue.get_timestamp_period());
                let ordered = ticks.windows(2).all(|w| w[0] <= w[1]);
                match (ticks.first(), ticks.last()) {
                    (Some(t0), Some(t1)) if ordered && t1 > t0 => {
                        ((t1 - t0) as f64 * period * 1e-6, Timer::GpuTimestamp)
                    }
                    _ => (wall_ms, Timer::WallClock),
                }
            }
            None => (wall_ms, Timer::WallClock),
        };
        let result: Vec<[f16; 4]> = self.read_texture(&self.result, 8)?;
        let count: Vec<u32> = self.read_texture(&count, 4)?;
        self.last = cur;
        Ok(FrameOutput {
            result,
            count,
            time_ms,
            timer,
        })
    }

    /// Builds the adaptive component at the first frame, checks later frames' controllers
    /// against it, and sets the frame's target.
    fn prepare_component(
        &mut self,
        setup: Option<&ComponentSetup>,
        p: &PassParams,
    ) -> Result<(), PassError> {
        let (Some(ad), Some(setup)) = (self.adaptive.as_mut(), setup) else {
            return Ok(());
        };
        let component = match &mut ad.component {
            Some((s, a)) if s.config == setup.config && s.control == setup.control => a,
            Some(_) => return Err(PassError::ControllerChanged),
            None => {
                let a = AdaptivePass::new(
                    &self.device,
                    setup.config,
                    setup.control,
                    self.width,
                    self.height,
                )?;
                check_encoding(&a, p)?;
                &mut ad.component.insert((*setup, a)).1
            }
        };
        component.set_target_variance(setup.target)?;
        Ok(())
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
                h.h = self.read_texture(a.history_texture(), 8)?;
                if let Some(cv) = a.cv_history_texture() {
                    h.j = self.read_texture(cv, 8)?;
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

    fn wait(&self) -> Result<(), PassError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| PassError::Device(e.to_string()))
    }

    fn map_read<T: bytemuck::Pod>(
        &self,
        buffer: &wgpu::Buffer,
        bytes: u64,
    ) -> Result<Vec<T>, PassError> {
        let slice = buffer.slice(0..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| PassError::Device(e.to_string()))?
            .map_err(|e| PassError::Device(e.to_string()))?;
        let out = {
            let view = slice
                .get_mapped_range()
                .map_err(|e| PassError::Device(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        buffer.unmap();
        Ok(out)
    }

    fn read_texture<T: bytemuck::Pod>(
        &self,
        texture: &wgpu::Texture,
        texel_bytes: u32,
    ) -> Result<Vec<T>, PassError> {
        let row = padded_row(self.width, texel_bytes);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("readback"),
            });
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(self.height),
                },
            },
            self.extent(),
        );
        self.queue.submit([encoder.finish()]);
        let bytes: Vec<u8> =
            self.map_read(&self.readback, u64::from(row) * u64::from(self.height))?;
        let tight = (self.width * texel_bytes) as usize;
        let mut packed = Vec::with_capacity(tight * self.height as usize);
        for line in bytes.chunks(row as usize) {
            packed.extend_from_slice(line.get(..tight).unwrap_or(line));
        }
        Ok(bytemuck::pod_collect_to_vec(&packed))
    }
}

/// A view of mip 0 (every texture but the lighting, whose whole mip chain AFIS reads).
fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        base_mip_level: 0,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// The bind group of one `sss.wgsl` entry point (its layout holds only the bindings it
/// uses): the uniform block at 0 and `views`.
fn sss_group(
    device: &wgpu::Device,
    params: &wgpu::Buffer,
    pipeline: &wgpu::ComputePipeline,
    views: &[(u32, wgpu::TextureView)],
) -> wgpu::BindGroup {
    crate::resources::bind_group(
        device,
        Some("sss"),
        &pipeline.get_bind_group_layout(0),
        &[(0, params)],
        views,
    )
}

fn dispatch(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    [width, height]: [u32; 2],
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
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
