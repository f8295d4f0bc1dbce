//! Stability at the extremes: a property-test matrix over the supported numeric range
//! (issue 6), for `f32` and `f64`.
//!
//! Luminances are log-uniform in magnitude over 1e-30..1e30 with both signs, and exact
//! zeros, subnormals, NaN, infinities and `+-MAX` injected at a low rate; weights `eta`
//! and `eta_cv` are log-uniform in 1e-7..1 (and exactly 1); targets log-uniform in
//! 1e-8..1e2; budgets anywhere in `1 <= min <= max <= 1024`. Multi-frame sequences run
//! through [`PixelController`] with each model and through [`SpvgConfig`] with each
//! [`CountPolicy`], and after every frame the test checks the crate's guarantees: no
//! panic, finite stored state, non-negative variances, counts in the budget (or 0 by the
//! zero-sample rule) and equal to the SPEC 2.1 count evaluated here in extended range, an
//! OCV coefficient inside its bound, and frames with usable observations absorbed.
//!
//! The generators are written here (not `spvg::arbitrary`) so this file stands alone.

use core::fmt::{Debug, Display};

use num_traits::Float;
use proptest::prelude::*;
use spvg::controller::CountPolicy;
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

/// `n` cases, unless `PROPTEST_CASES` asks for another number (a longer hunt).
fn cases(n: u32) -> ProptestConfig {
    let mut config = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = n;
    }
    config
}

/// Frames per generated sequence.
const FRAMES: usize = 50;

/// The two float types under test, with what the reference needs to know of them.
trait Real: Float + Debug + Display + Default + 'static {
    /// Machine epsilon as `f64` (twice the unit roundoff).
    const EPS: f64;
    fn of(v: f64) -> Self {
        Self::from(v).expect("f64 converts to every tested float type")
    }
    fn wide(self) -> f64 {
        self.to_f64()
            .expect("every tested float type widens to f64")
    }
}

impl Real for f32 {
    const EPS: f64 = f32::EPSILON as f64;
}

impl Real for f64 {
    const EPS: f64 = f64::EPSILON;
}

// ---------------------------------------------------------------------------------------
// Hard-case value generators
// ---------------------------------------------------------------------------------------

/// A value described independently of the float type, so one generated case runs in
/// `f32` and `f64` alike; [`Hard::get`] rounds it into the type.
#[derive(Clone, Copy, Debug)]
enum Hard {
    /// `+-10^log10`.
    Mag {
        neg: bool,
        log10: f64,
    },
    /// `+-0`.
    Zero {
        neg: bool,
    },
    /// `+-frac * MIN_POSITIVE` of the type: a subnormal (or 0).
    Sub {
        neg: bool,
        frac: f64,
    },
    /// `+-MAX` of the type.
    Max {
        neg: bool,
    },
    Nan,
    Inf {
        neg: bool,
    },
}

impl Hard {
    fn get<T: Real>(self) -> T {
        let sign = |neg: bool, v: T| if neg { -v } else { v };
        match self {
            Self::Mag { neg, log10 } => sign(neg, T::of(10_f64.powf(log10))),
            Self::Zero { neg } => sign(neg, T::zero()),
            Self::Sub { neg, frac } => sign(neg, T::min_positive_value() * T::of(frac)),
            Self::Max { neg } => sign(neg, T::max_value()),
            Self::Nan => T::nan(),
            Self::Inf { neg } => sign(neg, T::infinity()),
        }
    }
}

/// Luminance: both signs, magnitudes log-uniform in 1e-30..1e30, hard values at a low
/// rate.
fn hard_lum() -> impl Strategy<Value = Hard> {
    prop_oneof![
        90 => (any::<bool>(), -30.0..=30.0_f64).prop_map(|(neg, log10)| Hard::Mag { neg, log10 }),
        3 => any::<bool>().prop_map(|neg| Hard::Zero { neg }),
        3 => (any::<bool>(), 0.0..1.0_f64).prop_map(|(neg, frac)| Hard::Sub { neg, frac }),
        1 => any::<bool>().prop_map(|neg| Hard::Max { neg }),
        1 => Just(Hard::Nan),
        2 => any::<bool>().prop_map(|neg| Hard::Inf { neg }),
    ]
}

