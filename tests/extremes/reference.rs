//! References and per-frame checks of the extremes matrix: docs/algorithms.md §2.1-2.3 and docs/algorithms.md §3
//! evaluated in `f64` from the stored numbers, and the invariants checked after every frame.

use core::fmt::Debug;

use proptest::prelude::*;
use spvg::controller::CountPolicy;
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

use crate::Real;
use crate::generators::{FrameSpec, Hard, Params};

/// `ceil(clamp(x, min, max))` with NaN at `min`: the rounding rule, monotone in `x`.
pub(crate) fn clamp_ceil(x: f64, min: u32, max: u32) -> u32 {
    if x >= f64::from(max) {
        max
    } else if x > f64::from(min) {
        x.ceil() as u32
    } else {
        min
    }
}

/// The set of counts docs/algorithms.md §2.1/2.3/2.4 allows for a history, as `[lo, hi]`: the raw count
/// is evaluated in `f64` from the stored numbers (exact products for `f32` state; for
/// `f64` state the short-cut below avoids overflow), with an error band covering the
/// rounding of the implementation's operation order in `T`.
pub(crate) fn reference_counts<T: Real>(
    c: &SpvgConfig<T>,
    h: &SpvgHistory<T>,
    gamma: T,
    valid: bool,
) -> (u32, u32) {
    let (min, max) = (c.min_samples(), c.max_samples());
    let g = gamma.wide();
    if !(g >= c.eps_u().wide() && g > 0.0) {
        return (0, 0);
    }
    if let CountPolicy::Fixed(n) = c.policy() {
        return (n, n);
    }
    if !valid {
        return (min, min);
    }
    let eps = T::EPS;
    let r = h.variance.wide() / c.target_variance().wide();
    let nbar = h.mean_count.wide();
    let eta = c.eta().wide();
    let kappa = c.kappa().wide();
    // The damped correction (docs/algorithms.md §8.1) of the SPVG policy: the count per
    // unit of nbar, t, is clamped to [1 / (1 + c), 1 + c].
    let cap = match (c.policy(), c.max_change()) {
        (CountPolicy::Spvg, Some(m)) => Some(1.0 + m.wide()),
        _ => None,
    };
    // For r >= 1 every policy's raw count is at least r (Unreal) or r nbar (SPVG:
    // r nbar + kappa (r - 1) nbar (k - 1) >= r nbar; damped, nbar min(r, 1 + c)), so a
    // huge r means the maximum.
    let lower = match (c.policy(), cap) {
        (CountPolicy::UnrealClamp, _) => r,
        (_, Some(up)) => r.min(up) * nbar,
        _ => r * nbar,
    };
    if r >= 1.0 && lower > 2.0 * f64::from(max) {
        return (max, max);
    }
    let (n_hat, tol) = match c.policy() {
        CountPolicy::UnrealClamp => (r, 4.0 * eps * r),
        CountPolicy::TwoPhase => (r * nbar, 6.0 * eps * r * nbar),
        _ => {
            // `2 (1 - eta) / eta`: `2 / eta - 2` cancels near eta = 1.
            let b = kappa * (2.0 * (1.0 - eta) / eta);
            let t = r * (1.0 + b) - b;
            let tol_t = 16.0 * eps * (r + 1.0) * (1.0 + kappa * 2.0 / eta);
            match cap {
                // The clamp is 1-Lipschitz: the error of t passes through, bounded by the
                // band's width, plus the rounding of the bounds and of the product.
                Some(up) => (
                    nbar * t.clamp(1.0 / up, up),
                    nbar * (tol_t.min(up - 1.0 / up) + 4.0 * eps * up),
                ),
                None => (nbar * t, nbar * tol_t),
            }
        }
    };
    let slack = tol + 1e-9;
    (
        clamp_ceil(n_hat - slack, min, max),
        clamp_ceil(n_hat + slack, min, max),
    )
}

