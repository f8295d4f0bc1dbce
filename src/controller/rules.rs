//! The controller's rules, each written once as a small `#[inline(always)]` function.
//!
//! [`SpvgConfig::estimate`](super::SpvgConfig::estimate),
//! [`SpvgConfig::update`](super::SpvgConfig::update), the frame functions of
//! [`texel`](crate::texel) and the fuzz targets' lane reference all call these, so a rule
//! changes in one place. They are branch-free where the frame functions need it (every
//! arm computed, then selected), which lets the compiler vectorise the frame loops.
//!
//! A new [`CountPolicy`] is added in two places: its variant in `policy.rs` and its arm
//! in [`raw_count`] (the frame functions call [`raw_count`] too).

use num_traits::Float;

use super::{CountPolicy, SpvgConfig, SpvgHistory};
use crate::stats::{Weight, rules::ema, rules::saturate};

/// A stored non-negative number (variance, mean count) as texel decode reads it: NaN and
/// anything not `> 0` become 0, `+inf` becomes the largest finite value.
#[inline(always)]
#[must_use]
pub fn read_non_negative<T: Float>(v: T) -> T {
    let v = if v > T::zero() { v } else { T::zero() };
    if v > T::max_value() {
        T::max_value()
    } else {
        v
    }
}

/// A stored signed number (mean) as texel decode reads it: NaN becomes 0 and `+-inf`
/// the largest finite value of its sign.
#[inline(always)]
#[must_use]
pub fn read_signed<T: Float>(v: T) -> T {
    if v.is_nan() { T::zero() } else { saturate(v) }
}

/// A history as texel decode reads it ([`read_signed`] for the mean,
/// [`read_non_negative`] for the variance and the mean count): what
/// [`SpvgConfig::estimate`](super::SpvgConfig::estimate) reads, so a hand-built history
/// gives the count its stored texel would.
#[inline(always)]
#[must_use]
pub fn read_history<T: Float>(h: &SpvgHistory<T>) -> SpvgHistory<T> {
    SpvgHistory {
        mean: read_signed(h.mean),
        variance: read_non_negative(h.variance),
        mean_count: read_non_negative(h.mean_count),
    }
}

/// The uniforms of the count estimate, taken from a [`SpvgConfig`] once per frame (or
/// per call).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimateUniforms<T> {
    /// `sigma0^2`.
    pub target: T,
    /// `kappa`.
    pub kappa: T,
    /// `k - 1 = 2/eta - 2`.
    pub k_minus_1: T,
    /// The count rule.
    pub policy: CountPolicy,
    /// `Fixed(n)`'s `n` in `T` (0 for the other policies).
    pub fixed: T,
    /// Whether the damped correction (docs/algorithms.md §8.1) is on.
    pub damped: bool,
    /// The damped correction's lower bound on `n_hat / nbar`, `1 / (1 + c)`.
    pub cap_down: T,
    /// The damped correction's upper bound on `n_hat / nbar`, `1 + c`.
    pub cap_up: T,
    /// The resolve's steady weight `alpha` of the resolved-image rule
    /// (docs/algorithms.md §8.7), 0 when it is off.
    pub resolve: T,
    /// The allocation exponent `p` ([`SpvgConfig::allocation_exponent`]), 1 when
    /// equalising.
    pub exponent: T,
}

impl<T: Float> EstimateUniforms<T> {
    /// The uniforms of a configuration.
    #[inline(always)]
    #[must_use]
    pub fn new(config: &SpvgConfig<T>) -> Self {
        let fixed = match config.policy() {
            CountPolicy::Fixed(n) => T::from(n).unwrap_or(config.max_samples_f()),
            _ => T::zero(),
        };
        Self {
            target: config.target_variance(),
            kappa: config.kappa(),
            k_minus_1: config.k_minus_1(),
            policy: config.policy(),
            fixed,
            damped: config.max_change().is_some(),
            cap_down: config.cap_down(),
            cap_up: config.cap_up(),
            resolve: config.resolve_weight().unwrap_or_else(T::zero),
            exponent: config.allocation_exponent(),
        }
    }
}

