//! Every `spvg-wgpu` name this crate, its binaries and its tests use, in one place, under
//! the names of the crate's pairing scheme (`SssPass`/`SssTwin` for the subsurface pass
//! and its CPU twin, `AoPass`/`AoTwin` for the ambient-occlusion consumer): when
//! `spvg-wgpu` renames or moves an item, only this file changes.

pub use spvg_wgpu::adaptive::AdaptiveError;
pub use spvg_wgpu::ao::twin as ao_twin;
pub use spvg_wgpu::ao::{
    AoCpu as AoTwin, AoFrame, AoGpu as AoPass, AoMode, AoParams, AoScene, Motion,
};
pub use spvg_wgpu::frame::luminance;
pub use spvg_wgpu::{
    Backend, BackendChoice, CpuPass as SssTwin, FrameInputs, FrameOutput, FrameSums, GpuDevice,
    GpuPass as SssPass, History, Model, PassConfig, PassError, Reducer, Timer, acquire_device,
};
