//! # spvg-wgpu: a wgpu subsurface-scattering pass driven by spvg
//!
//! A compute pass (`shaders/sss.wgsl`, with shared WGSL in `shaders/shared/`) that renders
//! Burley subsurface scattering with per-pixel sample counts from the SPVG controller,
//! in three models: plain adaptive sampling (AS), constant control variate (CCV) and online
//! control variate (OCV), plus a fixed-count baseline. The CPU twin ([`twin`]) mirrors each
//! entry point in Rust on top of the core crate and is both the test oracle and the `cpu`
//! backend. [`scene`] has the procedural evaluation scenes of SPEC 7 with converged
//! references, and the `spvg-report` binary measures speed and accuracy.
//!
//! Device acquisition ([`acquire_device`]) is separate from the pass ([`run_inner`],
//! [`GpuPass::new`]) so tests can create their own device.

mod device;
mod error;
pub mod evaluate;
pub mod frame;
mod gpu;
pub mod metrics;
mod params;
pub mod plot;
pub mod reference;
mod runner;
pub mod scene;
pub mod shaders;
pub mod twin;

pub use device::{BackendChoice, GpuDevice, acquire_device};
pub use error::PassError;
pub use frame::{FrameInputs, FrameOutput, History, Timer};
pub use gpu::GpuPass;
pub use params::{Model, PassConfig, PassParams, sampling_profile};
pub use runner::{Backend, CpuPass, PassRunner, run_frames_on, run_inner};
