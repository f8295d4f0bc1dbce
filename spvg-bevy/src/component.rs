//! The main-world side: the camera component that asks for adaptive sampling, and the
//! status the plugin reports back on the camera.

use bevy::camera::Camera3d;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass};
use bevy::ecs::component::Component;
use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg_wgpu::adaptive::Control;

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
/// Changing `config` (other than its target variance) or `control` rebuilds the pass,
/// whose histories then start over; a new target variance, `dilation`, `reprojection` or
/// `skip_background` is applied in place and keeps the histories. (A new target variance
/// waits for the frame after the next update when the current frame's update was skipped:
/// both steps of a frame run one target.)
#[derive(Component, Clone, Debug, PartialEq)]
#[require(Camera3d, DepthPrepass, MotionVectorPrepass, SpvgStatus)]
pub struct AdaptiveSampling {
    /// The controller configuration (target variance, sample range, ...).
    pub config: SpvgConfig<f32>,
    /// The control model of the monitored value.
    pub control: Control,
    /// The count dilation radius (`AdaptivePass::set_count_dilation`; 0: off).
    pub dilation: u32,
    /// The reprojection rule (depth tolerance, footprint search, border prior).
    pub reprojection: Reprojection<f32>,
    /// `true` (the default): pixels where the prepass wrote no geometry are outside the
    /// pass mask, take 0 samples and keep no history. `false`: every pixel is covered (the
    /// background then has the far depth `1e30`).
    pub skip_background: bool,
}

impl AdaptiveSampling {
    /// Adaptive sampling with `config`, plain averaging (`Control::As`), no dilation, the
    /// default reprojection, the background skipped.
    #[must_use]
    pub fn new(config: SpvgConfig<f32>) -> Self {
        Self {
            config,
            control: Control::As,
            dilation: 0,
            reprojection: Reprojection::default(),
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
