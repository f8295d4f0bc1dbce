//! Exponential moving variance (EMV, Finch 2009).

use num_traits::Float;

use super::Weight;

/// Exponential moving variance with its mean:
/// `var_t = (1 - eta) var_{t-1} + eta (1 - eta) (x_t - mu_{t-1})^2`, computed with the old
/// mean, then `mu_t = (1 - eta) mu_{t-1} + eta x_t`.
///
/// The variance is never negative: both terms are non-negative and rounding keeps them so.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Emv, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut emv = Emv::seeded(0.0);
/// emv.update(&w, 2.0);
/// // Population variance of {0, 2} with equal weights is 1.
/// assert_eq!(emv.mean(), 1.0);
/// assert_eq!(emv.variance(), 1.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Emv<T> {
    mean: T,
    variance: T,
}

impl<T: Float> Emv<T> {
    /// The first-sample seed: mean `x`, variance zero. A non-finite `x` gives the zero
    /// state.
    #[inline]
    #[must_use]
    pub fn seeded(x: T) -> Self {
        Self::from_parts(x, T::zero())
    }

    /// Restores a state from stored numbers. Non-finite values become zero and a negative
    /// variance is clamped to zero, so a corrupt texel cannot poison later updates.
    #[inline]
    #[must_use]
    pub fn from_parts(mean: T, variance: T) -> Self {
        let mean = if mean.is_finite() { mean } else { T::zero() };
        let variance = if variance.is_finite() && variance > T::zero() {
            variance
        } else {
            T::zero()
        };
        Self { mean, variance }
    }

    /// Folds in one observation. Returns `false`, leaving the state unchanged, when `x`
    /// is not finite.
    #[inline]
    pub fn update(&mut self, w: &Weight<T>, x: T) -> bool {
        if !x.is_finite() {
            return false;
        }
        (self.mean, self.variance) = super::rules::emv(w, self.mean, self.variance, x);
        true
    }

    /// The current mean.
    #[inline]
    #[must_use]
    pub fn mean(&self) -> T {
        self.mean
    }

    /// The current variance (never negative).
    #[inline]
    #[must_use]
    pub fn variance(&self) -> T {
        self.variance
    }
}