/// The raw count `n_hat` of a (read, see [`read_history`]) variance and mean count, in
/// the operation order documented on
/// [`SpvgConfig::raw_estimate`](super::SpvgConfig::raw_estimate).
#[inline(always)]
#[must_use]
pub fn raw_count<T: Float>(u: &EstimateUniforms<T>, variance: T, mean_count: T) -> T {
    let r = saturate(variance / u.target);
    // Every arm is computed and one is selected on the uniform policy: the frame loop
    // stays branch-free.
    let per_count = saturate(u.kappa * saturate((r - T::one()) * u.k_minus_1) + r);
    // The damped correction bounds the count per unit of `nbar` (a uniform select).
    let capped = super::damping::cap(per_count, u.cap_down, u.cap_up);
    let per_count = if u.damped { capped } else { per_count };
    let spvg = saturate(per_count * mean_count);
    let two_phase = saturate(r * mean_count);
    let count = match u.policy {
        CountPolicy::Spvg => spvg,
        CountPolicy::TwoPhase => two_phase,
        CountPolicy::UnrealClamp => r,
        CountPolicy::Fixed(_) => return u.fixed,
    };
    crate::budget::allocate(u.exponent, count)
}

/// The budget of the rounding rule, taken from a [`SpvgConfig`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget<T> {
    /// `beta_min` in `T`.
    pub min_f: T,
    /// `beta_max` in `T`.
    pub max_f: T,
    /// The lower bound of a real count ([`SpvgConfig::floor_f`]): the fractional floor,
    /// or `beta_min` in `T` without fractional counts.
    pub floor_f: T,
    /// `beta_min`.
    pub min: u32,
    /// `beta_max`.
    pub max: u32,
}

impl<T: Float> Budget<T> {
    /// The budget of a configuration.
    #[inline(always)]
    #[must_use]
    pub fn new(config: &SpvgConfig<T>) -> Self {
        Self {
            min_f: config.min_samples_f(),
            max_f: config.max_samples_f(),
            floor_f: config.floor_f(),
            min: config.min_samples(),
            max: config.max_samples(),
        }
    }
}

/// `ceil(clamp(n_hat, min, max))` with NaN giving `min` (the rule documented on
/// [`SpvgConfig::round_count`](super::SpvgConfig::round_count)).
///
/// The ceiling of an in-range `n_hat` (below `max_f <= 2^32`) is its truncation plus one
/// when that is below it: exact (in `f32` the integers above `2^24` are the only values
/// there), and free of a `ceil` call, which is a libm call on x86-64 without SSE4.1.
#[inline(always)]
#[must_use]
pub fn round_count<T: Float>(b: &Budget<T>, n_hat: T) -> u32 {
    let t = n_hat.to_u32().unwrap_or(0);
    let up = T::from(t).is_some_and(|tf| tf < n_hat);
    let c = t.wrapping_add(u32::from(up)).clamp(b.min, b.max);
    // Written so that NaN fails the first comparison and +inf the second.
    if n_hat >= b.min_f {
        if n_hat < b.max_f { c } else { b.max }
    } else {
        b.min
    }
}

/// The zero-sample rule (docs/algorithms.md §2.4): `gamma >= eps_u && gamma > 0`.
#[inline(always)]
#[must_use]
pub fn samples_distant<T: Float>(eps_u: T, gamma: T) -> bool {
    gamma >= eps_u && gamma > T::zero()
}

/// The uniforms of the history update, taken from a [`SpvgConfig`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UpdateUniforms<T> {
    /// The history weight `eta`.
    pub weight: Weight<T>,
    /// `sigma0^2`, the variance of a disocclusion seed.
    pub target: T,
    /// [`CountPolicy::TwoPhase`] stores the count itself rather than its EMA.
    pub two_phase: bool,
    /// The firefly clamp's `k` ([`SpvgConfig::firefly_clamp`]), 0 when off.
    pub firefly_k: T,
    /// The age-aware weight ([`SpvgConfig::age_weight`]).
    pub age_weight: bool,
    /// The largest age that takes the spatial variance ([`SpvgConfig::spatial_variance`]),
    /// 0 when off.
    pub spatial_variance: u32,
}

