//! The count estimate (SPEC 2.1, 2.3, 2.4): history in, integer sample count out.
//!
//! The operation order here is normative: a WGSL port must evaluate the same sequence of
//! single-precision operations, with the derived constants uploaded from
//! [`SpvgConfig`] rather than recomputed, to produce the same counts bit for bit.

use num_traits::Float;

use super::{CountPolicy, SpvgConfig, SpvgHistory};
use crate::stats::saturate;

impl<T: Float> SpvgConfig<T> {
    /// Whether a pixel with distant energy ratio `gamma` takes distant samples at all
    /// (SPEC 2.4): `gamma >= eps_u && gamma > 0`.
    ///
    /// A NaN `gamma` takes no samples (its shading is NaN whatever the count), and
    /// `gamma = 0` takes none even with `eps_u = 0` (there is no distant energy, so
    /// dropping it is exact). Renderers without the near/far split pass `gamma = 1`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::SpvgConfig;
    /// let c = SpvgConfig::<f32>::published(); // eps_u = 0.01
    /// assert!(c.samples_distant(0.5));
    /// assert!(!c.samples_distant(0.005));
    /// assert!(!c.samples_distant(f32::NAN));
    /// ```
    #[inline]
    #[must_use]
    pub fn samples_distant(&self, gamma: T) -> bool {
        gamma >= self.eps_u() && gamma > T::zero()
    }

    /// The raw (real-valued) count `n_hat` of the configured [`CountPolicy`] from a
    /// history, before the budget clamp and rounding. Not sanitized: a corrupt history
    /// (NaN, or an infinite mean count) may give NaN, which
    /// [`round_count`](Self::round_count) maps to `min_samples`.
    ///
    /// Exact operation order in `T` (each line is one or two rounded operations, read
    /// left to right, with no fused multiply-add), with `inv_target` and `k_minus_1`
    /// taken from the configuration (computed once in `T` as `1 / sigma0^2` and
    /// `(2 / eta) - 2`), and `sat(x) = clamp(x, -MAX, MAX)` (the largest finite value of
    /// `T`; NaN passes through):
    ///
    /// ```text
    /// r     = sat(variance * inv_target)                     // var / sigma0^2
    /// e     = sat(r * mean_count)                            // E
    /// delta = sat(sat((r - 1) * mean_count) * k_minus_1)     // Delta
    /// Spvg:        n_hat = (kappa * delta) + e
    ///   damped (max_change = Some(c), docs/algorithms.md §8.1), then:
    ///              lo    = mean_count * cap_down            // cap_down = 1 / (1 + c)
    ///              hi    = mean_count * cap_up              // cap_up = 1 + c
    ///              n_hat = if n_hat < lo { lo } else if n_hat > hi { hi } else { n_hat }
    /// TwoPhase:    n_hat = e                        // mean_count holds n_prev
    /// UnrealClamp: n_hat = r
    /// Fixed(n):    n_hat = n
    /// ```
    ///
    /// `r - 1` rather than `(var - sigma0^2) / sigma0^2` keeps one division out of the
    /// per-pixel path and makes `Delta` exactly 0 when `r` is exactly 1. The saturation
    /// keeps every intermediate finite, so a finite history (every history that
    /// [`update`](Self::update) stores) gives a raw count that is finite or `+inf` (the
    /// final sum of two large terms), never NaN. Without it a saturated variance
    /// (`variance * inv_target` overflowing, e.g. `f32` deviations above ~1.8e19 with
    /// `sigma0^2 <= 1`) gave `0 * inf` with `kappa = 0` or `eta = 1`, i.e. NaN, and the
    /// pixel with the largest variance took `min_samples`.
    #[inline]
    #[must_use]
    pub fn raw_estimate(&self, history: &SpvgHistory<T>) -> T {
        let r = saturate(history.variance * self.inv_target());
        let e = saturate(r * history.mean_count);
        match self.policy() {
            CountPolicy::Spvg => {
                let delta =
                    saturate(saturate((r - T::one()) * history.mean_count) * self.k_minus_1());
                let n_hat = self.kappa() * delta + e;
                if self.max_change().is_some() {
                    let nbar = history.mean_count;
                    super::damping::cap(n_hat, nbar * self.cap_down(), nbar * self.cap_up())
                } else {
                    n_hat
                }
            }
            CountPolicy::TwoPhase => e,
            CountPolicy::UnrealClamp => r,
            CountPolicy::Fixed(n) => T::from(n).unwrap_or(self.max_samples_f()),
        }
    }

