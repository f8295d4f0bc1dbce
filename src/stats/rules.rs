//! The update rules of the streaming estimators, each written once as a small
//! `#[inline(always)]` function: the estimator types, the controller, the control
//! variates and the frame functions of [`texel`](crate::texel) all call these.

use num_traits::Float;

use super::Weight;

/// Clamps an infinity produced by overflow to the largest finite value of the same sign.
///
/// NaN passes through unchanged: callers reject NaN before it can reach the state.
/// Written as two selects in sequence, each on the previous one's result (NaN fails
/// both comparisons, so for `f32` it is `v.clamp(f32::MIN, f32::MAX)`), through
/// [`core::hint::select_unpredictable`]: a plain `if` here was turned back into
/// branches by LLVM (jump threading), which the frame loops' vectoriser then replayed
/// as masks; as selects each bound is one `min` or `max` instruction.
#[inline(always)]
#[must_use]
pub fn saturate<T: Float>(v: T) -> T {
    let v = core::hint::select_unpredictable(v > T::max_value(), T::max_value(), v);
    core::hint::select_unpredictable(v < T::min_value(), T::min_value(), v)
}

/// The deviation `sat(x - mean)` of an observation from the old mean.
#[inline(always)]
#[must_use]
pub fn deviation<T: Float>(x: T, mean: T) -> T {
    saturate(x - mean)
}

/// EMA step: `sat((1 - eta) mean + eta x)`.
#[inline(always)]
#[must_use]
pub fn ema<T: Float>(w: &Weight<T>, mean: T, x: T) -> T {
    saturate(w.retain() * mean + w.eta() * x)
}

/// Moment step with the deviations `dx`, `dy` from the old means and the rank-one
/// factor `factor` (`eta (1 - eta)` for Finch's EMV/EMC/EMCM, `eta` for the RiskMetrics
/// EWMA): `sat((1 - eta) m + factor sat(dx dy))`.
#[inline(always)]
#[must_use]
pub fn moment<T: Float>(retain: T, factor: T, m: T, dx: T, dy: T) -> T {
    saturate(retain * m + factor * saturate(dx * dy))
}

/// EMV step (Finch), old mean first: returns the new `(mean, variance)`.
///
/// ```text
/// d        = sat(x - mean)
/// variance = sat((1 - eta) variance + eta (1 - eta) sat(d d))
/// mean     = sat((1 - eta) mean + eta x)
/// ```
///
/// It is [`emv_guided`] with the old mean as the centre.
#[inline(always)]
#[must_use]
pub fn emv<T: Float>(w: &Weight<T>, mean: T, variance: T, x: T) -> (T, T) {
    emv_guided(w, mean, variance, x, mean)
}

/// The guided EMV step (the dissertation's Eq. 4.4, docs/algorithms.md §8.5): the
/// variance follows the deviation of `x` from an outside `centre` (a TAA history `C_t`)
/// instead of the old mean; the mean is the same EMA. Returns the new `(mean, variance)`:
///
/// ```text
/// d        = sat(x - centre)
/// variance = sat((1 - eta) variance + eta (1 - eta) sat(d d))
/// mean     = sat((1 - eta) mean + eta x)
/// ```
///
/// `centre` must be finite (callers choose the fallback for one that is not).
#[inline(always)]
#[must_use]
pub fn emv_guided<T: Float>(w: &Weight<T>, mean: T, variance: T, x: T, centre: T) -> (T, T) {
    let d = deviation(x, centre);
    (
        ema(w, mean, x),
        moment(w.retain(), w.eta_retain(), variance, d, d),
    )
}
