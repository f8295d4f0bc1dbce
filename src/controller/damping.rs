//! The damped correction (docs/algorithms.md §8.1): a per-frame cap on the count's
//! relative change against the history's mean count.
//!
//! The SPVG estimate `n_hat = nbar (r + kappa (k - 1)(r - 1))` extrapolates a variance
//! measured at about `nbar` samples to the count that reaches the target. The damped
//! policy trusts that extrapolation only within a factor `1 + c` of `nbar`: the count per
//! unit of `nbar`, `t = n_hat / nbar`, is clamped to `[1 / (1 + c), 1 + c]`, so `n_hat`
//! lies in `[nbar / (1 + c), nbar (1 + c)]` before the budget clamp. The
//! cap bounds the frame-to-frame noise of the count in the steady state (the EMV's
//! relative noise, `sqrt(2 eta / (2 - eta))` = 0.47 at `eta = 0.2`, no longer reaches the
//! count in full) and limits the growth of `nbar` from a cold start to a factor
//! `1 + eta c` per frame instead of jumping to `beta_max` while the variance is inflated
//! by the lag of a zero-seeded mean.
//!
//! The rule is one pure function, [`cap`], called by `rules::raw_count`, which the
//! per-pixel estimate and the frame functions of `spvg::texel` share, so both give the
//! same counts.

use num_traits::Float;

/// Clamps `x` (the count per unit of `nbar`, `t` in the operation order of
/// `SpvgConfig::raw_estimate`) to `[lo, hi] = [cap_down, cap_up]`, the configuration's
/// `1 / (1 + c)` and `1 + c`, each computed once in `T`.
///
/// Exact rule, in this order (a WGSL port uses these comparisons rather than `clamp`,
/// whose NaN behaviour WGSL leaves to the implementation):
///
/// ```text
/// if x < lo { lo } else if x > hi { hi } else { x }
/// ```
///
/// A NaN `x` fails both comparisons and passes through; a NaN bound compares false and
/// does not bind; an infinite `hi` never binds.
#[inline]
#[must_use]
pub(crate) fn cap<T: Float>(x: T, lo: T, hi: T) -> T {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::cap;

    #[test]
    fn cap_clamps_and_passes_nan() {
        assert_eq!(cap(5.0_f32, 6.0, 8.0), 6.0, "below");
        assert_eq!(cap(9.0_f32, 6.0, 8.0), 8.0, "above");
        assert_eq!(cap(7.0_f32, 6.0, 8.0), 7.0, "inside");
        assert!(cap(f32::NAN, 6.0, 8.0).is_nan(), "NaN passes through");
        assert_eq!(
            cap(7.0_f32, f32::NAN, f32::NAN),
            7.0,
            "NaN bounds do not bind"
        );
        assert_eq!(
            cap(f32::INFINITY, 0.0, f32::INFINITY),
            f32::INFINITY,
            "an infinite upper bound never binds"
        );
    }
}
