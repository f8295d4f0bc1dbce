//! Route 2 of docs/integrating.md: a renderer's own adaptive pass that calls the
//! spvg-shaders library itself instead of recording `spvg_wgpu::adaptive::AdaptivePass`.
//! Plain wgpu (its textures made with `spvg_wgpu::util`), the library (`spvg_shaders::WGSL`) and the renderer's shader (`pass.wgsl`):
//! estimate, dilation with the neighbour prior, sampling and update with the spatial
//! moments of young histories, one dispatch each, with the component's default rules.
//! Shared by `examples/route2/main.rs` and `tests/route2.rs` (included with `#[path]`).
#![allow(dead_code, reason = "the example and the test each use a part")]

use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Control, Params, ReprojectionRule, Storage, StoreRounding};
use wgpu::util::DeviceExt as _;

/// The pass's WGSL: the library, then `pass.wgsl`.
pub(crate) fn shader_source() -> String {
    format!("{}{}", spvg_shaders::WGSL, include_str!("pass.wgsl"))
}

/// Rust twin of `struct FrameUniforms` in `pass.wgsl` (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniforms {
    width: u32,
    height: u32,
    frame: u32,
    dilation: u32,
    /// `spvg_Reprojection`: the depth tolerance and the `spvg_REPROJECT_*` flags.
    rule: ReprojectionRule,
    /// The WGSL block rounds up to 16 bytes after `rule`.
    pad: [u32; 2],
}

const _: () = assert!(
    size_of::<FrameUniforms>() == 32,
    "FrameUniforms must match the 32-byte WGSL struct"
);

/// One frame's inputs, the frame size, `TEXTURE_BINDING`.
#[derive(Debug)]
pub(crate) struct Inputs<'a> {
    /// Motion vectors in the convention of `spvg::reproject` (`Rg32Float`).
    pub(crate) motion: &'a wgpu::Texture,
    /// Linear depth (`R32Float`).
    pub(crate) depth: &'a wgpu::Texture,
    /// The previous frame's depth (`R32Float`).
    pub(crate) previous_depth: &'a wgpu::Texture,
    /// The scene: the radiance's mean and noise amplitude per pixel (`Rg32Float`).
    pub(crate) radiance: &'a wgpu::Texture,
}

/// The renderer's adaptive pass: its pipelines, its history ping-pong and its textures
/// between the dispatches.
#[derive(Debug)]
pub(crate) struct Route2Pass {
    estimate: wgpu::ComputePipeline,
    dilate: wgpu::ComputePipeline,
    sample: wgpu::ComputePipeline,
    update: wgpu::ComputePipeline,
    controller: wgpu::Buffer,
    uniforms: wgpu::Buffer,
    history: [wgpu::Texture; 2],
    /// The estimate's counts, before the dilation (with a radius only).
    estimated: wgpu::Texture,
    /// The counts the frame samples with.
    count: wgpu::Texture,
    link: wgpu::Texture,
    value: wgpu::Texture,
    read: usize,
    frame: u32,
    width: u32,
    height: u32,
    dilation: u32,
    rule: ReprojectionRule,
}

/// A frame-size texture one dispatch writes and the next reads (`COPY_SRC` for the
/// read-backs).
fn texture(
    device: &wgpu::Device,
    label: &str,
    size: [u32; 2],
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    use wgpu::TextureUsages as U;
    let usage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
    spvg_wgpu::util::texture_2d(device, label, format, size, usage)
}

impl Route2Pass {
    /// The pass for `config` (AS: the history monitors the value itself), histories in
    /// f16 texels rounded to nearest, the variance relative to the power of two nearest
    /// the target (the component's storage); the default reprojection rule, no dilation.
    pub(crate) fn new(
        device: &wgpu::Device,
        config: &SpvgConfig<f32>,
        width: u32,
        height: u32,
    ) -> Result<Self, spvg::Error> {
        let storage = Storage {
            encoding: TexelEncoding::new(config.target_variance())?,
            layout: Layout::F16,
            rounding: StoreRounding::Nearest,
        };
        // The target as the f16 texel stores it, as the component runs it: a disocclusion
        // seed then decodes to the target exactly and estimates exactly its count.
        let config = storage.encoding.storable_config(config, Layout::F16)?;
        let params = Params::new(&config, Control::As, &storage);
        let controller = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("route2 spvg_Params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("route2 FrameUniforms"),
            size: size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("route2 pass.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader_source().into()),
        });
        // Layouts derived from each entry point: every dispatch binds what it uses.
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        use wgpu::TextureFormat as F;
        let size = [width, height];
        Ok(Self {
            estimate: pipeline("route2_estimate"),
            dilate: pipeline("route2_dilate"),
            sample: pipeline("route2_sample"),
            update: pipeline("route2_update"),
            controller,
            uniforms,
            history: [0, 1].map(|_| texture(device, "route2 history", size, F::Rgba16Float)),
            estimated: texture(device, "route2 estimated count", size, F::R32Uint),
            count: texture(device, "route2 count", size, F::R32Uint),
            link: texture(device, "route2 link", size, F::R32Uint),
            value: texture(device, "route2 value", size, F::R32Float),
            read: 0,
            frame: 0,
            width,
            height,
            dilation: 0,
            rule: ReprojectionRule::default(),
        })
    }

