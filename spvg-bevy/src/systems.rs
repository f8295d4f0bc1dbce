//! The plugin's systems: extraction (with the status written back to the camera),
//! per-view preparation, and the two `Core3d` steps around the user's pass.

use bevy::camera::Camera;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass, ViewPrepassTextures};
use bevy::ecs::entity::EntityHashMap;
use bevy::ecs::prelude::*;
use bevy::log::{error, warn};
use bevy::render::MainWorld;
use bevy::render::camera::ExtractedCamera;
use bevy::render::renderer::{RenderContext, RenderDevice, ViewQuery};
use bevy::render::sync_world::RenderEntity;
use bevy::render::view::{ExtractedView, Msaa};
use spvg_wgpu::adaptive::{EstimateInputs, Masks, UpdateInputs};

use crate::convert::ConvertPipeline;
use crate::{AdaptiveSampling, SpvgStatus, SpvgValue, SpvgView};

/// The conversion pipeline, shared by all views.
#[derive(Resource, Debug)]
pub(crate) struct SpvgPipelines(pub(crate) ConvertPipeline);

/// Errors of the render-world steps per render entity, with the settings that met them;
/// reported on the camera's [`SpvgStatus`] from the next extraction on, until the camera's
/// settings change (the same settings would fail again: the pass is not rebuilt every
/// frame for them).
#[derive(Resource, Debug, Default)]
pub(crate) struct SpvgErrors(pub(crate) EntityHashMap<(AdaptiveSampling, String)>);

pub(crate) fn init_pipelines(mut commands: Commands, device: Res<RenderDevice>) {
    commands.insert_resource(SpvgPipelines(ConvertPipeline::new(device.wgpu_device())));
}

/// Copies each camera's settings to its render entity, or removes them (and the view's
/// pass) where a requirement is missing; writes the status back to the camera.
pub(crate) fn extract(
    mut commands: Commands,
    mut main_world: ResMut<MainWorld>,
    mut errors: ResMut<SpvgErrors>,
) {
    let mut cameras = main_world.query::<(
        RenderEntity,
        &Camera,
        &AdaptiveSampling,
        &mut SpvgStatus,
        Has<DepthPrepass>,
        Has<MotionVectorPrepass>,
        Option<&Msaa>,
    )>();
    for (entity, camera, settings, mut status, depth, motion, msaa) in
        cameras.iter_mut(&mut main_world)
    {
        if errors
            .0
            .get(&entity)
            .is_some_and(|(failed, _)| failed != settings)
        {
            errors.0.remove(&entity);
        }
        let new = if let Some((_, e)) = errors.0.get(&entity) {
            SpvgStatus::Failed(e.clone())
        } else if !camera.is_active {
            SpvgStatus::Inactive
        } else if !depth || !motion {
            SpvgStatus::MissingPrepass {
                depth: !depth,
                motion_vectors: !motion,
            }
        } else if msaa.is_some_and(|m| *m != Msaa::Off) {
            SpvgStatus::Multisampled
        } else {
            SpvgStatus::Running
        };
        if new != *status {
            match &new {
                SpvgStatus::MissingPrepass { .. } | SpvgStatus::Multisampled => warn!(
                    "spvg-bevy: adaptive sampling is off for camera {entity}: {new:?} \
                     (AdaptiveSampling needs DepthPrepass, MotionVectorPrepass and Msaa::Off)"
                ),
                SpvgStatus::Failed(e) => {
                    error!("spvg-bevy: adaptive sampling failed for camera {entity}: {e}");
                }
                _ => {}
            }
            *status = new.clone();
        }
        let Ok(mut render) = commands.get_entity(entity) else {
            continue;
        };
        if new == SpvgStatus::Running {
            render.insert(settings.clone());
        } else {
            render.remove::<(AdaptiveSampling, SpvgView)>();
        }
    }
    // Cameras that lost the component: their render entity still exists.
    let mut without =
        main_world.query_filtered::<RenderEntity, (With<Camera>, Without<AdaptiveSampling>)>();
    for entity in without.iter(&main_world) {
        if let Ok(mut render) = commands.get_entity(entity) {
            render.remove::<(AdaptiveSampling, SpvgView)>();
        }
    }
}

