//! Every `spvg-wgpu` name this crate, its binaries and its tests use, in one place: the
//! component's error, the ambient-occlusion consumer (`AoPass`/`AoTwin`) and the
//! subsurface consumer (`SssPass`/`SssTwin`, the separable filter and the hybrid pass).

pub use spvg_wgpu::adaptive::AdaptiveError;
pub use spvg_wgpu::ao::twin as ao_twin;
pub use spvg_wgpu::ao::{AoFrame, AoGuide, AoMode, AoParams, AoPass, AoScene, AoTwin, Motion};
pub use spvg_wgpu::sss::twin::SeparableTwin;
pub use spvg_wgpu::sss::{
    FrameInputs, FrameOutput, FrameSums, Guide, History, HybridPass, HybridTimes, HybridTwin,
    Model, PassConfig, PassParams, PassTimes, Reducer, SeparableConfig, SeparableParams,
    SeparablePass, SssPass, SssTwin, Timer, luminance, technique_ids,
};
pub use spvg_wgpu::{Backend, BackendChoice, GpuDevice, PassError, acquire_device};
