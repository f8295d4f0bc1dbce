//! # spvg: single-pass variance-guided adaptive sampling
//!
//! A renderer calls this crate once per pixel per frame: before sampling, to learn how
//! many Monte Carlo samples the pixel needs, and after, to update a few numbers of
//! per-pixel history. The formulas are those of `docs/algorithms.md` (SPVG, Xie et al. 2020, and
//! real-time subsurface control variates, Xie & Olano 2021, with corrections).
//!
//! - [`stats`]: streaming exponentially weighted estimators (EMA, EMV, EMC, EMCM, EWMA).
//! - [`controller`]: the SPVG sample-count controller, with an optional damped correction.
//! - [`budget`]: a frame-level governor that sets `sigma0^2` so each frame's total sample
//!   count tracks a budget.
//! - [`frame_time`]: a frame-time governor that turns a target in milliseconds into the
//!   budget governor's per-frame sample budget, learning the pass's cost online.
//! - [`cv`]: control variates (AS, CCV, OCV) for temporally stable counts.
//! - [`burley`]: Burley's normalized diffusion profile: sampling, estimators, presets.
//! - [`sequence`]: pcg3d16 seeds and the fixed-point R2 sequence, bit-identical on GPU.
//! - [`texel`]: f16/f32 texel layouts, encodings and stochastic rounding of the histories.
//! - [`reproject`]: reading the history along motion vectors, and when it is valid.
//!
//! # Feature flags
//!
//! - `std` (default): float math and `std::error::Error` from the standard library.
//! - `libm`: float math through `libm`, for `no_std` targets. One of `std` and `libm`
//!   must be enabled.
//! - `nalgebra`: conversions of covariance and coefficient matrices to
//!   `nalgebra::SMatrix` (`to_nalgebra`, `coefficients_nalgebra` on
//!   [`stats::Emcm`] and [`stats::Ewma`]). `nalgebra` follows the math backend: `std`
//!   enables `nalgebra/std`, `libm` enables `nalgebra/libm`, so
//!   `--no-default-features --features libm,nalgebra` builds without std.
//! - `arbitrary`: the [`arbitrary`] module of hard-case generators shared by property
//!   tests and fuzz targets (implies `std`).
//! - `rayon`: `texel::update_frame_rayon` and `texel::update_frame_ocv_rayon`, the frame
//!   updates on rayon's thread pool (implies `std`). Other job systems use the range
//!   form, [`texel::update_frame_range`] and [`texel::update_frame_ocv_range`].
#![cfg_attr(all(not(feature = "std"), not(test)), no_std)]
// No unsafe code, with one exception: `texel::dispatch` calls the frame loops compiled
// for AVX2/FMA/F16C or AVX-512 after detecting those features at run time (x86-64 with
// `std`).
#![deny(unsafe_code)]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("spvg needs a float math backend: enable the `std` or the `libm` feature");

#[cfg(any(test, feature = "arbitrary"))]
pub mod arbitrary;
pub mod budget;
pub mod burley;
pub mod controller;
pub mod cv;
pub mod dilation;
mod error;
pub mod frame_time;
pub mod reproject;
pub mod sequence;
pub mod stats;
pub mod texel;

pub use controller::{SpvgConfig, SpvgHistory};
pub use cv::CvHistory;
pub use error::Error;
/// The float trait every generic type of this crate is bounded by, re-exported so that
/// generic code over [`SpvgConfig`], [`SpvgHistory`] and the estimators needs no
/// dependency of its own on `num-traits`.
pub use num_traits::Float;

// The README's example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