/// Creates, rebuilds or resizes each view's [`SpvgView`] to its physical viewport size.
pub(crate) fn prepare(
    mut commands: Commands,
    device: Res<RenderDevice>,
    mut errors: ResMut<SpvgErrors>,
    mut views: Query<(
        Entity,
        &AdaptiveSampling,
        &ExtractedCamera,
        &ExtractedView,
        Option<&mut SpvgView>,
    )>,
) {
    for (entity, settings, camera, view, spvg) in &mut views {
        let Some(size) = camera.physical_viewport_size else {
            continue;
        };
        let size = [size.x, size.y];
        let view_from_clip = view.clip_from_view.inverse();
        if let Some(mut spvg) = spvg {
            if spvg.size() != size
                && let Err(e) = spvg.resize(device.wgpu_device(), size)
            {
                errors.0.insert(entity, (settings.clone(), e.to_string()));
                commands.entity(entity).remove::<SpvgView>();
                continue;
            }
            match spvg.apply(settings) {
                Ok(true) => {
                    spvg.view_from_clip = view_from_clip;
                    continue;
                }
                Ok(false) => {}
                Err(e) => {
                    errors.0.insert(entity, (settings.clone(), e.to_string()));
                    commands.entity(entity).remove::<SpvgView>();
                    continue;
                }
            }
        }
        // New, or rebuilt for new settings: every history starts over.
        match SpvgView::new(device.wgpu_device(), settings, size) {
            Ok(mut spvg) => {
                spvg.view_from_clip = view_from_clip;
                commands.entity(entity).insert(spvg);
            }
            Err(e) => {
                errors.0.insert(entity, (settings.clone(), e.to_string()));
                commands.entity(entity).remove::<SpvgView>();
            }
        }
    }
}

/// `Core3d`, after the prepass: converts the prepass outputs and records the estimate.
pub(crate) fn estimate(
    view: ViewQuery<(Entity, &mut SpvgView, &ViewPrepassTextures)>,
    pipelines: Res<SpvgPipelines>,
    mut errors: ResMut<SpvgErrors>,
    mut ctx: RenderContext,
) {
    let (entity, mut spvg, prepass) = view.into_inner();
    let (Some(depth), Some(motion)) = (prepass.depth_only_view(), prepass.motion_vectors_view())
    else {
        // The extraction checks the components; this is a frame whose textures are not
        // there yet. Skipping it leaves the update without an estimate, which it skips too.
        return;
    };
    let device = ctx.render_device().wgpu_device().clone();
    spvg.advance();
    let size = spvg.size();
    let skip_background = spvg.settings().skip_background;
    let view_from_clip = spvg.view_from_clip;
    let out = [
        spvg.linear_depth().clone(),
        spvg.motion_pixels().clone(),
        spvg.mask().clone(),
    ];
    let encoder = ctx.command_encoder();
    pipelines.0.record(
        &device,
        encoder,
        view_from_clip,
        size,
        skip_background,
        depth,
        motion,
        [&out[0], &out[1], &out[2]],
    );
    let (previous_depth, mask, previous_mask) = (
        spvg.previous_linear_depth().clone(),
        spvg.mask().clone(),
        spvg.previous_mask().clone(),
    );
    let inputs = EstimateInputs {
        motion: &out[1],
        depth: &out[0],
        previous_depth: &previous_depth,
        reprojected_depth: None,
        masks: Some(Masks {
            current: &mask,
            previous: &previous_mask,
        }),
        gamma: None,
    };
    if let Err(e) = spvg.pass_mut().record_estimate(encoder, &inputs) {
        let failed = spvg.settings().clone();
        errors.0.insert(entity, (failed, format!("estimate: {e}")));
    }
}

/// `Core3d`, after the user's pass: records the update from the registered value.
pub(crate) fn update(
    view: ViewQuery<(Entity, &mut SpvgView, Option<&SpvgValue>)>,
    mut errors: ResMut<SpvgErrors>,
    mut ctx: RenderContext,
) {
    let (entity, mut spvg, registered) = view.into_inner();
    let (value, control) = match registered {
        Some(v) => (v.value.clone(), v.control.clone()),
        None => (spvg.value_texture().clone(), None),
    };
    let encoder = ctx.command_encoder();
    let inputs = UpdateInputs {
        value: &value,
        control: control.as_ref(),
        guide: None,
    };
    match spvg.pass_mut().record_update(encoder, &inputs) {
        // No estimate this frame (prepass textures missing): nothing to update.
        Err(spvg_wgpu::adaptive::AdaptiveError::UpdateWithoutEstimate) | Ok(()) => {}
        Err(e) => {
            let failed = spvg.settings().clone();
            errors.0.insert(entity, (failed, format!("update: {e}")));
        }
    }
}
