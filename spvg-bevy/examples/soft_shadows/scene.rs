//! The scene shared by the example and the headless tests: spheres over a ground plane under
//! a rectangular area light, cameras rendering headlessly to float images on a fixed time
//! step, a warm-up that makes runs repeatable, and a render-world readback of each frame.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::camera::{Hdr, RenderTarget, Viewport};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::diagnostic::FrameCount;
use bevy::image::Image;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{PipelineCache, TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::sync_world::MainEntity;
use bevy::render::texture::GpuImage;
use bevy::render::view::Msaa;
use bevy::render::{Render, RenderApp, RenderPlugin, RenderSystems};
use bevy::time::TimeUpdateStrategy;
use half::f16;
use spvg_bevy::spvg_wgpu::util::read_texture;
use spvg_bevy::{AdaptiveEffectPlugin, AdaptiveSampling, SpvgPlugin, SpvgView, wgpu};

use crate::effect::SoftShadows;

/// The occluders (centre, radius).
pub const SPHERES: [Vec4; 4] = [
    Vec4::new(0.0, 0.8, 0.0, 0.8),
    Vec4::new(-1.8, 0.5, 0.9, 0.5),
    Vec4::new(1.6, 0.6, -0.8, 0.6),
    Vec4::new(0.9, 0.3, 1.5, 0.3),
];

/// The light: a corner and its two edges.
pub const LIGHT: [Vec3; 3] = [
    Vec3::new(-1.5, 4.0, -1.0),
    Vec3::new(3.0, 0.0, 0.0),
    Vec3::new(0.0, 0.0, 2.0),
];

/// The effect on this scene, with `seed`.
pub fn shadows(seed: u32) -> SoftShadows {
    SoftShadows {
        seed,
        ..SoftShadows::new(&SPHERES, LIGHT)
    }
}

/// The time step of every app here: a fixed step, so two runs see the same times.
pub const STEP: Duration = Duration::from_micros(16_667);

/// How an app compiles its pipelines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compilation {
    /// Bevy's default: in the background, so the first frames go without some passes.
    Asynchronous,
    /// Each pipeline when first needed, before the frame goes on.
    Synchronous,
}

