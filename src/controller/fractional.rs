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
//!
//! Two rules sit on top (docs/algorithms.md §8.6, §8.7):
//!
//! - **No stall.** The floor in use is never below [`REVISIT_COUNT`] (1/32): with the
//!   golden-ratio rotation of the dither threshold, a pixel whose real count is at least
//!   1/32 samples at least once in every [`REVISIT_FRAMES`] (55) frames, however its
//!   variance reads.
//! - **The resolved image.** With
//!   [`resolve_weight`](super::SpvgConfigBuilder::resolve_weight) set, the count aims at
//!   `sigma0^2` for the image after a temporal resolve that blends the frame with weight
//!   `a`: `c = E a / (2 - a)` ([`resolved_factor`], [`resolve_weight`]).

use num_traits::Float;

use super::rules::{self, Budget, EstimateUniforms, count_value, samples_distant};
use super::{CountPolicy, SpvgConfig, SpvgHistory, young};
use crate::stats::Weight;
use crate::stats::rules::saturate;

/// The largest fractional floor: above 8 samples the integer floor loses nothing (the
/// published budget's floor, where counts no longer oscillate).
pub const MAX_FLOOR: f64 = 8.0;

/// The smallest real count a pixel with a valid history takes under fractional counts,
/// whatever its floor: `1/32`. The dither threshold of a pixel rotates by the golden ratio
/// each frame ([`sequence::dither_threshold`](crate::sequence::dither_threshold)), and
/// the frames between two visits of such a rotation to `[0, 1/32)` take at most three
/// lengths, Fibonacci numbers, the largest [`REVISIT_FRAMES`] (the three-gap theorem,
/// Slater's form). So a pixel with `c >= 1/32` never goes longer than that without a
/// sample, and a converged pixel spends 1/32 sample a frame on staying watched.
pub const REVISIT_COUNT: f64 = 1.0 / 32.0;

/// The most frames between two sampled frames of a pixel whose real count stays at or
/// above [`REVISIT_COUNT`] (and whose history stays valid): 55, the Fibonacci number that
/// bounds the return time of the golden-ratio rotation to an interval of length 1/32
/// (`21 + 34`; `tests/fractional.rs` walks the threshold sequence to check it).
pub const REVISIT_FRAMES: u32 = 55;

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
/// under fractional counts, with the resolve's weight `a` at the pixel
/// ([`resolve_weight`]; 1 where the resolved-image rule is off), in this order in `T`
/// (`sat` as in [`SpvgConfig::raw_estimate`](super::SpvgConfig::raw_estimate)):
///
/// ```text
/// m = if nbar > 1 { nbar } else { 1 }      // the count of a sampled frame
/// r = sat(var / target)
/// Spvg, TwoPhase: c = sat(r * m)           // E, the expected count
/// UnrealClamp:    c = r
/// Fixed(n):       return n
/// if a < 1 { sat(c * resolved_factor(a)) } else { c }
/// ```
///
/// Where `nbar >= 1` this is §2.1's `E` (the two-phase rule's count); the lag
/// correction `kappa Delta` is not applied, whatever `kappa` is (see the module docs for
/// why), and the damped correction is refused with fractional counts at validation.
#[inline(always)]
#[must_use]
pub fn fractional_raw_count<T: Float>(
    u: &EstimateUniforms<T>,
    variance: T,
    mean_count: T,
    a: T,
) -> T {
    let one = T::one();
    let m = if mean_count > one { mean_count } else { one };
    let r = saturate(variance / u.target);
    let e = saturate(r * m);
    let c = match u.policy {
        CountPolicy::Spvg | CountPolicy::TwoPhase => e,
        CountPolicy::UnrealClamp => r,
        CountPolicy::Fixed(_) => return u.fixed,
    };
    if a < one {
        saturate(c * resolved_factor(a))
    } else {
        c
    }
}

/// The share `a / (2 - a)` of one frame's variance that a resolve blending the frame with
/// weight `a` onto its history keeps in steady state: the resolved image's variance
/// is `a / (2 - a) Var(S)` (the exponential moving mean's, docs/algorithms.md §8.7), so
/// the count that gives the resolved image the variance `sigma0^2` is this factor times
/// the per-frame count. 1 at `a = 1` (no history), about `a / 2` for small `a`
/// (0.0526 at 0.1). In `T`: `a / (2 - a)`, for `a` in `(0, 1]` as [`resolve_weight`]
/// gives it.
///
/// # Examples
///
/// ```
/// use spvg::controller::fractional::resolved_factor;
/// assert_eq!(resolved_factor(1.0_f64), 1.0);
/// assert_eq!(resolved_factor(0.5_f64), 0.5 / 1.5);
/// ```
#[inline(always)]
#[must_use]
pub fn resolved_factor<T: Float>(a: T) -> T {
    a / (T::one() + T::one() - a)
}

