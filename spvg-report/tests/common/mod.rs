//! Shared helpers of the GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

use spvg_report::wgpu_api::{GpuDevice, Model, SssPass};

/// The device of GPU test `test` ([`spvg_gpu_test::GpuTest`]: skipped with the reason
/// where there is none, a failure under `SPVG_REQUIRE_GPU=1`).
pub(crate) fn device(test: &str) -> Option<GpuDevice> {
    spvg_gpu_test::GpuTest::new(test).device()
}

/// The subsurface pass on `dev` for `model` at `width x height`, timed by wall clock.
pub(crate) fn sss_pass(dev: &GpuDevice, model: Model, width: u32, height: u32) -> SssPass {
    SssPass::new(&dev.device, &dev.queue, width, height, model, false)
}