/// Non-negative luminance (for the monitored series of a sequence that stays in range).
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..=hi.log10()).prop_map(|e| 10_f64.powf(e))
}

/// How a frame's luminance relates to the sequence: a static pixel repeats a value (so
/// variances decay to exactly 0), a noisy one jitters around it, others jump anywhere.
#[derive(Clone, Copy, Debug)]
enum Lum {
    Fresh(Hard),
    Base,
    Jitter(f64),
}

impl Lum {
    fn get<T: Real>(self, base: T) -> T {
        match self {
            Self::Fresh(h) => h.get(),
            Self::Base => base,
            Self::Jitter(u) => base * T::of(1.0 + u),
        }
    }
}

fn lum() -> impl Strategy<Value = Lum> {
    prop_oneof![
        3 => hard_lum().prop_map(Lum::Fresh),
        2 => Just(Lum::Base),
        2 => (-1e-3..1e-3_f64).prop_map(Lum::Jitter),
    ]
}

/// `gamma` in `[0, 1]` with exact ends and tiny values, plus NaN and negatives.
fn gamma() -> impl Strategy<Value = Hard> {
    prop_oneof![
        10 => (-8.0..=0.0_f64).prop_map(|log10| Hard::Mag { neg: false, log10 }),
        6 => Just(Hard::Mag { neg: false, log10: 0.0 }),
        2 => (-30.0..-8.0_f64).prop_map(|log10| Hard::Mag { neg: false, log10 }),
        1 => Just(Hard::Zero { neg: false }),
        1 => Just(Hard::Nan),
        1 => (-30.0..=0.0_f64).prop_map(|log10| Hard::Mag { neg: true, log10 }),
    ]
}

/// A weight: log-uniform in 1e-7..1, or exactly 1.
fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![9 => log_uniform(1e-7, 1.0), 1 => Just(1.0)]
}

/// `[min, max]` with `1 <= min <= max <= 1024`, the degenerate `[1, 1]` often.
fn budget() -> impl Strategy<Value = (u32, u32)> {
    prop_oneof![
        6 => (1_u32..=1024).prop_flat_map(|min| (Just(min), min..=1024)),
        2 => (1_u32..=16).prop_flat_map(|min| (Just(min), min..=64)),
        1 => Just((1, 1)),
        1 => Just((1024, 1024)),
    ]
}

/// Controller parameters in the supported range (as `f64`, rounded into the type).
#[derive(Clone, Copy, Debug)]
struct Params {
    eta: f64,
    target: f64,
    kappa: f64,
    min: u32,
    max: u32,
    eps_u: f64,
    /// Selects the policy; `Fixed` takes a count from the budget.
    policy: u8,
    fixed: f64,
    eta_cv: f64,
    a0: f64,
}

fn params() -> impl Strategy<Value = Params> {
    (
        weight(),
        log_uniform(1e-8, 1e2),
        prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0_f64],
        budget(),
        prop_oneof![Just(0.0), Just(0.01), 0.0..=1.0_f64],
        0_u8..4,
        0.0..=1.0_f64,
        weight(),
        prop_oneof![Just(0.0), Just(1.0), 0.0..4.0_f64],
    )
        .prop_map(
            |(eta, target, kappa, (min, max), eps_u, policy, fixed, eta_cv, a0)| Params {
                eta,
                target,
                kappa,
                min,
                max,
                eps_u,
                policy,
                fixed,
                eta_cv,
                a0,
            },
        )
}

impl Params {
    fn policy(&self) -> CountPolicy {
        match self.policy {
            0 => CountPolicy::Spvg,
            1 => CountPolicy::TwoPhase,
            2 => CountPolicy::UnrealClamp,
            _ => {
                let span = f64::from(self.max - self.min);
                CountPolicy::Fixed(self.min + (self.fixed * span).floor() as u32)
            }
        }
    }

