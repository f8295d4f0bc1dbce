//! Per-pixel histories in RGBA16F / RGBA32F texels (docs/algorithms.md §4).
//!
//! A renderer keeps the SPVG history `H = (mu, var, nbar)` and, for the online control
//! variate, `J = (Sigma_xy, Sigma_yy, zeta_f, zeta_g)` in textures between frames. This
//! module fixes the texel layouts ([`SpvgTexel16`], [`SpvgTexel32`], [`CvTexel16`],
//! [`CvTexel32`]), the encodings ([`TexelEncoding`]), the `f32 -> f16` store with optional
//! stochastic rounding ([`to_f16`], [`Rounding`]), and a check that tells whether the
//! configured weights can move `f16` storage at all ([`check_precision`]).
//!
//! # Channel order (the WGSL shader must read the same)
//!
//! | texel | r | g | b | a |
//! |---|---|---|---|---|
//! | SPVG `H` | `mu` | `var * 2^-k` | `nbar` | `0` (spare) |
//! | CV `J` | `Sigma_xy * 2^-c` | `Sigma_yy * 2^-c` | `zeta_f` | `zeta_g` |
//!
//! `2^k` is the power of two nearest `sigma0^2` and `2^c` the CV scale
//! ([`TexelEncoding::variance_scale`], [`TexelEncoding::cv_scale`]).
//!
//! # Why these encodings
//!
//! - **Mean** `mu` (HDR luminance): stored as is. `f16`'s relative step is the same in
//!   every normal binade, so a scale only moves the window `[6.1e-5, 65504]`, whose
//!   geometric centre is already near 2, where display-referred luminance lives. Luminance
//!   above 65504 saturates; below `6.1e-5` it loses relative precision (subnormals).
//! - **Variance**: stored relative to `sigma0^2` (to a power of two within `sqrt 2` of
//!   it), the quantity the controller divides by: the counts the controller can ask for
//!   (`var / sigma0^2 * nbar` between the budget bounds) correspond to stored values near
//!   1, in the middle of `f16`'s range. Saturation at 65504 (`var > 6.5` for `sigma0^2 =
//!   1e-4`) still asks for the maximum count; it only shortens the decay after a spike.
//! - **Mean count** `nbar`: stored as is. It lies in `[0, beta_max]`; dividing by
//!   `beta_max = 64` (a power of two) would change no bit, and any other scale no
//!   precision. The step is 1/32 in `[32, 64)`, a tiny fraction of one sample; keeping raw
//!   counts also keeps stored history valid when the budget changes at run time.
//! - **Control variate moments** `Sigma_xy`, `Sigma_yy`: only the ratio
//!   `(Sigma_xy + eps_a) / (Sigma_yy + eps_a)` is used, and what matters is their size
//!   relative to `eps_a`. Stored as is, `eps_a = 1e-6` would be an `f16` subnormal (6%
//!   steps); scaled by `2^-c` it sits in the normal range. See
//!   [`TexelEncoding::with_cv_scale`] for the choice of `c` and how `eps_a` is applied.
//! - **Control variate means** `zeta_f`, `zeta_g`: luminances, stored as is like `mu`.
//!
//! Nothing non-finite is ever stored: NaN becomes 0, overflow saturates at `+-65504`
//! (`f16`) or `+-f32::MAX`, negative variances and counts become 0.
//!
//! # Frozen updates
//!
//! With round-to-nearest, an `f16` EMA cannot move when `eta |x - mu|` is under half an
//! ulp of `mu` (relative `2^-12` to `2^-11`): with `eta = 0.005` a change under about 10%
//! of the mean is lost, with `eta_cv = 1e-6` nothing ever moves and OCV silently becomes
//! CCV. [`check_precision`] reports this for given weights; [`Rounding::Stochastic`]
//! makes the stored state move in expectation; [`Layout::F32`] moves it for any `eta`
//! above `2^-24`.