/// A headless app on a fixed time step: Bevy's default plugins without pipelined rendering
/// (each `update` renders its own frame, so a readback in the render world is that frame's),
/// plus spvg and the effect. `log`: Bevy's logger (a process has one; the tests make
/// several apps).
pub fn app(compilation: Compilation, log: bool) -> App {
    let mut app = App::new();
    let mut plugins = DefaultPlugins
        .build()
        .disable::<PipelinedRenderingPlugin>()
        .set(RenderPlugin {
            synchronous_pipeline_compilation: compilation == Compilation::Synchronous,
            ..default()
        });
    if !log {
        plugins = plugins.disable::<LogPlugin>();
    }
    #[cfg(feature = "window")]
    {
        // With Bevy's windowing built in, the headless app opens no window and needs no
        // display.
        plugins = plugins
            .disable::<bevy::winit::WinitPlugin>()
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: bevy::window::ExitCondition::DontExit,
                ..default()
            });
    }
    app.add_plugins(plugins)
        .add_plugins((SpvgPlugin, AdaptiveEffectPlugin::<SoftShadows>::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
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
    for (s, m) in SPHERES.into_iter().zip(spheres) {
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

/// A `size` `Rgba16Float` render target image that can be read back.
pub fn target_image(world: &mut World, size: [u32; 2]) -> Handle<Image> {
    let mut image = Image::new_target_texture(size[0], size[1], TextureFormat::Rgba16Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    world.resource_mut::<Assets<Image>>().add(image)
}

/// A camera with Bevy's TAA rendering to a new `size` image (see [`spawn_camera_on`]).
pub fn spawn_camera(
    world: &mut World,
    size: [u32; 2],
    effect: Option<SoftShadows>,
    adaptive: Option<AdaptiveSampling>,
) -> (Entity, Handle<Image>) {
    let image = target_image(world, size);
    let camera = spawn_camera_on(world, image.clone(), None, effect, adaptive);
    (camera, image)
}

/// A camera with Bevy's TAA rendering to `target`, in `viewport` (`None`: all of it), with
/// the effect and spvg's settings where given (the effect alone brings the default
/// `AdaptiveSampling`).
pub fn spawn_camera_on(
    world: &mut World,
    target: Handle<Image>,
    viewport: Option<Viewport>,
    effect: Option<SoftShadows>,
    adaptive: Option<AdaptiveSampling>,
) -> Entity {
    let mut e = world.spawn((
        Camera3d::default(),
        RenderTarget::Image(target.into()),
        Hdr,
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        TemporalAntiAliasing::default(),
        camera_pose(0.0),
    ));
    if let Some(viewport) = viewport {
        e.insert(Camera {
            viewport: Some(viewport),
            ..default()
        });
    }
    if let Some(adaptive) = adaptive {
        e.insert(adaptive);
    }
    if let Some(effect) = effect {
        e.insert(effect);
    }
    e.id()
}

/// One view's spvg data of a frame, read back after its submission.
#[derive(Default, Clone, Debug, PartialEq)]
pub struct ViewFrame {
    /// The frame size (the viewport).
    pub size: [u32; 2],
    pub motion: Vec<[f32; 2]>,
    pub depth: Vec<f32>,
    pub previous_depth: Vec<f32>,
    pub mask: Vec<u32>,
    pub previous_mask: Vec<u32>,
    pub count: Vec<u32>,
    pub value: Vec<f32>,
    pub history: Vec<[u16; 4]>,
    /// `SpvgView::frames` and `SpvgView::updates` after the frame.
    pub estimates: u64,
    pub updates: u64,
}

/// One frame read back in the render world after its submission.
#[derive(Default, Clone, Debug)]
pub struct Frame {
    /// Each view with spvg, by its main-world camera.
    pub views: Vec<(Entity, ViewFrame)>,
    /// The final images (after TAA) of the [`Targets`], in that order, RGBA.
    pub images: Vec<Vec<[f32; 4]>>,
    /// Pipelines still waiting to be compiled (or for their shaders) after the frame.
    pub waiting_pipelines: usize,
}

impl Frame {
    /// The spvg data of `camera`'s view.
    pub fn view(&self, camera: Entity) -> Option<&ViewFrame> {
        self.views
            .iter()
            .find(|(e, _)| *e == camera)
            .map(|(_, v)| v)
    }
}

/// The frames read back so far (shared by both worlds).
#[derive(Resource, Clone, Default)]
pub struct Captures(pub Arc<Mutex<Vec<Frame>>>);

impl Captures {
    /// The frames so far, or none if the lock was poisoned by a failed readback.
    pub fn frames(&self) -> Vec<Frame> {
        self.0.lock().map(|f| f.clone()).unwrap_or_default()
    }

    /// The last frame so far.
    pub fn last(&self) -> Option<Frame> {
        self.0.lock().ok().and_then(|f| f.last().cloned())
    }

    /// Forgets the frames so far.
    pub fn clear(&self) {
        if let Ok(mut f) = self.0.lock() {
            f.clear();
        }
    }
}

/// The images read back with each frame, in the order [`Frame::images`] holds them.
#[derive(Resource, Clone, Default)]
pub struct Targets(pub Vec<Handle<Image>>);

/// Sets the images read back with each frame (in both worlds).
pub fn set_targets(app: &mut App, targets: Vec<Handle<Image>>) {
    let targets = Targets(targets);
    app.insert_resource(targets.clone());
    app.sub_app_mut(RenderApp).insert_resource(targets);
}

/// Adds the readback (after the render step, before cleanup) of every view with spvg and
/// of the [`Targets`] images; returns where the frames go.
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
    views: Query<(&MainEntity, &SpvgView)>,
    targets: Option<Res<Targets>>,
    images: Res<RenderAssets<GpuImage>>,
    cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    captures: Res<Captures>,
) {
    let (d, q) = (device.wgpu_device(), &**queue);
    // A failed readback is a lost device: the test then fails on missing frames.
    let f32s = |t: &wgpu::Texture| read_texture::<f32>(d, q, t).unwrap_or_default();
    let u32s = |t: &wgpu::Texture| read_texture::<u32>(d, q, t).unwrap_or_default();
    let mut frame = Frame {
        waiting_pipelines: cache.waiting_pipelines().count(),
        ..default()
    };
    for (camera, view) in &views {
        let data = ViewFrame {
            size: view.size(),
            motion: read_texture::<[f32; 2]>(d, q, view.motion_pixels()).unwrap_or_default(),
            depth: f32s(view.linear_depth()),
            previous_depth: f32s(view.previous_linear_depth()),
            mask: u32s(view.mask()),
            previous_mask: u32s(view.previous_mask()),
            count: u32s(view.count_texture()),
            value: f32s(view.value_texture()),
            history: read_texture::<[u16; 4]>(d, q, view.adaptive_pass().history_texture())
                .unwrap_or_default(),
            estimates: view.frames(),
            updates: view.updates(),
        };
        frame.views.push((camera.id(), data));
    }
    frame.views.sort_by_key(|(e, _)| *e);
    for h in targets.iter().flat_map(|t| t.0.iter()) {
        let pixels = images.get(h).map_or_else(Vec::new, |gpu| {
            read_texture::<[u16; 4]>(d, q, &gpu.texture)
                .unwrap_or_default()
                .iter()
                .map(|p| p.map(|c| f16::from_bits(c).to_f32()))
                .collect()
        });
        frame.images.push(pixels);
    }
    if let Ok(mut frames) = captures.0.lock() {
        frames.push(frame);
    }
}

/// The most frames a warm-up may take.
const WARM_UP_LIMIT: usize = 600;

/// Makes the next frames of `app` repeatable: renders a throwaway camera set up like the
/// measured ones (`size`, the effect, spvg) until every pipeline it needs is compiled, then
/// removes it and restarts Bevy's frame count (TAA's jitter and the effect's sample sequence
/// follow it). Bevy loads its shaders in the background, so how many frames the pipelines
/// take depends on the machine; measured from a fresh app, the first frames would differ
/// from run to run. Returns the frames it took, or an error after [`WARM_UP_LIMIT`].
pub fn warm_up(app: &mut App, captures: &Captures, size: [u32; 2]) -> Result<usize, String> {
    let world = app.world_mut();
    let (camera, image) = spawn_camera(world, size, Some(shadows(0)), None);
    let mut ready_in_a_row = 0;
    for frame in 1..=WARM_UP_LIMIT {
        app.update();
        let last = captures.last().unwrap_or_default();
        let drawn = last.view(camera).is_some_and(|v| v.updates > 0);
        ready_in_a_row = if drawn && last.waiting_pipelines == 0 {
            ready_in_a_row + 1
        } else {
            0
        };
        // Two frames in a row: TAA compiles its steady-state pipeline after its first frame.
        if ready_in_a_row == 2 {
            let world = app.world_mut();
            world.despawn(camera);
            world.resource_mut::<Assets<Image>>().remove(&image);
            // One frame without it, so the render world drops its view.
            app.update();
            app.world_mut().resource_mut::<FrameCount>().0 = 0;
            captures.clear();
            return Ok(frame);
        }
    }
    Err(format!(
        "the pipelines were not ready after {WARM_UP_LIMIT} frames"
    ))
}
