//! The R2 low-discrepancy sequence (Roberts 2018) in 32-bit fixed point (docs/algorithms.md §6).
//!
//! A point is `x_m = frac(s + m alpha)` with `alpha = (1/phi2, 1/phi2^2)`. In fixed point
//! a `u32` `u` stands for `u / 2^32`, the step is `R2_STEP = round(2^32 alpha)`, and
//! `frac` is the wrap-around of `u32` addition, so the sequence is pure integer arithmetic
//! and identical on CPU and GPU.
//!
//! # Accuracy against the irrational sequence
//!
//! The rounding residuals `delta = R2_STEP - 2^32 alpha` are `-0.010348` (x) and
//! `+0.220238` (y), in units of `2^-32`. Point `m` of the fixed-point sequence therefore
//! differs from `frac(s + m alpha)` (circular distance) by exactly `m |delta| 2^-32`
//! (plus the rounding of `s` itself when `s` is not a multiple of `2^-32`):
//!
//! - x: `<= 2^-24` for `m <= 24_737`; `2.4e-6` at `m = 1e6`;
//! - y: `<= 2^-24` for `m <= 1_162`; `2.1e-7` at `m = 4096`, `5.1e-5` at `m = 1e6`.
//!
//! It is itself a Kronecker sequence with the rational step `R2_STEP / 2^32`, which keeps
//! R2's low discrepancy far beyond the sample counts of a frame; the drift only matters
//! when comparing with a floating-point R2.

/// `phi2`, the plastic number: the real root of `x^3 = x + 1`.
pub const PHI2: f64 = 1.324_717_957_244_746;

/// The R2 step in fixed point: `[round(2^32 / phi2), round(2^32 / phi2^2)]`
/// `= [0xC13F_A9A9, 0x91E1_0DA6]`.
///
/// `2^32 / phi2 = 3242174889.0103...`, `2^32 / phi2^2 = 2447445413.7798...`
/// (tests recompute both, in `f64` and exactly in integers).
pub const R2_STEP: [u32; 2] = [3_242_174_889, 2_447_445_414];

/// Point `index` of the R2 sequence with offset `offset`, in fixed point:
/// `offset[k] + index * R2_STEP[k]` per component, both operations wrapping `u32`.
///
/// WGSL twin: `offset + index * vec2<u32>(0xC13FA9A9u, 0x91E10DA6u)`.
///
/// # Examples
///
/// ```
/// use spvg::sequence::{R2_STEP, r2_point};
/// assert_eq!(r2_point([0, 0], 1), R2_STEP);
/// assert_eq!(r2_point([5, 7], 0), [5, 7]);
/// ```
#[inline]
#[must_use]
pub const fn r2_point(offset: [u32; 2], index: u32) -> [u32; 2] {
    [
        offset[0].wrapping_add(index.wrapping_mul(R2_STEP[0])),
        offset[1].wrapping_add(index.wrapping_mul(R2_STEP[1])),
    ]
}

/// The fixed-point value `u / 2^32` as an `f32` in `[0, 1)`, keeping the top 24 bits:
/// `(u >> 8) as f32 * 2^-24`.
///
/// Both steps are exact (`u >> 8 < 2^24` is an `f32` integer, the scale a power of two),
/// so every IEEE implementation, the GPU's included, gives the same bits. WGSL twin:
/// `f32(u >> 8u) * 5.9604644775390625e-8` (`= 0x1p-24`). The largest value is
/// `1 - 2^-24 < 1`.
///
/// # Examples
///
/// ```
/// use spvg::sequence::to_unit_f32;
/// assert_eq!(to_unit_f32(0), 0.0);
/// assert_eq!(to_unit_f32(1 << 31), 0.5);
/// assert_eq!(to_unit_f32(u32::MAX), 1.0 - f32::EPSILON / 2.0);
/// ```
#[inline]
#[must_use]
pub fn to_unit_f32(u: u32) -> f32 {
    // `as` is exact here: the value is below 2^24.
    (u >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The fixed-point value `u / 2^32` as an `f64` in `[0, 1)`, all 32 bits, exact:
/// `u as f64 * 2^-32`.
///
/// # Examples
///
/// ```
/// use spvg::sequence::to_unit_f64;
/// assert_eq!(to_unit_f64(1 << 30), 0.25);
/// assert!(to_unit_f64(u32::MAX) < 1.0);
/// ```
#[inline]
#[must_use]
pub fn to_unit_f64(u: u32) -> f64 {
    f64::from(u) * (1.0 / 4_294_967_296.0)
}

/// An R2 offset from a [`pixel_seed`](super::pixel_seed): the two first 16-bit lanes
/// moved into the top 16 bits, `[seed[0] << 16, seed[1] << 16]`.
///
/// The offset then has the same 16 random bits as the hash, as the most significant bits
/// of the unit value (a uniform offset on a grid of `2^-16`); any bits of the lanes above
/// 16 are shifted out. The third lane is left for the caller (for example a random
/// rotation or a third dimension).
///
/// # Examples
///
/// ```
/// use spvg::sequence::r2_offset_from_seed;
/// assert_eq!(r2_offset_from_seed([0x1234, 0xABCD, 7]), [0x1234_0000, 0xABCD_0000]);
/// ```
#[inline]
#[must_use]
pub const fn r2_offset_from_seed(seed: [u32; 3]) -> [u32; 2] {
    [seed[0] << 16, seed[1] << 16]
}