/// Whether every number of an SPVG history is finite and the variance and mean count are
/// non-negative.
pub(crate) fn history_ok<T: Real>(h: &SpvgHistory<T>) -> bool {
    [h.mean, h.variance, h.mean_count]
        .iter()
        .all(|v| v.is_finite())
        && h.variance >= T::zero()
        && h.mean_count >= T::zero()
}

pub(crate) fn cv_ok<T: Real>(j: &CvHistory<T>) -> bool {
    [j.cov_fg, j.var_g, j.mean_f, j.mean_g]
        .iter()
        .all(|v| v.is_finite())
        && j.var_g >= T::zero()
}

/// What a model-specific check needs to know about one frame.
pub(crate) trait Checked<T: Real>: ControlModel<T> {
    fn state_ok(state: &Self::State) -> bool;
    /// Whether `alpha` is this model's coefficient, inside the model's bound.
    fn alpha_ok(&self, alpha: T, fbar: T, g: T) -> bool;
    /// Compares `alpha` with the coefficient evaluated here in `f64` from `state`.
    fn alpha_matches(
        &self,
        _state: &Self::State,
        _alpha: T,
        _fbar: T,
        _g: T,
    ) -> Result<(), String> {
        Ok(())
    }
}

impl<T: Real> Checked<T> for As {
    fn state_ok(_: &()) -> bool {
        true
    }
    fn alpha_ok(&self, alpha: T, _: T, _: T) -> bool {
        alpha == T::zero()
    }
}

impl<T: Real> Checked<T> for Ccv {
    fn state_ok(_: &()) -> bool {
        true
    }
    fn alpha_ok(&self, alpha: T, _: T, _: T) -> bool {
        alpha == T::one()
    }
}

impl<T: Real> Checked<T> for Ocv<T> {
    fn state_ok(j: &CvHistory<T>) -> bool {
        cv_ok(j)
    }
    /// `D = [0, a0 + fbar / G]` where `G > 0` and the bound is finite (an empty `D`, a
    /// negative bound, leaves 0), otherwise `[0, inf)`.
    fn alpha_ok(&self, alpha: T, fbar: T, g: T) -> bool {
        if !(alpha.is_finite() && alpha >= T::zero()) {
            return false;
        }
        if g > T::zero() {
            let upper = self.a0() + fbar / g;
            if upper.is_finite() {
                return alpha <= upper.max(T::zero());
            }
        }
        true
    }
    /// docs/algorithms.md §3 in `f64` from the stored `T` numbers: `(cov + eps) / (var + eps)`, clamped
    /// to `D` where the implementation's upper bound (computed in `T`) is finite, and
    /// rounded into `T`'s range. The tolerance covers the rounding of the two sums, the
    /// quotient and the bound in `T`.
    fn alpha_matches(&self, j: &CvHistory<T>, alpha: T, fbar: T, g: T) -> Result<(), String> {
        let eps_a = self.eps_a().wide();
        let (cov, var) = (j.cov_fg.wide(), j.var_g.wide());
        let ratio = (cov + eps_a) / (var + eps_a);
        let mut want = ratio;
        // Relative rounding, plus the spacing of subnormals for a quotient that lands
        // there.
        let mut tol = 4.0 * T::EPS * ((cov.abs() + eps_a) / (var + eps_a))
            + T::EPS * T::min_positive_value().wide();
        if g > T::zero() && (self.a0() + fbar / g).is_finite() {
            let upper = self.a0().wide() + fbar.wide() / g.wide();
            want = want.min(upper);
            // `a0 + fbar / G` can cancel (fbar ~ -G): its rounding error scales with the
            // terms, not with the small sum.
            tol += 4.0 * T::EPS * (self.a0().wide().abs() + (fbar.wide() / g.wide()).abs());
        }
        let want = want.max(0.0).min(T::max_value().wide());
        let got = alpha.wide();
        if (got - want).abs() <= tol || (got == want) {
            Ok(())
        } else {
            Err(format!(
                "alpha {got} != {want} (tol {tol}, raw ratio {ratio}, state {j:?})"
            ))
        }
    }
}

