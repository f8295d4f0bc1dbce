//! The conversion pass: Bevy's prepass depth (reverse-Z NDC), motion vectors (UV units)
//! and geometry coverage to the component's linear depth, pixel motion and mask
//! (`convert.wgsl` says how each is converted and why).

use bevy::math::Mat4;
use bevy::render::render_resource::{
    Extent3d, Texture, TextureDescriptor, TextureDimension, TextureFormat as Tf,
    TextureUsages as Tu, TextureView, TextureViewId,
};
use bevy::render::renderer::RenderDevice;
use bytemuck::{Pod, Zeroable};

/// Format of the converted linear depth (one of the component's depth formats).
pub const LINEAR_DEPTH_FORMAT: Tf = Tf::R32Float;
/// Format of the converted motion vectors, in pixels (one of the component's motion formats).
pub const MOTION_PIXELS_FORMAT: Tf = Tf::Rg32Float;
/// Format of the converted geometry mask (one of the component's mask formats).
pub const MASK_FORMAT: Tf = Tf::R32Uint;
/// Format of the monitored-value textures the plugin owns for each view.
pub const VALUE_FORMAT: Tf = Tf::R32Float;

const SOURCE: &str = include_str!("convert.wgsl");

/// The uniform block of `convert.wgsl` (twin of its `Convert`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct ConvertBlock {
    pub(crate) view_from_clip: [f32; 16],
    pub(crate) size: [u32; 2],
    pub(crate) origin: [u32; 2],
    pub(crate) skip_background: u32,
    pub(crate) pad: [u32; 3],
}

const _: () = assert!(
    size_of::<ConvertBlock>() == 96,
    "ConvertBlock must have the layout of convert.wgsl's Convert"
);

impl ConvertBlock {
    pub(crate) fn new(
        view_from_clip: Mat4,
        size: [u32; 2],
        origin: [u32; 2],
        skip_background: bool,
    ) -> Self {
        Self {
            view_from_clip: view_from_clip.to_cols_array(),
            size,
            origin,
            skip_background: u32::from(skip_background),
            pad: [0; 3],
        }
    }
}

/// The conversion pipeline, shared by every view (it holds no per-view state).
#[derive(Debug)]
pub(crate) struct ConvertPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// One view's conversion resources, made once: its uniform buffer (written every frame)
/// and a bind group per output slot, made again only when Bevy hands over other prepass
/// textures (a resize, another camera setup).
#[derive(Debug)]
pub(crate) struct ConvertBindings {
    uniform: wgpu::Buffer,
    written: Option<ConvertBlock>,
    groups: [Option<([TextureViewId; 2], wgpu::BindGroup)>; 2],
}

impl ConvertPipeline {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("spvg-bevy convert.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SOURCE.into()),
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: cs,
            ty,
            count: None,
        };
        let texture = |sample_type| wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let storage = |format| wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("spvg-bevy convert"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(1, texture(wgpu::TextureSampleType::Depth)),
                entry(
                    2,
                    texture(wgpu::TextureSampleType::Float { filterable: false }),
                ),
                entry(3, storage(LINEAR_DEPTH_FORMAT)),
                entry(4, storage(MOTION_PIXELS_FORMAT)),
                entry(5, storage(MASK_FORMAT)),
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

    /// Records the conversion of this frame's prepass outputs (`depth`, `motion`) into the
    /// outputs of `slot`, with the block last written to `bindings`.
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &mut ConvertBindings,
        slot: usize,
        [depth, motion]: [&TextureView; 2],
        out: [&TextureView; 3],
    ) {
        let key = [depth.id(), motion.id()];
        let group = match &mut bindings.groups[slot] {
            Some((k, group)) if *k == key => group,
            entry => {
                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("spvg-bevy convert"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: bindings.uniform.as_entire_binding(),
                        },
                        view_entry(1, depth),
                        view_entry(2, motion),
                        view_entry(3, out[0]),
                        view_entry(4, out[1]),
                        view_entry(5, out[2]),
                    ],
                });
                &mut entry.insert((key, group)).1
            }
        };
        let size = bindings.written.map_or([0, 0], |b| b.size);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("spvg-bevy convert"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &*group, &[]);
        pass.dispatch_workgroups(size[0].div_ceil(8), size[1].div_ceil(8), 1);
    }
}

fn view_entry(binding: u32, view: &TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

impl ConvertBindings {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("spvg-bevy convert"),
                size: size_of::<ConvertBlock>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            written: None,
            groups: [None, None],
        }
    }

    /// Writes `block` for the next conversion, unless it is what the buffer holds.
    pub(crate) fn write(&mut self, queue: &wgpu::Queue, block: ConvertBlock) {
        if self.written != Some(block) {
            queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&block));
            self.written = Some(block);
        }
    }

    /// Forgets the bind groups (their outputs were made anew).
    pub(crate) fn clear(&mut self) {
        self.groups = [None, None];
    }
}

/// A 2D texture of the plugin's (converted inputs, value textures) with its default view.
pub(crate) fn texture(
    device: &RenderDevice,
    label: &'static str,
    format: Tf,
    size: [u32; 2],
) -> (Texture, TextureView) {
    let mut usage = Tu::TEXTURE_BINDING | Tu::STORAGE_BINDING | Tu::COPY_SRC;
    if format == VALUE_FORMAT {
        // The user's pass may write the value from a fragment shader, and the update step
        // copies a viewport out of the render-target-sized one.
        usage |= Tu::RENDER_ATTACHMENT | Tu::COPY_DST;
    }
    let texture = device.create_texture(&TextureDescriptor {
        label: Some(label),
        size: Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}
