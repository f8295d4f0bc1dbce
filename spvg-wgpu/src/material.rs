//! Burley materials for the scenes: per-channel shape `d` from the SPEC 5 presets.

/// A subsurface material: mean free path `l` (mm) and albedo `A` per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Name used in reports.
    pub name: &'static str,
    /// Mean free path per channel, mm.
    pub mean_free_path: [f32; 3],
    /// Single-scattering albedo per channel.
    pub albedo: [f32; 3],
}

/// skin1 (SPEC 5).
pub const SKIN1: Material = Material {
    name: "skin1",
    mean_free_path: [3.75, 1.47, 0.79],
    albedo: [0.44, 0.22, 0.13],
};

/// marble (SPEC 5).
pub const MARBLE: Material = Material {
    name: "marble",
    mean_free_path: [8.51, 5.57, 3.96],
    albedo: [0.83, 0.79, 0.75],
};

impl Material {
    /// Shape `d` per channel by the diffuse-mean-free-path fit
    /// `d = l / (3.5 + 100 (A - 0.33)^4)` (SPEC 5, the default fit).
    #[must_use]
    pub fn shape(&self) -> [f32; 3] {
        core::array::from_fn(|c| {
            let a = self.albedo[c] - 0.33;
            self.mean_free_path[c] / (3.5 + 100.0 * (a * a) * (a * a))
        })
    }

    /// Shape of the sampling profile: the widest channel, so every channel's profile is
    /// covered by the samples.
    #[must_use]
    pub fn sampling_shape(&self) -> f32 {
        self.shape().into_iter().fold(0.0, f32::max)
    }
}
