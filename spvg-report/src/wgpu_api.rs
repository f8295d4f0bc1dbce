//! Every `spvg-wgpu` name this crate, its binary and its tests use, in one place: the
//! component (its twin, inputs, readback and texture formats, for the motion section's
//! check of each GPU frame against the twin and for the GPU-readiness study), the
//! ambient-occlusion consumer (`AoPass`/`AoTwin`), the subsurface consumer
//! (`SssPass`/`SssTwin`, the separable filter and the hybrid pass) and device handling.

pub use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, COUNT_FORMAT, Control, EstimateData, EstimateInputs,
    HISTORY_FORMAT, UpdateData, UpdateInputs, read_texture,
};
pub use spvg_wgpu::ao::twin as ao_twin;
pub use spvg_wgpu::ao::{AoFrame, AoGuide, AoMode, AoParams, AoPass, AoScene, AoTwin, Motion};
pub use spvg_wgpu::sss::twin::SeparableTwin;
pub use spvg_wgpu::sss::{
    FrameInputs, FrameOutput, FrameSums, Guide, History, HybridPass, HybridTimes, HybridTwin,
    MAX_SEPARABLE_SAMPLES, Model, PassConfig, PassParams, PassTimes, Reducer, SeparableConfig,
    SeparableParams, SeparablePass, SssPass, SssTwin, TECHNIQUE_AFIS, Timer, luminance,
    technique_ids,
};
pub use spvg_wgpu::{Backend, GpuDevice, PassError, acquire_device};
