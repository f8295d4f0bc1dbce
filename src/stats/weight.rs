//! The exponential weight shared by every pixel's estimators.

use num_traits::Float;

use crate::Error;

/// A validated exponential weight `eta` in `(0, 1]`, with the derived constants that every
/// update needs precomputed once: `1 - eta` and `eta (1 - eta)`.
///
/// Per-pixel estimator states hold only per-pixel numbers; the weight is shared by all
/// pixels and passed to each `update`, so it is validated once, never in the hot loop.
///
/// # Examples
///
/// ```
/// use spvg::stats::Weight;
/// let w = Weight::new(0.2_f64).unwrap();
/// assert_eq!(w.eta(), 0.2);
/// assert!((w.retain() - 0.8).abs() < 1e-15);
/// assert!(Weight::new(0.0_f64).is_err());
/// assert!(Weight::new(f64::NAN).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weight<T> {
    eta: T,
    retain: T,
    eta_retain: T,
}

impl<T: Float> Weight<T> {
    /// Validates `eta` and precomputes the derived constants.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `eta` when it is not finite or outside `(0, 1]`.
    pub fn new(eta: T) -> Result<Self, Error> {
        if !(eta.is_finite() && eta > T::zero() && eta <= T::one()) {
            return Err(Error::invalid(
                "eta",
                eta.to_f64().unwrap_or(f64::NAN),
                "must be finite and in (0, 1]",
            ));
        }
        let retain = T::one() - eta;
        Ok(Self {
            eta,
            retain,
            eta_retain: eta * retain,
        })
    }

    /// The weight `eta = 1`: the update replaces the state by the sample (the mean becomes
    /// the sample, the variance zero). Used where history is invalid (disocclusion).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::stats::Weight;
    /// assert_eq!(Weight::<f32>::one().eta(), 1.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn one() -> Self {
        Self {
            eta: T::one(),
            retain: T::zero(),
            eta_retain: T::zero(),
        }
    }

    /// The weight `eta` given to the new sample.
    #[inline]
    #[must_use]
    pub fn eta(&self) -> T {
        self.eta
    }

    /// `1 - eta`, the weight kept by the old state.
    #[inline]
    #[must_use]
    pub fn retain(&self) -> T {
        self.retain
    }

    /// `eta (1 - eta)`, the factor of the squared deviation in the variance update.
    #[inline]
    #[must_use]
    pub fn eta_retain(&self) -> T {
        self.eta_retain
    }

    /// Converts the weight to another float type, re-deriving the constants in that type.
    ///
    /// Returns `None` when `eta` does not fit the target type as a valid weight (for
    /// example an `eta` that rounds to zero in `f16`).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::stats::Weight;
    /// let w = Weight::new(0.2_f64).unwrap();
    /// assert!((w.cast::<f32>().unwrap().eta() - 0.2).abs() < 1e-7);
    /// assert!(Weight::new(1e-9_f64).unwrap().cast::<half::f16>().is_none());
    /// ```
    #[must_use]
    pub fn cast<U: Float>(&self) -> Option<Weight<U>> {
        Weight::new(U::from(self.eta)?).ok()
    }
}
