//! Parameter validation over and beyond the documented ranges.

use proptest::prelude::*;
use spvg::SpvgConfig;
use spvg::controller::CountPolicy;
use spvg::cv::Ocv;

use crate::generators::{Hard, params};
use crate::{Real, cases};

/// Parameter values around and beyond the valid ranges: every `Hard` value, values just
/// outside `[0, 1]`, and the in-range distributions of the matrix.
pub(crate) fn any_param() -> impl Strategy<Value = Hard> {
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
pub(crate) fn nudge<T: Real>(v: T, step: i8) -> T {
    match step {
        1 => T::one() + T::epsilon(),
        -1 => -T::min_positive_value(),
        _ => v,
    }
}

pub(crate) fn nudge_step() -> impl Strategy<Value = i8> {
    prop_oneof![4 => Just(0_i8), 1 => Just(1), 1 => Just(-1)]
}

pub(crate) fn counts() -> impl Strategy<Value = u32> {
    prop_oneof![
        3 => 0_u32..=1100,
        1 => Just(0),
        1 => Just(1),
        // Either side of the table's budget ceiling (`MAX_BUDGET`, 4096).
        1 => Just(4096),
        1 => Just(4097),
        1 => Just(u32::MAX)
    ]
}

/// The validity rule of the configuration table, evaluated here in `T`.
pub(crate) fn config_valid<T: Real>(
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
        // The table's `max_samples` row: at most `MAX_BUDGET`, written here as the
        // documented number rather than the constant the code under test uses.
        && max <= 4096
        && unit(eps_u)
        && fixed.is_none_or(|n| min <= n && n <= max)
}

pub(crate) fn check_validation<T: Real>(
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
