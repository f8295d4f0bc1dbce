//! Hard-case value generators for the extremes matrix: luminances log-uniform in
//! magnitude with special values at a low rate, parameters over the supported range, and
//! frame sequences mixing static, jittering and jumping pixels.

use proptest::prelude::*;
use spvg::SpvgConfig;
use spvg::controller::CountPolicy;
use spvg::cv::Ocv;

use crate::{FRAMES, Real};

/// A value described independently of the float type, so one generated case runs in
/// `f32` and `f64` alike; [`Hard::get`] rounds it into the type.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Hard {
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
    pub(crate) fn get<T: Real>(self) -> T {
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
pub(crate) fn hard_lum() -> impl Strategy<Value = Hard> {
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
pub(crate) fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..=hi.log10()).prop_map(|e| 10_f64.powf(e))
}

/// How a frame's luminance relates to the sequence: a static pixel repeats a value (so
/// variances decay to exactly 0), a noisy one jitters around it, others jump anywhere.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Lum {
    Fresh(Hard),
    Base,
    Jitter(f64),
}

impl Lum {
    pub(crate) fn get<T: Real>(self, base: T) -> T {
        match self {
            Self::Fresh(h) => h.get(),
            Self::Base => base,
            Self::Jitter(u) => base * T::of(1.0 + u),
        }
    }
}

pub(crate) fn lum() -> impl Strategy<Value = Lum> {
    prop_oneof![
        3 => hard_lum().prop_map(Lum::Fresh),
        2 => Just(Lum::Base),
        2 => (-1e-3..1e-3_f64).prop_map(Lum::Jitter),
    ]
}

/// `gamma` in `[0, 1]` with exact ends and tiny values, plus NaN and negatives.
pub(crate) fn gamma() -> impl Strategy<Value = Hard> {
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
pub(crate) fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![9 => log_uniform(1e-7, 1.0), 1 => Just(1.0)]
}

/// `[min, max]` with `1 <= min <= max <= 1024`, the degenerate `[1, 1]` often.
pub(crate) fn budget() -> impl Strategy<Value = (u32, u32)> {
    prop_oneof![
        6 => (1_u32..=1024).prop_flat_map(|min| (Just(min), min..=1024)),
        2 => (1_u32..=16).prop_flat_map(|min| (Just(min), min..=64)),
        1 => Just((1, 1)),
        1 => Just((1024, 1024)),
    ]
}

/// Controller parameters in the supported range (as `f64`, rounded into the type).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    pub(crate) eta: f64,
    pub(crate) target: f64,
    pub(crate) kappa: f64,
    pub(crate) min: u32,
    pub(crate) max: u32,
    pub(crate) eps_u: f64,
    /// Selects the policy; `Fixed` takes a count from the budget.
    pub(crate) policy: u8,
    pub(crate) fixed: f64,
    pub(crate) eta_cv: f64,
    pub(crate) a0: f64,
    /// The damped correction's cap `c` (docs/algorithms.md §8.1), off in two cases of three.
    pub(crate) max_change: Option<f64>,
    /// The firefly clamp's `k` (docs/algorithms.md §8.3), off in two cases of three.
    pub(crate) firefly_clamp: Option<f64>,
}

pub(crate) fn params() -> impl Strategy<Value = Params> {
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
        prop_oneof![2 => Just(None), 1 => log_uniform(1e-3, 10.0).prop_map(Some)],
        prop_oneof![2 => Just(None), 1 => log_uniform(0.1, 100.0).prop_map(Some)],
    )
        .prop_map(
            |(
                eta,
                target,
                kappa,
                (min, max),
                eps_u,
                policy,
                fixed,
                eta_cv,
                a0,
                max_change,
                firefly_clamp,
            )| {
                Params {
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
                    max_change,
                    firefly_clamp,
                }
            },
        )
}

impl Params {
    pub(crate) fn policy(&self) -> CountPolicy {
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

    pub(crate) fn config<T: Real>(&self) -> SpvgConfig<T> {
        SpvgConfig::builder()
            .eta(T::of(self.eta))
            .target_variance(T::of(self.target))
            .kappa(T::of(self.kappa))
            .budget(self.min, self.max)
            .eps_u(T::of(self.eps_u))
            .policy(self.policy())
            .max_change(self.max_change.map(T::of))
            .firefly_clamp(self.firefly_clamp.map(T::of))
            .build()
            .unwrap_or_else(|e| panic!("in-range parameters rejected: {e} ({self:?})"))
    }

    pub(crate) fn ocv<T: Real>(&self) -> Ocv<T> {
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
pub(crate) struct FrameSpec {
    pub(crate) radiance: Lum,
    pub(crate) preintegrated: Lum,
    pub(crate) gamma: Hard,
    pub(crate) valid: bool,
}

pub(crate) fn frames() -> impl Strategy<Value = Vec<FrameSpec>> {
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
