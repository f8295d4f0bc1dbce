//! The effect helper: a user's adaptive effect as a WGSL (WESL) fragment shader and a
//! camera component, in the spirit of Bevy's `FullscreenMaterial`. The plugin owns the
//! pipeline, the bind groups (Bevy's view uniform, the main colour, spvg's counts, the
//! prepass depth and motion, spvg's links and previous history, the component as a
//! uniform), the value target and the order
//! between the estimate, the main pass and the update.

use core::any::type_name;
use core::marker::PhantomData;

use bevy::app::{App, Plugin};
use bevy::asset::{AssetServer, Handle};
use bevy::camera::Camera;
use bevy::core_pipeline::FullscreenShader;
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::schedule::Core3d;
use bevy::ecs::prelude::*;
use bevy::log::error;
use bevy::render::render_resource::binding_types::{
    sampler, texture_2d, texture_depth_2d, uniform_buffer,
};
use bevy::render::render_resource::encase::internal::WriteInto;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, BufferId,
    CachedRenderPipelineId, ColorTargetState, ColorWrites, FilterMode, FragmentState, Operations,
    PipelineCache, RenderPassColorAttachment, RenderPassDescriptor, RenderPipelineDescriptor,
    Sampler, SamplerBindingType, SamplerDescriptor, ShaderStages, ShaderType,
    SpecializedRenderPipeline, SpecializedRenderPipelines, TextureFormat, TextureSampleType,
    TextureViewId, UniformBuffer, VertexState,
};
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::sync_world::RenderEntity;
use bevy::render::view::{ExtractedView, ViewTarget, ViewUniform, ViewUniformOffset, ViewUniforms};
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::{Shader, ShaderRef};

use crate::{AdaptiveSampling, SpvgPlugin, SpvgSystems, SpvgView, VALUE_FORMAT};

/// A user's adaptive effect: a camera component whose fields are the effect's settings, and
/// a fragment shader that takes spvg's count of samples per pixel.
///
/// Add [`AdaptiveEffectPlugin::<T>`](AdaptiveEffectPlugin) (and [`SpvgPlugin`]) to the app and
/// `T` to a 3D camera; `T` requires [`AdaptiveSampling`] (its default settings unless the
/// camera has its own). Each frame, for each such camera, the plugin runs the shader over
/// the camera's viewport after the main pass (`SpvgSystems::Effect`: after the estimate
/// and `Core3dSystems::MainPass`, before the update and `Core3dSystems::EarlyPostProcess`,
/// so Bevy's TAA resolves the result), with Bevy's fullscreen vertex shader.
///
/// # The shader
///
/// A WESL shader with one fragment entry point taking
/// `bevy_core_pipeline::fullscreen_vertex_shader::FullscreenVertexOutput` and returning
/// `spvg_bevy::effect::EffectOutput` (`@location(0) color`, `@location(1) value`). Group 0
/// is declared by the module `spvg_bevy::effect` (Bevy's `View` uniform, the main colour
/// and a linear sampler, spvg's counts, the prepass depth and motion vectors, spvg's links
/// and previous history, with functions that read each at a fragment position); group 1, binding 0 is `T` as a
/// uniform, declared in the shader with the struct `T` derives [`ShaderType`] for. The
/// `color` output replaces the main colour; `value` is the monitored value spvg learns from
/// (the luminance of the effect's Monte Carlo result).
///
/// ```wgsl
/// import bevy_core_pipeline::fullscreen_vertex_shader::FullscreenVertexOutput;
/// import spvg_bevy::effect::{EffectOutput, sample_count, source_color};
///
/// struct Noise { amount: f32 }
/// @group(1) @binding(0) var<uniform> settings: Noise;
///
/// @fragment
/// fn fragment(in: FullscreenVertexOutput) -> EffectOutput {
///     let n = sample_count(in.position); // 0 outside spvg's mask
///     // ... take n samples ...
///     return EffectOutput(source_color(in.position), 1.0);
/// }
/// ```
///
/// # Frames without the effect
///
/// Until the pipeline is compiled (Bevy compiles pipelines asynchronously by default),
/// and on frames without this frame's estimate, the effect does not run and the camera's
/// image goes without it; spvg's update skips those frames, so the histories stay those of
/// the last frame the effect wrote.
///
/// One adaptive effect per camera: the value is the camera's.
pub trait AdaptiveEffect: Component + Clone + ShaderType + WriteInto {
    /// The effect's fragment shader (WESL; see the trait's docs for its interface).
    fn fragment_shader() -> ShaderRef;
}

