//! Shared helpers of the GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

use spvg_wgpu::{GpuDevice, acquire_device};

/// A wgpu device, or `None` after printing a skip message. With `SPVG_REQUIRE_GPU=1` (CI
/// sets it after installing lavapipe, mesa-vulkan-drivers) a missing adapter fails the
/// test instead, so a machine without Vulkan cannot go green without running the GPU tests.
///
/// # Panics
///
/// With `SPVG_REQUIRE_GPU=1` and no adapter, naming the missing adapter.
pub(crate) fn device(test: &str) -> Option<GpuDevice> {
    match acquire_device() {
        Ok(d) => {
            eprintln!("{test}: running on {}", d.describe());
            Some(d)
        }
        Err(e) if std::env::var("SPVG_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
            panic!("{test}: SPVG_REQUIRE_GPU=1 but no wgpu adapter was found ({e})")
        }
        Err(e) => {
            eprintln!(
                "{test}: SKIPPED, no wgpu adapter ({e}); set SPVG_REQUIRE_GPU=1 to make this \
                 a failure"
            );
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
