//! The conversion pass: Bevy's prepass depth (reverse-Z NDC), motion vectors (UV units)
//! and geometry coverage to the component's linear depth, pixel motion and mask
//! (`convert.wgsl` says how each is converted and why).

use bevy::math::Mat4;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt as _;
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

/// Format of the converted linear depth (one of the component's depth formats).
pub const LINEAR_DEPTH_FORMAT: Tf = Tf::R32Float;
/// Format of the converted motion vectors, in pixels (one of the component's motion formats).
pub const MOTION_PIXELS_FORMAT: Tf = Tf::Rg32Float;
/// Format of the converted geometry mask (one of the component's mask formats).
pub const MASK_FORMAT: Tf = Tf::R32Uint;
/// Format of the monitored-value texture the plugin owns for each view.
pub const VALUE_FORMAT: Tf = Tf::R32Float;

const SOURCE: &str = include_str!("convert.wgsl");

/// The uniform block of `convert.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ConvertBlock {
    view_from_clip: [f32; 16],
    size: [u32; 2],
    skip_background: u32,
    pad: u32,
}

/// The conversion pipeline, shared by every view (it holds no per-view state).
#[derive(Debug)]
pub(crate) struct ConvertPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ConvertPipeline {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("spvg-bevy convert.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SOURCE.into()),
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let storage = |binding, format| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: cs,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("spvg-bevy convert"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: cs,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: cs,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: cs,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                storage(3, LINEAR_DEPTH_FORMAT),
                storage(4, MOTION_PIXELS_FORMAT),
                storage(5, MASK_FORMAT),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("spvg-bevy convert"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("spvg-bevy convert"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("convert"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self { layout, pipeline }
    }

    /// Records the conversion of this frame's prepass outputs into `out`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        view_from_clip: Mat4,
        size: [u32; 2],
        skip_background: bool,
        depth: &wgpu::TextureView,
        motion: &wgpu::TextureView,
        out: [&wgpu::Texture; 3],
    ) {
        let block = ConvertBlock {
            view_from_clip: view_from_clip.to_cols_array(),
            size,
            skip_background: u32::from(skip_background),
            pad: 0,
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("spvg-bevy convert"),
            contents: bytemuck::bytes_of(&block),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let views = out.map(|t| t.create_view(&Default::default()));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spvg-bevy convert"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(depth),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(motion),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&views[0]),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&views[1]),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::TextureView(&views[2]),
                },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("spvg-bevy convert"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(size[0].div_ceil(8), size[1].div_ceil(8), 1);
    }
}

/// A frame-size texture of the plugin's (converted inputs, the value texture).
pub(crate) fn texture(
    device: &wgpu::Device,
    label: &str,
    format: Tf,
    size: [u32; 2],
) -> wgpu::Texture {
    let mut usage = Tu::TEXTURE_BINDING | Tu::STORAGE_BINDING | Tu::COPY_SRC;
    if format == VALUE_FORMAT {
        // The user's pass may write the value from a fragment shader.
        usage |= Tu::RENDER_ATTACHMENT;
    }
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size[0],
            height: size[1],
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
