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
