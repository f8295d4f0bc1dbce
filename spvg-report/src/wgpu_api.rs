//! Every `spvg-wgpu` and `spvg-effects` name this crate, its binaries and its tests use, in one place: the
//! component's error, the ambient-occlusion consumer (`AoPass`/`AoTwin`) and the
//! subsurface consumer (`SssPass`/`SssTwin`, the separable filter and the hybrid pass).

pub use spvg_effects::ao::twin as ao_twin;
pub use spvg_effects::ao::{AoFrame, AoGuide, AoMode, AoParams, AoPass, AoScene, AoTwin, Motion};
pub use spvg_effects::sss::twin::SeparableTwin;
pub use spvg_effects::sss::{
    FrameInputs, FrameOutput, FrameSums, Guide, History, HybridPass, HybridTimes, HybridTwin,
    Model, PassConfig, PassParams, PassTimes, Reducer, SeparableConfig, SeparableParams,
    SeparablePass, SssPass, SssTwin, Timer, luminance, technique_ids,
};
pub use spvg_effects::{Backend, BackendChoice, PassError, check_frame_size};
pub use spvg_wgpu::adaptive::{AdaptiveError, AdaptiveSettings};
pub use spvg_wgpu::util::{GpuDevice, acquire_device};
