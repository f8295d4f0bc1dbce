//! Exponential moving covariance (EMC) of two streams.

use num_traits::Float;

use super::{Weight, rules};

/// Exponential moving covariance of two streams `x`, `y` with EMA means `mu`, `nu`:
/// `cov_t = (1 - eta) cov_{t-1} + eta (1 - eta) (x_t - mu_{t-1}) (y_t - nu_{t-1})`,
/// then both means are updated. `Emc(x, x)` is exactly [`Emv`](super::Emv)`(x)`.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Emc, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut emc = Emc::seeded(0.0, 0.0);
/// emc.update(&w, 2.0, -4.0);
/// assert_eq!(emc.covariance(), -2.0);
/// assert_eq!((emc.mean_x(), emc.mean_y()), (1.0, -2.0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Emc<T> {
    mean_x: T,
    mean_y: T,
    covariance: T,
}

impl<T: Float> Emc<T> {
    /// The first-sample seed: means `(x, y)`, covariance zero. Non-finite values become
    /// zero.
    #[inline]
    #[must_use]
    pub fn seeded(x: T, y: T) -> Self {
        Self::from_parts(x, y, T::zero())
    }

    /// Restores a state from stored numbers; non-finite values become zero.
    #[inline]
    #[must_use]
    pub fn from_parts(mean_x: T, mean_y: T, covariance: T) -> Self {
        let finite_or_zero = |v: T| if v.is_finite() { v } else { T::zero() };
        Self {
            mean_x: finite_or_zero(mean_x),
            mean_y: finite_or_zero(mean_y),
            covariance: finite_or_zero(covariance),
        }
    }

    /// Folds in one pair of observations. Returns `false`, leaving the state unchanged,
    /// when `x` or `y` is not finite.
    #[inline]
    pub fn update(&mut self, w: &Weight<T>, x: T, y: T) -> bool {
        if !(x.is_finite() && y.is_finite()) {
            return false;
        }
        let dx = rules::deviation(x, self.mean_x);
        let dy = rules::deviation(y, self.mean_y);
        self.covariance = rules::moment(w.retain(), w.eta_retain(), self.covariance, dx, dy);
        self.mean_x = rules::ema(w, self.mean_x, x);
        self.mean_y = rules::ema(w, self.mean_y, y);
        true
    }

    /// The current covariance.
    #[inline]
    #[must_use]
    pub fn covariance(&self) -> T {
        self.covariance
    }

    /// The current mean of the `x` stream.
    #[inline]
    #[must_use]
    pub fn mean_x(&self) -> T {
        self.mean_x
    }

    /// The current mean of the `y` stream.
    #[inline]
    #[must_use]
    pub fn mean_y(&self) -> T {
        self.mean_y
    }
}