/// Runs a sequence through a [`PixelController`] and checks every frame.
pub(crate) fn run_pixel<T: Real, M: Checked<T> + Debug>(
    p: &Params,
    model: M,
    base: (Hard, Hard),
    seq: &[FrameSpec],
) -> Result<(), TestCaseError>
where
    M::State: Debug,
{
    let config = p.config::<T>();
    let pixel = PixelController::new(config, model);
    let (base_r, base_b) = (base.0.get::<T>(), base.1.get::<T>());
    let mut h = SpvgHistory::<T>::default();
    let mut j = M::State::default();
    for (t, f) in seq.iter().enumerate() {
        let frame = PixelFrame {
            radiance: f.radiance.get(base_r),
            preintegrated: f.preintegrated.get(base_b),
            gamma: f.gamma.get(),
        };
        let (lo, hi) = reference_counts(&config, &h, frame.gamma, f.valid);
        let n = pixel.count(&h, frame.gamma, f.valid);
        prop_assert!(
            lo <= n && n <= hi,
            "frame {t}: count {n} not in [{lo}, {hi}] for {h:?}, {frame:?}, valid {} (raw {})",
            f.valid,
            config.raw_estimate(&h)
        );
        let before = (h, j);
        let u = pixel.update(&mut h, &mut j, frame, n, f.valid);
        let (fbar, g) = PixelController::<T, M>::split(&frame);
        prop_assert!(
            history_ok(&h),
            "frame {t}: history {h:?} after {frame:?} (was {:?})",
            before.0
        );
        prop_assert!(
            M::state_ok(&j),
            "frame {t}: CV state {j:?} after {frame:?} (was {:?})",
            before.1
        );
        prop_assert!(
            pixel.model().alpha_ok(u.alpha, fbar, g),
            "frame {t}: alpha {} outside the bound for fbar {fbar}, G {g}",
            u.alpha
        );
        let from = if f.valid {
            before.1
        } else {
            M::State::default()
        };
        if let Err(e) = pixel.model().alpha_matches(&from, u.alpha, fbar, g) {
            prop_assert!(false, "frame {t}: {e} for fbar {fbar}, G {g}");
        }
        // Liveness: a frame that sampled with finite inputs is absorbed (an overflow
        // saturates, it must not silently freeze the pixel); non-finite ones are refused.
        let finite = [frame.radiance, frame.preintegrated, frame.gamma]
            .iter()
            .all(|v| v.is_finite());
        prop_assert_eq!(
            u.accepted,
            n > 0 && finite,
            "frame {}: {:?} with n = {} (alpha {}, S {}, state {:?})",
            t,
            frame,
            n,
            u.alpha,
            u.monitored,
            before
        );
        if !u.accepted && f.valid {
            prop_assert_eq!(
                before.0,
                h,
                "frame {}: a refused frame changed the history",
                t
            );
        }
    }
    Ok(())
}

/// Runs a sequence of monitored values straight through [`SpvgConfig`].
pub(crate) fn run_config<T: Real>(
    p: &Params,
    base: Hard,
    seq: &[FrameSpec],
) -> Result<(), TestCaseError> {
    let config = p.config::<T>();
    let base = base.get::<T>();
    let mut h = SpvgHistory::<T>::default();
    for (t, f) in seq.iter().enumerate() {
        let s = f.radiance.get(base);
        let gamma = f.gamma.get::<T>();
        let (lo, hi) = reference_counts(&config, &h, gamma, f.valid);
        let n = config.estimate_with_validity(&h, gamma, f.valid);
        prop_assert!(
            lo <= n && n <= hi,
            "frame {t}: count {n} not in [{lo}, {hi}] for {h:?}, gamma {gamma}, valid {}",
            f.valid
        );
        let before = h;
        let accepted = config.update(&mut h, s, n, f.valid);
        prop_assert!(
            history_ok(&h),
            "frame {t}: {h:?} after S = {s} (was {before:?})"
        );
        prop_assert_eq!(
            accepted,
            n > 0 && s.is_finite(),
            "frame {}: acceptance of S = {}, n = {}",
            t,
            s,
            n
        );
        if !accepted && f.valid {
            prop_assert_eq!(
                before,
                h,
                "frame {}: a refused frame changed the history",
                t
            );
        }
        if accepted && let Err(e) = update_matches(&config, &before, s, n, f.valid, &h) {
            prop_assert!(false, "frame {t}: {e}");
        }
    }
    Ok(())
}

