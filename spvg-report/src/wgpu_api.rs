//! Every `spvg-wgpu` and `spvg-effects` name this crate, its binary and its tests use, in
//! one place: the component (its twin, inputs, settings, readback and texture formats, for
//! the motion section's check of each GPU frame against the twin and for the GPU-readiness
//! study), the ambient-occlusion effect (`AoPass`/`AoTwin`), the subsurface effect
//! (`SssPass`/`SssTwin`, the separable filter and the hybrid pass) and device handling.

pub use spvg_effects::ao::twin as ao_twin;
pub use spvg_effects::ao::{AoFrame, AoGuide, AoMode, AoParams, AoPass, AoScene, AoTwin, Motion};
pub use spvg_effects::sss::twin::SeparableTwin;
pub use spvg_effects::sss::{
    FrameInputs, FrameOutput, FrameSums, Guide, History, HybridPass, HybridTimes, HybridTwin,
    MAX_SEPARABLE_SAMPLES, Model, PassConfig, PassParams, PassTimes, Reducer, SeparableConfig,
    SeparableParams, SeparablePass, SssPass, SssTwin, TECHNIQUE_AFIS, Timer, luminance,
    technique_ids,
};
pub use spvg_effects::{Backend, BackendChoice, PassError, check_frame_size};
pub use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveSettings, AdaptiveTwin, Control, EstimateData,
    EstimateInputs, UpdateData, UpdateInputs,
};
pub use spvg_wgpu::util::{GpuDevice, acquire_device, block_on, read_texture};

/// The format of the component's count texture.
pub const COUNT_FORMAT: wgpu::TextureFormat = AdaptivePass::COUNT_FORMAT;
/// The format of the component's history texture.
pub const HISTORY_FORMAT: wgpu::TextureFormat = AdaptivePass::HISTORY_FORMAT;