/// Runs the [`AdaptiveEffect`] `T` on every 3D camera that has it. It sets itself up in
/// [`Plugin::finish`], so it may be added before or after [`SpvgPlugin`] and Bevy's render
/// plugins; it needs both.
pub struct AdaptiveEffectPlugin<T>(PhantomData<fn() -> T>);

impl<T> Default for AdaptiveEffectPlugin<T> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<T> core::fmt::Debug for AdaptiveEffectPlugin<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "AdaptiveEffectPlugin<{}>", type_name::<T>())
    }
}

impl<T: AdaptiveEffect> Plugin for AdaptiveEffectPlugin<T> {
    fn build(&self, app: &mut App) {
        // An error here means the requirement is already registered, which is what we want.
        let _ = app.try_register_required_components::<T, AdaptiveSampling>();
    }

    fn finish(&self, app: &mut App) {
        if !app.is_plugin_added::<SpvgPlugin>() {
            error!(
                "spvg-bevy: {self:?} needs SpvgPlugin; add it to the app (the effect does not run)"
            );
            return;
        }
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<SpecializedRenderPipelines<EffectPipeline<T>>>()
            .add_systems(RenderStartup, init_pipeline::<T>)
            .add_systems(ExtractSchedule, extract::<T>)
            .add_systems(
                Render,
                prepare::<T>.in_set(RenderSystems::PrepareBindGroups),
            )
            .add_systems(Core3d, draw::<T>.in_set(SpvgSystems::Effect));
    }
}

/// The effect's pipeline parts, specialised per view target format.
#[derive(Resource)]
struct EffectPipeline<T> {
    layout: BindGroupLayoutDescriptor,
    settings_layout: BindGroupLayoutDescriptor,
    sampler: Sampler,
    vertex: VertexState,
    fragment: Handle<Shader>,
    marker: PhantomData<fn() -> T>,
}

impl<T: AdaptiveEffect> SpecializedRenderPipeline for EffectPipeline<T> {
    type Key = TextureFormat;

    fn specialize(&self, format: TextureFormat) -> RenderPipelineDescriptor {
        RenderPipelineDescriptor {
            label: Some(format!("spvg-bevy effect<{}>", type_name::<T>()).into()),
            layout: vec![self.layout.clone(), self.settings_layout.clone()],
            vertex: self.vertex.clone(),
            fragment: Some(FragmentState {
                shader: self.fragment.clone(),
                targets: vec![
                    Some(ColorTargetState {
                        format,
                        blend: None,
                        write_mask: ColorWrites::ALL,
                    }),
                    Some(VALUE_FORMAT.into()),
                ],
                ..Default::default()
            }),
            ..Default::default()
        }
    }
}

