//! The threshold of dithered count rounding (docs/algorithms.md §8.6): one fixed-point
//! value per pixel and frame that alternates between neighbours and between frames.
//!
//! A real-valued count `c` is realised as `floor(c) + [xi < frac(c)]`
//! ([`realise_count`](crate::controller::fractional::realise_count)). For the mean of the
//! realised counts to follow `c` over a small neighbourhood and over a few frames, and
//! not only over the whole frame, `xi` must be spread evenly in both:
//!
//! - **in space**, the R2 lattice `frac(px / phi2 + py / phi2^2)` (Roberts' R2 dither
//!   mask: the same steps as [`r2_point`](super::r2_point), here over the pixel grid): any
//!   window of the frame holds thresholds spread over `[0, 1)` about as evenly as a
//!   blue-noise mask, so `c = 0.25` samples about one pixel in four in every small window
//!   (a horizontal neighbour's threshold is `0.2451` away, a vertical one's `0.5698`);
//! - **in time**, a rotation by the golden ratio per frame, `frac(... + frame / phi)`:
//!   at a fixed pixel the thresholds of successive frames form a Kronecker sequence, whose
//!   gaps take at most three lengths, so `c = 0.25` samples every third to fifth frame and
//!   never twice in a row.
//!
//! Both are integer arithmetic on wrapping `u32`, like the rest of the module, so the CPU
//! and the GPU (`spvg_dither_threshold` in `spvg-shaders/wgsl/sequence.wgsl`) agree bit
//! for bit.
//!
//! The rotation is in screen space. A surface point that moves by `v` pixels per frame
//! sees its threshold advance by `frac(1/phi - v . (1/phi2, 1/phi2^2))` per frame instead
//! of `1/phi`; where that step is near 0 (for example `v = (1, 5)` px per frame, step
//! 0.014) the point's samples come in runs rather than evenly spread, though their mean
//! over the runs is still `c`.

use super::R2_STEP;

/// The golden-ratio step of the threshold between frames, `round(2^32 / phi)` with
/// `phi = (1 + sqrt 5) / 2`: `2^32 / phi = 2654435769.497...`.
pub const GOLDEN_STEP: u32 = 0x9E37_79B9;

/// The dither threshold of pixel `(px, py)` in frame `frame`, in fixed point (`u / 2^32`):
/// `px * R2_STEP[0] + py * R2_STEP[1] + frame * GOLDEN_STEP`, every operation wrapping.
///
/// WGSL twin: `spvg_dither_threshold(px, py, frame)` (WGSL `u32` arithmetic wraps).
/// [`to_unit_f32`](super::to_unit_f32) turns it into the float the rounding compares.
///
/// # Examples
///
/// ```
/// use spvg::sequence::{GOLDEN_STEP, R2_STEP, dither_threshold};
/// assert_eq!(dither_threshold(0, 0, 0), 0);
/// assert_eq!(dither_threshold(1, 0, 0), R2_STEP[0]);
/// assert_eq!(dither_threshold(0, 0, 2), GOLDEN_STEP.wrapping_mul(2));
/// ```
#[inline]
#[must_use]
pub const fn dither_threshold(px: u32, py: u32, frame: u32) -> u32 {
    px.wrapping_mul(R2_STEP[0])
        .wrapping_add(py.wrapping_mul(R2_STEP[1]))
        .wrapping_add(frame.wrapping_mul(GOLDEN_STEP))
}
