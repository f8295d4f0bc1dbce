//! Shared helpers of the GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

use spvg_wgpu::{GpuDevice, acquire_device};

/// A wgpu device, or `None` after printing a skip message. On this project's machines and
/// CI lavapipe (mesa-vulkan-drivers) provides one, so the GPU tests really run there.
pub(crate) fn device(test: &str) -> Option<GpuDevice> {
    match acquire_device() {
        Ok(d) => {
            eprintln!("{test}: running on {}", d.describe());
            Some(d)
        }
        Err(e) => {
            eprintln!("{test}: SKIPPED, no wgpu adapter ({e})");
            None
        }
    }
}

/// A single-mip 2D texture descriptor of `w x h` texels.
pub(crate) fn texture_desc(
    w: u32,
    h: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'static> {
    wgpu::TextureDescriptor {
        label: None,
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
    }
}
