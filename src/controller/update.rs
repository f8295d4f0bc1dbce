//! The history update after sampling (docs/algorithms.md §2.2 and 2.3).

use num_traits::Float;

use super::{SpvgConfig, SpvgHistory, rules};

impl<T: Float> SpvgConfig<T> {
    /// Folds the frame's monitored value `sample` (`S_t`) and the count actually used
    /// into the history. Returns `true` when the history absorbed the frame.
    ///
    /// With a valid history (docs/algorithms.md §2.2), in this order in `T` (no fused multiply-add;
    /// `retain = 1 - eta` and `eta_retain = eta (1 - eta)` from [`weight`](Self::weight)):
    ///
    /// ```text
    /// d          = sample - mean
    /// variance   = retain * variance + eta_retain * (d * d)   // EMV, with the old mean
    /// mean       = retain * mean + eta * sample                // EMA
    /// mean_count = retain * mean_count + eta * f32(count)      // EMA of the count
    /// ```
    ///
    /// With the firefly clamp on ([`firefly_clamp`](super::SpvgConfigBuilder::firefly_clamp)
    /// `= Some(k)`, docs/algorithms.md §8.3) `sample` is first replaced by its clamp to
    /// `[mean - k sigma, mean + k sigma]`, `sigma = sqrt(max(variance, sigma0^2))` of the
    /// read history, in the order of [`rules::firefly_clamp`]; the refusal of a
    /// non-finite sample below looks at the sample as given.
    ///
    /// Under [`CountPolicy::TwoPhase`](super::CountPolicy::TwoPhase) the last line is
    /// `mean_count = f32(count)`: that baseline has no temporal accumulation of the count,
    /// so `mean_count` holds `n_prev`.
    ///
    /// With an invalid history (`history_valid = false`, disocclusion, docs/algorithms.md §2.3) the
    /// weight is 1 and the variance is not estimated from nothing:
    /// `mean = sample`, `variance = sigma0^2`, `mean_count = count` (never clamped: there
    /// is no history to clamp against).
    ///
    /// Frames without a usable observation: a non-finite `sample` or `count == 0` (the
    /// zero-sample rule of docs/algorithms.md §2.4, where the frame carries no Monte Carlo estimate of
    /// the distant part) leave a valid history unchanged and reset an invalid one to the
    /// zero history (the stale numbers belong to another surface; zero is what docs/algorithms.md §2.3
    /// treats an invalid history as, so the next frame takes `min_samples`). Both return
    /// `false`.
    ///
    /// Stored numbers are read defensively (a non-finite mean or mean count, or a
    /// non-finite or negative variance, reads as 0), and overflow saturates to the
    /// largest finite value: nothing non-finite is ever stored.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder().eta(0.5).target_variance(0.01).build().unwrap();
    /// let mut h = SpvgHistory::default();
    /// // Disocclusion: seed from the sample, variance = sigma0^2.
    /// assert!(c.update(&mut h, 2.0, 8, false));
    /// assert_eq!(h, SpvgHistory { mean: 2.0, variance: 0.01, mean_count: 8.0 });
    /// // Normal frame: EMV with the old mean, then EMA.
    /// assert!(c.update(&mut h, 4.0, 16, true));
    /// assert_eq!(h, SpvgHistory { mean: 3.0, variance: 0.5 * 0.01 + 0.25 * 4.0, mean_count: 12.0 });
    /// // A NaN sample is ignored.
    /// assert!(!c.update(&mut h, f64::NAN, 16, true));
    /// assert_eq!(h.mean, 3.0);
    /// ```
    #[inline]
    pub fn update(
        &self,
        history: &mut SpvgHistory<T>,
        sample: T,
        count: u32,
        history_valid: bool,
    ) -> bool {
        let (next, accepted) = rules::update(
            &rules::UpdateUniforms::new(self),
            read_for_update(history),
            *history,
            sample,
            count,
            history_valid,
        );
        *history = next;
        accepted
    }

    /// [`update`](Self::update) with the TAA-guided variance (the dissertation's Eq. 4.4,
    /// docs/algorithms.md §8.5): `guide` is `C_t`, the renderer's resolved TAA history at
    /// this pixel (reprojected, clamped to the current neighbourhood, before its blend
    /// with this frame), in the luminance space of `sample`. With a valid history the
    /// variance line becomes
    ///
    /// ```text
    /// d          = sample - guide
    /// variance   = retain * variance + eta_retain * (d * d)
    /// ```
    ///
    /// and everything else (the mean, the mean count, the firefly clamp against the
    /// pixel's own history, the disocclusion seed, refused frames) is
    /// [`update`](Self::update)'s. With `guide` equal to the history's mean it is
    /// [`update`](Self::update) exactly.
    ///
    /// A non-finite `guide` (no TAA history at this pixel, or a poisoned one) falls back
    /// to [`update`](Self::update): the deviation is taken from the pixel's own mean, so
    /// nothing non-finite is ever stored.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder().eta(0.5).target_variance(0.01).build().unwrap();
    /// let mut h = SpvgHistory { mean: 3.0, variance: 0.02, mean_count: 8.0 };
    /// // The TAA history says 3.5: the deviation is 4 - 3.5, not 4 - 3.
    /// assert!(c.update_guided(&mut h, 4.0, 3.5, 8, true));
    /// assert_eq!(h, SpvgHistory { mean: 3.5, variance: 0.5 * 0.02 + 0.25 * 0.25, mean_count: 8.0 });
    /// // No TAA history: the unguided update.
    /// let (mut g, mut u) = (h, h);
    /// c.update_guided(&mut g, 2.0, f64::NAN, 8, true);
    /// c.update(&mut u, 2.0, 8, true);
    /// assert_eq!(g, u);
    /// ```
    #[inline]
    pub fn update_guided(
        &self,
        history: &mut SpvgHistory<T>,
        sample: T,
        guide: T,
        count: u32,
        history_valid: bool,
    ) -> bool {
        let (next, accepted) = rules::update_guided(
            &rules::UpdateUniforms::new(self),
            read_for_update(history),
            *history,
            sample,
            guide,
            count,
            history_valid,
        );
        *history = next;
        accepted
    }
}

