//! The steps' inputs, uploaded once per size, and the texture helpers the copy kernel
//! shares.

use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::bytes::{MOTION_FORMAT, SCALAR_FORMAT};
use crate::wgpu_api::GpuDevice;

/// The steps' inputs: a pan of 1.5 px right and 0.5 px up over a sloped surface (so most
/// histories stay valid, as in a moving camera), and two noisy monitored values taken in
/// turn (so the controller sees variance).
pub(super) struct Inputs {
    pub(super) motion: wgpu::Texture,
    pub(super) depth: wgpu::Texture,
    pub(super) value: [wgpu::Texture; 2],
}

/// A hash in [0, 1) of a pixel and a seed (plausible noise, not a quality RNG).
pub(super) fn noise(x: u32, y: u32, seed: u32) -> f32 {
    let mut v = x.wrapping_mul(0x9E37_79B9) ^ y.wrapping_mul(0x85EB_CA6B) ^ seed;
    v ^= v >> 16;
    v = v.wrapping_mul(0x7FEB_352D);
    v ^= v >> 15;
    (v >> 8) as f32 / (1u32 << 24) as f32
}

impl Inputs {
    pub(super) fn new(d: &GpuDevice, [w, h]: [u32; 2]) -> Self {
        let pixels = |f: &dyn Fn(u32, u32) -> Vec<f32>| -> Vec<u8> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .flat_map(|(x, y)| f(x, y))
                .flat_map(f32::to_le_bytes)
                .collect()
        };
        let motion = upload(
            d,
            "readiness motion",
            MOTION_FORMAT,
            [w, h],
            &pixels(&|_, _| vec![1.5, -0.5]),
        );
        let depth = upload(
            d,
            "readiness depth",
            SCALAR_FORMAT,
            [w, h],
            &pixels(&|x, y| vec![2.0 + 3.0 * y as f32 / h as f32 + 0.5 * x as f32 / w as f32]),
        );
        let value = [1, 2].map(|seed| {
            upload(
                d,
                "readiness value",
                SCALAR_FORMAT,
                [w, h],
                &pixels(&|x, y| vec![0.4 + 0.2 * noise(x, y, seed)]),
            )
        });
        Self {
            motion,
            depth,
            value,
        }
    }
}

pub(super) fn texture(
    d: &GpuDevice,
    label: &str,
    format: Tf,
    [w, h]: [u32; 2],
    usage: Tu,
) -> wgpu::Texture {
    d.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A sampled texture holding `data` (tightly packed rows).
pub(super) fn upload(
    d: &GpuDevice,
    label: &str,
    format: Tf,
    [w, h]: [u32; 2],
    data: &[u8],
) -> wgpu::Texture {
    let t = texture(d, label, format, [w, h], Tu::TEXTURE_BINDING | Tu::COPY_DST);
    d.queue.write_texture(
        t.as_image_copy(),
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * format.block_copy_size(None).unwrap_or(0)),
            rows_per_image: Some(h),
        },
        t.size(),
    );
    t
}
