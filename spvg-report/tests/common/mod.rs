//! Shared helpers of the GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

use spvg_report::wgpu_api::{GpuDevice, Model, SssPass, acquire_device};

/// Set to `1` where a wgpu adapter must exist (CI after installing software Vulkan): a
/// GPU test then fails, naming the missing adapter, instead of skipping.
pub(crate) const REQUIRE_GPU: &str = "SPVG_REQUIRE_GPU";

/// A wgpu device, or `None` after printing a skip message. On this project's machines and
/// CI lavapipe (mesa-vulkan-drivers) provides one, so the GPU tests really run there.
///
/// # Panics
///
/// When no adapter is found and [`REQUIRE_GPU`] is `1`: the test fails and says which
/// adapter is missing, so a machine without Vulkan cannot pass the GPU tests by skipping
/// them.
pub(crate) fn device(test: &str) -> Option<GpuDevice> {
    match acquire_device() {
        Ok(d) => {
            eprintln!("{test}: running on {}", d.describe());
            Some(d)
        }
        Err(e) => {
            assert!(
                std::env::var(REQUIRE_GPU).as_deref() != Ok("1"),
                "{test}: {e}; {REQUIRE_GPU}=1 requires a wgpu adapter (lavapipe: install \
                 mesa-vulkan-drivers; VK_ICD_FILENAMES={})",
                std::env::var("VK_ICD_FILENAMES").unwrap_or_else(|_| "(unset)".into())
            );
            eprintln!(
                "{test}: SKIPPED, no wgpu adapter ({e}); set {REQUIRE_GPU}=1 to fail instead"
            );
            None
        }
    }
}

/// The subsurface pass on `dev` for `model` at `width x height`, timed by wall clock.
pub(crate) fn sss_pass(dev: &GpuDevice, model: Model, width: u32, height: u32) -> SssPass {
    SssPass::new(&dev.device, &dev.queue, width, height, model, false)
}