impl<T: Float> SpvgConfig<T> {
    /// [`update`](Self::update) with the young-history rules (docs/algorithms.md §8.4):
    /// `age` is the number of frames the history has absorbed (0 for a history never
    /// written; a valid history reads as at least 1) and becomes its age after this frame
    /// ([`young::next_age`](super::young::next_age)); `spatial` is the variance of this
    /// frame's monitored values over the pixel's same-surface neighbours
    /// ([`young::SpatialMoments`](super::young::SpatialMoments)), or `None`.
    ///
    /// With [`age_weight`](super::SpvgConfigBuilder::age_weight) on, a valid history
    /// updates with the weight `max(eta, 1 / (age + 1))`
    /// ([`young::age_weight`](super::young::age_weight)) in the operation order of
    /// [`update`](Self::update). With
    /// [`spatial_variance`](super::SpvgConfigBuilder::spatial_variance)`(frames)` an
    /// absorbed frame whose new age is at most `frames` stores `spatial` (where given) as
    /// the variance. With both off, the history is exactly what [`update`](Self::update)
    /// stores. Returns `true` when the history absorbed the frame.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder()
    ///     .target_variance(0.01)
    ///     .age_weight(true)
    ///     .spatial_variance(1)
    ///     .build()
    ///     .unwrap();
    /// let (mut h, mut age) = (SpvgHistory::default(), 0);
    /// // The seed takes the neighbourhood's variance instead of sigma0^2.
    /// assert!(c.update_young(&mut h, &mut age, 2.0, 8, false, Some(0.5)));
    /// assert_eq!((h, age), (SpvgHistory { mean: 2.0, variance: 0.5, mean_count: 8.0 }, 1));
    /// // Its second frame weighs 1/2, not eta = 0.2.
    /// assert!(c.update_young(&mut h, &mut age, 4.0, 8, true, Some(9.0)));
    /// assert_eq!((h.mean, h.variance, age), (3.0, 0.5 * 0.5 + 0.25 * 4.0, 2));
    /// ```
    #[inline]
    pub fn update_young(
        &self,
        history: &mut SpvgHistory<T>,
        age: &mut u32,
        sample: T,
        count: u32,
        history_valid: bool,
        spatial: Option<T>,
    ) -> bool {
        self.update_young_guided(
            history,
            age,
            sample,
            T::nan(),
            count,
            history_valid,
            spatial,
        )
    }

    /// [`update_young`](Self::update_young) with the TAA guide of
    /// [`update_guided`](Self::update_guided) (docs/algorithms.md §8.5): the variance
    /// follows `sample - guide` where `guide` is finite, the pixel's own mean elsewhere;
    /// the age-aware weight and the young variance are
    /// [`update_young`](Self::update_young)'s. This is the texel rule the GPU component
    /// runs when its update is given a guide.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder().eta(0.5).target_variance(0.01).build().unwrap();
    /// let h0 = SpvgHistory { mean: 3.0, variance: 0.02, mean_count: 8.0 };
    /// let (mut g, mut age) = (h0, 4);
    /// assert!(c.update_young_guided(&mut g, &mut age, 4.0, 3.5, 8, true, None));
    /// // With the young rules off it is the guided update, and the age counts on.
    /// let mut u = h0;
    /// c.update_guided(&mut u, 4.0, 3.5, 8, true);
    /// assert_eq!((g, age), (u, 5));
    /// ```
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn update_young_guided(
        &self,
        history: &mut SpvgHistory<T>,
        age: &mut u32,
        sample: T,
        guide: T,
        count: u32,
        history_valid: bool,
        spatial: Option<T>,
    ) -> bool {
        let spatial = spatial.filter(|v| v.is_finite() && *v >= T::zero());
        let (next, next_age, accepted) = rules::update_young_guided(
            &rules::UpdateUniforms::new(self),
            read_for_update(history),
            *history,
            sample,
            guide,
            count,
            history_valid,
            *age,
            spatial,
        );
        (*history, *age) = (next, next_age);
        accepted
    }
}

/// The update's defensive read of a stored history: a non-finite mean or mean count,
/// or a non-finite or not positive variance or mean count, reads as 0.
#[inline(always)]
pub(super) fn read_for_update<T: Float>(h: &SpvgHistory<T>) -> SpvgHistory<T> {
    let finite_or_zero = |v: T| if v.is_finite() { v } else { T::zero() };
    let positive_or_zero = |v: T| {
        if v.is_finite() && v > T::zero() {
            v
        } else {
            T::zero()
        }
    };
    SpvgHistory {
        mean: finite_or_zero(h.mean),
        variance: positive_or_zero(h.variance),
        mean_count: positive_or_zero(h.mean_count),
    }
}
