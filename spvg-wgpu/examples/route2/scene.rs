//! The moving scene of the Route 2 example and its test: a tilted surface under a panning
//! camera with a disc crossing it, as the G-buffer a renderer would hand its adaptive
//! pass (motion, depth) plus the radiance its sampling pass draws from. Shared by
//! `examples/route2/main.rs` and `tests/route2.rs` (included with `#[path]`).

use wgpu::util::DeviceExt as _;

/// One frame of [`Scene`], row-major.
#[derive(Clone, Debug, Default)]
pub(crate) struct SceneFrame {
    /// Motion vectors in the convention of `spvg::reproject`.
    pub(crate) motion: Vec<[f32; 2]>,
    /// Linear depth.
    pub(crate) depth: Vec<f32>,
    /// The radiance's mean and noise amplitude.
    pub(crate) radiance: Vec<[f32; 2]>,
}

/// A tilted surface seen by a camera panning at fractional, changing speeds (pixels enter
/// at the edges: the border prior), with a disc at half the depth crossing it at 2.3 px per
/// frame (the surface it uncovers is disoccluded; next to its silhouette the footprint
/// search finds the surface one texel away).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scene {
    /// Width in pixels.
    pub(crate) width: u32,
    /// Height in pixels.
    pub(crate) height: u32,
}

impl Scene {
    fn camera(t: u32) -> [f32; 2] {
        let t = t as f32;
        [1.5 * t - 0.125 * t * t, 0.35 * t]
    }

    fn disc(t: u32) -> [f32; 2] {
        [6.0 + 2.3 * t as f32, 12.0]
    }

    /// Frame `t`.
    pub(crate) fn frame(&self, t: u32) -> SceneFrame {
        let (c, cp) = (Self::camera(t), Self::camera(t.saturating_sub(1)));
        let (o, op) = (Self::disc(t), Self::disc(t.saturating_sub(1)));
        let mut f = SceneFrame::default();
        for y in 0..self.height {
            for x in 0..self.width {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let (wx, wy) = (px + c[0], py + c[1]);
                if (px - o[0]).powi(2) + (py - o[1]).powi(2) < 30.0 {
                    f.motion.push([o[0] - op[0], o[1] - op[1]]);
                    f.depth.push(0.5);
                    f.radiance.push([0.2, 0.015]);
                } else {
                    f.motion.push([cp[0] - c[0], cp[1] - c[1]]);
                    f.depth.push(1.0 + 0.003 * wx);
                    // Smooth lighting, a noise amplitude that varies over the surface: at
                    // the published target (1e-4) the counts spread over the budget.
                    let mean = 0.5 + 0.09 * (0.2 * wx).sin() * (0.15 * wy).cos();
                    let amplitude = 0.015 + 0.12 * (0.5 + 0.5 * (0.37 * wx + 0.23 * wy).sin());
                    f.radiance.push([mean, amplitude]);
                }
            }
        }
        f
    }

    /// `frame` uploaded: motion, depth, radiance.
    pub(crate) fn upload(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame: &SceneFrame,
    ) -> [wgpu::Texture; 3] {
        use wgpu::TextureFormat as F;
        let put = |format: F, data: &[u8]| {
            device.create_texture_with_data(
                queue,
                &wgpu::TextureDescriptor {
                    label: Some("route2 scene"),
                    size: wgpu::Extent3d {
                        width: self.width,
                        height: self.height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                data,
            )
        };
        [
            put(F::Rg32Float, bytemuck::cast_slice(&frame.motion)),
            put(F::R32Float, bytemuck::cast_slice(&frame.depth)),
            put(F::Rg32Float, bytemuck::cast_slice(&frame.radiance)),
        ]
    }
}
