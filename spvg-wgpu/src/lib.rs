//! # spvg-wgpu: spvg on wgpu: a reusable adaptive-sampling component and two consumers
//!
//! [`adaptive`] is the component a renderer adopts: [`adaptive::AdaptivePass`] owns the
//! per-pixel history, reprojects it along motion vectors with disocclusion, and records an
//! estimate step (counts) and an update step into the caller's command encoder; its CPU
//! twin is [`adaptive::AdaptiveTwin`]. [`ao`] is a consumer built on it (stochastic ambient
//! occlusion on a procedural height field, with moving cameras and objects). The guide is
//! `docs/integrating.md` in the repository.
//!
//! The subsurface demo ([`GpuPass`], `shaders/sss.wgsl`, with shared WGSL in
//! `shaders/shared/`) renders Burley subsurface scattering with per-pixel sample counts from
//! the SPVG controller, in three models: plain adaptive sampling (AS), constant control
//! variate (CCV) and online control variate (OCV), plus a fixed-count baseline. Its adaptive
//! models are the first consumer of the component: per frame `sss_gamma` (the distant-energy
//! ratio), the component's estimate (static camera: zero motion, the subsurface mask and its
//! previous frame), `sss_sample` (that many Burley samples; the result, the monitored and the
//! control luminance), the component's update. The CPU twin ([`twin`], with
//! [`adaptive::AdaptiveTwin`] for the component) mirrors each entry point in Rust on top of
//! the core crate and is both the test oracle and the `cpu` backend ([`CpuPass`]). The
//! scenes, references and the speed/accuracy report live in the `spvg-report` crate.
//!
//! Device acquisition ([`acquire_device`]) is separate from the pass ([`run_inner`],
//! [`GpuPass::new`]) so tests can create their own device. [`Backend::resolve`] picks
//! `auto` (a wgpu adapter: hardware first, then software Vulkan such as lavapipe; else the
//! CPU twin), `gpu` or `cpu`.
//!
//! The frame budget governor's inputs (`spvg::budget`: the frame's total and the clamped
//! demand curve of the next frame) come from a reduction pass ([`ReducePass`],
//! `shaders/reduce.wgsl`, twin [`twin::reduce_demand`]); see [`reduce`] for its one frame
//! of latency.
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
//! use spvg_wgpu::{CpuPass, FrameInputs, Model, PassConfig};
//!
//! let (w, h) = (16, 12);
//! let cfg = PassConfig::default();
//! let mut pass = CpuPass::new(Model::Ccv, 16 * 12);
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
//!     let params = cfg.params(Model::Ccv, &SKIN1, w, h, t).unwrap();
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

pub mod adaptive;
pub mod ao;
mod device;
mod error;
pub mod frame;
mod gpu;
mod params;
pub mod reduce;
mod resources;
mod runner;
pub mod shaders;
pub mod twin;

pub use device::{BackendChoice, GpuDevice, acquire_device, check_frame_size};
pub use error::PassError;
pub use frame::{FrameInputs, FrameOutput, History, Timer};
pub use gpu::GpuPass;
pub use params::{Model, PassConfig, PassParams, sampling_profile};
pub use reduce::{DemandPartial, FrameSums, ReduceInputs, ReducePass, Reducer};
pub use runner::{Backend, CpuPass, PassRunner, run_frames_on, run_inner};
