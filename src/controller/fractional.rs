//! Fractional counts (docs/algorithms.md §8.6): a real-valued floor, a real-valued count
//! per pixel, and its realisation by dithered rounding, each rule written once here.
//!
//! Under a temporal resolve that blends each frame with weight `a` into a history, a
//! pixel whose resolve has converged needs far less than one sample per frame: one
//! sample every few frames keeps the resolved image as noisy as one sample every frame
//! would over a shorter window. The integer floor `beta_min >= 1` makes that impossible.
//! With [`SpvgConfigBuilder::fractional_floor`](super::SpvgConfigBuilder::fractional_floor)
//! set, a pixel with a valid history takes
//!
//! - a **real count** `c` in `[beta, beta_max]` ([`real_count`]): the expected count
//!   `E = r m` of §2.1 with the mean count read as the count of a *sampled* frame,
//!   `m = max(nbar, 1)` ([`fractional_raw_count`]);
//! - a **realised count** `n = floor(c) + [xi < frac(c)]` ([`realise_count`]) with the
//!   threshold `xi` of [`sequence::dither_threshold`](crate::sequence::dither_threshold),
//!   so that `E[n] = c` and the samples of `c < 1` are spread over neighbours and frames.
//!
//! The update ([`SpvgConfig::update_fractional`]) records `c`, not `n`, in the mean count
//! where `n` is the dither's outcome ([`recorded_count`]); a frame with `n = 0` keeps the
//! mean and the variance and updates only the mean count (a skipped frame); and a frame
//! of `n <` [`SPAN_SAMPLES`] samples weighs `n / SPAN_SAMPLES` of a frame in the mean and
//! the variance ([`span_weight`]).
//!
//! Why `m = max(nbar, 1)`: the variance a history holds is that of the frames that took
//! samples. Below one sample per frame those frames take exactly one sample, so the
//! variance is the per-sample variance `v1` whatever `c` is, and `E = var nbar` with
//! `nbar ~ c < 1` would read `v1 c` and push the count further down (the count would
//! collapse to the floor wherever `v1 < sigma0^2`). The count of a sampled frame is
//! `E[n | n > 0] = max(c, 1)`, and `m` is its moving average.
//!
//! Why low counts oscillated, and what changed (measured in docs/algorithms.md §8.6):
//!
//! - **The lag correction amplifies the variance's noise.** `kappa Delta` moves the count
//!   by `nbar (1 + K) dr`, `K = kappa (k - 1)` (2.6 with the published parameters), for a
//!   change `dr` of `var / sigma0^2`, and the moving variance of a few frames has a
//!   relative noise of about `sqrt(2 eta / (2 - eta))` (0.47 at `eta = 0.2`) however many
//!   samples a frame takes. Above the floor of 8 that noise is clipped at 8 for most
//!   pixels; below it, the count swings by more than its own size and spends far more
//!   than it needs (`tests/fractional.rs` simulates it). Below one sample the correction
//!   has nothing to correct at all: the variance does not depend on the count there.
//!   Fractional counts use `E` alone (the rule with `kappa = 0`).
//! - **The variance of one or two samples a frame is the noisiest.** A frame of one
//!   sample of a binary integrand (ambient occlusion) is 0 or 1, and a moving variance of
//!   about ten such values swings far more than one of ten 8-sample means. With the span
//!   weight the history spans `SPAN_SAMPLES / eta` samples rather than `1 / eta` frames
//!   below [`SPAN_SAMPLES`] samples a frame: the time its samples span.
//! - **The dither's own noise** must not reach the mean count ([`recorded_count`]).

use num_traits::Float;

use super::rules::{self, Budget, EstimateUniforms, count_value, samples_distant};
use super::{CountPolicy, SpvgConfig, SpvgHistory};
use crate::stats::Weight;
use crate::stats::rules::saturate;

/// The largest fractional floor: above 8 samples the integer floor loses nothing (the
/// published budget's floor, where counts no longer oscillate).
pub const MAX_FLOOR: f64 = 8.0;

/// A pixel's count for one frame: the samples it takes and, where it took a fractional
/// decision, the real count they realise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCount<T> {
    /// The realised count `n`: the samples the pixel takes this frame.
    pub count: u32,
    /// The real count `c` that `count` realises (`E[count] = c`); `None` where the
    /// integer rule decided (fractional counts off, no valid history, the zero-sample
    /// rule).
    pub real: Option<T>,
}