fn init_pipeline<T: AdaptiveEffect>(
    mut commands: Commands,
    device: Res<RenderDevice>,
    assets: Res<AssetServer>,
    fullscreen: Res<FullscreenShader>,
) {
    let fragment = match T::fragment_shader() {
        ShaderRef::Default => {
            error!(
                "spvg-bevy: {}::fragment_shader() is ShaderRef::Default; an adaptive effect \
                 needs its own shader (the effect does not run)",
                type_name::<T>()
            );
            return;
        }
        ShaderRef::Handle(handle) => handle,
        ShaderRef::Path(path) => assets.load(path),
    };
    let layout = BindGroupLayoutDescriptor::new(
        "spvg-bevy effect",
        &BindGroupLayoutEntries::sequential(
            ShaderStages::FRAGMENT,
            (
                uniform_buffer::<ViewUniform>(true),
                texture_2d(TextureSampleType::Float { filterable: true }),
                sampler(SamplerBindingType::Filtering),
                texture_2d(TextureSampleType::Uint),
                texture_depth_2d(),
                texture_2d(TextureSampleType::Float { filterable: false }),
                texture_2d(TextureSampleType::Uint),
                texture_2d(TextureSampleType::Float { filterable: false }),
            ),
        ),
    );
    let settings_layout = BindGroupLayoutDescriptor::new(
        "spvg-bevy effect settings",
        &BindGroupLayoutEntries::single(ShaderStages::FRAGMENT, uniform_buffer::<T>(false)),
    );
    commands.insert_resource(EffectPipeline::<T> {
        layout,
        settings_layout,
        sampler: device.create_sampler(&SamplerDescriptor {
            label: Some("spvg-bevy effect"),
            mag_filter: FilterMode::Linear,
            min_filter: FilterMode::Linear,
            ..Default::default()
        }),
        vertex: fullscreen.to_vertex_state(),
        fragment,
        marker: PhantomData,
    });
}

/// Copies each camera's `T` to its render entity, or removes it (with the view's effect
/// state) where the camera has none.
fn extract<T: AdaptiveEffect>(
    mut commands: Commands,
    cameras: Extract<Query<(RenderEntity, Option<&T>), With<Camera>>>,
) {
    for (entity, effect) in &cameras {
        let Ok(mut render) = commands.get_entity(entity) else {
            continue;
        };
        match effect {
            Some(effect) => render.insert(effect.clone()),
            None => render.remove::<(T, EffectView<T>)>(),
        };
    }
}

/// What the main-colour bind group was made from; a new one is made when any differs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct GroupKey {
    view_uniforms: BufferId,
    textures: [TextureViewId; 6],
}

/// A view's effect state, made once: its pipeline, its settings uniform and bind group, and
/// the main bind groups of the two main textures Bevy alternates between.
#[derive(Component)]
struct EffectView<T: AdaptiveEffect> {
    pipeline: CachedRenderPipelineId,
    settings: UniformBuffer<T>,
    settings_group: Option<(BufferId, BindGroup)>,
    groups: Vec<(GroupKey, BindGroup)>,
}

/// Specialises each view's pipeline and writes its settings uniform.
fn prepare<T: AdaptiveEffect>(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    cache: Res<PipelineCache>,
    pipeline: Option<Res<EffectPipeline<T>>>,
    mut specialized: ResMut<SpecializedRenderPipelines<EffectPipeline<T>>>,
    mut views: Query<(Entity, &T, &ExtractedView, Option<&mut EffectView<T>>), With<SpvgView>>,
    stale: Query<Entity, (With<EffectView<T>>, Or<(Without<T>, Without<SpvgView>)>)>,
) {
    for entity in &stale {
        commands.entity(entity).remove::<EffectView<T>>();
    }
    let Some(pipeline) = pipeline else {
        return;
    };
    for (entity, effect, view, state) in &mut views {
        let id = specialized.specialize(&cache, &pipeline, view.target_format);
        let parts = (&*device, &*queue, &*cache, &*pipeline);
        match state {
            Some(mut state) => state.refresh(id, effect, parts),
            None => {
                let mut state = EffectView::<T> {
                    pipeline: id,
                    settings: UniformBuffer::from(effect.clone()),
                    settings_group: None,
                    groups: Vec::new(),
                };
                state.refresh(id, effect, parts);
                commands.entity(entity).insert(state);
            }
        }
    }
}