/// The weight `a` the resolve gives this frame at a pixel, for the resolved-image rule
/// with the steady weight `alpha` (0 when the rule is off) and a history `age` frames old
/// ([`young::read_age`]), in this order in `T`:
///
/// ```text
/// if !(alpha > 0)          { 1 }                      // the rule is off
/// else if input > 0 && input <= MAX { min(input, 1) } // the renderer's own weight
/// else { young = 1 / (f(clamp(age, 1, AGE_CAP)) + 1); if young > alpha { young } else { alpha } }
/// ```
///
/// `input` is the weight the renderer's resolve will give the current frame at the pixel
/// (its blend weight, or `1 / (history length + 1)` of an accumulation); NaN, 0 or less
/// and infinities mean "none" and the age stands in for it: a resolve that accumulates
/// from the same disocclusion as the history averages its first `age + 1` frames
/// plainly, then settles at `alpha`.
///
/// # Examples
///
/// ```
/// use spvg::controller::fractional::resolve_weight;
/// assert_eq!(resolve_weight(0.1_f32, 3, f32::NAN), 0.25); // a young history
/// assert_eq!(resolve_weight(0.1_f32, 40, f32::NAN), 0.1); // settled
/// assert_eq!(resolve_weight(0.1_f32, 40, 0.6), 0.6); // the resolve rejected its history
/// assert_eq!(resolve_weight(0.0_f32, 40, 0.6), 1.0); // the rule is off
/// ```
#[inline(always)]
#[must_use]
pub fn resolve_weight<T: Float>(alpha: T, age: u32, input: T) -> T {
    let one = T::one();
    // Written so that a NaN alpha reads as off.
    if alpha > T::zero() {
        if input > T::zero() && input <= T::max_value() {
            return if input < one { input } else { one };
        }
        let a = T::from(age.clamp(1, young::AGE_CAP)).unwrap_or_else(T::one) + one;
        let young = one / a;
        if young > alpha { young } else { alpha }
    } else {
        one
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

/// The real count `c` of a read variance and mean count with the resolve's weight `a`
/// (1 where the resolved-image rule is off): [`clamp_real`] of [`fractional_raw_count`].
#[inline(always)]
#[must_use]
pub fn real_count<T: Float>(
    u: &EstimateUniforms<T>,
    b: &Budget<T>,
    variance: T,
    mean_count: T,
    a: T,
) -> T {
    clamp_real(b, fractional_raw_count(u, variance, mean_count, a))
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
    /// The weight the resolve gives this frame at a pixel whose history is `age` frames
    /// old, with the renderer's own weight `input` where it has one (NaN where not):
    /// [`resolve_weight`] with this configuration's
    /// [`resolve_weight`](super::SpvgConfigBuilder::resolve_weight) (1 when the
    /// resolved-image rule is off).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::SpvgConfig;
    /// let c = SpvgConfig::<f32>::builder()
    ///     .fractional_floor(Some(0.0))
    ///     .resolve_weight(Some(0.1))
    ///     .build()
    ///     .unwrap();
    /// assert_eq!(c.resolve_weight_at(1, f32::NAN), 0.5);
    /// assert_eq!(c.resolve_weight_at(100, f32::NAN), 0.1);
    /// ```
    #[inline]
    #[must_use]
    pub fn resolve_weight_at(&self, age: u32, input: T) -> T {
        resolve_weight(self.resolve_weight().unwrap_or_else(T::zero), age, input)
    }

    /// The real count `c` of a valid history under fractional counts (docs/algorithms.md
    /// §8.6): [`real_count`] of the history read as texel decode reads it
    /// ([`rules::read_history`]), in `[floor_f, max_samples_f]`, for a settled history
    /// (the resolve's weight `alpha` where the resolved-image rule is on; see
    /// [`real_count_at`](Self::real_count_at) for a history of known age). Computed
    /// whatever the configuration; only
    /// [`estimate_fractional`](Self::estimate_fractional) with fractional counts on uses
    /// it.
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
    /// // Behind a resolve of weight 0.5, a third of that: 0.25 * 0.5 / 1.5.
    /// let r = c.to_builder().resolve_weight(Some(0.5)).build().unwrap();
    /// assert!((r.real_count(&h) - 0.25 / 3.0).abs() < 1e-15);
    /// ```
    #[inline]
    #[must_use]
    pub fn real_count(&self, history: &SpvgHistory<T>) -> T {
        self.real_count_at(history, young::AGE_CAP, T::nan())
    }

    /// [`real_count`](Self::real_count) of a history `age` frames old, with the
    /// renderer's resolve weight `input` at the pixel (NaN where it has none): the
    /// resolved-image rule's `a` is [`resolve_weight_at`](Self::resolve_weight_at)`(age,
    /// input)`.
    #[inline]
    #[must_use]
    pub fn real_count_at(&self, history: &SpvgHistory<T>, age: u32, input: T) -> T {
        let h = rules::read_history(history);
        real_count(
            &EstimateUniforms::new(self),
            &Budget::new(self),
            h.variance,
            h.mean_count,
            self.resolve_weight_at(age, input),
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
    /// [`estimate_with_validity`](Self::estimate_with_validity) with `real = None`. A
    /// history whose age is known takes [`estimate_resolved`](Self::estimate_resolved);
    /// this is that for a settled history without the renderer's resolve weight.
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
        self.estimate_resolved(history, young::AGE_CAP, gamma, history_valid, xi, T::nan())
    }

    /// [`estimate_fractional`](Self::estimate_fractional) of a history `age` frames old
    /// ([`young::read_age`](super::young::read_age) of its texel), with the renderer's
    /// resolve weight `input` at the pixel (NaN where it has none): the real count is
    /// [`real_count_at`](Self::real_count_at)`(history, age, input)`. Without the
    /// resolved-image rule `age` and `input` change nothing.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f32>::builder()
    ///     .target_variance(0.0625)
    ///     .fractional_floor(Some(0.0))
    ///     .resolve_weight(Some(0.1))
    ///     .build()
    ///     .unwrap();
    /// let h = SpvgHistory { mean: 0.5, variance: 0.25, mean_count: 1.0 };
    /// // Per frame this history asks for 4 samples; a settled resolve (a = 0.1) keeps
    /// // 0.1 / 1.9 of a frame's variance, so a fifth of a sample does.
    /// let settled = c.estimate_resolved(&h, 100, 1.0, true, 0, f32::NAN).real.unwrap();
    /// assert!((settled - 4.0 * 0.1 / 1.9).abs() < 1e-6);
    /// // A resolve that rejected its history (a = 1) needs the per-frame count.
    /// assert_eq!(c.estimate_resolved(&h, 100, 1.0, true, 0, 1.0).real, Some(4.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn estimate_resolved(
        &self,
        history: &SpvgHistory<T>,
        age: u32,
        gamma: T,
        history_valid: bool,
        xi: u32,
        input: T,
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
        let c = self.real_count_at(history, age, input);
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
        self.update_moment(
            history,
            age,
            sample,
            guide,
            T::nan(),
            count,
            real,
            history_valid,
            spatial,
        )
    }

    /// [`update_fractional`](Self::update_fractional) with the frame's second moment
    /// (docs/algorithms.md §8.8): `second_moment` is the mean of the squares of the
    /// samples whose mean is `sample` (`sum(x^2) / n` beside `sample = sum(x) / n`). Where
    /// the frame took at least 2 samples and `second_moment` is finite, an absorbed
    /// frame's variance follows the EMA of the frame's per-sample variance over the mean
    /// count ([`rules::per_sample_variance`], [`rules::sampling_variance_step`]) rather
    /// than the EMV of its deviation, so `variance * mean_count`, the per-sample variance
    /// the estimate reads, holds only what samples can remove, and variance
    /// that samples cannot remove (sub-pixel jitter at edges, motion, a clamp in the
    /// resolve) buys no samples. A NaN `second_moment` (none) is
    /// [`update_fractional`](Self::update_fractional) exactly; so is a frame of 0 or 1
    /// samples.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f64>::builder().eta(0.5).target_variance(0.01).build().unwrap();
    /// let h0 = SpvgHistory { mean: 0.5, variance: 0.02, mean_count: 4.0 };
    /// let (mut h, mut age) = (h0, 4);
    /// // A frame whose mean jumped by 0.5 (an edge under jitter) but whose 4 samples
    /// // agree: the variance follows the in-frame spread (0), not the jump.
    /// assert!(c.update_moment(&mut h, &mut age, 1.0, f64::NAN, 1.0, 4, None, true, None));
    /// assert_eq!(h.variance, 0.5 * 0.02);
    /// // Without the moment the jump enters the variance.
    /// let (mut u, mut age) = (h0, 4);
    /// c.update_moment(&mut u, &mut age, 1.0, f64::NAN, f64::NAN, 4, None, true, None);
    /// assert_eq!(u.variance, 0.5 * 0.02 + 0.25 * 0.25);
    /// ```
    #[inline]
    #[allow(
        clippy::too_many_arguments,
        reason = "the fractional update's arguments and the second moment"
    )]
    pub fn update_moment(
        &self,
        history: &mut SpvgHistory<T>,
        age: &mut u32,
        sample: T,
        guide: T,
        second_moment: T,
        count: u32,
        real: Option<T>,
        history_valid: bool,
        spatial: Option<T>,
    ) -> bool {
        let spatial = spatial.filter(|v| v.is_finite() && *v >= T::zero());
        let (next, next_age, accepted) = rules::update_moment(
            &rules::UpdateUniforms::new(self),
            super::update::read_for_update(history),
            *history,
            sample,
            guide,
            second_moment,
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