impl<T: Float> UpdateUniforms<T> {
    /// The uniforms of a configuration.
    #[inline(always)]
    #[must_use]
    pub fn new(config: &SpvgConfig<T>) -> Self {
        Self {
            weight: config.weight(),
            target: config.target_variance(),
            two_phase: config.policy() == CountPolicy::TwoPhase,
            firefly_k: config.firefly_clamp().unwrap_or_else(T::zero),
            age_weight: config.age_weight(),
            spatial_variance: config.spatial_variance(),
        }
    }
}

/// A count as `T`, saturated (an `f16` cannot hold every `u32`).
#[inline(always)]
#[must_use]
pub fn count_value<T: Float>(count: u32) -> T {
    T::from(count).map_or(T::max_value(), saturate)
}

/// The disocclusion seed (docs/algorithms.md §2.3) of `sample` with `count` samples:
/// `mean = sample`, `variance = sigma0^2`, `mean_count = count`; the zero history when
/// the frame has no usable observation (`count == 0` or a non-finite `sample`).
#[inline(always)]
#[must_use]
pub fn seed<T: Float>(target: T, sample: T, count: u32) -> SpvgHistory<T> {
    let ok = count != 0 && sample.is_finite();
    let z = T::zero();
    SpvgHistory {
        mean: if ok { sample } else { z },
        variance: if ok { target } else { z },
        mean_count: if ok { count_value(count) } else { z },
    }
}

/// The firefly clamp (docs/algorithms.md §8.3) of a finite `sample` against a read
/// history's `mean` and `variance`, in this order in `T`:
///
/// ```text
/// floor = if variance > sigma0^2 { variance } else { sigma0^2 }
/// reach = k * sqrt(floor)
/// lo    = mean - reach
/// hi    = mean + reach
/// s     = if sample < lo { lo } else if sample > hi { hi } else { sample }
/// ```
///
/// The variance is floored at `sigma0^2`: a history whose variance reads 0 (a constant
/// pixel, or one flushed to zero in an `f16` texel) would otherwise pin every later value
/// to its mean, and it could never follow a real change of the scene. With the floor a
/// step of any size still moves the history by `eta k sigma0` on its first frame, and
/// the variance it adds widens the next frame's interval (by the factor
/// `(1 - eta)(1 + eta k^2)` on the variance while the step is clamped), so a real
/// change is tracked within a few frames. `reach` and the bounds may overflow to
/// infinity, which only opens that side; `s` is always `sample` or a finite bound.
#[inline(always)]
#[must_use]
pub fn firefly_clamp<T: Float>(k: T, target: T, mean: T, variance: T, sample: T) -> T {
    let floor = if variance > target { variance } else { target };
    let reach = k * floor.sqrt();
    let lo = mean - reach;
    let hi = mean + reach;
    if sample < lo {
        lo
    } else if sample > hi {
        hi
    } else {
        sample
    }
}

/// One frame of the update (docs/algorithms.md §2.2, §2.3) on a read history `h`:
/// returns the new history and whether the frame was absorbed. `kept` is what a refused
/// frame leaves behind a valid history (the stored history itself). With the firefly
/// clamp on, a valid history absorbs [`firefly_clamp`] of the sample.
///
/// It is [`update_guided`] without a guide: the variance follows the deviation from the
/// history's own mean.
#[inline(always)]
#[must_use]
pub fn update<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    count: u32,
    valid: bool,
) -> (SpvgHistory<T>, bool) {
    update_weighted(
        u,
        &u.weight,
        &u.weight,
        h,
        kept,
        sample,
        h.mean,
        count,
        -T::one(),
        valid,
        -T::one(),
    )
}

/// The centre of the guided update's deviation (docs/algorithms.md §8.5): the guide
/// where it is finite, else the read history's mean (the unguided form). A renderer's
/// TAA history is missing or poisoned at some pixels (the first frame, a NaN that
/// escaped its clamp); those pixels then keep the pixel's own statistics rather than
/// store a non-finite variance.
#[inline(always)]
#[must_use]
pub fn guide_centre<T: Float>(guide: T, mean: T) -> T {
    if guide.is_finite() { guide } else { mean }
}

