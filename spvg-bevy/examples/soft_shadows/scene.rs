//! The scene shared by the example and the headless test: spheres over a ground plane under
//! a rectangular area light, cameras rendering headlessly to float images, and a render-world
//! readback of a frame.

use std::sync::{Arc, Mutex};

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::image::Image;
use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_asset::RenderAssets;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::texture::GpuImage;
use bevy::render::view::Msaa;
use bevy::render::{Render, RenderApp, RenderPlugin, RenderSystems};
use half::f16;
use spvg_bevy::spvg_wgpu::adaptive::read_texture;
use spvg_bevy::{AdaptiveSampling, SpvgPlugin, SpvgView};

use crate::effect::{ShadowScene, SoftShadows, SoftShadowsPlugin};

/// The occluders and the light.
pub fn shadow_scene() -> ShadowScene {
    ShadowScene {
        spheres: vec![
            Vec4::new(0.0, 0.8, 0.0, 0.8),
            Vec4::new(-1.8, 0.5, 0.9, 0.5),
            Vec4::new(1.6, 0.6, -0.8, 0.6),
            Vec4::new(0.9, 0.3, 1.5, 0.3),
        ],
        light_corner: Vec3::new(-1.5, 4.0, -1.0),
        light_u: Vec3::new(3.0, 0.0, 0.0),
        light_v: Vec3::new(0.0, 0.0, 2.0),
    }
}

/// A headless app: Bevy's default plugins without pipelined rendering (each `update`
/// renders its own frame, so a readback in the render world is that frame's) and with
/// synchronous pipeline compilation, plus spvg and the effect.
pub fn app() -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .build()
            .disable::<PipelinedRenderingPlugin>()
            .set(RenderPlugin {
                synchronous_pipeline_compilation: true,
                ..default()
            }),
    )
    .add_plugins((SpvgPlugin, SoftShadowsPlugin))
    .insert_resource(shadow_scene());
    app
}

/// The meshes: a ground plane and the occluding spheres, unlit so that the main pass colour
/// is the material's colour and the effect's visibility is all the shading.
pub fn spawn_scene(world: &mut World, colors: bool) {
    let mut material = |c: Color| {
        world
            .resource_mut::<Assets<StandardMaterial>>()
            .add(StandardMaterial {
                base_color: c,
                unlit: true,
                ..default()
            })
    };
    let palette = [
        Color::srgb(0.9, 0.35, 0.3),
        Color::srgb(0.35, 0.8, 0.4),
        Color::srgb(0.35, 0.5, 0.95),
        Color::srgb(0.95, 0.8, 0.3),
    ];
    let ground = material(Color::WHITE);
    let spheres: Vec<_> = (0..4)
        .map(|k| material(if colors { palette[k] } else { Color::WHITE }))
        .collect();
    let plane = world
        .resource_mut::<Assets<Mesh>>()
        .add(Plane3d::default().mesh().size(12.0, 12.0));
    world.spawn((Mesh3d(plane), MeshMaterial3d(ground)));
    for (s, m) in shadow_scene().spheres.into_iter().zip(spheres) {
        let mesh = world
            .resource_mut::<Assets<Mesh>>()
            .add(Sphere::new(s.w).mesh().uv(48, 24));
        world.spawn((
            Mesh3d(mesh),
            MeshMaterial3d(m),
            Transform::from_translation(s.truncate()),
        ));
    }
}

/// The camera path: an orbit around the scene, `t` in frames.
pub fn camera_pose(t: f32) -> Transform {
    let a = 0.6 + 0.02 * t;
    Transform::from_xyz(6.0 * a.cos(), 3.5, 6.0 * a.sin())
        .looking_at(Vec3::new(0.0, 0.4, 0.0), Vec3::Y)
}

