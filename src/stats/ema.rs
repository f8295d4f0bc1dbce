//! Exponential moving average (EMA).

use num_traits::Float;

use super::Weight;

/// Exponential moving average: `mu_t = (1 - eta) mu_{t-1} + eta x_t`.
///
/// `Default` is the zero state (what a freshly cleared history texture holds);
/// [`Ema::seeded`] is the first-sample seed (`mu = x_0`).
///
/// # Examples
///
/// ```
/// use spvg::stats::{Ema, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut ema = Ema::seeded(2.0);
/// assert!(ema.update(&w, 4.0));
/// assert_eq!(ema.mean(), 3.0);
/// assert!(!ema.update(&w, f64::NAN)); // ignored: the state is unchanged
/// assert_eq!(ema.mean(), 3.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ema<T> {
    mean: T,
}

impl<T: Float> Ema<T> {
    /// The first-sample seed: the mean is `x`. A non-finite `x` gives the zero state.
    #[inline]
    #[must_use]
    pub fn seeded(x: T) -> Self {
        Self {
            mean: if x.is_finite() { x } else { T::zero() },
        }
    }

    /// Restores a state from its stored mean (non-finite values become zero).
    #[inline]
    #[must_use]
    pub fn from_mean(mean: T) -> Self {
        Self::seeded(mean)
    }

    /// Folds in one observation. Returns `false`, leaving the state unchanged, when `x`
    /// is not finite.
    #[inline]
    pub fn update(&mut self, w: &Weight<T>, x: T) -> bool {
        if !x.is_finite() {
            return false;
        }
        // The convex form cannot overflow except by one rounding step at the very top of
        // the range, which `saturate` absorbs.
        self.mean = super::rules::ema(w, self.mean, x);
        true
    }

    /// The current mean.
    #[inline]
    #[must_use]
    pub fn mean(&self) -> T {
        self.mean
    }
}
