//! # The first consumer: Burley subsurface scattering with per-pixel sample counts
//!
//! [`SssPass`] (`shaders/sss.wgsl` here, with `shaders/params.wgsl` and
//! `shaders/estimator.wgsl`, and the crate's `common/direction.wgsl`) renders subsurface
//! scattering in three models: plain adaptive sampling (AS), constant control variate
//! (CCV) and online control variate (OCV), plus a fixed-count baseline ([`Model`]). Its
//! adaptive models run the component ([`spvg_wgpu::adaptive::AdaptivePass`]): per frame
//! `sss_gamma` (the distant-energy ratio), the component's estimate (static camera: zero
//! motion, the subsurface mask and its previous frame), `sss_sample` (that many Burley
//! samples; the result, the monitored and the control luminance), the component's update.
//!
//! [`SssTwin`] is the same pass on the CPU ([`twin`]: one function per entry point, on the
//! core crate and the component's twin [`spvg_wgpu::adaptive::AdaptiveTwin`]); it is both the
//! test oracle and the `cpu` backend. [`SssRunner`] is either, as [`Backend::pass`]
//! resolves it. The scenes, references and the speed/accuracy report live in the
//! `spvg-report` crate.
//!
//! The frame budget governor's inputs (`spvg::budget`: the frame's total and the clamped
//! demand curve of the next frame) come from a reduction pass ([`ReducePass`],
//! `shaders/reduce.wgsl`, twin [`twin::reduce_demand`]) over the subsurface pass's
//! history; see [`reduce`] for its one frame of latency.
//!
//! [`SeparablePass`] (`shaders/separable.wgsl`, twin [`twin::SeparableTwin`]) is the other
//! [`Technique`]: separable subsurface scattering with the kernel of the separable profile
//! fitted to the material's Burley profiles ([`SeparableConfig`]), and, given a per-pixel
//! technique and the AFIS result ([`twin::HybridSources`]), the separable half of the
//! hybrid pass ([`HybridPass`], twin [`HybridTwin`]: AFIS with the adaptive count where
//! the caller tags the frame, the separable filter elsewhere).
//!
//! Lighting is read from mip 0 of the lighting texture, or with `PassConfig::afis` from
//! the mip level of filtered sampling (AFIS, docs/algorithms.md §5) for each sample.
//!
//! # Examples
//!
//! A few frames of a flashing light on a flat skin surface through CCV on the CPU twin:
//!
//! ```
//! use half::f16;
//! use spvg::burley::presets::SKIN1;
//! use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssTwin};
//!
//! let (w, h) = (16, 12);
//! let cfg = PassConfig::default();
//! let mut pass = SssTwin::new(Model::Ccv, w, h);
//! for t in 0..3 {
//!     // A light whose intensity changes every frame, a surface at 1 m, all subsurface.
//!     let level = f16::from_f32(0.25 * (t + 1) as f32);
//!     let inputs = FrameInputs {
//!         width: w,
//!         height: h,
//!         lighting: vec![[level, level, level, f16::ONE]; 16 * 12],
//!         depth: vec![1000.0; 16 * 12],
//!         mask: vec![1; 16 * 12],
//!     };
//!     let params = pass.frame_params(&cfg, &SKIN1, t).unwrap();
//!     let out = pass.run_frame(&params, &inputs).unwrap();
//!     // The first frame (cold history) takes beta_min; counts stay in the budget.
//!     assert!(out.count.iter().all(|&n| n == 0 || (8..=64).contains(&n)));
//!     if t == 0 {
//!         assert!(out.count.iter().all(|&n| n == 0 || n == 8));
//!     }
//! }
//! // CCV keeps one 8-byte history texel per pixel.
//! assert_eq!(Model::Ccv.history_bytes_per_pixel(), 8);
//! assert_eq!(pass.history().h.len(), 16 * 12);
//! ```
//!
//! [`Backend::pass`]: crate::Backend::pass

