//! # spvg-bevy: SPVG adaptive sampling in Bevy's render world
//!
//! [`SpvgPlugin`] runs the `spvg-wgpu` component ([`spvg_wgpu::adaptive::AdaptivePass`])
//! inside Bevy 0.20.1's render world, on Bevy's own prepass, for every 3D camera with
//! [`AdaptiveSampling`]. Your stochastic effect takes spvg's per-pixel sample count and
//! reports the luminance of its result; the plugin does the rest. Bevy 0.20.1 is built on
//! wgpu 30, the component's wgpu, so the component records into Bevy's command encoder as
//! it is. The API speaks Bevy's render types; where wgpu's own types show (the component's
//! textures), [`wgpu`] is re-exported, so `bevy` and `spvg-bevy` are the only dependencies
//! an app needs.
//!
//! ## An effect in a shader and a component
//!
//! [`AdaptiveEffect`] is a camera component whose fields are your effect's settings, and a
//! WESL fragment shader; [`AdaptiveEffectPlugin`] runs it with the counts bound, writes its
//! monitored value and orders it between spvg's steps:
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy::render::render_resource::ShaderType;
//! use bevy::shader::ShaderRef;
//! use spvg_bevy::{AdaptiveEffect, AdaptiveEffectPlugin, SpvgPlugin};
//!
//! /// The effect's settings: group 1, binding 0 of its shader.
//! #[derive(Component, Clone, ShaderType)]
//! struct Grain {
//!     amount: f32,
//! }
//!
//! impl AdaptiveEffect for Grain {
//!     fn fragment_shader() -> ShaderRef {
//!         "shaders/grain.wesl".into()
//!     }
//! }
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, SpvgPlugin, AdaptiveEffectPlugin::<Grain>::default()))
//!     .add_systems(Startup, |mut commands: Commands| {
//!         // `Grain` brings `AdaptiveSampling`, which brings the depth and motion prepasses.
//!         commands.spawn((Camera3d::default(), Msaa::Off, Grain { amount: 0.5 }));
//!     })
//!     .run();
//! ```
//!
//! The shader's interface is in [`AdaptiveEffect`]'s docs; the module it imports,
//! `spvg_bevy::effect` ([`EFFECT_IMPORT_PATH`]), declares the bindings and reads each at a
//! fragment position.
//!
//! ## Per frame
//!
//! For each camera, in its `Core3d` schedule, the plugin configures these sets:
//!
//! ```text
//! Core3dSystems::Prepass             Bevy: depth, motion vectors
//! SpvgSystems::Estimate              after Prepass, before MainPass: convert (depth -> linear,
//!                                    UV motion -> pixels, geometry mask), record_estimate
//!                                    -> the count texture
//! Core3dSystems::MainPass            Bevy: the main colour
//! SpvgSystems::Effect                after Estimate and MainPass, before Update and
//!                                    EarlyPostProcess: the effect (AdaptiveEffectPlugin's,
//!                                    or your own pass) reads the counts, writes the
//!                                    colour and the value, marks the value written
//! SpvgSystems::Update                after Effect and MainPass, before EarlyPostProcess:
//!                                    record_update -> new history (only if marked)
//! Core3dSystems::EarlyPostProcess    Bevy's TAA resolves the image
//! ```
//!
//! A pass of your own goes `.in_set(SpvgSystems::Effect)`, which carries the whole order;
//! [`SpvgView`] says what it reads and writes.
//!
//! ## Frames without a value
//!
//! The update runs only on frames whose value was marked written
//! ([`SpvgView::mark_value_written`]; the effect helper marks it after drawing). A frame
//! whose effect returned early (its pipeline still compiling, which is Bevy's default
//! asynchronous compilation, or its inputs missing) is skipped: the history, the previous
//! depth and the previous mask stay those of the last updated frame, and the next estimate
//! continues from them. No stale or zeroed value reaches the history. Bevy's motion vectors
//! span one frame, so a history kept over skipped frames is reprojected along the current
//! frame's motion only: under camera or object motion it lands off by the skipped frames'
//! motion wherever the depth test still passes. Skips come mostly at start-up, before there
//! is any history.
//!
//! ## Viewports
//!
//! The pass runs at the camera's physical viewport size. Bevy's prepass and main textures
//! span the whole render target, so the conversion reads them at the viewport pixel plus
//! the viewport's origin; spvg's own textures (counts, converted inputs) are the viewport's
//! size; the value target is the render target's size, so a pass writes it at the same
//! texel as its colour. Several cameras may share a target, each with its own viewport.
//!
//! ## Inputs from Bevy's prepass
//!
//! - **Depth**: Bevy's prepass depth is reverse-Z NDC depth; the plugin converts it to the
//!   linear depth along the view axis through the inverse projection (perspective and
//!   orthographic alike). Pixels without geometry (NDC depth 0) are outside the pass mask
//!   unless [`AdaptiveSampling::skip_background`] is `false`.
//! - **Motion vectors**: Bevy stores this frame's position minus the previous frame's in UV
//!   units of the viewport, `+y` down (`MotionVectorPrepass`); the component takes the same
//!   difference in pixels, so the plugin multiplies by the viewport size and keeps the sign.
//! - **Previous depth**: the plugin keeps its own converted depth of the last updated frame
//!   (ping-pong), so the depth test compares two depths converted the same way and no
//!   `DepthPrepassDoubleBuffer` is needed.
//!
//! ## Requirements
//!
//! A camera with [`AdaptiveSampling`] needs `DepthPrepass` and `MotionVectorPrepass`
//! (required components, added with it) and `Msaa::Off`. Without them the plugin skips the
//! camera, sets its [`SpvgStatus`] and logs a warning; it never panics.
//!
//! ## The shader library
//!
//! The plugin registers the `spvg-shaders` WGSL library as a WESL module: a Bevy shader
//! imports it with `import spvg_bevy::spvg::{spvg_pcg3d16, ...};` ([`SHADER_IMPORT_PATH`]).
//!
//! ## Feature flags
//!
//! - `window`: Bevy's windowing (X11), input, UI and text, for the interactive
//!   `soft_shadows` example (`cargo run --example soft_shadows --features window`). The
//!   library does not use them; without it the crate and its tests build headless.
//!
//! ## Build
//!
//! This crate is its own Cargo workspace inside the spvg repository, pinned to Rust 1.97.1
//! (Bevy 0.20.1's `rust-version`) by its `rust-toolchain.toml`, with its own `Cargo.lock`
//! and target directory, so that the main workspace keeps its toolchain and does not build
//! Bevy.

