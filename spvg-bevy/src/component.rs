//! The main-world side: the camera component that asks for adaptive sampling, and the
//! status the plugin reports back on the camera.

use bevy::camera::Camera3d;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass};
use bevy::ecs::component::Component;
use spvg::SpvgConfig;
use spvg_wgpu::adaptive::AdaptiveSettings;

/// Gives a 3D camera its own [`AdaptivePass`](spvg_wgpu::adaptive::AdaptivePass): per-pixel
/// sample counts from the SPVG controller, estimated after Bevy's prepass from its depth
/// and motion vectors, and updated from the monitored value the user's pass writes.
///
/// # What the camera needs
///
/// - [`DepthPrepass`] and [`MotionVectorPrepass`] (required components: inserted with this
///   one unless the camera has them). `TemporalAntiAliasing` requires both too.
/// - `Msaa::Off`: the prepass textures are read texel by texel, and a multisampled depth
///   has no single depth per pixel.
///
/// Without them (a prepass removed later, MSAA on, an inactive camera) the plugin does not
/// run for that camera: it drops the camera's pass, sets [`SpvgStatus`] to say why and
/// logs one warning when the status changes. It never panics.
///
/// # Settings
///
/// `settings` is the component's own settings type, the one `AdaptivePass` and
/// `AdaptiveTwin` take: a change is handed to the pass between frames
/// (`AdaptivePass::set_settings`) and keeps the histories, except a new control model,
/// which starts them over. (A change waits for the frame after the next update when the
/// current frame's update was skipped: both steps of a frame run one setting.)
#[derive(Component, Clone, Debug, PartialEq)]
#[require(Camera3d, DepthPrepass, MotionVectorPrepass, SpvgStatus)]
pub struct AdaptiveSampling {
    /// The component's settings: controller (target variance, sample range, young-history
    /// rules, firefly clamp), control model, reprojection, count dilation, neighbour prior.
    pub settings: AdaptiveSettings,
    /// `true` (the default): pixels where the prepass wrote no geometry are outside the
    /// pass mask, take 0 samples and keep no history. `false`: every pixel is covered (the
    /// background then has the far depth `1e30`).
    pub skip_background: bool,
}

impl AdaptiveSampling {
    /// Adaptive sampling with `config` and the component's other default settings
    /// (plain averaging, no dilation, the default reprojection), the background skipped.
    #[must_use]
    pub fn new(config: SpvgConfig<f32>) -> Self {
        Self::with_settings(AdaptiveSettings {
            config,
            ..AdaptiveSettings::default()
        })
    }

    /// Adaptive sampling with `settings`, the background skipped.
    #[must_use]
    pub fn with_settings(settings: AdaptiveSettings) -> Self {
        Self {
            settings,
            skip_background: true,
        }
    }
}

impl Default for AdaptiveSampling {
    /// [`AdaptiveSampling::new`] with `SpvgConfig::published()`.
    fn default() -> Self {
        Self::new(SpvgConfig::published())
    }
}

/// Whether the plugin runs for a camera with [`AdaptiveSampling`], and if not, why. The
/// plugin writes it every frame during extraction.
#[derive(Component, Clone, Debug, Default, PartialEq, Eq)]
pub enum SpvgStatus {
    /// Not extracted yet (the first frame has not rendered).
    #[default]
    Pending,
    /// The pass runs for this camera.
    Running,
    /// The camera is inactive (`Camera::is_active` is false).
    Inactive,
    /// A required prepass component is missing.
    MissingPrepass {
        /// [`DepthPrepass`] is missing.
        depth: bool,
        /// [`MotionVectorPrepass`] is missing.
        motion_vectors: bool,
    },
    /// MSAA is on; the plugin needs `Msaa::Off`.
    Multisampled,
    /// The component refused the settings or the frame (its error, as text); kept until
    /// the camera's settings change.
    Failed(String),
}
