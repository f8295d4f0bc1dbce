//! The example's effect: its settings and its shader (`assets/shaders/soft_shadows.wesl`),
//! run by spvg-bevy's effect helper, which binds spvg's counts, Bevy's prepass and these
//! settings, writes the monitored value and orders the pass around spvg's steps.

use bevy::prelude::*;
use bevy::render::render_resource::ShaderType;
use bevy::shader::ShaderRef;
use spvg_bevy::AdaptiveEffect;

/// Soft shadows from a rectangular area light, occluded by up to 16 spheres: per pixel,
/// spvg's count of shadow rays. A camera with it gets `AdaptiveSampling` (required).
#[derive(Component, Clone, Debug, ShaderType)]
pub struct SoftShadows {
    /// A corner of the light and its two edges.
    pub light_corner: Vec3,
    pub light_u: Vec3,
    pub light_v: Vec3,
    /// Occluders (centre, radius); the first `sphere_count` are used.
    pub spheres: [Vec4; 16],
    pub sphere_count: u32,
    /// Mixed into the light samples' sequence: cameras with different seeds sample
    /// independently.
    pub seed: u32,
    /// Non-zero: show spvg's counts (blue at `count_range.x` to red at `count_range.y`, log
    /// scale) instead of the shadowed image.
    pub show_counts: u32,
    pub count_range: UVec2,
}

impl SoftShadows {
    /// The effect for `spheres` (centre, radius) under the light `corner + [0, 1]^2 (u, v)`.
    pub fn new(spheres: &[Vec4], [corner, u, v]: [Vec3; 3]) -> Self {
        let mut all = [Vec4::ZERO; 16];
        for (slot, s) in all.iter_mut().zip(spheres) {
            *slot = *s;
        }
        Self {
            light_corner: corner,
            light_u: u,
            light_v: v,
            spheres: all,
            sphere_count: spheres.len().min(16) as u32,
            seed: 0,
            show_counts: 0,
            count_range: UVec2::new(1, 64),
        }
    }
}

impl AdaptiveEffect for SoftShadows {
    fn fragment_shader() -> ShaderRef {
        "shaders/soft_shadows.wesl".into()
    }
}
