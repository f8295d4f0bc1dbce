//! # spvg-web: the adaptive-sampling component in a browser
//!
//! A demo page, compiled to wasm32 with wgpu's WebGPU backend and wasm-bindgen: the
//! ambient-occlusion effect of `spvg-effects` (its scene, its WGSL and its CPU twin)
//! rendered through the component of `spvg-wgpu`, with a camera a person pans and orbits,
//! a floating sphere they move, fixed counts or adaptive sampling, and side by side the
//! image after TAA, the count heat map and the error against a converged reference.
//!
//! Everything but the page's DOM code is ordinary Rust that also runs natively, so the
//! native tests run the page's own passes and its browser check on a device with
//! WebGPU's default limits:
//! - [`scene`]: the view (camera, floating sphere) and the check's scripted path;
//! - [`renderer`]: the passes on a device, driven asynchronously (the readbacks are
//!   awaited, never blocked on: a browser cannot block);
//! - [`check`]: the GPU frames against the component's twin, frame by frame, and the
//!   equal-quality figure;
//! - [`metrics`]: PSNR and the equal-quality interpolation;
//! - [`form`]: the page's fields and URL parameters validated (refusals named);
//! - [`graph`]: the frame-time graph's series and layout (fixed-count side and adaptive
//!   run, one point per frame).
//!
//! `scripts/web-check.sh` in the repository builds the page, serves it and runs the check
//! in headless Chromium.

pub mod check;
mod clock;
pub mod form;
pub mod graph;
pub mod metrics;
#[cfg(target_arch = "wasm32")]
mod page;
pub mod renderer;
pub mod scene;

pub use clock::now_ms;
/// The page's entry point, which `web/index.html` calls once the module is loaded.
#[cfg(target_arch = "wasm32")]
pub use page::start;