/// The raw real count of a (read, see [`rules::read_history`]) variance and mean count
/// under fractional counts, in this order in `T` (`sat` as in
/// [`SpvgConfig::raw_estimate`](super::SpvgConfig::raw_estimate)):
///
/// ```text
/// m = if nbar > 1 { nbar } else { 1 }      // the count of a sampled frame
/// r = sat(var / target)
/// Spvg, TwoPhase: c = sat(r * m)           // E, the expected count
/// UnrealClamp:    c = r
/// Fixed(n):       c = n
/// ```
///
/// Where `nbar >= 1` this is §2.1's `E` (the two-phase rule's count); the lag
/// correction `kappa Delta` is not applied, whatever `kappa` is (see the module docs for
/// why), and the damped correction is refused with fractional counts at validation.
#[inline(always)]
#[must_use]
pub fn fractional_raw_count<T: Float>(u: &EstimateUniforms<T>, variance: T, mean_count: T) -> T {
    let one = T::one();
    let m = if mean_count > one { mean_count } else { one };
    let r = saturate(variance / u.target);
    let e = saturate(r * m);
    match u.policy {
        CountPolicy::Spvg | CountPolicy::TwoPhase => e,
        CountPolicy::UnrealClamp => r,
        CountPolicy::Fixed(_) => u.fixed,
    }
}

/// The real count: `raw` clamped to `[floor_f, max_f]` of the budget, in this order:
///
/// ```text
/// if raw >= floor_f { if raw < max_f { raw } else { max_f } } else { floor_f }
/// ```
///
/// so NaN gives the floor and `+inf` the maximum, as the integer rounding does.
#[inline(always)]
#[must_use]
pub fn clamp_real<T: Float>(b: &Budget<T>, raw: T) -> T {
    if raw >= b.floor_f {
        if raw < b.max_f { raw } else { b.max_f }
    } else {
        b.floor_f
    }
}

/// The real count `c` of a read variance and mean count: [`clamp_real`] of
/// [`fractional_raw_count`].
#[inline(always)]
#[must_use]
pub fn real_count<T: Float>(
    u: &EstimateUniforms<T>,
    b: &Budget<T>,
    variance: T,
    mean_count: T,
) -> T {
    clamp_real(b, fractional_raw_count(u, variance, mean_count))
}

/// `2^-24`, the unit of a threshold's top 24 bits.
#[inline(always)]
fn unit<T: Float>(xi: u32) -> T {
    // Both conversions are exact: `xi >> 8 < 2^24` and a power of two.
    T::from(xi >> 8).unwrap_or_else(T::zero) * T::from(1.0 / 16_777_216.0).unwrap_or_else(T::zero)
}

/// The realised count of a real count `c` with the threshold `xi` (fixed point, `u / 2^32`,
/// [`sequence::dither_threshold`](crate::sequence::dither_threshold)):
/// `floor(c) + [xi < frac(c)]`, in this order in `T`:
///
/// ```text
/// if c > 0 {
///     if c < 2^32 {
///         w = trunc(c)                         // an integer of T, exact
///         f = c - w                            // exact (Sterbenz for c >= 1)
///         u = f(xi >> 8) * 2^-24               // exact, sequence::to_unit_f32 in f32
///         w + [u < f]
///     } else { u32::MAX }
/// } else { 0 }                                 // 0, negative or NaN
/// ```
///
/// Every step is exact, so the CPU and the GPU agree bit for bit, and for `xi` uniform
/// over its 2^24 top-bit values `E[n] = floor(c) + ceil(frac(c) 2^24) 2^-24`, within
/// `2^-24` of `c`.
///
/// # Examples
///
/// ```
/// use spvg::controller::fractional::realise_count;
/// assert_eq!(realise_count(2.0_f32, 0), 2);
/// assert_eq!(realise_count(0.25_f32, 0), 1); // the threshold 0 is below 0.25
/// assert_eq!(realise_count(0.25_f32, 1 << 30), 0); // 0.25 is not below 0.25
/// assert_eq!(realise_count(1.75_f32, 3 << 30), 1); // 0.75 is not below 0.75
/// assert_eq!(realise_count(f32::NAN, 0), 0);
/// ```
#[inline(always)]
#[must_use]
pub fn realise_count<T: Float>(c: T, xi: u32) -> u32 {
    let two_32 = T::from(4_294_967_296.0).unwrap_or_else(T::max_value);
    // Written so that NaN fails the first comparison.
    if c > T::zero() {
        if c < two_32 {
            let whole = c.to_u32().unwrap_or(0);
            let frac = c - T::from(whole).unwrap_or_else(T::zero);
            whole + u32::from(unit::<T>(xi) < frac)
        } else {
            u32::MAX
        }
    } else {
        0
    }
}

