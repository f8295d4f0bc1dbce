//! # spvg-bevy: SPVG adaptive sampling in Bevy's render world
//!
//! [`SpvgPlugin`] runs the `spvg-wgpu` component ([`spvg_wgpu::adaptive::AdaptivePass`])
//! inside Bevy 0.20.1's render world, on Bevy's own prepass, for every 3D camera with
//! [`AdaptiveSampling`]. Bevy 0.20.1 is built on wgpu 30, the component's wgpu, so the
//! component records into Bevy's command encoder as it is.
//!
//! Per frame and camera, in the camera's `Core3d` schedule:
//!
//! ```text
//! Core3dSystems::Prepass     Bevy: depth, motion vectors
//! SpvgSystems::Estimate      convert (depth -> linear, UV motion -> pixels, geometry mask),
//!                            AdaptivePass::record_estimate               -> count texture
//! <your pass>                reads SpvgView::count_texture, takes that many samples,
//!                            writes its monitored value (SpvgView::value_texture or SpvgValue)
//! SpvgSystems::Update        AdaptivePass::record_update                 -> new history
//! Core3dSystems::EarlyPostProcess   Bevy's TAA resolves the image
//! ```
//!
//! `SpvgSystems::Estimate` runs after `Core3dSystems::Prepass` and before
//! `Core3dSystems::MainPass`; `SpvgSystems::Update` after `Core3dSystems::MainPass` and
//! before `Core3dSystems::EarlyPostProcess`. Order your pass
//! `.after(SpvgSystems::Estimate).before(SpvgSystems::Update)`.
//!
//! ## Inputs from Bevy's prepass
//!
//! - **Depth**: Bevy's prepass depth is reverse-Z NDC depth; the plugin converts it to the
//!   linear depth along the view axis through the inverse projection (perspective and
//!   orthographic alike). Pixels without geometry (NDC depth 0) are outside the pass mask
//!   unless [`AdaptiveSampling::skip_background`] is `false`.
//! - **Motion vectors**: Bevy stores this frame's position minus the previous frame's in UV
//!   units, `+y` down (`MotionVectorPrepass`); the component takes the same difference in
//!   pixels, so the plugin multiplies by the viewport size and keeps the sign.
//! - **Previous depth**: the plugin keeps its own converted depth of the previous frame
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
//! ## Build
//!
//! This crate is its own Cargo workspace inside the spvg repository, pinned to Rust 1.97.1
//! (Bevy 0.20.1's `rust-version`) by its `rust-toolchain.toml`, with its own `Cargo.lock`
//! and target directory, so that the main workspace keeps its toolchain and does not build
//! Bevy.

mod component;
mod convert;
mod library;
mod systems;
mod view;

use bevy::app::{App, Plugin};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::ecs::schedule::{IntoScheduleConfigs, SystemSet};
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};

pub use component::{AdaptiveSampling, SpvgStatus};
pub use convert::{LINEAR_DEPTH_FORMAT, MASK_FORMAT, MOTION_PIXELS_FORMAT, VALUE_FORMAT};
pub use library::{SHADER_IMPORT_PATH, SHADER_LIBRARY_HANDLE};
pub use view::{SpvgValue, SpvgView};

pub use spvg;
pub use spvg_shaders;
pub use spvg_wgpu;

/// The plugin's `Core3d` system sets (see the [crate docs](crate) for where they run).
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub enum SpvgSystems {
    /// Converts the prepass outputs and records `AdaptivePass::record_estimate`.
    Estimate,
    /// Records `AdaptivePass::record_update`.
    Update,
}

/// Runs the SPVG adaptive-sampling component for every 3D camera with
/// [`AdaptiveSampling`], and registers the shader library. It sets itself up in
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
