//! The user side of the soft-shadow example (and of the headless test): a stochastic
//! effect that reads spvg's counts in its own render-world pass, written the way a Bevy
//! user would write it, against the plugin's public API only.

use std::collections::HashMap;

use bevy::asset::uuid_handle;
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::diagnostic::FrameCount;
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, CachedRenderPipelineId, FragmentState, PipelineCache,
    RenderPipelineDescriptor, VertexState,
};
use bevy::render::renderer::{RenderContext, RenderDevice, ViewQuery};
use bevy::render::sync_world::RenderEntity;
use bevy::render::view::{ExtractedView, ViewTarget};
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderSystems};
use bevy::shader::Shader;
use bytemuck::{Pod, Zeroable};
use spvg_bevy::{SpvgSystems, SpvgView, VALUE_FORMAT};
use wgpu::util::DeviceExt as _;

/// Spheres (at most 16) that cast shadows, and the rectangular area light.
#[derive(Resource, Clone, Debug)]
pub struct ShadowScene {
    /// Centre and radius of each occluding sphere.
    pub spheres: Vec<Vec4>,
    /// A corner of the light and its two edges.
    pub light_corner: Vec3,
    pub light_u: Vec3,
    pub light_v: Vec3,
}

/// How many shadow rays a camera's effect takes per pixel.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SoftShadows {
    /// spvg's count (the camera also needs `AdaptiveSampling`).
    Adaptive,
    /// This many everywhere.
    Fixed(u32),
    /// This many everywhere, on a sequence independent of the other modes' (a reference
    /// image must not share the estimates it judges).
    Reference(u32),
}

pub struct SoftShadowsPlugin;

/// The effect's shader (WESL: it imports the spvg library by module path).
const EFFECT_SHADER: Handle<Shader> = uuid_handle!("0b6f6c1e-8f0e-4a53-9d0c-3c1f5e2a7d41");

impl Plugin for SoftShadowsPlugin {
    fn build(&self, app: &mut App) {
        if let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() {
            let _ = shaders.insert(
                EFFECT_SHADER.id(),
                Shader::from_wesl(include_str!("effect.wesl"), "soft_shadows/effect.wesl"),
            );
        }
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<EffectPipelines>()
            .add_systems(ExtractSchedule, extract)
            .add_systems(Render, queue_pipelines.in_set(RenderSystems::Prepare))
            .add_systems(
                Core3d,
                soft_shadows
                    .after(Core3dSystems::MainPass)
                    .after(SpvgSystems::Estimate)
                    .before(SpvgSystems::Update)
                    .before(Core3dSystems::EarlyPostProcess),
            );
    }
}