impl<T: AdaptiveEffect> EffectView<T> {
    /// Takes this frame's pipeline and settings; the settings' bind group is made once (and
    /// again only if the buffer was made anew).
    fn refresh(
        &mut self,
        pipeline_id: CachedRenderPipelineId,
        effect: &T,
        (device, queue, cache, pipeline): (
            &RenderDevice,
            &RenderQueue,
            &PipelineCache,
            &EffectPipeline<T>,
        ),
    ) {
        self.pipeline = pipeline_id;
        self.settings.set(effect.clone());
        self.settings.write_buffer(device, queue);
        if let Some(buffer) = self.settings.buffer()
            && self.settings_group.as_ref().map(|(id, _)| *id) != Some(buffer.id())
        {
            let group = device.create_bind_group(
                "spvg-bevy effect settings",
                &cache.get_bind_group_layout(&pipeline.settings_layout),
                &BindGroupEntries::single(buffer.as_entire_binding()),
            );
            self.settings_group = Some((buffer.id(), group));
        }
    }
}

/// `Core3d`, `SpvgSystems::Effect`: draws the effect over the view's viewport into the main
/// colour and the value target, and marks the value written.
fn draw<T: AdaptiveEffect>(
    view: ViewQuery<(
        &ViewTarget,
        &mut SpvgView,
        &mut EffectView<T>,
        &ViewPrepassTextures,
        &ViewUniformOffset,
        &ExtractedView,
    )>,
    pipeline: Option<Res<EffectPipeline<T>>>,
    cache: Res<PipelineCache>,
    view_uniforms: Res<ViewUniforms>,
    mut ctx: RenderContext,
) {
    let (target, mut spvg, mut state, prepass, offset, extracted) = view.into_inner();
    let state = &mut *state;
    let (
        Some(pipeline),
        Some(render_pipeline),
        Some(depth),
        Some(motion),
        Some(view_buffer),
        Some(view_binding),
        Some((_, settings_group)),
    ) = (
        pipeline,
        cache.get_render_pipeline(state.pipeline),
        prepass.depth_only_view(),
        prepass.motion_vectors_view(),
        view_uniforms.uniforms.buffer(),
        view_uniforms.uniforms.binding(),
        state.settings_group.as_ref(),
    )
    else {
        // Compiling, or a frame without its inputs: no value this frame, so the update
        // skips it.
        return;
    };
    if !spvg.estimated() {
        // The counts are not this frame's.
        return;
    }
    let history = spvg.history_view().clone();
    let post = target.post_process_write();
    let key = GroupKey {
        view_uniforms: view_buffer.id(),
        textures: [
            post.source.id(),
            spvg.count_view().id(),
            depth.id(),
            motion.id(),
            spvg.link_view().id(),
            history.id(),
        ],
    };
    let group = match state.groups.iter().position(|(k, _)| *k == key) {
        Some(k) => &state.groups[k].1,
        None => {
            let group = ctx.render_device().create_bind_group(
                "spvg-bevy effect",
                &cache.get_bind_group_layout(&pipeline.layout),
                &BindGroupEntries::sequential((
                    view_binding,
                    post.source,
                    &pipeline.sampler,
                    spvg.count_view(),
                    depth,
                    motion,
                    spvg.link_view(),
                    &history,
                )),
            );
            // Bevy alternates between two main textures and spvg between two histories:
            // keep a group for each pair.
            if state.groups.len() >= 4 {
                state.groups.remove(0);
            }
            state.groups.push((key, group));
            &state.groups[state.groups.len() - 1].1
        }
    };
    let [x, y, width, height] = extracted.viewport.to_array().map(|v| v as f32);
    {
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some("spvg-bevy effect"),
                color_attachments: &[
                    Some(RenderPassColorAttachment {
                        view: post.destination,
                        depth_slice: None,
                        resolve_target: None,
                        ops: Operations::default(),
                    }),
                    Some(RenderPassColorAttachment {
                        view: spvg.value_target_view(),
                        depth_slice: None,
                        resolve_target: None,
                        ops: Operations::default(),
                    }),
                ],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        pass.set_pipeline(render_pipeline);
        pass.set_bind_group(0, &**group, &[offset.offset]);
        pass.set_bind_group(1, &**settings_group, &[]);
        pass.set_viewport(x, y, width, height, 0.0, 1.0);
        pass.draw(0..3, 0..1);
    }
    spvg.mark_value_written();
}
