//! Sample sequences shared bit-for-bit by the CPU and the GPU (docs/algorithms.md §6): the pcg3d16 hash
//! for per-pixel, per-frame seeds, the R2 low-discrepancy sequence in 32-bit fixed
//! point, and the threshold of dithered count rounding ([`dither_threshold`]).
//!
//! Everything here is integer arithmetic on wrapping `u32` plus one conversion to float
//! that is exact, so a WGSL port computing the same operations gets the same bits.
//!
//! # Examples
//!
//! ```
//! use spvg::sequence::{pixel_seed, r2_offset_from_seed, r2_point, to_unit_f32};
//! let offset = r2_offset_from_seed(pixel_seed(12, 34, 5));
//! let [u, v] = r2_point(offset, 7);
//! let (x, y) = (to_unit_f32(u), to_unit_f32(v));
//! assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
//! ```

mod dither;
mod pcg;
mod r2;

pub use dither::{GOLDEN_STEP, dither_threshold};
pub use pcg::{PCG3D16_INCREMENT, PCG3D16_MULTIPLIER, pcg3d16, pixel_seed};
pub use r2::{PHI2, R2_STEP, r2_offset_from_seed, r2_point, to_unit_f32, to_unit_f64};
