//! The example in a window (feature `window`): the scene under an orbit camera, with
//! toggles for spvg's adaptive counts against a fixed count and for the counts view, and
//! the mean count on screen.
//!
//! Drag with the left mouse button to orbit, scroll to zoom; `Space` pauses the automatic
//! orbit, `A` switches between adaptive counts and a fixed count (the adaptive mean when
//! switched, rounded up), `C` shows spvg's counts (blue: fewest, red: most, log scale).
//! The automatic orbit advances a fixed angle per frame, and Bevy's time a fixed step, so
//! the views do not depend on the frame rate.

use std::sync::{Arc, Mutex};

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::view::Msaa;
use bevy::render::{Render, RenderApp, RenderSystems};
use bevy::time::TimeUpdateStrategy;
use spvg_bevy::spvg::SpvgConfig;
use spvg_bevy::spvg_wgpu::util::read_texture;
use spvg_bevy::{AdaptiveEffectPlugin, AdaptiveSampling, AdaptiveSettings, SpvgPlugin, SpvgView};

use crate::scene::{STEP, shadows, spawn_scene};

/// How often (in frames) the render world reads the counts back for the on-screen mean.
const MEAN_EVERY: u32 = 15;

/// Opens the window and runs until it is closed.
pub fn run(config: SpvgConfig<f32>) -> Result<(), Box<dyn std::error::Error>> {
    let mean = MeanCount::default();
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "spvg-bevy: soft shadows".into(),
            resolution: (960, 540).into(),
            ..default()
        }),
        ..default()
    }))
    .add_plugins((SpvgPlugin, AdaptiveEffectPlugin::<SoftShadowsFx>::default()))
    .insert_resource(TimeUpdateStrategy::ManualDuration(STEP))
    .insert_resource(Mode {
        config,
        fixed: None,
        counts: false,
    })
    .insert_resource(mean.clone())
    .add_systems(Startup, setup)
    .add_systems(Update, (orbit, toggle, show_mean).chain());
    app.sub_app_mut(RenderApp)
        .insert_resource(mean)
        .add_systems(
            Render,
            read_mean
                .after(RenderSystems::Render)
                .before(RenderSystems::Cleanup),
        );
    app.run();
    Ok(())
}

/// The effect of `effect.rs`.
type SoftShadowsFx = crate::effect::SoftShadows;

/// What the toggles set: the adaptive configuration, the fixed count when fixed, and
/// whether the counts view is on.
#[derive(Resource)]
struct Mode {
    config: SpvgConfig<f32>,
    fixed: Option<u32>,
    counts: bool,
}

/// The orbit camera's state.
#[derive(Component)]
struct Orbit {
    yaw: f32,
    pitch: f32,
    radius: f32,
    auto: bool,
}

impl Orbit {
    fn pose(&self) -> Transform {
        let (y, p) = (self.yaw, self.pitch);
        let eye = Vec3::new(p.cos() * y.cos(), p.sin(), p.cos() * y.sin()) * self.radius;
        Transform::from_translation(eye).looking_at(Vec3::new(0.0, 0.4, 0.0), Vec3::Y)
    }
}

/// The mean count over the covered pixels, read back in the render world.
#[derive(Resource, Clone, Default)]
struct MeanCount(Arc<Mutex<Option<f64>>>);

#[derive(Component)]
struct Label;

fn setup(world: &mut World) {
    spawn_scene(world, true);
    let orbit = Orbit {
        yaw: 0.6,
        pitch: 0.53,
        radius: 6.9,
        auto: true,
    };
    let config = world.resource::<Mode>().config;
    let mut effect = shadows(0);
    effect.count_range = UVec2::new(config.min_samples(), config.max_samples());
    world.spawn((
        Camera3d::default(),
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        TemporalAntiAliasing::default(),
        orbit.pose(),
        orbit,
        effect,
        AdaptiveSampling::with_settings(AdaptiveSettings {
            config,
            dilation: 1,
            ..AdaptiveSettings::default()
        }),
    ));
    world.spawn((
        Text::new(""),
        Node {
            position_type: PositionType::Absolute,
            top: px(12),
            left: px(12),
            ..default()
        },
        Label,
    ));
}