    fn config<T: Real>(&self) -> SpvgConfig<T> {
        SpvgConfig::builder()
            .eta(T::of(self.eta))
            .target_variance(T::of(self.target))
            .kappa(T::of(self.kappa))
            .budget(self.min, self.max)
            .eps_u(T::of(self.eps_u))
            .policy(self.policy())
            .build()
            .unwrap_or_else(|e| panic!("in-range parameters rejected: {e} ({self:?})"))
    }

    fn ocv<T: Real>(&self) -> Ocv<T> {
        Ocv::new(
            T::of(self.eta_cv),
            T::of(spvg::cv::DEFAULT_EPS_A),
            T::of(self.a0),
        )
        .unwrap_or_else(|e| panic!("in-range OCV parameters rejected: {e} ({self:?})"))
    }
}

/// One frame of a generated sequence.
#[derive(Clone, Copy, Debug)]
struct FrameSpec {
    radiance: Lum,
    preintegrated: Lum,
    gamma: Hard,
    valid: bool,
}

fn frames() -> impl Strategy<Value = Vec<FrameSpec>> {
    let frame = (lum(), lum(), gamma(), prop::bool::weighted(0.85)).prop_map(
        |(radiance, preintegrated, gamma, valid)| FrameSpec {
            radiance,
            preintegrated,
            gamma,
            valid,
        },
    );
    prop::collection::vec(frame, FRAMES)
}

// ---------------------------------------------------------------------------------------
// References
// ---------------------------------------------------------------------------------------

/// `ceil(clamp(x, min, max))` with NaN at `min`: the rounding rule, monotone in `x`.
fn clamp_ceil(x: f64, min: u32, max: u32) -> u32 {
    if x >= f64::from(max) {
        max
    } else if x > f64::from(min) {
        x.ceil() as u32
    } else {
        min
    }
}