/// docs/algorithms.md §2.2/2.3 evaluated in `f64` from the stored `T` numbers, compared with the
/// stored result where no exact intermediate leaves `T`'s range (past it the
/// implementation saturates, which [`history_ok`] and the count reference cover). The
/// tolerance covers the rounding of the documented operations in `T`, including the
/// rounding of `1 - eta` and `eta (1 - eta)`, and subnormal spacing.
pub(crate) fn update_matches<T: Real>(
    c: &SpvgConfig<T>,
    before: &SpvgHistory<T>,
    s: T,
    n: u32,
    valid: bool,
    got: &SpvgHistory<T>,
) -> Result<(), String> {
    let nf = f64::from(n);
    if !valid {
        let want = (s.wide(), c.target_variance().wide(), nf);
        let got = (got.mean.wide(), got.variance.wide(), got.mean_count.wide());
        return if got == want {
            Ok(())
        } else {
            Err(format!("disocclusion seed {got:?} != {want:?}"))
        };
    }
    let eta = c.eta().wide();
    let (mean, var, nbar) = (
        before.mean.wide(),
        before.variance.wide(),
        before.mean_count.wide(),
    );
    // The firefly clamp (docs/algorithms.md §8.3) to mean +- k sqrt(max(var, sigma0^2));
    // `bound_err` is what rounding the bound in `T` can move the clamped value by (the
    // bound sits on the mean's grid when the mean dwarfs k sigma).
    let (s_used, bound_err) = match c.firefly_clamp() {
        Some(k) => {
            let reach = k.wide() * var.max(c.target_variance().wide()).sqrt();
            let (lo, hi) = (mean - reach, mean + reach);
            let err = 4.0 * T::EPS * (mean.abs() + reach);
            (s.wide().clamp(lo, hi), err)
        }
        None => (s.wide(), 0.0),
    };
    let d = s_used - mean;
    let want_var = (1.0 - eta) * var + eta * (1.0 - eta) * d * d;
    let want_mean = (1.0 - eta) * mean + eta * s_used;
    let want_count = match c.policy() {
        CountPolicy::TwoPhase => nf,
        _ => (1.0 - eta) * nbar + eta * nf,
    };
    let big = T::max_value().wide() / 4.0;
    if !(d.abs() < big && d * d < big && want_var < big && want_mean.abs() < big) {
        return Ok(());
    }
    let eps = T::EPS;
    let tiny = 8.0 * eps * T::min_positive_value().wide();
    // `1 - eta` in `T` is off by up to eps/2 absolutely, which matters for eta ~ 1.
    let checks = [
        (
            "variance",
            got.variance.wide(),
            want_var,
            8.0 * eps * (want_var + var + eta * d * d)
                + 3.0 * eta * (d.abs() + bound_err) * bound_err,
        ),
        (
            "mean",
            got.mean.wide(),
            want_mean,
            4.0 * eps * ((1.0 - eta) * mean.abs() + eta * s_used.abs() + mean.abs())
                + eta * bound_err,
        ),
        (
            "mean_count",
            got.mean_count.wide(),
            want_count,
            4.0 * eps * (nbar + nf),
        ),
    ];
    for (what, got, want, tol) in checks {
        if (got - want).abs() > tol + tiny {
            return Err(format!(
                "{what} {got} != {want} (tol {}) from {before:?}, S {s}, n {n}",
                tol + tiny
            ));
        }
    }
    Ok(())
}
