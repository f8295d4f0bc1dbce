//! The control-variate rules, each written once as a small `#[inline(always)]`
//! function: [`PixelController`](super::PixelController), [`Ocv`](super::Ocv) and the
//! frame functions of [`texel`](crate::texel) all call these, so a rule changes in one
//! place. Branch-free where the frame loops need it.

use num_traits::Float;

use super::CvHistory;
use crate::stats::rules::saturate;
use crate::stats::{Emcm, Weight};

/// The distant estimate `fbar = L_o - (1 - gamma) B` and the control `G = gamma B`,
/// saturated when all three inputs are finite; a non-finite input gives a non-finite
/// `fbar` or `G` (so the frame is refused).
#[inline(always)]
#[must_use]
pub fn split<T: Float>(radiance: T, preintegrated: T, gamma: T) -> (T, T) {
    let fbar = radiance - (T::one() - gamma) * preintegrated;
    let g = gamma * preintegrated;
    if radiance.is_finite() && preintegrated.is_finite() && gamma.is_finite() {
        (saturate(fbar), saturate(g))
    } else {
        (fbar, g)
    }
}

/// The monitored residual `S = fbar - alpha G`: saturated when `fbar` and `G` are
/// finite, left non-finite (and so refused) otherwise.
#[inline(always)]
#[must_use]
pub fn residual<T: Float>(fbar: T, g: T, alpha: T) -> T {
    let s = fbar - alpha * g;
    if fbar.is_finite() && g.is_finite() {
        saturate(s)
    } else {
        s
    }
}

/// The unclamped OCV coefficient `(cov_fg + eps_a) / (var_g + eps_a)`, saturated to
/// `+-MAX`, or 1 where it is NaN (a corrupt state falls back to CCV).
#[inline(always)]
#[must_use]
pub fn raw_coefficient<T: Float>(eps_a: T, cov_fg: T, var_g: T) -> T {
    let a = (cov_fg + eps_a) / (var_g + eps_a);
    if a.is_nan() { T::one() } else { saturate(a) }
}

/// Clamps a coefficient to `D = [0, a0 + fbar / G]`; the upper bound applies only where
/// `G > 0` and it is finite.
#[inline(always)]
#[must_use]
pub fn clamp_to_bound<T: Float>(a0: T, alpha: T, fbar: T, g: T) -> T {
    let upper = a0 + fbar / g;
    let a = if g > T::zero() && upper.is_finite() {
        alpha.min(upper)
    } else {
        alpha
    };
    a.max(T::zero())
}

/// One frame of the OCV state update (EMCM of `Z = [fbar, G]` through
/// [`Emcm`], old means first), on `fbar` and `G` as the state update sees them
/// (`round` is the model's [`update_inputs`](super::Ocv::update_inputs)). Returns the
/// new state and whether it absorbed the frame.
///
/// - non-finite `fbar` or `G`: a valid state is kept as it is, an invalid one reset to
///   the zero state (refused);
/// - `valid = false` (disocclusion): the first-sample seed, means `fbar` and `G`,
///   moments 0;
/// - otherwise the EMCM step on the stored state read defensively
///   ([`Emcm::from_parts`]).
#[inline(always)]
#[must_use]
pub fn update_state<T: Float>(
    w: &Weight<T>,
    state: &CvHistory<T>,
    fbar: T,
    g: T,
    valid: bool,
    round: impl Fn(T, T) -> (T, T),
) -> (CvHistory<T>, bool) {
    let ok = fbar.is_finite() && g.is_finite();
    let (fbar, g) = round(fbar, g);
    let z = T::zero();
    let mut m =
        Emcm::<T, 2>::from_parts([state.mean_f, state.mean_g], [z, state.cov_fg, state.var_g]);
    // `fbar` and `G` finite: the update is absorbed (its result is discarded otherwise).
    let _ = m.update(w, [fbar, g]);
    let [mean_f, mean_g] = m.mean();
    let absorbed = CvHistory {
        cov_fg: m.covariance(1, 0),
        var_g: m.covariance(1, 1),
        mean_f,
        mean_g,
    };
    let seeded = CvHistory {
        cov_fg: z,
        var_g: z,
        mean_f: fbar,
        mean_g: g,
    };
    let zero = CvHistory {
        cov_fg: z,
        var_g: z,
        mean_f: z,
        mean_g: z,
    };
    let next = match (ok, valid) {
        (true, true) => absorbed,
        (true, false) => seeded,
        (false, true) => *state,
        (false, false) => zero,
    };
    (next, ok)
}