fn orbit(
    mut cameras: Query<(&mut Orbit, &mut Transform)>,
    buttons: Res<ButtonInput<MouseButton>>,
    keys: Res<ButtonInput<KeyCode>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
) {
    for (mut orbit, mut pose) in &mut cameras {
        if keys.just_pressed(KeyCode::Space) {
            orbit.auto = !orbit.auto;
        }
        if orbit.auto {
            orbit.yaw += 0.004;
        }
        if buttons.pressed(MouseButton::Left) {
            orbit.yaw += motion.delta.x * 0.005;
            orbit.pitch = (orbit.pitch + motion.delta.y * 0.005).clamp(0.1, 1.45);
        }
        orbit.radius = (orbit.radius * (1.0 - 0.1 * scroll.delta.y)).clamp(3.0, 14.0);
        *pose = orbit.pose();
    }
}

fn toggle(
    keys: Res<ButtonInput<KeyCode>>,
    mut mode: ResMut<Mode>,
    mean: Res<MeanCount>,
    mut cameras: Query<(&mut AdaptiveSampling, &mut SoftShadowsFx)>,
) {
    if keys.just_pressed(KeyCode::KeyC) {
        mode.counts = !mode.counts;
    }
    if keys.just_pressed(KeyCode::KeyA) {
        mode.fixed = match mode.fixed {
            Some(_) => None,
            None => {
                let mean = mean.0.lock().ok().and_then(|m| *m).unwrap_or(8.0);
                let (lo, hi) = (mode.config.min_samples(), mode.config.max_samples());
                Some((mean.ceil() as u32).clamp(lo, hi))
            }
        };
    }
    // A fixed count is spvg with a budget of one count.
    let config = match mode.fixed {
        Some(n) => mode
            .config
            .to_builder()
            .min_samples(n)
            .max_samples(n)
            .build(),
        None => Ok(mode.config),
    };
    for (mut adaptive, mut effect) in &mut cameras {
        if let Ok(config) = config
            && adaptive.settings.config != config
        {
            adaptive.settings.config = config;
        }
        let counts = u32::from(mode.counts);
        if effect.show_counts != counts {
            effect.show_counts = counts;
        }
    }
}

fn show_mean(mode: Res<Mode>, mean: Res<MeanCount>, mut label: Single<&mut Text, With<Label>>) {
    let mean = mean.0.lock().ok().and_then(|m| *m);
    let figure = mean.map_or_else(|| "-".into(), |m| format!("{m:.1}"));
    let counts = match mode.fixed {
        Some(n) => format!("fixed {n}"),
        None => "adaptive".into(),
    };
    let view = if mode.counts { "counts" } else { "shadows" };
    label.0 = format!(
        "{figure} spp ({counts}), {view}\n\
         [A] adaptive/fixed  [C] counts  [Space] orbit  drag, scroll: view"
    );
}

/// Render world: every [`MEAN_EVERY`] frames, the mean of the counts over the covered
/// pixels (the counts are 0 exactly outside the mask).
fn read_mean(
    views: Query<&SpvgView>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mean: Res<MeanCount>,
    mut frame: Local<u32>,
) {
    *frame += 1;
    if !frame.is_multiple_of(MEAN_EVERY) {
        return;
    }
    for view in &views {
        let Ok(counts) = read_texture::<u32>(device.wgpu_device(), &queue, view.count_texture())
        else {
            continue;
        };
        let covered = counts.iter().filter(|c| **c != 0).count();
        let spent: u64 = counts.iter().map(|c| u64::from(*c)).sum();
        if let Ok(mut m) = mean.0.lock() {
            *m = (covered > 0).then(|| spent as f64 / covered as f64);
        }
    }
}