//!
//! # Frame functions
//!
//! [`update_frame`] (AS, CCV), [`update_frame_ocv`] and [`estimate_frame`] process a
//! whole frame from structure-of-arrays inputs ([`FrameInputs`]), in chunks of 64 pixels
//! with branch-free lane code, and give bit for bit what the per-pixel loop (decode,
//! [`PixelController`](crate::cv::PixelController), encode) gives; slices of different
//! lengths are an error, not a panic ([`FrameInputsBuf`], feature `std`, owns inputs of
//! equal lengths built pixel by pixel). [`update_frame_parallel`] and
//! [`update_frame_ocv_parallel`] (feature `std`) split a frame over threads with the same
//! bits, and [`update_frame_range`] / [`update_frame_ocv_range`] let any job system do the
//! same (first pixel index plus sub-slices). `f16` texels are widened and narrowed 8
//! values per F16C instruction in the AVX2 and AVX-512 loops and wherever F16C is
//! compiled in, otherwise by a branch-free conversion that vectorises with SSE2 or NEON;
//! all are bit-identical to `half::f16::{to_f32, from_f32}`.
//!
//! # Getting the speed
//!
//! The portable build is the fast build: with `std` on x86-64 the frame loops are also
//! compiled for AVX2/FMA/F16C and for AVX-512 F/BW/VL, and the highest variant the CPU
//! has is chosen at run time ([`selected_loop_variant`] says which; bit-identical
//! results). On AVX2 CPUs `RUSTFLAGS="-C target-cpu=native"` adds little on top (the
//! AVX-512 variant is not yet measured against it). For large frames on
//! otherwise idle cores use [`update_frame_parallel`] / [`update_frame_ocv_parallel`], the
//! `rayon` feature, or your own job system through [`update_frame_range`] /
//! [`update_frame_ocv_range`].
//!
//! # Measured
//!
//! **Counts: f16 storage against f64 state** (`tests/texel_counts.rs`, run it with
//! `--nocapture`): one pixel, 300 frames of a switching light with a 2% flicker, the
//! published parameters, common random numbers; `k` scales all luminances (and
//! `sigma0^2 = 1e-4 k^2`). Mean count of the f64 run, then mean `|n_f16 - n_f64|`, the
//! largest difference and the fraction of frames whose count differs. `f32` texels gave
//! exactly the f64 counts in every case.
//!
//! | k | model | f64 mean n | f16 RN: mean, max, frames | f16 SR: mean, max, frames |
//! |---|---|---|---|---|
//! | 1 | AS | 43.09 | 0.44, 13, 14% | 0.39, 9, 14% |
//! | 1 | CCV | 32.24 | 0.16, 4, 13% | 0.24, 5, 15% |
//! | 1 | OCV | 44.92 | 0.06, 11, 1.3% | 0.06, 11, 0.7% |
//! | 1e-4 | AS | 43.09 | 0.32, 9, 14% | 0.67, 20, 16% |
//! | 1e-4 | CCV | 32.24 | 0.61, 13, 26% | 0.75, 21, 27% |
//! | 1e-4 | OCV | 44.92 | 0.08, 13, 1.3% | 0.003, 1, 0.3% |
//! | 1e4 | AS | 43.09 | 0.29, 10, 13% | 0.33, 9, 14% |
//! | 1e4 | CCV | 32.24 | 0.07, 4, 5% | 0.11, 2, 9% |
//! | 1e4 | OCV | 44.92 | 0.02, 5, 0.7% | 0.04, 9, 0.7% |
//!
//! Storage shifts the average count by at most 0.25 samples; single frames can differ by
//! up to 20 samples where a transient is caught one frame earlier or later. `k = 1e-4`
//! (the dark phase at 1e-5, an f16 subnormal) roughly doubles the CCV error.
//!
//! **Frame update speed**: `BENCHMARKS.md` at the repository root has the figures of
//! `cargo bench --bench batch` (1080p and 2160p; ns per pixel, GB/s of history and input
//! traffic, the fraction of a plain copy's bandwidth and the speed-up over a
//! straightforward scalar loop) for the portable build, `-C target-cpu=native` and the
//! multi-threaded functions; the section above says how to get the speed.

mod batch;
mod channels;
mod chunk;
mod dispatch;
mod encoding;
mod inputs;
#[cfg(feature = "std")]
mod parallel;
mod precision;
mod range;
#[cfg(feature = "rayon")]
mod rayon;
mod rounding;
mod types;

pub use batch::{ConstantCoefficient, FrameInputs, estimate_frame, update_frame, update_frame_ocv};
pub use dispatch::{LoopVariant, selected_loop_variant};
pub use encoding::{Layout, Texel, TexelEncoding};
#[cfg(feature = "std")]
pub use inputs::FrameInputsBuf;
#[cfg(feature = "std")]
pub use parallel::{update_frame_ocv_parallel, update_frame_parallel};
pub use precision::{
    Mobility, PrecisionReport, QuantityPrecision, StoredQuantity, check_config_precision,
    check_precision,
};
pub use range::{update_frame_ocv_range, update_frame_range};
#[cfg(feature = "rayon")]
pub use rayon::{update_frame_ocv_rayon, update_frame_rayon};
pub use rounding::{Rounding, channel_bits, to_f16};
pub use types::{CvTexel16, CvTexel32, SpvgTexel16, SpvgTexel32};