    /// Rounds a raw count to the budget: `ceil(clamp(n_hat, min_samples, max_samples))`,
    /// with a NaN `n_hat` giving `min_samples`.
    ///
    /// Exact rule (a WGSL port uses these comparisons, not `clamp`, whose NaN behaviour
    /// WGSL leaves to the implementation):
    ///
    /// ```text
    /// if n_hat >= min_f {
    ///     if n_hat < max_f { min(u32(ceil(n_hat)), max_samples) }
    ///     else             { max_samples }               // at or above, or +inf
    /// } else               { min_samples }               // below the budget, or NaN
    /// ```
    ///
    /// NaN goes to the minimum so that a poisoned history (only a corrupt texture can
    /// hold one: [`update`](Self::update) never stores a non-finite value) does not burn
    /// the maximum budget; `+inf` is ordered and means "enormous variance", so it takes the
    /// maximum like any large finite value.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::SpvgConfig;
    /// let c = SpvgConfig::<f32>::published(); // budget [8, 64]
    /// assert_eq!(c.round_count(12.01), 13);
    /// assert_eq!(c.round_count(12.0), 12);
    /// assert_eq!(c.round_count(-3.0), 8);
    /// assert_eq!(c.round_count(f32::NAN), 8);
    /// assert_eq!(c.round_count(f32::INFINITY), 64);
    /// ```
    #[inline]
    #[must_use]
    pub fn round_count(&self, n_hat: T) -> u32 {
        // Written so that NaN fails the first comparison and +inf the second.
        if n_hat >= self.min_samples_f() {
            if n_hat < self.max_samples_f() {
                // `n_hat` is finite and in [min, max): its ceiling fits in u32.
                n_hat.ceil().to_u32().map_or(self.max_samples(), |n| {
                    n.clamp(self.min_samples(), self.max_samples())
                })
            } else {
                self.max_samples()
            }
        } else {
            self.min_samples()
        }
    }

    /// The count for a pixel with a valid history (SPEC 2.1 and 2.4): 0 when
    /// [`samples_distant`](Self::samples_distant) is false, otherwise
    /// [`round_count`](Self::round_count)`(`[`raw_estimate`](Self::raw_estimate)`)`, which
    /// is always within `[min_samples, max_samples]` whatever the history holds (NaN,
    /// infinities and negative values included).
    ///
    /// A cold (all-zero) history gives `n_hat = 0`, so the first frame takes
    /// `min_samples`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f32>::published();
    /// assert_eq!(c.estimate(&SpvgHistory::default(), 1.0), 8); // cold start
    /// assert_eq!(c.estimate(&SpvgHistory::default(), 0.0), 0); // nothing scatters far
    /// // At the target variance (here exactly representable) the SPVG estimate keeps the
    /// // mean count.
    /// let c = SpvgConfig::<f32>::builder().target_variance(0.25).build().unwrap();
    /// let h = SpvgHistory { mean: 0.5, variance: 0.25, mean_count: 20.0 };
    /// assert_eq!(c.estimate(&h, 1.0), 20);
    /// ```
    #[inline]
    #[must_use]
    pub fn estimate(&self, history: &SpvgHistory<T>, gamma: T) -> u32 {
        if !self.samples_distant(gamma) {
            return 0;
        }
        if let CountPolicy::Fixed(n) = self.policy() {
            return n;
        }
        self.round_count(self.raw_estimate(history))
    }

    /// The count for a pixel whose history may be invalid (SPEC 2.3): with
    /// `history_valid = false` the history is treated as zero, so every history-based
    /// policy gives `max(n_hat(0), beta_min) = min_samples` (and `Fixed(n)` gives `n`);
    /// the zero-sample rule still applies first. With `history_valid = true` this is
    /// [`estimate`](Self::estimate).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f32>::published();
    /// let stale = SpvgHistory { mean: 3.0, variance: 1.0, mean_count: 64.0 };
    /// assert_eq!(c.estimate_with_validity(&stale, 1.0, true), 64);
    /// assert_eq!(c.estimate_with_validity(&stale, 1.0, false), 8);
    /// ```
    #[inline]
    #[must_use]
    pub fn estimate_with_validity(
        &self,
        history: &SpvgHistory<T>,
        gamma: T,
        history_valid: bool,
    ) -> u32 {
        if history_valid {
            self.estimate(history, gamma)
        } else {
            self.estimate(&super::zero_history(), gamma)
        }
    }
}
