//! # spvg-effects: two renderers built on the SPVG adaptive-sampling component
//!
//! Each effect is one folder with its Rust (the pass on a wgpu device and its CPU twin)
//! and its WGSL, and reaches the component ([`spvg_wgpu::adaptive`]) through its public
//! API only, as any renderer would:
//! - [`sss`]: Burley subsurface scattering ([`sss::SssPass`] / [`sss::SssTwin`]) in the
//!   models AS, CCV, OCV and a fixed-count baseline, with filtered sampling (AFIS), the
//!   separable filter and the hybrid of both, and the frame budget governor's reduction
//!   ([`sss::ReducePass`]);
//! - [`ao`]: stochastic ambient occlusion on a procedural height field with moving cameras
//!   and objects ([`ao::AoPass`] / [`ao::AoTwin`]).
//!
//! [`Backend::resolve`] picks where an effect runs: `auto` (a wgpu adapter, hardware
//! first, then software Vulkan such as lavapipe; else the CPU twin), `gpu` or `cpu`.

pub mod ao;
mod common;
mod device;
mod error;
mod gpu;
pub mod sss;

pub use device::{Backend, BackendChoice, check_frame_size};
pub use error::PassError;