mod frame;
mod hybrid;
mod params;
mod pass;
mod record;
pub mod reduce;
mod runner;
mod separable;
mod separable_pass;
mod separable_tiles;
mod tiles;
pub mod twin;

pub use frame::{FrameInputs, FrameOutput, Guide, History, LUMA, Timer, luminance};
pub use hybrid::{
    HybridOutput, HybridPass, HybridTimes, HybridTwin, TECHNIQUE_AFIS, technique_ids,
};
pub use params::{Model, PassConfig, PassParams, sampling_profile};
pub use pass::{PassTimes, SssPass};
pub use reduce::{DemandPartial, FrameSums, ReduceInputs, ReducePass, Reducer};
pub use runner::SssRunner;
pub use separable::{MAX_SEPARABLE_SAMPLES, SeparableConfig, SeparableParams, Technique};
pub use separable_pass::{SEPARABLE_WGSL, SeparablePass, separable_source};
pub use twin::SssTwin;

/// The uniform block of every subsurface entry point (`shaders/params.wgsl`: `struct
/// PassParams`, the Rust [`PassParams`]).
pub const PARAMS_WGSL: &str = include_str!("shaders/params.wgsl");

/// The unified estimator the entry points share (`shaders/estimator.wgsl`).
const ESTIMATOR_WGSL: &str = include_str!("shaders/estimator.wgsl");

/// The subsurface pass (`shaders/sss.wgsl`): entry points `sss_fixed`, `sss_gamma` and
/// `sss_sample` (the adaptive models' count control is [`spvg_wgpu::adaptive::AdaptivePass`]).
pub const SSS_WGSL: &str = include_str!("shaders/sss.wgsl");

/// The budget reduction (`shaders/reduce.wgsl`): entry point `reduce_demand`.
pub const REDUCE_WGSL: &str = include_str!("shaders/reduce.wgsl");

/// The library ([`spvg_shaders::WGSL`]), the pass's uniform block, the sample direction,
/// the estimator and `entry`, as one WGSL module source.
fn with_prelude(entry: (&str, &str)) -> String {
    crate::gpu::assemble(&[
        ("spvg_shaders::WGSL", spvg_shaders::WGSL),
        ("sss/shaders/params.wgsl", PARAMS_WGSL),
        ("common/direction.wgsl", crate::common::DIRECTION_WGSL),
        ("sss/shaders/estimator.wgsl", ESTIMATOR_WGSL),
        entry,
    ])
}

/// The assembled subsurface pass (with the component's decoder of a classified
/// dispatch, which `sss_sample_classified` calls).
#[must_use]
pub fn sss_source() -> String {
    let classified = spvg_wgpu::adaptive::AdaptivePass::CLASSIFIED_WGSL;
    with_prelude(("sss/shaders/sss.wgsl", &format!("{classified}{SSS_WGSL}")))
}

/// `sss_sample_one_pass` (`shaders/sss_one_pass.wgsl`), joined after the component's
/// one-pass module.
const SSS_ONE_PASS_WGSL: &str = include_str!("shaders/sss_one_pass.wgsl");

/// The assembled subsurface pass of the one-pass form: [`sss_source`], the component's
/// one-pass module `one_pass` (its bindings at group 2) and `shaders/sss_one_pass.wgsl`.
#[must_use]
pub fn sss_one_pass_source(one_pass: &str) -> String {
    let classified = spvg_wgpu::adaptive::AdaptivePass::CLASSIFIED_WGSL;
    with_prelude((
        "sss/shaders/sss.wgsl, the component's one-pass module, sss/shaders/sss_one_pass.wgsl",
        &format!("{classified}{SSS_WGSL}{one_pass}{SSS_ONE_PASS_WGSL}"),
    ))
}

/// The assembled budget reduction.
#[must_use]
pub fn reduce_source() -> String {
    with_prelude(("sss/shaders/reduce.wgsl", REDUCE_WGSL))
}
