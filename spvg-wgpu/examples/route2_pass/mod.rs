//! Route 2 of docs/integrating.md: a renderer's own single compute pass that calls the
//! spvg-shaders library itself (reprojection, estimate, dilation, its own sampling, update)
//! instead of recording `spvg_wgpu::adaptive::AdaptivePass`. Plain wgpu; shared by
//! `examples/route2.rs` and `tests/route2.rs` (included with `#[path]`), with the moving
//! scene both run.
#![allow(dead_code, reason = "the example and the test each use a part")]

use spvg::SpvgConfig;
use spvg::reproject::{BorderCount, Reprojection};
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Control, Params, Storage, StoreRounding};
use wgpu::util::DeviceExt as _;

/// The pass's WGSL: the library, then `route2.wgsl`.
pub(crate) fn shader_source() -> String {
    format!("{}{}", spvg_shaders::WGSL, include_str!("route2.wgsl"))
}

/// Rust twin of `struct FrameUniforms` in `route2.wgsl` (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniforms {
    width: u32,
    height: u32,
    frame: u32,
    dilation: u32,
    /// `spvg_Reprojection`: the depth tolerance and the `spvg_REPROJECT_*` flags.
    depth_tolerance: f32,
    reproject_flags: u32,
    pad: [u32; 2],
}

/// The library's `spvg_REPROJECT_*` flags of a reprojection rule.
pub(crate) fn reproject_flags(r: &Reprojection<f32>) -> u32 {
    u32::from(r.border_prior())
        | (u32::from(r.footprint_search()) << 1)
        | (u32::from(r.border_count() == BorderCount::Maximum) << 2)
}

/// One frame's inputs, the frame size, `TEXTURE_BINDING`.
#[derive(Debug)]
pub(crate) struct Inputs<'a> {
    /// Motion in pixels, this frame's position minus the previous one's (`Rg32Float`).
    pub(crate) motion: &'a wgpu::Texture,
    /// Linear depth (`R32Float`).
    pub(crate) depth: &'a wgpu::Texture,
    /// The previous frame's depth (`R32Float`).
    pub(crate) previous_depth: &'a wgpu::Texture,
    /// The scene: the radiance's mean and noise amplitude per pixel (`Rg32Float`).
    pub(crate) radiance: &'a wgpu::Texture,
}

/// The renderer's adaptive pass: its pipeline, its history ping-pong and its outputs.
#[derive(Debug)]
pub(crate) struct Route2Pass {
    pipeline: wgpu::ComputePipeline,
    controller: wgpu::Buffer,
    uniforms: wgpu::Buffer,
    history: [wgpu::Texture; 2],
    count: wgpu::Texture,
    value: wgpu::Texture,
    read: usize,
    frame: u32,
    width: u32,
    height: u32,
    dilation: u32,
    reprojection: Reprojection<f32>,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl Route2Pass {
    /// The pass for `config` (AS: the history monitors the value itself), histories in
    /// f16 texels rounded to nearest, the variance relative to the power of two nearest
    /// the target; the default reprojection rule, no dilation.
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
            label: Some("route2.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader_source().into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("route2"),
            layout: None,
            module: &module,
            entry_point: Some("route2"),
            compilation_options: Default::default(),
            cache: None,
        });
        use wgpu::TextureFormat as F;
        use wgpu::TextureUsages as U;
        let out = U::STORAGE_BINDING | U::COPY_SRC;
        let history = [0, 1].map(|_| {
            texture(
                device,
                "route2 history",
                width,
                height,
                F::Rgba16Float,
                out | U::TEXTURE_BINDING,
            )
        });
        Ok(Self {
            pipeline,
            controller,
            uniforms,
            history,
            count: texture(device, "route2 count", width, height, F::R32Uint, out),
            value: texture(
                device,
                "route2 value",
                width,
                height,
                F::R32Float,
                out | U::TEXTURE_BINDING,
            ),
            read: 0,
            frame: 0,
            width,
            height,
            dilation: 0,
            reprojection: Reprojection::default(),
        })
    }

    /// The count dilation radius (0: off).
    pub(crate) fn set_count_dilation(&mut self, radius: u32) {
        self.dilation = radius;
    }

    /// The reprojection rule.
    pub(crate) fn set_reprojection(&mut self, reprojection: Reprojection<f32>) {
        self.reprojection = reprojection;
    }

    /// Records the frame's pass into `encoder` (its uniforms written through `queue`).
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
            depth_tolerance: self.reprojection.depth_tolerance(),
            reproject_flags: reproject_flags(&self.reprojection),
            pad: [0; 2],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let views = [
            view(inputs.motion),
            view(inputs.depth),
            view(inputs.previous_depth),
            view(inputs.radiance),
            view(&self.history[self.read]),
            view(&self.history[1 - self.read]),
            view(&self.count),
            view(&self.value),
        ];
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: self.controller.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: self.uniforms.as_entire_binding(),
            },
        ];
        entries.extend(
            views
                .iter()
                .zip(2..)
                .map(|(v, binding)| wgpu::BindGroupEntry {
                    binding,
                    resource: wgpu::BindingResource::TextureView(v),
                }),
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("route2"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("route2"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        self.read = 1 - self.read;
        self.frame += 1;
    }

    /// The counts of the last frame (`R32Uint`).
    pub(crate) fn count_texture(&self) -> &wgpu::Texture {
        &self.count
    }

    /// The monitored values of the last frame: the mean of its samples (`R32Float`).
    pub(crate) fn value_texture(&self) -> &wgpu::Texture {
        &self.value
    }

    /// The history after the last frame (`Rgba16Float`, spare channel = written).
    pub(crate) fn history_texture(&self) -> &wgpu::Texture {
        &self.history[self.read]
    }
}

/// A wgpu device on the first adapter, and its description.
pub(crate) fn device() -> Result<(wgpu::Device, wgpu::Queue, String), String> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
        .into_iter()
        .next()
        .ok_or("no wgpu adapter (install mesa-vulkan-drivers for lavapipe)")?;
    let info = adapter.get_info();
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("route2"),
        ..Default::default()
    }))
    .map_err(|e| e.to_string())?;
    Ok((
        device,
        queue,
        format!("{} [{:?}, {:?}]", info.name, info.device_type, info.backend),
    ))
}

