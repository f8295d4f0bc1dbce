//! # spvg-wgpu: the SPVG adaptive-sampling component for wgpu, and two renderers built on it
//!
//! [`adaptive`] is the component a renderer adopts: [`adaptive::AdaptivePass`] owns the
//! per-pixel history, reprojects it along motion vectors with disocclusion, and records an
//! estimate step (counts) and an update step into the caller's command encoder; its CPU
//! twin is [`adaptive::AdaptiveTwin`]. It depends on the core crate (`spvg`), the WGSL
//! library (`spvg-shaders`), wgpu and this crate's GPU utilities only. The guide is
//! `docs/integrating.md` in the repository.
//!
//! Two consumers sit beside it, each a folder with its Rust (the pass on a device, its CPU
//! twin) and its WGSL:
//! - [`sss`]: Burley subsurface scattering ([`sss::SssPass`] / [`sss::SssTwin`]) in the
//!   models AS, CCV, OCV and a fixed-count baseline, with the frame budget governor's
//!   reduction ([`sss::ReducePass`]);
//! - [`ao`]: stochastic ambient occlusion on a procedural height field with moving cameras
//!   and objects ([`ao::AoPass`] / [`ao::AoTwin`]).
//!
//! What both consumers share is in [`common`]. Device acquisition ([`acquire_device`]) is
//! separate from the passes so tests can create their own device; [`Backend::resolve`]
//! picks `auto` (a wgpu adapter: hardware first, then software Vulkan such as lavapipe;
//! else the CPU twin), `gpu` or `cpu`.
//!
//! The scenes, references and the speed/accuracy report live in the `spvg-report` crate.

pub mod adaptive;
pub mod ao;
pub mod common;
mod device;
mod error;
pub mod sss;

pub use device::{Backend, BackendChoice, GpuDevice, acquire_device, check_frame_size};
pub use error::PassError;
