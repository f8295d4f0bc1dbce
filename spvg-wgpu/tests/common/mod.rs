//! Shared helpers of the GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

use spvg_gpu_test::GpuDevice;

pub(crate) mod scene;

/// The component's settings with `config` and `control`, the rest default.
pub(crate) fn settings(
    config: spvg::SpvgConfig<f32>,
    control: spvg_wgpu::adaptive::Control,
) -> spvg_wgpu::adaptive::AdaptiveSettings {
    spvg_wgpu::adaptive::AdaptiveSettings {
        config,
        control,
        ..Default::default()
    }
}

/// A sampled texture of `size` holding `data` (one `T` per texel, rows top to bottom).
pub(crate) fn upload<T: bytemuck::Pod>(
    dev: &GpuDevice,
    format: wgpu::TextureFormat,
    size: [u32; 2],
    data: &[T],
) -> wgpu::Texture {
    use wgpu::util::DeviceExt as _;
    dev.device.create_texture_with_data(
        &dev.queue,
        &spvg_wgpu::util::texture_2d_desc(
            "upload",
            format,
            size,
            wgpu::TextureUsages::TEXTURE_BINDING,
        ),
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(data),
    )
}

/// The bits of each channel of `f16` texels: compared with `assert_eq!`, bit-identity
/// (NaN payloads and the sign of zero included), which `==` on the values is not.
pub(crate) fn bits(v: &[[half::f16; 4]]) -> Vec<[u16; 4]> {
    v.iter().map(|t| t.map(half::f16::to_bits)).collect()
}
