//! Streaming, exponentially weighted estimators (SPEC section 1).
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

mod ema;
mod emc;
mod emcm;
mod emv;
mod ewma;
mod packed;
mod weight;

pub use ema::Ema;
pub use emc::Emc;
pub use emcm::Emcm;
pub use emv::Emv;
pub use ewma::Ewma;
pub use packed::{Dim, Packed};
pub use weight::Weight;

use num_traits::Float;

/// Clamps an infinity produced by overflow to the largest finite value of the same sign.
///
/// NaN passes through unchanged: callers reject NaN before it can reach the state.
#[inline]
#[must_use]
pub(crate) fn saturate<T: Float>(v: T) -> T {
    if v.is_infinite() {
        if v > T::zero() {
            T::max_value()
        } else {
            T::min_value()
        }
    } else {
        v
    }
}