/// A camera with Bevy's TAA rendering to a `size` `Rgba16Float` image; with
/// [`SoftShadows::Adaptive`] it also gets spvg's [`AdaptiveSampling`] with `adaptive`.
pub fn spawn_camera(
    world: &mut World,
    size: [u32; 2],
    mode: Option<SoftShadows>,
    adaptive: Option<AdaptiveSampling>,
) -> (Entity, Handle<Image>) {
    let mut image =
        Image::new_target_texture(size[0], size[1], wgpu::TextureFormat::Rgba16Float, None);
    image.texture_descriptor.usage |= wgpu::TextureUsages::COPY_SRC;
    let handle = world.resource_mut::<Assets<Image>>().add(image);
    let mut e = world.spawn((
        Camera3d::default(),
        RenderTarget::Image(handle.clone().into()),
        Hdr,
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        TemporalAntiAliasing::default(),
        camera_pose(0.0),
    ));
    if let Some(mode) = mode {
        e.insert(mode);
    }
    if let Some(adaptive) = adaptive {
        e.insert(adaptive);
    }
    (e.id(), handle)
}

/// One frame read back in the render world after its submission.
#[derive(Default, Clone)]
pub struct Frame {
    pub motion: Vec<[f32; 2]>,
    pub depth: Vec<f32>,
    pub previous_depth: Vec<f32>,
    pub mask: Vec<u32>,
    pub previous_mask: Vec<u32>,
    pub count: Vec<u32>,
    pub value: Vec<f32>,
    pub history: Vec<[u16; 4]>,
    /// The final images (after TAA) of the cameras in [`Targets`] order, RGBA.
    pub images: Vec<Vec<[f32; 4]>>,
}

/// The frames read back so far (shared by both worlds).
#[derive(Resource, Clone, Default)]
pub struct Captures(pub Arc<Mutex<Vec<Frame>>>);

/// The cameras' target images, in the order [`Frame::images`] holds them.
#[derive(Resource, Clone)]
pub struct Targets(pub Vec<Handle<Image>>);

/// Adds the readback (after the render step, before cleanup) of the view with spvg and of
/// the [`Targets`] images; returns where the frames go.
pub fn add_capture(app: &mut App) -> Captures {
    let captures = Captures::default();
    app.sub_app_mut(RenderApp)
        .insert_resource(captures.clone())
        .add_systems(
            Render,
            capture
                .after(RenderSystems::Render)
                .before(RenderSystems::Cleanup),
        );
    captures
}

fn capture(
    views: Query<&SpvgView>,
    targets: Option<Res<Targets>>,
    images: Res<RenderAssets<GpuImage>>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    captures: Res<Captures>,
) {
    let Ok(view) = views.single() else {
        return;
    };
    let (d, q) = (device.wgpu_device(), &**queue);
    let f32s = |t: &wgpu::Texture| read_texture::<f32>(d, q, t).expect("readback");
    let u32s = |t: &wgpu::Texture| read_texture::<u32>(d, q, t).expect("readback");
    let mut frame = Frame {
        motion: read_texture::<[f32; 2]>(d, q, view.motion_pixels()).expect("readback"),
        depth: f32s(view.linear_depth()),
        previous_depth: f32s(view.previous_linear_depth()),
        mask: u32s(view.mask()),
        previous_mask: u32s(view.previous_mask()),
        count: u32s(view.count_texture()),
        value: f32s(view.value_texture()),
        history: read_texture::<[u16; 4]>(d, q, view.adaptive_pass().history_texture())
            .expect("readback"),
        images: Vec::new(),
    };
    for h in targets.iter().flat_map(|t| t.0.iter()) {
        let pixels = images.get(h).map_or_else(Vec::new, |gpu| {
            read_texture::<[u16; 4]>(d, q, &gpu.texture)
                .expect("image readback")
                .iter()
                .map(|p| p.map(|c| f16::from_bits(c).to_f32()))
                .collect()
        });
        frame.images.push(pixels);
    }
    captures.0.lock().expect("lock").push(frame);
}