/// One frame of [`Scene`], row-major.
#[derive(Clone, Debug, Default)]
pub(crate) struct SceneFrame {
    /// Pixels, this frame's position minus the previous frame's.
    pub(crate) motion: Vec<[f32; 2]>,
    /// Linear depth.
    pub(crate) depth: Vec<f32>,
    /// The radiance's mean and noise amplitude.
    pub(crate) radiance: Vec<[f32; 2]>,
}

/// A tilted surface seen by a camera panning at fractional, changing speeds (pixels enter
/// at the edges: the border prior), with a disc at half the depth crossing it at 2.3 px per
/// frame (the surface it uncovers is disoccluded; next to its silhouette the footprint
/// search finds the surface one texel away).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scene {
    /// Width in pixels.
    pub(crate) width: u32,
    /// Height in pixels.
    pub(crate) height: u32,
}

impl Scene {
    fn camera(t: u32) -> [f32; 2] {
        let t = t as f32;
        [1.5 * t - 0.125 * t * t, 0.35 * t]
    }

    fn disc(t: u32) -> [f32; 2] {
        [6.0 + 2.3 * t as f32, 12.0]
    }

    /// Frame `t`.
    pub(crate) fn frame(&self, t: u32) -> SceneFrame {
        let (c, cp) = (Self::camera(t), Self::camera(t.saturating_sub(1)));
        let (o, op) = (Self::disc(t), Self::disc(t.saturating_sub(1)));
        let mut f = SceneFrame::default();
        for y in 0..self.height {
            for x in 0..self.width {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let (wx, wy) = (px + c[0], py + c[1]);
                if (px - o[0]).powi(2) + (py - o[1]).powi(2) < 30.0 {
                    f.motion.push([o[0] - op[0], o[1] - op[1]]);
                    f.depth.push(0.5);
                    f.radiance.push([0.2, 0.05]);
                } else {
                    f.motion.push([cp[0] - c[0], cp[1] - c[1]]);
                    f.depth.push(1.0 + 0.003 * wx);
                    // Smooth lighting, a noise amplitude that varies over the surface.
                    let mean = 0.5 + 0.3 * (0.2 * wx).sin() * (0.15 * wy).cos();
                    let amplitude = 0.05 + 0.4 * (0.5 + 0.5 * (0.37 * wx + 0.23 * wy).sin());
                    f.radiance.push([mean, amplitude]);
                }
            }
        }
        f
    }

    /// `frame` uploaded: motion, depth, radiance.
    pub(crate) fn upload(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame: &SceneFrame,
    ) -> [wgpu::Texture; 3] {
        use wgpu::TextureFormat as F;
        let put = |format: F, data: &[u8]| {
            device.create_texture_with_data(
                queue,
                &wgpu::TextureDescriptor {
                    label: Some("route2 scene"),
                    size: wgpu::Extent3d {
                        width: self.width,
                        height: self.height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                data,
            )
        };
        [
            put(F::Rg32Float, bytemuck::cast_slice(&frame.motion)),
            put(F::R32Float, bytemuck::cast_slice(&frame.depth)),
            put(F::Rg32Float, bytemuck::cast_slice(&frame.radiance)),
        ]
    }
}
