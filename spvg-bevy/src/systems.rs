//! The plugin's systems: extraction (with the status written back to the camera),
//! per-view preparation, and the two `Core3d` steps around the user's pass.

use bevy::camera::Camera;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass, ViewPrepassTextures};
use bevy::ecs::entity::{EntityHashMap, EntityHashSet};
use bevy::ecs::prelude::*;
use bevy::log::{error, warn};
use bevy::render::MainWorld;
use bevy::render::camera::ExtractedCamera;
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::sync_world::RenderEntity;
use bevy::render::view::{ExtractedView, Msaa};
use spvg_wgpu::adaptive::AdaptiveError;

use crate::convert::{ConvertBlock, ConvertPipeline};
use crate::view::Geometry;
use crate::{AdaptiveSampling, SpvgStatus, SpvgValue, SpvgView};

/// The conversion pipeline, shared by all views.
#[derive(Resource, Debug)]
pub(crate) struct SpvgPipelines(pub(crate) ConvertPipeline);

/// Errors of the render-world steps per render entity, with the settings that met them;
/// reported on the camera's [`SpvgStatus`] from the next extraction on, until the camera's
/// settings change (the same settings would fail again: the pass is not rebuilt every
/// frame for them) or the camera goes.
#[derive(Resource, Debug, Default)]
pub(crate) struct SpvgErrors(pub(crate) EntityHashMap<(AdaptiveSampling, String)>);

pub(crate) fn init_pipelines(mut commands: Commands, device: Res<RenderDevice>) {
    commands.insert_resource(SpvgPipelines(ConvertPipeline::new(device.wgpu_device())));
}

/// Copies each camera's settings to its render entity, or removes them (and the view's
/// pass) where a requirement is missing; writes the status back to the camera. Forgets the
/// errors of cameras that are gone or no longer ask for adaptive sampling.
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
    let mut present = EntityHashSet::default();
    for (entity, camera, settings, mut status, depth, motion, msaa) in
        cameras.iter_mut(&mut main_world)
    {
        present.insert(entity);
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
    errors.0.retain(|entity, _| present.contains(entity));
    // Cameras that lost the component: their render entity still exists.
    let mut without =
        main_world.query_filtered::<RenderEntity, (With<Camera>, Without<AdaptiveSampling>)>();
    for entity in without.iter(&main_world) {
        if let Ok(mut render) = commands.get_entity(entity) {
            render.remove::<(AdaptiveSampling, SpvgView)>();
        }
    }
}

/// Creates, rebuilds or resizes each view's [`SpvgView`] to its physical viewport, and
/// writes the conversion's uniform block for the frame.
pub(crate) fn prepare(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
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
        let Some(target) = camera.physical_target_size else {
            continue;
        };
        let geometry = Geometry {
            origin: [view.viewport.x, view.viewport.y],
            size: [view.viewport.z, view.viewport.w],
            target: target.to_array(),
        };
        let result: Result<(), String> =
            if (0..2).any(|k| geometry.origin[k] + geometry.size[k] > geometry.target[k]) {
                Err(format!(
                    "the viewport (origin {:?}, size {:?}) does not fit in its {:?} render target",
                    geometry.origin, geometry.size, geometry.target
                ))
            } else {
                match spvg {
                    Some(mut spvg) => spvg
                        .set_geometry(&device, geometry)
                        .and_then(|()| spvg.apply(&device, settings))
                        .map(|new| {
                            if let Some(new) = new {
                                // New settings that need a new pass: every history starts over.
                                *spvg = new;
                            }
                            write_convert(&mut spvg, view, &queue);
                        }),
                    None => SpvgView::new(&device, settings, geometry).map(|mut spvg| {
                        write_convert(&mut spvg, view, &queue);
                        commands.entity(entity).insert(spvg);
                    }),
                }
                .map_err(|e: AdaptiveError| e.to_string())
            };
        if let Err(e) = result {
            errors.0.insert(entity, (settings.clone(), e));
            commands.entity(entity).remove::<SpvgView>();
        }
    }
}

fn write_convert(spvg: &mut SpvgView, view: &ExtractedView, queue: &RenderQueue) {
    let g = spvg.geometry();
    let skip = spvg.settings().skip_background;
    let block = ConvertBlock::new(view.clip_from_view.inverse(), g.size, g.origin, skip);
    spvg.write_convert(queue, block);
}

/// `Core3d`, after the prepass: starts the view's frame, converts the prepass outputs and
/// records the estimate.
pub(crate) fn estimate(
    view: ViewQuery<(Entity, &mut SpvgView, &ViewPrepassTextures)>,
    pipelines: Res<SpvgPipelines>,
    mut errors: ResMut<SpvgErrors>,
    mut ctx: RenderContext,
) {
    let (entity, mut spvg, prepass) = view.into_inner();
    spvg.begin_frame();
    let (Some(depth), Some(motion)) = (prepass.depth_only_view(), prepass.motion_vectors_view())
    else {
        // The extraction checks the components; this is a frame whose textures are not
        // there yet. Without an estimate the update skips the frame too.
        return;
    };
    let device = ctx.render_device().wgpu_device().clone();
    let encoder = ctx.command_encoder();
    if let Err(e) = spvg.record_estimate(&pipelines.0, &device, encoder, [depth, motion]) {
        let failed = spvg.settings().clone();
        errors.0.insert(entity, (failed, format!("estimate: {e}")));
    }
}

/// `Core3d`, after the user's pass: records the update, on frames with an estimate whose
/// value the user's pass marked written; other frames keep every history as it was.
pub(crate) fn update(
    view: ViewQuery<(Entity, &mut SpvgView, Option<&SpvgValue>)>,
    mut errors: ResMut<SpvgErrors>,
    mut ctx: RenderContext,
) {
    let (entity, mut spvg, registered) = view.into_inner();
    if !spvg.ready_for_update() {
        spvg.end_frame(false);
        return;
    }
    let result = spvg.record_update(ctx.command_encoder(), registered);
    if let Err(e) = &result {
        let failed = spvg.settings().clone();
        errors.0.insert(entity, (failed, format!("update: {e}")));
    }
    spvg.end_frame(result.is_ok());
}