/// [`update`] with the TAA-guided variance (the dissertation's Eq. 4.4, docs/algorithms.md
/// §8.5): on a valid history the variance follows `sample - guide`, where `guide` is the
/// resolved TAA history `C_t` at this pixel in the monitored luminance space; the mean
/// and the mean count are [`update`]'s. A non-finite guide gives [`update`] exactly
/// ([`guide_centre`]). The disocclusion seed and refused frames are [`update`]'s too. With
/// the firefly clamp on, the sample is clamped against the pixel's own history as in
/// [`update`] (the clamp bounds what the history absorbs; the guide only moves the centre
/// of the deviation).
#[inline(always)]
#[must_use]
pub fn update_guided<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    guide: T,
    count: u32,
    valid: bool,
) -> (SpvgHistory<T>, bool) {
    let centre = guide_centre(guide, h.mean);
    update_weighted(
        u,
        &u.weight,
        &u.weight,
        h,
        kept,
        sample,
        centre,
        count,
        -T::one(),
        valid,
        -T::one(),
    )
}

/// The update with the weight `w` in place of the configuration's in the mean and the
/// variance (the age-aware weight of [`update_young`], the span weight of fractional
/// counts) and `w_count` in the mean count, the deviation taken from `centre` (finite: the read mean, or
/// the guide of [`update_guided`]) and the frame's real count `real` (negative for the
/// integer rule; docs/algorithms.md §8.6): the mean count records
/// [`recorded_count`](super::fractional::recorded_count)`(real, count)`, and a skipped
/// frame ([`skips`](super::fractional::skips)) keeps the read mean and variance and moves
/// only the mean count, without being absorbed. `s2` is the frame's
/// [`per_sample_variance`] (negative: none), which the variance of an absorbed frame
/// then follows instead of the deviation ([`sampling_variance_step`]).
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
fn update_weighted<T: Float>(
    u: &UpdateUniforms<T>,
    w: &Weight<T>,
    w_count: &Weight<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    centre: T,
    count: u32,
    real: T,
    valid: bool,
    s2: T,
) -> (SpvgHistory<T>, bool) {
    let accepted = count != 0 && sample.is_finite();
    let n = super::fractional::recorded_count::<T>(real, count);
    // The firefly clamp (a uniform select: off, the sample passes unchanged) bounds
    // what a valid history absorbs; the seed below takes the sample as it is.
    let clamped = firefly_clamp(u.firefly_k, u.target, h.mean, h.variance, sample);
    let observed = if u.firefly_k > T::zero() {
        clamped
    } else {
        sample
    };
    // EMV about the centre (the old mean, or the guide), then EMA (the rules of
    // `stats::Emv`), EMA of the count.
    let (mean, temporal) = crate::stats::rules::emv_guided(w, h.mean, h.variance, observed, centre);
    let mean_count = if u.two_phase {
        n
    } else {
        ema(w_count, h.mean_count, n)
    };
    let variance = if s2 >= T::zero() {
        sampling_variance_step(u, w, h.variance, h.mean_count, mean_count, s2)
    } else {
        temporal
    };
    let absorbed = SpvgHistory {
        mean,
        variance,
        mean_count,
    };
    let skipped = SpvgHistory { mean_count, ..h };
    let next = if valid {
        if accepted {
            absorbed
        } else if super::fractional::skips(count, real, valid) {
            skipped
        } else {
            kept
        }
    } else {
        // The seed is the zero history for a refused frame.
        seed(u.target, sample, count)
    };
    (next, accepted)
}