/// The count a frame records in the mean count: the real count `real` where the
/// realised `count` is the dither's outcome (`count <= real + 1`, a skipped frame
/// included), else `count` (a count raised above it, by the count dilation, is what the
/// frame's variance reflects). A `real` that is not finite and `>= 0` means the integer
/// rule decided: `count`. In this order in `T`: `n = f(count)`,
/// `if real >= 0 && real <= MAX && n <= real + 1 { real } else { n }`.
///
/// The dither's own noise never reaches the mean count this way: at `c = 1.5` the
/// realised counts alternate 1 and 2, and an EMA of them would swing by several percent
/// each frame, a swing the count estimate then multiplies.
#[inline(always)]
#[must_use]
pub fn recorded_count<T: Float>(real: T, count: u32) -> T {
    let n = count_value::<T>(count);
    if is_real(real) && n <= real + T::one() {
        real
    } else {
        n
    }
}

/// The samples a frame needs to weigh a whole frame in the history under fractional
/// counts: the published floor, where the integer rule's counts no longer oscillate.
pub const SPAN_SAMPLES: u32 = 8;

/// The weight of a sampled frame of `count` samples in the mean and the variance under
/// fractional counts: `w` (the history's weight, `eta` or the age-aware weight) times
/// `count / SPAN_SAMPLES` below [`SPAN_SAMPLES`] samples, `w` at or above, in this order
/// in `T`: `e = w.eta * (f(count) / 8)`, `Weight(e)` with `retain = 1 - e`,
/// `eta_retain = e * retain` (as the age-aware weight builds its own). `count = 0` gives
/// `w` (a skipped frame absorbs nothing anyway).
///
/// The history then spans about `SPAN_SAMPLES / eta` samples rather than `1 / eta`
/// frames: ten frames of 8 samples or eighty of one, so a variance of one-sample frames
/// is estimated from as many samples as one of 8-sample frames.
#[inline(always)]
#[must_use]
pub fn span_weight<T: Float>(w: &Weight<T>, count: u32) -> Weight<T> {
    if count == 0 || count >= SPAN_SAMPLES {
        return *w;
    }
    // The division by a power of two is exact.
    let e = w.eta() * (count_value::<T>(count) / count_value::<T>(SPAN_SAMPLES));
    Weight::new(e).unwrap_or(*w)
}

/// Whether a frame is a skipped frame of a fractional count: a valid history, no sample,
/// and a real count (finite, `>= 0`) that decided it. Such a frame keeps the history's
/// mean and variance and records `real` in its mean count.
#[inline(always)]
#[must_use]
pub fn skips<T: Float>(count: u32, real: T, valid: bool) -> bool {
    valid && count == 0 && is_real(real)
}

/// Whether `real` is a real count that decided a frame (finite and `>= 0`); the update
/// rules take anything else (by convention -1) as the integer rule's frame.
#[inline(always)]
#[must_use]
pub fn is_real<T: Float>(real: T) -> bool {
    real >= T::zero() && real <= T::max_value()
}

impl<T: Float> SpvgConfig<T> {
    /// The real count `c` of a valid history under fractional counts (docs/algorithms.md
    /// §8.6): [`real_count`] of the history read as texel decode reads it
    /// ([`rules::read_history`]), in `[floor_f, max_samples_f]`. Computed whatever the
    /// configuration; only [`estimate_fractional`](Self::estimate_fractional) with
    /// fractional counts on uses it.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder()
    ///     .target_variance(0.01)
    ///     .fractional_floor(Some(0.0))
    ///     .build()
    ///     .unwrap();
    /// // A quarter of the target's variance at one sample a frame: a quarter sample.
    /// let h = SpvgHistory { mean: 0.5, variance: 0.0025, mean_count: 0.25 };
    /// assert_eq!(c.real_count(&h), 0.25);
    /// ```
    #[inline]
    #[must_use]
    pub fn real_count(&self, history: &SpvgHistory<T>) -> T {
        let h = rules::read_history(history);
        real_count(
            &EstimateUniforms::new(self),
            &Budget::new(self),
            h.variance,
            h.mean_count,
        )
    }