    /// The count dilation radius (0: off, and with it the neighbour prior).
    pub(crate) fn set_count_dilation(&mut self, radius: u32) {
        self.dilation = radius;
    }

    /// The reprojection rule.
    pub(crate) fn set_reprojection(&mut self, reprojection: &Reprojection<f32>) {
        self.rule = ReprojectionRule::new(reprojection);
    }

    /// Records the frame's four dispatches into `encoder` (its uniforms written through
    /// `queue`): estimate, dilation (with a radius), sampling, update.
    pub(crate) fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &Inputs<'_>,
    ) {
        let uniforms = FrameUniforms {
            width: self.width,
            height: self.height,
            frame: self.frame,
            dilation: self.dilation,
            rule: self.rule,
            pad: [0; 2],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let (h_in, h_out) = (&self.history[self.read], &self.history[1 - self.read]);
        // Without a radius the estimate writes the counts the frame samples with.
        let estimated = if self.dilation > 0 {
            &self.estimated
        } else {
            &self.count
        };
        let mut dispatch = |label: &str,
                            pipeline: &wgpu::ComputePipeline,
                            buffers: &[(u32, &wgpu::Buffer)],
                            textures: &[(u32, &wgpu::Texture)]| {
            let views: Vec<_> = textures.iter().map(|&(b, t)| (b, view(t))).collect();
            let entries: Vec<_> = buffers
                .iter()
                .map(|&(binding, b)| wgpu::BindGroupEntry {
                    binding,
                    resource: b.as_entire_binding(),
                })
                .chain(views.iter().map(|(binding, v)| wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: wgpu::BindingResource::TextureView(v),
                }))
                .collect();
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        };
        let (controller, frame) = ((0, &self.controller), (1, &self.uniforms));
        dispatch(
            "route2 estimate",
            &self.estimate,
            &[controller, frame],
            &[
                (2, inputs.motion),
                (3, inputs.depth),
                (4, inputs.previous_depth),
                (6, h_in),
                (9, estimated),
                (11, &self.link),
            ],
        );
        if self.dilation > 0 {
            dispatch(
                "route2 dilate",
                &self.dilate,
                &[frame],
                &[(3, inputs.depth), (8, &self.estimated), (9, &self.count)],
            );
        }
        dispatch(
            "route2 sample",
            &self.sample,
            &[frame],
            &[(5, inputs.radiance), (8, &self.count), (13, &self.value)],
        );
        dispatch(
            "route2 update",
            &self.update,
            &[controller, frame],
            &[
                (3, inputs.depth),
                (6, h_in),
                (7, h_out),
                (8, &self.count),
                (10, &self.link),
                (12, &self.value),
            ],
        );
        self.read = 1 - self.read;
        self.frame += 1;
    }

    /// The counts the last frame sampled with (`R32Uint`).
    pub(crate) fn count_texture(&self) -> &wgpu::Texture {
        &self.count
    }

    /// The last estimate's decisions (`R32Uint`): 1 + the previous frame's texel index of
    /// a continued history, else 0.
    pub(crate) fn link_texture(&self) -> &wgpu::Texture {
        &self.link
    }

    /// The monitored values of the last frame: the mean of its samples (`R32Float`).
    pub(crate) fn value_texture(&self) -> &wgpu::Texture {
        &self.value
    }

    /// The history after the last frame (`Rgba16Float`, spare channel = the history's
    /// age, 0 where none was written).
    pub(crate) fn history_texture(&self) -> &wgpu::Texture {
        &self.history[self.read]
    }
}