/// The set of counts SPEC 2.1/2.3/2.4 allows for a history, as `[lo, hi]`: the raw count
/// is evaluated in `f64` from the stored numbers (exact products for `f32` state; for
/// `f64` state the short-cut below avoids overflow), with an error band covering the
/// rounding of the implementation's operation order in `T`.
fn reference_counts<T: Real>(
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
    // For r >= 1 every policy's raw count is at least r (Unreal) or r nbar (SPVG:
    // r nbar + kappa (r - 1) nbar (k - 1) >= r nbar), so a huge r means the maximum.
    let lower = match c.policy() {
        CountPolicy::UnrealClamp => r,
        _ => r * nbar,
    };
    if r >= 1.0 && lower > 2.0 * f64::from(max) {
        return (max, max);
    }
    let (n_hat, tol) = match c.policy() {
        CountPolicy::UnrealClamp => (r, 4.0 * eps * r),
        CountPolicy::TwoPhase => (r * nbar, 6.0 * eps * r * nbar),
        _ => {
            let b = kappa * (2.0 / eta - 2.0);
            let n_hat = nbar * (r * (1.0 + b) - b);
            (
                n_hat,
                16.0 * eps * nbar * (r + 1.0) * (1.0 + kappa * 2.0 / eta),
            )
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
fn history_ok<T: Real>(h: &SpvgHistory<T>) -> bool {
    [h.mean, h.variance, h.mean_count]
        .iter()
        .all(|v| v.is_finite())
        && h.variance >= T::zero()
        && h.mean_count >= T::zero()
}

fn cv_ok<T: Real>(j: &CvHistory<T>) -> bool {
    [j.cov_fg, j.var_g, j.mean_f, j.mean_g]
        .iter()
        .all(|v| v.is_finite())
        && j.var_g >= T::zero()
}

/// What a model-specific check needs to know about one frame.
trait Checked<T: Real>: ControlModel<T> {
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
    /// SPEC 3 in `f64` from the stored `T` numbers: `(cov + eps) / (var + eps)`, clamped
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
            tol += 4.0 * T::EPS * upper.abs();
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
fn run_pixel<T: Real, M: Checked<T> + Debug>(
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
fn run_config<T: Real>(p: &Params, base: Hard, seq: &[FrameSpec]) -> Result<(), TestCaseError> {
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

/// SPEC 2.2/2.3 evaluated in `f64` from the stored `T` numbers, compared with the
/// stored result where no exact intermediate leaves `T`'s range (past it the
/// implementation saturates, which [`history_ok`] and the count reference cover). The
/// tolerance covers the rounding of the documented operations in `T`, including the
/// rounding of `1 - eta` and `eta (1 - eta)`, and subnormal spacing.
fn update_matches<T: Real>(
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
    let d = s.wide() - mean;
    let want_var = (1.0 - eta) * var + eta * (1.0 - eta) * d * d;
    let want_mean = (1.0 - eta) * mean + eta * s.wide();
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
            8.0 * eps * (want_var + var + eta * d * d),
        ),
        (
            "mean",
            got.mean.wide(),
            want_mean,
            4.0 * eps * ((1.0 - eta) * mean.abs() + eta * s.wide().abs() + mean.abs()),
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

proptest! {
    #![proptest_config(cases(256))]

    #[test]
    fn pixel_controller_f32_every_model(
        p in params(), base in (hard_lum(), hard_lum()), seq in frames(),
    ) {
        run_pixel::<f32, _>(&p, As, base, &seq)?;
        run_pixel::<f32, _>(&p, Ccv, base, &seq)?;
        run_pixel::<f32, _>(&p, p.ocv::<f32>(), base, &seq)?;
    }

    #[test]
    fn pixel_controller_f64_every_model(
        p in params(), base in (hard_lum(), hard_lum()), seq in frames(),
    ) {
        run_pixel::<f64, _>(&p, As, base, &seq)?;
        run_pixel::<f64, _>(&p, Ccv, base, &seq)?;
        run_pixel::<f64, _>(&p, p.ocv::<f64>(), base, &seq)?;
    }

    #[test]
    fn config_every_policy(p in params(), base in hard_lum(), seq in frames()) {
        for policy in 0..4 {
            let p = Params { policy, ..p };
            run_config::<f32>(&p, base, &seq)?;
            run_config::<f64>(&p, base, &seq)?;
        }
    }
}

// ---------------------------------------------------------------------------------------
// Parameter validation
// ---------------------------------------------------------------------------------------

/// Parameter values around and beyond the valid ranges: every `Hard` value, values just
/// outside `[0, 1]`, and the in-range distributions of the matrix.
fn any_param() -> impl Strategy<Value = Hard> {
    prop_oneof![
        4 => (any::<bool>(), -45.0..=45.0_f64).prop_map(|(neg, log10)| Hard::Mag { neg, log10 }),
        4 => (-8.0..=0.0_f64).prop_map(|log10| Hard::Mag { neg: false, log10 }),
        1 => (any::<bool>(), -340.0..=310.0_f64).prop_map(|(neg, log10)| Hard::Mag { neg, log10 }),
        1 => Just(Hard::Mag { neg: false, log10: 0.0 }),
        1 => any::<bool>().prop_map(|neg| Hard::Zero { neg }),
        1 => (any::<bool>(), 0.0..1.0_f64).prop_map(|(neg, frac)| Hard::Sub { neg, frac }),
        1 => any::<bool>().prop_map(|neg| Hard::Max { neg }),
        1 => Just(Hard::Nan),
        1 => any::<bool>().prop_map(|neg| Hard::Inf { neg }),
    ]
}

/// `v`, or its neighbour one ulp above 1 (`step = 1`) or below 0 (`step = -1`).
fn nudge<T: Real>(v: T, step: i8) -> T {
    match step {
        1 => T::one() + T::epsilon(),
        -1 => -T::min_positive_value(),
        _ => v,
    }
}

fn nudge_step() -> impl Strategy<Value = i8> {
    prop_oneof![4 => Just(0_i8), 1 => Just(1), 1 => Just(-1)]
}

fn counts() -> impl Strategy<Value = u32> {
    prop_oneof![3 => 0_u32..=1100, 1 => Just(0), 1 => Just(1), 1 => Just(u32::MAX)]
}

/// The validity rule of the configuration table, evaluated here in `T`.
fn config_valid<T: Real>(
    eta: T,
    target: T,
    kappa: T,
    (min, max): (u32, u32),
    eps_u: T,
    fixed: Option<u32>,
) -> bool {
    let two = T::one() + T::one();
    let unit = |v: T| v >= T::zero() && v <= T::one();
    eta.is_finite()
        && eta > T::zero()
        && eta <= T::one()
        && (two / eta).is_finite()
        && target.is_finite()
        && target > T::zero()
        && (T::one() / target).is_finite()
        && unit(kappa)
        && min >= 1
        && min <= max
        && unit(eps_u)
        && fixed.is_none_or(|n| min <= n && n <= max)
}

fn check_validation<T: Real>(
    vals: [Hard; 4],
    nudges: [i8; 3],
    budget: (u32, u32),
    fixed: Option<u32>,
    ocv: [Hard; 3],
) -> Result<(), TestCaseError> {
    let eta = nudge(vals[0].get::<T>(), nudges[0]);
    let target = vals[1].get::<T>();
    let kappa = nudge(vals[2].get::<T>(), nudges[1]);
    let eps_u = nudge(vals[3].get::<T>(), nudges[2]);
    let policy = fixed.map_or(CountPolicy::Spvg, CountPolicy::Fixed);
    let built = SpvgConfig::<T>::builder()
        .eta(eta)
        .target_variance(target)
        .kappa(kappa)
        .budget(budget.0, budget.1)
        .eps_u(eps_u)
        .policy(policy)
        .build();
    let want = config_valid(eta, target, kappa, budget, eps_u, fixed);
    prop_assert_eq!(
        built.is_ok(),
        want,
        "eta {} target {} kappa {} budget {:?} eps_u {} policy {:?}: {:?}",
        eta,
        target,
        kappa,
        budget,
        eps_u,
        policy,
        built
    );
    if let Ok(c) = built {
        prop_assert!(
            c.inv_target().is_finite() && c.k_minus_1().is_finite() && c.k_minus_1() >= T::zero(),
            "derived constants of {c:?}"
        );
    }
    let [eta_cv, eps_a, a0] = ocv.map(Hard::get::<T>);
    let finite_nonneg = |v: T| v.is_finite() && v >= T::zero();
    let want = eta_cv.is_finite() && eta_cv > T::zero() && eta_cv <= T::one();
    let got = Ocv::new(eta_cv, eps_a, a0);
    prop_assert_eq!(
        got.is_ok(),
        want && finite_nonneg(eps_a) && finite_nonneg(a0),
        "Ocv::new({}, {}, {}): {:?}",
        eta_cv,
        eps_a,
        a0,
        got
    );
    prop_assert_eq!(
        Ocv::with_weight(eta_cv).is_ok(),
        want,
        "with_weight({})",
        eta_cv
    );
    Ok(())
}

proptest! {
    #![proptest_config(cases(512))]

    /// Construction returns `Err` (never panics) exactly outside the documented ranges.
    #[test]
    fn validation_matches_the_documented_ranges(
        vals in [any_param(), any_param(), any_param(), any_param()],
        nudges in [nudge_step(), nudge_step(), nudge_step()],
        budget in (counts(), counts()),
        fixed in prop::option::weighted(0.3, counts()),
        ocv in [any_param(), any_param(), any_param()],
    ) {
        check_validation::<f32>(vals, nudges, budget, fixed, ocv)?;
        check_validation::<f64>(vals, nudges, budget, fixed, ocv)?;
    }

    /// Everything in the supported range is accepted, in both types.
    #[test]
    fn supported_range_is_accepted(p in params()) {
        let _ = (p.config::<f32>(), p.config::<f64>(), p.ocv::<f32>(), p.ocv::<f64>());
    }
}

// ---------------------------------------------------------------------------------------
// Measured degradations (the thresholds stated in the controller's "Supported numeric
// range" documentation), each against a bound derived from IEEE rounding
// ---------------------------------------------------------------------------------------

/// Deviations beyond `sqrt(MAX)` square past the range: `d^2` saturates, so the stored
/// variance stops growing at `eta (1 - eta) MAX` (from a zero variance), and the count is
/// the maximum.
#[test]
fn variance_saturates_past_sqrt_max() {
    let c = SpvgConfig::<f32>::published();
    let root = f64::from(f32::MAX).sqrt();
    let w = c.weight();
    for d in [1e18_f32, 1.8e19, 1.85e19, 1e20, 1e30, f32::MAX] {
        let mut h = SpvgHistory {
            mean: 0.0,
            variance: 0.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, d, 8, true), "d {d} refused");
        let exact = f64::from(w.eta_retain()) * f64::from(d) * f64::from(d);
        if f64::from(d) < root {
            let err = (f64::from(h.variance) - exact).abs();
            assert!(
                err <= 1e-6 * exact,
                "{} != {exact} (tol {})",
                h.variance,
                1e-6 * exact
            );
        } else {
            assert_eq!(
                h.variance,
                w.eta_retain() * f32::MAX,
                "d {d}: saturated d^2"
            );
        }
        assert_eq!(c.estimate(&h, 1.0), 64, "d {d}: count");
    }
}

/// `1 - eta` rounds to 1 in `f32` for `eta <= 2^-25` (half an ulp below 1, ties to even):
/// such a weight cannot decay anything. Validation accepts it (it is a valid weight in
/// exact arithmetic); the documentation states the limit.
#[test]
fn f32_retain_is_one_below_2_pow_minus_25() {
    for (eta, frozen) in [
        (2f32.powi(-26), true),
        (2f32.powi(-25), true),
        (2f32.powi(-24), false),
    ] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .build()
            .expect("valid");
        let mut h = SpvgHistory {
            mean: 1.0,
            variance: 1.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, 1.0, 8, true), "refused");
        assert_eq!(
            h.variance == 1.0,
            frozen,
            "eta {eta}: variance {}",
            h.variance
        );
    }
}

/// At `eta = 1e-7` in `f32` a mean at 1 moves only for large steps. From IEEE rounding:
/// `1 - eta` rounds to `1 - 2^-23`, and `(1 - 2^-23) + eta x` leaves 1 upwards only
/// past `1 + 2^-24` (`x > (2^-23 + 2^-24) / eta`, about +79%) and downwards only below
/// `1 - 2^-25` (`x < (2^-23 - 2^-25) / eta`, about -11%).
#[test]
fn f32_tiny_weight_moves_a_mean_at_one_only_for_large_steps() {
    let eta = 1e-7_f32;
    let c = SpvgConfig::<f32>::builder()
        .eta(eta)
        .build()
        .expect("valid");
    let up = (2f64.powi(-23) + 2f64.powi(-24)) / f64::from(eta);
    let down = (2f64.powi(-23) - 2f64.powi(-25)) / f64::from(eta);
    for (x, moves) in [
        (up * 0.99, false),
        (up * 1.01, true),
        (down * 1.01, false),
        (down * 0.99, true),
    ] {
        let mut h = SpvgHistory {
            mean: 1.0_f32,
            variance: 0.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, x as f32, 8, true), "refused");
        assert_eq!(
            h.mean != 1.0,
            moves,
            "x {x} (up {up}, down {down}): mean {}",
            h.mean
        );
    }
}

/// Tiny deviations: `eta (1 - eta) d^2` falls below half the smallest `f32` subnormal
/// (`2^-150`) for `d < sqrt(2^-150 / (eta (1 - eta)))`, about 6.6e-23 at `eta = 0.2`, and
/// the variance reads 0 (up to the rounding of `d^2` among subnormals).
#[test]
fn f32_tiny_deviations_underflow() {
    let c = SpvgConfig::<f32>::published();
    let edge = (2f64.powi(-150) / f64::from(c.weight().eta_retain())).sqrt();
    for (d, zero) in [(edge * 0.7, true), (edge * 1.5, false)] {
        let mut h = SpvgHistory::default();
        assert!(c.update(&mut h, d as f32, 8, true), "refused");
        assert_eq!(
            h.variance == 0.0,
            zero,
            "d {d} (edge {edge}): var {}",
            h.variance
        );
        assert_eq!(c.estimate(&h, 1.0), 8, "count at a vanishing variance");
    }
}

/// A static pixel in `f32` from a cold history: the mean moves only while
/// `|eta (S - mean)|` exceeds about half an ulp of the mean, so it stalls short of `S`
/// by `ulp / (2 eta)` up to rounding (bounded here by `[ulp/(4 eta), 2 ulp/eta]`;
/// measured 0.87 to 2.2 times `ulp / (2 eta)`), and the variance settles at the square of
/// that stall (within 10%) instead of 0. Where that floor
/// exceeds `sigma0^2` the static pixel takes the maximum count for ever.
#[test]
fn f32_small_weights_stall_the_mean() {
    for (eta, s) in [(1e-4_f32, 1.0_f32), (1e-4, 1.9), (1e-4, 100.0), (1e-5, 1.9)] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .target_variance(1e-6)
            .budget(1, 1024)
            .build()
            .expect("valid");
        let mut h = SpvgHistory::default();
        for _ in 0..(20.0 / eta) as usize {
            c.update(&mut h, s, 16, true);
        }
        // The ulp just below `s`, where the stalled mean lies.
        let ulp = f64::from(s) - f64::from(s.next_down());
        let stall = f64::from(s) - f64::from(h.mean);
        let (lo, hi) = (ulp / (4.0 * f64::from(eta)), 2.0 * ulp / f64::from(eta));
        assert!(
            lo <= stall && stall <= hi,
            "eta {eta}, S {s}: stall {stall} not in [{lo}, {hi}]"
        );
        let var = f64::from(h.variance);
        assert!(
            (var - stall * stall).abs() <= 0.1 * stall * stall,
            "eta {eta}, S {s}: variance {var} vs stall^2 {}",
            stall * stall
        );
        // Predicted from the stall's lower bound alone: a floor this far above the
        // target gives r >= 4 with nbar = 16, i.e. the maximum count.
        if 0.9 * lo * lo > 4.0 * 1e-6 {
            assert_eq!(c.estimate(&h, 1.0), 1024, "eta {eta}, S {s}: var {var}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// Regressions: one per defect the matrix found
// ---------------------------------------------------------------------------------------

/// Defect 1: with `kappa = 0` or `eta = 1`, a saturated variance made `variance *
/// inv_target` overflow and `0 * inf` turned the raw count into NaN, so the pixel with
/// the largest variance took `min_samples`. SPEC 2.1's `n_hat` is `+inf`-large there
/// (`E = r nbar` alone exceeds any budget), so the count is `max_samples`.
#[test]
fn regression_saturated_variance_takes_the_maximum() {
    for (eta, kappa) in [(0.2_f32, 0.0_f32), (1.0, 0.0), (1.0, 0.5), (7.9e-6, 0.0)] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .target_variance(1e-4)
            .kappa(kappa)
            .budget(8, 64)
            .build()
            .expect("valid");
        let h = SpvgHistory {
            mean: 0.0,
            variance: f32::MAX,
            mean_count: 8.0,
        };
        let n = c.estimate(&h, 1.0);
        assert_eq!(
            n,
            64,
            "eta {eta}, kappa {kappa}: raw {}",
            c.raw_estimate(&h)
        );
    }
    // The same through the update: f32 deviations of 1e20 square past f32::MAX.
    let c = SpvgConfig::<f32>::builder()
        .kappa(0.0)
        .build()
        .expect("valid");
    let mut h = SpvgHistory::default();
    let mut n = c.estimate(&h, 1.0);
    for t in 0..8 {
        let s = if t % 2 == 0 { 1e20 } else { -1e20 };
        assert!(c.update(&mut h, s, n, true), "frame {t} refused");
        n = c.estimate(&h, 1.0);
    }
    assert_eq!(n, 64, "history {h:?}");
}

/// Defect 2: `PixelController::update` dropped frames whose inputs were all finite when
/// the residual `fbar - alpha G` (or `fbar` itself) overflowed: with `G < 0` OCV's
/// `alpha` has no upper bound, the SPVG history refused the infinite residual, the CV
/// state was therefore not updated either, and the pixel froze for as long as the
/// lighting stayed there. Finite input now saturates (the crate's overflow policy), as
/// an `f64` evaluation of the same residual, clamped to the `f32` range, predicts.
#[test]
fn regression_overflowing_residual_saturates_instead_of_freezing() {
    let config = SpvgConfig::<f32>::builder()
        .eta(1.0)
        .budget(1, 2)
        .build()
        .expect("valid");
    let ocv = Ocv::<f32>::new(1.0, 1e-6, 0.0).expect("valid");
    let pixel = PixelController::new(config, ocv);
    // The state the matrix reached (f32, eta = eta_cv = 1, budget [1, 2]).
    let mut j = CvHistory {
        cov_fg: 3.498_657_8e18,
        var_g: 1.923_165_3e-5,
        mean_f: 3.638_419_2e23,
        mean_g: 0.999_990_34,
    };
    let mut h = SpvgHistory {
        mean: 2.0,
        variance: 0.0,
        mean_count: 1.0,
    };
    let frame = PixelFrame {
        radiance: 1.0,
        preintegrated: -2.829_276_8e23,
        gamma: 1.0,
    };
    let alpha = pixel.model().coefficient(&j, 1.0, frame.preintegrated);
    let exact = 1.0 - f64::from(alpha) * f64::from(frame.preintegrated);
    let want = exact.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32;
    let u = pixel.update(&mut h, &mut j, frame, 1, true);
    assert!(u.accepted, "finite frame refused: {u:?}");
    assert_eq!(
        u.monitored, want,
        "residual {} vs exact {exact}",
        u.monitored
    );
    assert!(history_ok(&h) && cv_ok(&j), "state {h:?} {j:?}");

    // `fbar` itself overflowing (|radiance| + |(1 - gamma) B| beyond f32::MAX).
    let pixel = PixelController::new(config, As);
    let frame = PixelFrame {
        radiance: 3e38_f32,
        preintegrated: -3e38,
        gamma: 0.5,
    };
    let exact = 3e38 + 0.5 * 3e38_f64;
    assert!(exact > f64::from(f32::MAX), "the case must overflow f32");
    let mut h = SpvgHistory::default();
    let u = pixel.update(&mut h, &mut (), frame, 1, true);
    assert!(u.accepted, "finite frame refused: {u:?}");
    assert_eq!(u.monitored, f32::MAX, "saturated fbar");
    // Non-finite input is still refused.
    let frame = PixelFrame {
        radiance: f32::INFINITY,
        ..frame
    };
    assert!(
        !pixel.update(&mut h, &mut (), frame, 1, true).accepted,
        "inf accepted"
    );
}

/// Defect 3: an OCV ratio `(cov + eps_a) / (var + eps_a)` that overflowed `T` fell back
/// to 1 (CCV) instead of keeping its sign, so the coefficient jumped from the bound it
/// pointed to (the upper bound of `D` for a huge positive covariance, 0 for a huge
/// negative one) to 1. The reference evaluates the ratio in `f64` (where it is finite)
/// and clamps it to `D`.
#[test]
fn regression_overflowing_ratio_keeps_its_sign() {
    let ocv = Ocv::<f32>::with_weight(0.1).expect("valid");
    let (fbar, g) = (1.0_f32, 1e-30_f32);
    let upper = f64::from(ocv.a0()) + f64::from(fbar) / f64::from(g);
    for cov in [1e33_f32, -1e33] {
        let j = CvHistory {
            cov_fg: cov,
            var_g: 1e-7,
            mean_f: 0.0,
            mean_g: 0.0,
        };
        let eps = f64::from(ocv.eps_a());
        let ratio = (f64::from(cov) + eps) / (1e-7_f64 + eps);
        assert!(
            ratio.abs() > f64::from(f32::MAX),
            "the case must overflow f32"
        );
        let want = ratio.clamp(0.0, upper);
        let got = f64::from(ocv.coefficient(&j, fbar, g));
        assert!(
            (got - want).abs() <= 1e-6 * want,
            "cov {cov}: {got} != {want} (tol {})",
            1e-6 * want
        );
    }
}