    /// The count of a pixel under fractional counts (docs/algorithms.md §8.6): with
    /// [`fractional_floor`](super::SpvgConfigBuilder::fractional_floor) set, a valid
    /// history and `gamma` passing [`samples_distant`](Self::samples_distant), the
    /// [`real_count`](Self::real_count) `c` realised with the threshold `xi`
    /// ([`realise_count`], `xi` from
    /// [`sequence::dither_threshold`](crate::sequence::dither_threshold)); `Fixed(n)`
    /// gives `n` and `c = n`. Everywhere else (fractional counts off, no valid history,
    /// the zero-sample rule) it is
    /// [`estimate_with_validity`](Self::estimate_with_validity) with `real = None`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// use spvg::sequence::dither_threshold;
    /// let c = SpvgConfig::<f32>::builder()
    ///     .target_variance(0.01)
    ///     .fractional_floor(Some(0.25))
    ///     .build()
    ///     .unwrap();
    /// let h = SpvgHistory { mean: 0.5, variance: 0.0, mean_count: 0.25 };
    /// // At the floor: one frame in four takes a sample (16 of 64, give or take the
    /// // sequence's discrepancy), never two frames in a row.
    /// let n: Vec<u32> = (0..64)
    ///     .map(|t| c.estimate_fractional(&h, 1.0, true, dither_threshold(3, 5, t)).count)
    ///     .collect();
    /// assert!((15..=17).contains(&n.iter().sum::<u32>()));
    /// assert!(n.windows(2).all(|w| w[0] + w[1] <= 1));
    /// // Without history the integer floor seeds it.
    /// assert_eq!(c.estimate_fractional(&h, 1.0, false, 0).count, 8);
    /// ```
    #[inline]
    #[must_use]
    pub fn estimate_fractional(
        &self,
        history: &SpvgHistory<T>,
        gamma: T,
        history_valid: bool,
        xi: u32,
    ) -> FrameCount<T> {
        let integer = FrameCount {
            count: self.estimate_with_validity(history, gamma, history_valid),
            real: None,
        };
        if self.fractional_floor().is_none()
            || !history_valid
            || !samples_distant(self.eps_u(), gamma)
        {
            return integer;
        }
        if let CountPolicy::Fixed(n) = self.policy() {
            return FrameCount {
                count: n,
                real: Some(count_value(n)),
            };
        }
        let c = self.real_count(history);
        FrameCount {
            count: realise_count(c, xi),
            real: Some(c),
        }
    }

    /// [`update_young_guided`](Self::update_young_guided) with the frame's real count
    /// (docs/algorithms.md §8.6): `real` is
    /// [`FrameCount::real`] of the estimate, `count` the samples the pixel took (the
    /// realised count, or more where the count dilation raised it).
    ///
    /// - A valid history with `count = 0` and a real count skipped the frame: its mean,
    ///   variance and age stay, and its mean count moves towards `real` as any frame's
    ///   does (`mean_count = retain * mean_count + eta * real`). Returns `false` (no
    ///   observation absorbed).
    /// - Otherwise the frame is [`update_young_guided`](Self::update_young_guided)'s, with
    ///   [`recorded_count`]`(real, count)` in place of `count` in the mean count.
    ///
    /// With `real = None` it is [`update_young_guided`](Self::update_young_guided)
    /// exactly. A `guide` that is not finite is the unguided update.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder()
    ///     .eta(0.5)
    ///     .target_variance(0.01)
    ///     .spatial_variance(0)
    ///     .fractional_floor(Some(0.0))
    ///     .build()
    ///     .unwrap();
    /// let (mut h, mut age) = (SpvgHistory { mean: 0.5, variance: 0.02, mean_count: 1.0 }, 4);
    /// // A skipped frame: the statistics stay, the mean count follows c = 0.5.
    /// assert!(!c.update_fractional(&mut h, &mut age, f64::NAN, f64::NAN, 0, Some(0.5), true, None));
    /// assert_eq!((h, age), (SpvgHistory { mean: 0.5, variance: 0.02, mean_count: 0.75 }, 4));
    /// // A sampled frame records c = 0.5, not its one sample.
    /// assert!(c.update_fractional(&mut h, &mut age, 0.7, f64::NAN, 1, Some(0.5), true, None));
    /// assert_eq!(h.mean_count, 0.625);
    /// ```
    #[inline]
    #[allow(
        clippy::too_many_arguments,
        reason = "the guided young update's arguments and the real count"
    )]
    pub fn update_fractional(
        &self,
        history: &mut SpvgHistory<T>,
        age: &mut u32,
        sample: T,
        guide: T,
        count: u32,
        real: Option<T>,
        history_valid: bool,
        spatial: Option<T>,
    ) -> bool {
        let spatial = spatial.filter(|v| v.is_finite() && *v >= T::zero());
        let (next, next_age, accepted) = rules::update_fractional(
            &rules::UpdateUniforms::new(self),
            super::update::read_for_update(history),
            *history,
            sample,
            guide,
            count,
            real.unwrap_or_else(|| -T::one()),
            history_valid,
            *age,
            spatial,
        );
        (*history, *age) = (next, next_age);
        accepted
    }
}