/// One frame of the update with the young-history rules (docs/algorithms.md §8.4) on a
/// read history `h` that is `age` frames old ([`young::read_age`](super::young::read_age)):
/// returns the new history, its age ([`young::next_age`](super::young::next_age)) and
/// whether the frame was absorbed. `spatial` is the variance of this frame's
/// same-surface neighbourhood ([`young::SpatialMoments::variance`](super::young::SpatialMoments::variance)),
/// `None` where there is none.
///
/// - With [`UpdateUniforms::age_weight`] a valid history updates with
///   [`young::age_weight`](super::young::age_weight) instead of `eta` (the seed is
///   unchanged).
/// - An absorbed frame's variance is then
///   [`young::young_variance`](super::young::young_variance) of the new age: the spatial
///   variance while the age is at most [`UpdateUniforms::spatial_variance`].
///
/// With both off this is [`update`] and the age beside it.
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn update_young<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    count: u32,
    valid: bool,
    age: u32,
    spatial: Option<T>,
) -> (SpvgHistory<T>, u32, bool) {
    update_young_guided(u, h, kept, sample, T::nan(), count, valid, age, spatial)
}

/// [`update_young`] with the TAA guide of [`update_guided`]: the deviation is taken from
/// [`guide_centre`]`(guide, h.mean)`, the age-aware weight and the young variance are
/// [`update_young`]'s. A non-finite guide gives [`update_young`] exactly. It is
/// [`update_fractional`] without a real count.
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn update_young_guided<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    guide: T,
    count: u32,
    valid: bool,
    age: u32,
    spatial: Option<T>,
) -> (SpvgHistory<T>, u32, bool) {
    update_fractional(
        u,
        h,
        kept,
        sample,
        guide,
        count,
        -T::one(),
        valid,
        age,
        spatial,
    )
}

/// [`update_young_guided`] with the frame's real count `real` (docs/algorithms.md §8.6;
/// negative: the integer rule, which is [`update_young_guided`] exactly): the mean count
/// records [`recorded_count`](super::fractional::recorded_count)`(real, count)`, and a
/// skipped frame ([`skips`](super::fractional::skips): a valid history, no sample, a real
/// count) keeps the read mean and variance and its age, moves only the mean count, and
/// returns `false` (nothing absorbed). A frame of fewer than
/// [`SPAN_SAMPLES`](super::fractional::SPAN_SAMPLES) samples with a real count updates
/// the mean and the variance with the [`span_weight`](super::fractional::span_weight).
/// It is [`update_moment`] without a second moment (docs/algorithms.md §8.4 to §8.6).
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn update_fractional<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    guide: T,
    count: u32,
    real: T,
    valid: bool,
    age: u32,
    spatial: Option<T>,
) -> (SpvgHistory<T>, u32, bool) {
    update_moment(
        u,
        h,
        kept,
        sample,
        guide,
        T::nan(),
        count,
        real,
        valid,
        age,
        spatial,
    )
}

/// [`update_fractional`] with the frame's second moment `second_moment`, the mean of the
/// squares of the samples whose mean is `sample` (docs/algorithms.md §8.8): where it
/// gives a [`per_sample_variance`] (finite, at least 2 samples) an absorbed frame's
/// variance follows the EMA of that per-sample variance over the mean count
/// ([`sampling_variance_step`]) instead of the EMV of the deviation, so the count
/// follows the variance its samples can remove and never a temporal term that does not
/// fall with `n` (sub-pixel jitter at edges, motion, a clamp in the resolve). A
/// non-finite `second_moment` (none supplied) or a frame of fewer than 2 samples is
/// [`update_fractional`] exactly. Everything else (the mean, the mean count, the seed,
/// refused and skipped frames, the young variance) is [`update_fractional`]'s. This is
/// the one texel rule the component runs.
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn update_moment<T: Float>(
    u: &UpdateUniforms<T>,
    h: SpvgHistory<T>,
    kept: SpvgHistory<T>,
    sample: T,
    guide: T,
    second_moment: T,
    count: u32,
    real: T,
    valid: bool,
    age: u32,
    spatial: Option<T>,
) -> (SpvgHistory<T>, u32, bool) {
    let s2 = per_sample_variance(sample, second_moment, count);
    let w = if u.age_weight && valid {
        super::young::age_weight(&u.weight, age)
    } else {
        u.weight
    };
    // Fractional counts: a frame of fewer than SPAN_SAMPLES samples weighs in proportion
    // to its samples in the mean and the variance; the mean count keeps `w`.
    let w_stats = if super::fractional::is_real(real) {
        super::fractional::span_weight(&w, count)
    } else {
        w
    };
    let centre = guide_centre(guide, h.mean);
    let (mut next, accepted) = update_weighted(
        u, &w_stats, &w, h, kept, sample, centre, count, real, valid, s2,
    );
    let age = super::young::next_age(age, valid, accepted);
    if accepted {
        next.variance =
            super::young::young_variance(u.spatial_variance, age, next.variance, spatial);
    }
    (next, age, accepted)
}