fn extract(
    mut commands: Commands,
    scene: Extract<Option<Res<ShadowScene>>>,
    cameras: Extract<Query<(RenderEntity, &SoftShadows)>>,
) {
    if let Some(scene) = scene.as_ref() {
        commands.insert_resource((**scene).clone());
    }
    for (entity, mode) in &cameras {
        commands.entity(entity).insert(*mode);
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Block {
    world_from_clip: [f32; 16],
    light_corner: [f32; 4],
    light_u: [f32; 4],
    light_v: [f32; 4],
    size: [u32; 2],
    frame: u32,
    fixed_count: u32,
    sphere_count: u32,
    pad: [u32; 3],
    spheres: [[f32; 4]; 16],
}

/// The effect's pipelines (in Bevy's pipeline cache) per target format, and per view a
/// scratch value texture for cameras without spvg.
#[derive(Resource, Default)]
struct EffectPipelines {
    ids: HashMap<wgpu::TextureFormat, CachedRenderPipelineId>,
    scratch: HashMap<Entity, wgpu::Texture>,
    no_counts: Option<wgpu::Texture>,
}

fn layout() -> BindGroupLayoutDescriptor {
    let fs = wgpu::ShaderStages::FRAGMENT;
    let tex = |binding, sample_type| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: fs,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    BindGroupLayoutDescriptor::new(
        "soft shadows",
        &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: fs,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            tex(1, wgpu::TextureSampleType::Depth),
            tex(2, wgpu::TextureSampleType::Uint),
            tex(3, wgpu::TextureSampleType::Float { filterable: false }),
        ],
    )
}

/// Queues the effect's pipeline for each view target format in use (Bevy compiles the WESL
/// shader, resolving its import of the spvg library).
fn queue_pipelines(
    views: Query<&ViewTarget, With<SoftShadows>>,
    cache: Res<PipelineCache>,
    mut pipelines: ResMut<EffectPipelines>,
) {
    for target in &views {
        let format = target.main_texture_format();
        pipelines.ids.entry(format).or_insert_with(|| {
            cache.queue_render_pipeline(RenderPipelineDescriptor {
                label: Some("soft shadows".into()),
                layout: vec![layout()],
                vertex: VertexState {
                    shader: EFFECT_SHADER,
                    entry_point: Some("vertex".into()),
                    ..default()
                },
                fragment: Some(FragmentState {
                    shader: EFFECT_SHADER,
                    entry_point: Some("fragment".into()),
                    targets: vec![Some(format.into()), Some(VALUE_FORMAT.into())],
                    ..default()
                }),
                ..default()
            })
        });
    }
}

fn texture(device: &wgpu::Device, format: wgpu::TextureFormat, size: [u32; 2]) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("soft shadows scratch"),
        size: wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

#[allow(clippy::type_complexity)]
fn soft_shadows(
    view: ViewQuery<(
        Entity,
        &SoftShadows,
        &ViewTarget,
        &ViewPrepassTextures,
        &ExtractedView,
        &ExtractedCamera,
        Option<&SpvgView>,
    )>,
    scene: Option<Res<ShadowScene>>,
    mut pipelines: ResMut<EffectPipelines>,
    cache: Res<PipelineCache>,
    frame: Res<FrameCount>,
    device: Res<RenderDevice>,
    mut ctx: RenderContext,
) {
    let (entity, mode, target, prepass, extracted, camera, spvg) = view.into_inner();
    let (Some(scene), Some(depth), Some(size)) = (
        scene,
        prepass.depth_only_view(),
        camera.physical_viewport_size,
    ) else {
        return;
    };
    let size = [size.x, size.y];
    let device = device.wgpu_device();
    let (fixed_count, count_view, value) = match (mode, spvg) {
        (SoftShadows::Adaptive, Some(spvg)) => {
            (0, spvg.count_view().clone(), spvg.value_texture().clone())
        }
        (SoftShadows::Adaptive, None) => return,
        (SoftShadows::Fixed(n) | SoftShadows::Reference(n), _) => {
            let scratch = pipelines
                .scratch
                .entry(entity)
                .or_insert_with(|| texture(device, VALUE_FORMAT, size));
            if scratch.width() != size[0] || scratch.height() != size[1] {
                *scratch = texture(device, VALUE_FORMAT, size);
            }
            let scratch = scratch.clone();
            let counts = pipelines
                .no_counts
                .get_or_insert_with(|| texture(device, wgpu::TextureFormat::R32Uint, [1, 1]))
                .create_view(&Default::default());
            ((*n).max(1), counts, scratch)
        }
    };
    let Some(pipeline) = pipelines
        .ids
        .get(&target.main_texture_format())
        .and_then(|id| cache.get_render_pipeline(*id))
    else {
        // Not compiled yet: the frame goes without the effect.
        return;
    };
    let layout = cache.get_bind_group_layout(&layout());
    let world_from_clip =
        extracted.world_from_view.to_matrix() * extracted.clip_from_view.inverse();
    let mut spheres = [[0.0; 4]; 16];
    for (s, v) in spheres.iter_mut().zip(&scene.spheres) {
        *s = v.to_array();
    }
    let block = Block {
        world_from_clip: world_from_clip.to_cols_array(),
        light_corner: scene.light_corner.extend(0.0).to_array(),
        light_u: scene.light_u.extend(0.0).to_array(),
        light_v: scene.light_v.extend(0.0).to_array(),
        size,
        // Bevy's frame counter: the cameras of a frame share the sequence, but for the
        // reference.
        frame: match mode {
            SoftShadows::Reference(_) => frame.0 ^ 0x5bd1_e995,
            _ => frame.0,
        },
        fixed_count,
        sphere_count: scene.spheres.len().min(16) as u32,
        pad: [0; 3],
        spheres,
    };
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("soft shadows"),
        contents: bytemuck::bytes_of(&block),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let post = target.post_process_write();
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("soft shadows"),
        layout: &layout,
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
                resource: wgpu::BindingResource::TextureView(&count_view),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(post.source),
            },
        ],
    });
    let value_view = value.create_view(&Default::default());
    let mut pass = ctx
        .command_encoder()
        .begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("soft shadows"),
            color_attachments: &[
                Some(wgpu::RenderPassColorAttachment {
                    view: post.destination,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations::default(),
                }),
                Some(wgpu::RenderPassColorAttachment {
                    view: &value_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations::default(),
                }),
            ],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    pass.draw(0..3, 0..1);
}
