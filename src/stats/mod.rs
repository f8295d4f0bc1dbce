//! Streaming, exponentially weighted estimators (docs/algorithms.md §1).
//!
//! Each estimator is a small `Copy` state holding only per-pixel numbers; the shared
//! exponential weight is a separate validated [`Weight`].
//!
//! # Non-finite input and overflow
//!
//! Every `update` follows one policy so that stored state is never poisoned:
//! - an update with any non-finite input (NaN, +-inf) leaves the state unchanged and
//!   returns `false`;
//! - an update with finite input whose exact result would exceed the type's range
//!   saturates at `+-T::max_value()` instead of storing an infinity.
//!
//! For the matrix estimators ([`Emcm`], [`Ewma`]) one non-finite component skips the
//! whole update. Saturation clamps each entry on its own, so once squares overflow the
//! matrix is no longer guaranteed positive semi-definite; below that it is PSD up to
//! rounding of order `eps * trace`.
//!
//! # Storage precision: `f16`
//!
//! The estimators are generic over `num_traits::Float`, so `Emv<half::f16>` works, but
//! every `f16` operation rounds to 11 significant bits: an update is 3-4 roundings
//! (`x - mu`, the square, the two products and sums), and increments smaller than half
//! an ulp of the state are lost outright, which bites as `eta` shrinks. Computing in
//! `f32` and rounding to `f16` only when storing (a half-float history texture) pays one
//! rounding per stored number. Measured by `tests/f16_drift.rs` (`cargo test --test
//! f16_drift -- --nocapture`): relative drift from an `f64` reference, RMS over steps
//! 100..1000 of a 0.5 +- 0.2 signal with a step to 0.8, zero start:
//!
//! | `eta` | `f16` compute: mean / variance | `f32` compute, `f16` store: mean / variance |
//! |-------|--------------------------------|---------------------------------------------|
//! | 1/4   | 4.1e-4 / 1.6e-3                | 3.3e-4 / 1.2e-3                             |
//! | 1/16  | 6.5e-4 / 1.3e-3                | 5.7e-4 / 1.2e-3                             |
//! | 1/64  | 2.8e-3 / 2.9e-3                | 6.4e-4 / 1.1e-3                             |
//!
//! The stored `f16` state itself (half-ulp `2^-11 ~ 4.9e-4`) sets the floor of both; the
//! gap is the arithmetic's extra roundings, and it widens (4x on the mean at `1/64`) as
//! `eta d` approaches the state's ulp. Prefer `f32` arithmetic with `f16` storage.

mod ema;
mod emc;
mod emcm;
mod emv;
mod ewma;
mod moving_covariance;
mod packed;
pub mod rules;
mod weight;

pub use ema::Ema;
pub use emc::Emc;
pub use emcm::{Emcm, Finch};
pub use emv::Emv;
pub use ewma::{Ewma, RiskMetrics};
pub use moving_covariance::{MovingCovariance, UpdateRule};
pub use packed::{Dim, Packed};
pub use weight::Weight;

pub(crate) use rules::saturate;