/// The per-sample variance of a frame (docs/algorithms.md §8.8): with `sample` the mean
/// of the frame's `count` samples and `second_moment` the mean of their squares, the
/// unbiased `s^2 = n (q - S^2) / (n - 1)`, in this order in `T` (`sat` saturates to
/// `+-MAX`):
///
/// ```text
/// if count < 2 or sample, second_moment not finite: -1        // none
/// n = f(count)
/// v = sat(sat(second_moment - sat(sample * sample)) * n) / (n - 1)
/// v if v > 0 else 0                                           // rounding below 0 reads 0
/// ```
///
/// Its expectation is the variance of one sample over the frame's own samples, without
/// any term from how the frame's mean moves between frames.
///
/// # Examples
///
/// ```
/// use spvg::controller::rules::per_sample_variance;
/// // Four binary rays, one hit: s^2 = 4/3 * 0.25 * 0.75 = 0.25.
/// assert_eq!(per_sample_variance(0.25f64, 0.25, 4), 0.25);
/// assert_eq!(per_sample_variance(0.25f64, 0.25, 1), -1.0);
/// assert_eq!(per_sample_variance(0.25f64, f64::NAN, 4), -1.0);
/// ```
#[inline(always)]
#[must_use]
pub fn per_sample_variance<T: Float>(sample: T, second_moment: T, count: u32) -> T {
    if count < 2 || !sample.is_finite() || !second_moment.is_finite() {
        return -T::one();
    }
    let n = count_value::<T>(count);
    let spread = saturate(second_moment - saturate(sample * sample));
    let v = saturate(spread * n) / (n - T::one());
    if v > T::zero() { v } else { T::zero() }
}

/// The variance of an absorbed frame with a [`per_sample_variance`] `s2 >= 0`
/// (docs/algorithms.md §8.8). The history keeps `variance * mean_count`, the per-sample
/// variance the estimate reads (§2.1's `E = var / sigma0^2 * nbar`), as an EMA of `s2`
/// with the frame's weight `w`; `s2` is first capped, with the firefly clamp on, at
/// `k^2 max(variance * mean_count, sigma0^2)` (a firefly widens the frame's spread as it
/// widens its deviation, and the clamp bounds both alike). In this order in `T`, with
/// `count_old` the read mean count and `count_new` the mean count after the frame:
///
/// ```text
/// per    = sat(variance * count_old)
/// floor  = if per > sigma0^2 { per } else { sigma0^2 }
/// cap    = sat(sat(k * k) * floor)                 // only with k > 0
/// v      = if s2 > cap { cap } else { s2 }
/// per    = sat(retain * per + eta * v)
/// variance = if count_new > 0 { per / count_new } else { 0 }
/// ```
#[inline(always)]
#[must_use]
pub fn sampling_variance_step<T: Float>(
    u: &UpdateUniforms<T>,
    w: &Weight<T>,
    variance: T,
    count_old: T,
    count_new: T,
    s2: T,
) -> T {
    let per = saturate(variance * count_old);
    let mut v = s2;
    if u.firefly_k > T::zero() {
        let floor = if per > u.target { per } else { u.target };
        let cap = saturate(saturate(u.firefly_k * u.firefly_k) * floor);
        if v > cap {
            v = cap;
        }
    }
    let per = ema(w, per, v);
    if count_new > T::zero() {
        per / count_new
    } else {
        T::zero()
    }
}
