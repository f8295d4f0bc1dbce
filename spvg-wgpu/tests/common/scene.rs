//! The moving scene of the GPU-vs-twin tests: a panning camera, an occluder crossing the
//! surface, a mask band, the zero-sample rule and non-finite inputs.

use spvg_wgpu::adaptive::{EstimateData, Masks};

/// A small integer hash (splitmix-style) for deterministic noise.
pub(crate) fn hash(mut x: u64) -> f32 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((x ^ (x >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

/// One frame of a moving scene, row-major.
#[derive(Clone, Debug, Default)]
pub(crate) struct Frame {
    pub(crate) motion: Vec<[f32; 2]>,
    pub(crate) depth: Vec<f32>,
    pub(crate) mask: Vec<u8>,
    pub(crate) gamma: Vec<f32>,
    pub(crate) value: Vec<f32>,
    pub(crate) control: Vec<f32>,
    /// The renderer's resolve weight per pixel (the resolved-image rule's input): every
    /// kind of texel, "none" (NaN, 0, negative, infinite) at about 4 pixels in 10.
    pub(crate) resolve: Vec<f32>,
}

/// The resolve weights of [`Frame::resolve`], picked per pixel and frame.
const RESOLVE_WEIGHTS: [f32; 10] = [
    f32::NAN,
    0.0,
    -0.5,
    f32::INFINITY,
    0.04,
    0.1,
    0.3,
    0.7,
    1.0,
    3.0,
];

/// A surface seen by a panning camera (offset `pan(t)` in pixels, fractional speeds that
/// change sign), a disc occluder at half the depth crossing it at 2.3 px per frame, a
/// column band outside the mask, a few pixels under the zero-sample rule, and in frame 4
/// NaN/inf motion and depth and a NaN value.
pub(crate) struct MovingScene {
    pub(crate) w: u32,
    pub(crate) h: u32,
}

impl MovingScene {
    pub(crate) fn pan(t: u32) -> [f32; 2] {
        let t = t as f32;
        [1.5 * t - 0.125 * t * t, 0.25 * t]
    }

    pub(crate) fn occluder(t: u32) -> [f32; 2] {
        [4.0 + 2.3 * t as f32, 11.0]
    }

    pub(crate) fn frame(&self, t: u32) -> Frame {
        let (c, cp) = (Self::pan(t), Self::pan(t.saturating_sub(1)));
        let (o, op) = (Self::occluder(t), Self::occluder(t.saturating_sub(1)));
        let mut f = Frame::default();
        for y in 0..self.h {
            for x in 0..self.w {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let (wx, wy) = (px + c[0], py + c[1]);
                let in_disc = (px - o[0]).powi(2) + (py - o[1]).powi(2) < 25.0;
                let (motion, depth, cell) = if in_disc {
                    ([o[0] - op[0], o[1] - op[1]], 0.5, 1_000_000)
                } else {
                    let cell = (wx.floor() as i64 + 1000) * 4096 + (wy.floor() as i64 + 1000);
                    ([cp[0] - c[0], cp[1] - c[1]], 1.0 + 0.002 * wx, cell as u64)
                };
                // Smooth lighting with a noise amplitude that varies over the surface.
                let base = 0.5 + 0.3 * (0.2 * wx).sin() * (0.15 * wy).cos();
                let amp = 0.02 + 0.2 * hash(cell.wrapping_mul(31) / 7);
                let noise = amp * (hash(cell.wrapping_mul(1 << 20) ^ u64::from(t)) - 0.5);
                f.motion.push(motion);
                f.depth.push(depth);
                f.mask.push(u8::from(!(30..33).contains(&x)));
                f.gamma
                    .push(if (x + 3 * y) % 17 == 0 { 0.005 } else { 0.8 });
                f.control.push(0.8 * base);
                let pick = hash(u64::from(x) * 7919 + u64::from(y) * 104_729 + u64::from(t));
                f.resolve
                    .push(RESOLVE_WEIGHTS[(pick * RESOLVE_WEIGHTS.len() as f32) as usize]);
                f.value.push(0.8 * base * 1.05 + noise);
            }
        }
        if t == 4 {
            let at = |x: u32, y: u32| (y * self.w + x) as usize;
            f.motion[at(3, 3)] = [f32::NAN, 0.0];
            f.motion[at(4, 3)] = [0.0, f32::INFINITY];
            f.depth[at(5, 3)] = f32::INFINITY;
            f.value[at(6, 3)] = f32::NAN;
        }
        f
    }
}

/// The twin's estimate inputs of frame `cur` after `prev`, with the frame's resolve
/// weights (read only where the resolved-image rule is on).
pub(crate) fn data<'a>(cur: &'a Frame, prev: &'a Frame) -> EstimateData<'a> {
    EstimateData::new(&cur.motion, &cur.depth, &prev.depth)
        .with_masks(Some(Masks {
            current: &cur.mask,
            previous: &prev.mask,
        }))
        .with_gamma(Some(&cur.gamma))
        .with_resolve_weight(Some(&cur.resolve))
}

pub(crate) struct Textures {
    pub(crate) motion: wgpu::Texture,
    pub(crate) depth: wgpu::Texture,
    pub(crate) mask: wgpu::Texture,
    pub(crate) gamma: wgpu::Texture,
    pub(crate) value: wgpu::Texture,
    pub(crate) control: wgpu::Texture,
    pub(crate) resolve: wgpu::Texture,
}

pub(crate) fn textures(dev: &spvg_gpu_test::GpuDevice, f: &Frame, w: u32, h: u32) -> Textures {
    use wgpu::TextureFormat as F;
    Textures {
        motion: super::upload(dev, F::Rg32Float, [w, h], &f.motion),
        depth: super::upload(dev, F::R32Float, [w, h], &f.depth),
        mask: super::upload(dev, F::R8Uint, [w, h], &f.mask),
        gamma: super::upload(dev, F::R32Float, [w, h], &f.gamma),
        value: super::upload(dev, F::R32Float, [w, h], &f.value),
        control: super::upload(dev, F::R32Float, [w, h], &f.control),
        resolve: super::upload(dev, F::R32Float, [w, h], &f.resolve),
    }
}