mod component;
mod configure;
mod convert;
mod effect;
mod library;
mod systems;
mod view;

use bevy::app::{App, Plugin};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::ecs::schedule::{IntoScheduleConfigs, SystemSet};
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};

pub use component::{AdaptiveSampling, SpvgStatus};
pub use convert::{LINEAR_DEPTH_FORMAT, MASK_FORMAT, MOTION_PIXELS_FORMAT, VALUE_FORMAT};
pub use effect::{AdaptiveEffect, AdaptiveEffectPlugin};
pub use library::{
    EFFECT_IMPORT_PATH, EFFECT_SHADER_HANDLE, SHADER_IMPORT_PATH, SHADER_LIBRARY_HANDLE,
};
/// The component's settings type, which [`AdaptiveSampling`] holds.
pub use spvg_wgpu::adaptive::AdaptiveSettings;
pub use view::{SpvgValue, SpvgView};

pub use spvg;
pub use spvg_shaders;
pub use spvg_wgpu;
/// The wgpu of Bevy 0.20.1 and of `spvg-wgpu` (one version: `cargo tree -d` lists it once),
/// for the component's own types ([`SpvgView::adaptive_pass`]).
pub use wgpu;

/// The plugin's `Core3d` system sets (see the [crate docs](crate) for where they run).
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub enum SpvgSystems {
    /// Converts the prepass outputs and records `AdaptivePass::record_estimate`.
    Estimate,
    /// The user's effect: after the estimate and the main pass, before the update and
    /// Bevy's early post-processing (TAA). Put your own pass here.
    Effect,
    /// Records `AdaptivePass::record_update`, on frames whose value was marked written.
    Update,
}

/// Runs the SPVG adaptive-sampling component for every 3D camera with
/// [`AdaptiveSampling`], and registers the shader modules. It sets itself up in
/// [`Plugin::finish`], after every plugin is built, so it may be added before or after
/// Bevy's render plugins (`DefaultPlugins`); without them it does nothing.
#[derive(Debug, Default, Clone, Copy)]
pub struct SpvgPlugin;

impl Plugin for SpvgPlugin {
    fn build(&self, _app: &mut App) {}

    fn finish(&self, app: &mut App) {
        library::register(app);
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<systems::SpvgErrors>()
            .add_systems(RenderStartup, systems::init_pipelines)
            .add_systems(ExtractSchedule, systems::extract)
            .add_systems(
                Render,
                systems::prepare.in_set(RenderSystems::PrepareResources),
            )
            .configure_sets(
                Core3d,
                (
                    SpvgSystems::Estimate
                        .after(Core3dSystems::Prepass)
                        .before(Core3dSystems::MainPass),
                    SpvgSystems::Effect
                        .after(SpvgSystems::Estimate)
                        .after(Core3dSystems::MainPass)
                        .before(SpvgSystems::Update)
                        .before(Core3dSystems::EarlyPostProcess),
                    SpvgSystems::Update
                        .after(Core3dSystems::MainPass)
                        .before(Core3dSystems::EarlyPostProcess),
                ),
            )
            .add_systems(
                Core3d,
                (
                    systems::estimate.in_set(SpvgSystems::Estimate),
                    systems::update.in_set(SpvgSystems::Update),
                ),
            );
    }
}
