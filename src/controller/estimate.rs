//! The count estimate (docs/algorithms.md §2.1, §2.3, §2.4): history in, integer sample count out.
//!
//! The operation order here is normative: a WGSL port must evaluate the same sequence of
//! single-precision operations, with the derived constants uploaded from
//! [`SpvgConfig`] rather than recomputed, to produce the same counts bit for bit.

use num_traits::Float;

use super::{CountPolicy, SpvgConfig, SpvgHistory, rules};

impl<T: Float> SpvgConfig<T> {
    /// Whether a pixel with distant energy ratio `gamma` takes distant samples at all
    /// (docs/algorithms.md §2.4): `gamma >= eps_u && gamma > 0`.
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
        rules::samples_distant(self.eps_u(), gamma)
    }

    /// The raw (real-valued) count `n_hat` of the configured [`CountPolicy`] from a
    /// history, before the budget clamp and rounding.
    ///
    /// The history is read as texel decode reads it ([`rules::read_history`]): NaN and
    /// anything not `> 0` in the variance or the mean count read as 0, `+inf` as the
    /// largest finite value. A hand-built history therefore gives the count its stored
    /// texel would, and every history gives a finite raw count or `+-MAX`, never NaN.
    ///
    /// Exact operation order in `T` (each line is one or two rounded operations, read
    /// left to right, with no fused multiply-add), with `target = sigma0^2`,
    /// `k_minus_1` taken from the configuration (computed once in `T` as
    /// `(2 * retain) / eta` with `retain = 1 - eta`, i.e. `2/eta - 2` without its
    /// cancellation near `eta = 1`), and `sat(x) = clamp(x, -MAX, MAX)` (the largest finite value of `T`; NaN
    /// passes through):
    ///
    /// ```text
    /// var   = read_non_negative(variance)                // NaN, <= 0 -> 0; +inf -> MAX
    /// nbar  = read_non_negative(mean_count)
    /// r     = sat(var / target)                          // one correctly rounded division
    /// t     = sat((kappa * sat((r - 1) * k_minus_1)) + r)  // n_hat per unit of nbar
    ///   damped (max_change = Some(c), docs/algorithms.md §8.1), with cap_down =
    ///   1 / (1 + c) and cap_up = 1 + c computed once in T:
    ///       t = if t < cap_down { cap_down } else if t > cap_up { cap_up } else { t }
    /// Spvg:        n_hat = sat(t * nbar)                 // = kappa Delta + E
    /// TwoPhase:    n_hat = sat(r * nbar)                 // mean_count holds n_prev
    /// UnrealClamp: n_hat = r
    /// Fixed(n):    n_hat = n
    /// then, unless Fixed: n_hat = allocate(p, n_hat)     // budget::allocate; p = 1: n_hat
    /// ```
    ///
    /// Why this order:
    /// - `var / target` rather than `var * (1 / target)`: the reciprocal is rounded once,
    ///   so `var * fl(1 / sigma0^2)` is not exactly 1 at `var == sigma0^2` for about 15%
    ///   of targets, and `Delta` multiplies that error by `nbar kappa (2/eta - 2)` (with
    ///   `eta = 1e-7` it turned the count right after a disocclusion, 32, into 8). The
    ///   division gives `r == 1` exactly there, so `n_hat == nbar` exactly.
    /// - `nbar` factored out: `kappa Delta + E = nbar (kappa (r - 1) (k - 1) + r)`. The
    ///   former order formed `(r - 1) nbar (k - 1)` first, which overflows for a large
    ///   mean count and saturated to the maximum count where exact arithmetic gives the
    ///   minimum. Now `(r - 1) (k - 1)` can only overflow upwards (`r - 1 >= -1` and
    ///   `k - 1` is finite), where the count is large anyway, and `t` keeps its sign.
    /// - The saturation keeps every intermediate finite, so `0 * inf` (a saturated
    ///   variance with `kappa = 0`, `eta = 1` or a zero mean count) cannot give NaN.
    ///
    /// [`rules::read_history`]: super::rules::read_history
    #[inline]
    #[must_use]
    pub fn raw_estimate(&self, history: &SpvgHistory<T>) -> T {
        let h = rules::read_history(history);
        rules::raw_count(
            &rules::EstimateUniforms::new(self),
            h.variance,
            h.mean_count,
        )
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
    /// NaN goes to the minimum so that a poisoned raw count does not burn the maximum
    /// budget; `+inf` is ordered and means "enormous variance", so it takes the maximum
    /// like any large finite value.
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
        rules::round_count(&rules::Budget::new(self), n_hat)
    }

    /// The count for a pixel with a valid history (docs/algorithms.md §2.1 and 2.4): 0 when
    /// [`samples_distant`](Self::samples_distant) is false, otherwise
    /// [`round_count`](Self::round_count)`(`[`raw_estimate`](Self::raw_estimate)`)`, which
    /// is always within `[min_samples, max_samples]` whatever the history holds (NaN,
    /// infinities and negative values read as texel decode reads them, see
    /// [`raw_estimate`](Self::raw_estimate)).
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

    /// The count for a pixel whose history may be invalid (docs/algorithms.md §2.3): with
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
