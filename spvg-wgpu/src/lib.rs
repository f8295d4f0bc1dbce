//! # spvg-wgpu: the SPVG adaptive-sampling component for wgpu
//!
//! [`adaptive`] is the component a renderer adopts: [`adaptive::AdaptivePass`] owns the
//! per-pixel history, reprojects it along motion vectors with disocclusion, and records an
//! estimate step (counts) and an update step into the caller's command encoder, around
//! the renderer's own sampling pass; its CPU twin is [`adaptive::AdaptiveTwin`]; both take
//! one [`adaptive::AdaptiveSettings`]. [`util`] holds the small wgpu helpers the component
//! is built with (textures, pipelines, dispatches, readback), public so that renderers and
//! tests use them instead of copies.
//!
//! It depends on the core crate (`spvg`), the WGSL library (`spvg-shaders`) and wgpu only.
//! The integration guide is `docs/integrating.md` in the repository; the subsurface and
//! ambient-occlusion effects built on this crate's public API are in `spvg-effects`.

pub mod adaptive;
pub mod util;
