//! Invariants of the SPVG controller (`spvg::controller`): configuration validation and a
//! multi-frame sequence of estimates and updates.

use spvg::controller::{CountPolicy, MAX_BUDGET, SpvgConfig, SpvgHistory};

use crate::input::{Input, Real, same};

/// Most frames one input drives (keeps each execution short).
const MAX_FRAMES: usize = 64;

/// Decodes a configuration and up to 64 frames from `data` and runs them in `f64` and
/// `f32`, asserting:
/// - the builder returns `Ok` exactly for parameters in their documented ranges (checked
///   against an independent predicate), never panics, and its errors display;
/// - per frame, the count is 0 exactly when the zero-sample rule applies
///   (`gamma >= eps_u && gamma > 0` fails), is `n` under `Fixed(n)`, `min_samples` for an
///   invalid history, and otherwise within `[min_samples, max_samples]` and equal to an
///   `f64` evaluation of docs/algorithms.md §2.1 up to the rounding error bound of its terms;
/// - `update` absorbs a frame exactly when the count is non-zero and the sample finite; a
///   refused frame leaves a valid history unchanged and zeroes an invalid one; a
///   disoccluded frame seeds `(S, sigma0^2, n)`;
/// - the history stays finite, with a non-negative variance and a mean count no larger
///   than the largest count used, even after a corrupt (fuzzed) history was injected.
///
/// Layout: a selector byte (bit k set: parameter k is drawn from all floats instead of
/// its valid range), 8 bytes each for `eta`, `sigma0^2`, `kappa`, `eps_u`, the budget and
/// the policy; then per frame a flag byte (bit 0 history valid, bit 1 the renderer
/// overrides the count with the next byte, bit 2 inject a corrupt history, bit 3 `gamma`
/// from all floats), 8 bytes of sample, 8 of `gamma`, and the optional extras.
pub fn check_controller(data: &[u8]) {
    run::<f64>(data);
    run::<f32>(data);
}

pub(crate) fn config<T: Real>(
    input: &mut Input<'_>,
) -> (spvg::controller::SpvgConfigBuilder<T>, bool) {
    let wild = input.byte();
    let pick = |input: &mut Input<'_>, k: u8, valid: fn(&mut Input<'_>) -> T| {
        if wild & (1 << k) != 0 {
            input.hard::<T>()
        } else {
            valid(input)
        }
    };
    let eta = pick(input, 0, |i| i.weight::<T>());
    let target = pick(input, 1, |i| {
        let v = i.finite::<T>().abs();
        if v > T::zero() { v } else { T::from_f64(1e-4) }
    });
    let kappa = pick(input, 2, |i| i.unit::<T>(T::from_f64(0.2)));
    let eps_u = pick(input, 3, |i| i.unit::<T>(T::from_f64(0.01)));
    let budget = input.bits();
    let (min, max) = if wild & (1 << 4) == 0 {
        let min = 1 + (budget & 63) as u32;
        (min, min + ((budget >> 8) & 127) as u32)
    } else if budget & (1 << 63) == 0 {
        ((budget & 0xff) as u32, ((budget >> 8) & 0xff) as u32)
    } else {
        // Raw 32-bit halves: budgets up to u32::MAX (beyond f16 and f32 integer range).
        (budget as u32, (budget >> 32) as u32)
    };
    let p = input.bits();
    let policy = match p & 3 {
        0 => CountPolicy::Spvg,
        1 => CountPolicy::TwoPhase,
        2 => CountPolicy::UnrealClamp,
        _ if wild & (1 << 5) != 0 => CountPolicy::Fixed((p >> 32) as u32),
        _ => CountPolicy::Fixed(min + ((p >> 8) % (u64::from(max.saturating_sub(min)) + 1)) as u32),
    };
    // The documented ranges, written independently of the builder.
    let two = T::one() + T::one();
    let in_unit = |v: T| v >= T::zero() && v <= T::one();
    let valid = eta.is_finite()
        && eta > T::zero()
        && eta <= T::one()
        && (two / eta - two).is_finite()
        && target.is_finite()
        && target > T::zero()
        && (T::one() / target).is_finite()
        && in_unit(kappa)
        && in_unit(eps_u)
        && min >= 1
        && (1..=MAX_BUDGET).contains(&max)
        && min <= max
        && match policy {
            CountPolicy::Fixed(n) => (min..=max).contains(&n),
            _ => true,
        };
    let builder = SpvgConfig::<T>::builder()
        .eta(eta)
        .target_variance(target)
        .kappa(kappa)
        .eps_u(eps_u)
        .budget(min, max)
        .policy(policy);
    (builder, valid)
}

fn run<T: Real>(data: &[u8]) {
    let mut input = Input::new(data);
    let (builder, valid) = config::<T>(&mut input);
    let c = match builder.build() {
        Ok(c) => {
            assert!(
                valid,
                "{}: accepted invalid parameters {builder:?}",
                T::NAME
            );
            c
        }
        Err(e) => {
            assert!(
                !valid,
                "{}: rejected valid parameters {builder:?}: {e}",
                T::NAME
            );
            assert!(!format!("{e}").is_empty(), "empty error message");
            return;
        }
    };
    let mut h = SpvgHistory::<T>::default();
    // Whether `h` may hold a corrupt (injected) value that `update` has not yet replaced.
    let mut corrupt = false;
    // The largest count the mean count may hold: counts used, and an injected corrupt
    // (finite) mean count, which the EMA legitimately keeps decaying from.
    let mut largest_count = 0.0_f64;
    for frame in 0..MAX_FRAMES {
        if input.is_empty() {
            break;
        }
        let flags = input.byte();
        let history_valid = flags & 1 != 0;
        let sample = input.hard::<T>();
        let gamma = if flags & 8 != 0 {
            input.hard::<T>()
        } else {
            input.unit::<T>(c.eps_u())
        };
        let overridden = (flags & 2 != 0).then(|| u32::from(input.byte()));
        if flags & 4 != 0 {
            h = SpvgHistory {
                mean: input.hard(),
                variance: input.hard(),
                mean_count: input.hard(),
            };
            corrupt = true;
            if h.mean_count.is_finite() {
                largest_count = largest_count.max(h.mean_count.wide());
            }
        }

        let n = c.estimate_with_validity(&h, gamma, history_valid);
        check_count(&c, &h, gamma, history_valid && !corrupt, history_valid, n);

        let used = overridden.unwrap_or(n);
        let before = h;
        let accepted = c.update(&mut h, sample, used, history_valid);
        let expect = used != 0 && sample.is_finite();
        assert_eq!(
            accepted,
            expect,
            "{}: update({sample:?}, {used}) accepted {accepted}",
            T::NAME
        );
        let fields = |h: &SpvgHistory<T>| [h.mean, h.variance, h.mean_count];
        match (accepted, history_valid) {
            (false, true) => assert!(
                same(fields(&h), fields(&before)),
                "{}: refused frame changed {before:?} to {h:?}",
                T::NAME
            ),
            (false, false) => {
                assert_eq!(
                    h,
                    SpvgHistory::default(),
                    "invalid refused frame not zeroed"
                );
                corrupt = false;
            }
            (true, false) => {
                let n_t = T::from(used).map_or(T::max_value(), |v| v.min(T::max_value()));
                assert_eq!(
                    h,
                    SpvgHistory {
                        mean: sample,
                        variance: c.target_variance(),
                        mean_count: n_t
                    },
                    "{}: disocclusion seed",
                    T::NAME
                );
                corrupt = false;
            }
            (true, true) => corrupt = false,
        }
        if accepted {
            largest_count = largest_count.max(f64::from(used));
            if c.policy() == CountPolicy::TwoPhase {
                assert_eq!(h.mean_count, T::from(used).unwrap_or(T::nan()), "n_prev");
            }
        }
        if !corrupt {
            check_history(&h);
            // An EMA of counts in [0, largest] stays there, up to rounding: `fl(1 - eta) +
            // eta` may exceed 1 by half an ulp, and each blend rounds, so the excess grows
            // by a few eps per frame when little decays (tiny eta).
            let frames = f64::from(u32::try_from(frame).unwrap_or(u32::MAX)) + 1.0;
            let bound = largest_count * (1.0 + 4.0 * frames * T::epsilon().wide());
            assert!(
                h.mean_count.wide() <= bound,
                "{}: mean count {:?} above the largest count {largest_count}",
                T::NAME,
                h.mean_count
            );
        }
    }
}

/// The history invariants after any frame: finite fields, a non-negative variance and a
/// non-negative mean count.
pub(crate) fn check_history<T: Real>(h: &SpvgHistory<T>) {
    assert!(
        h.mean.is_finite() && h.variance.is_finite() && h.mean_count.is_finite(),
        "{}: non-finite history {h:?}",
        T::NAME
    );
    assert!(
        h.variance >= T::zero(),
        "{}: negative variance {h:?}",
        T::NAME
    );
    assert!(
        h.mean_count >= T::zero(),
        "{}: negative count {h:?}",
        T::NAME
    );
}

/// The count rule: zero-sample rule first, then `Fixed`, disocclusion, and the clamp of
/// the docs/algorithms.md §2.1 estimate (checked against `f64` where the history is trusted).
fn check_count<T: Real>(
    c: &SpvgConfig<T>,
    h: &SpvgHistory<T>,
    gamma: T,
    trusted: bool,
    history_valid: bool,
    n: u32,
) {
    let distant = gamma >= c.eps_u() && gamma > T::zero();
    if !distant {
        assert_eq!(
            n,
            0,
            "{}: gamma {gamma:?} < eps_u {:?} sampled",
            T::NAME,
            c.eps_u()
        );
        return;
    }
    if let CountPolicy::Fixed(k) = c.policy() {
        assert_eq!(n, k, "{}: Fixed({k}) gave {n}", T::NAME);
        return;
    }
    assert!(
        (c.min_samples()..=c.max_samples()).contains(&n),
        "{}: count {n} outside [{}, {}] for {h:?}",
        T::NAME,
        c.min_samples(),
        c.max_samples()
    );
    if !history_valid {
        assert_eq!(n, c.min_samples(), "{}: disocclusion count", T::NAME);
        return;
    }
    if trusted && let Some((lo, hi)) = reference_count(c, h) {
        assert!(
            (lo..=hi).contains(&n),
            "{}: count {n} outside the f64 reference [{lo}, {hi}] for {h:?}, {c:?}",
            T::NAME
        );
    }
}

/// docs/algorithms.md §2.1 in `f64` from the stored history, with an interval covering the rounding
/// error of the evaluation in `T` (a few `eps_T` per term). `None` where a term nears
/// `T`'s overflow (there the library saturates, which this reference does not model).
fn reference_count<T: Real>(c: &SpvgConfig<T>, h: &SpvgHistory<T>) -> Option<(u32, u32)> {
    let var = h.variance.wide();
    let nbar = h.mean_count.wide();
    // `var / sigma0^2` with the target as stored in T (one rounded division in T).
    let r = var / c.target_variance().wide();
    // `2 (1 - eta) / eta`, not `2 / eta - 2`: the latter cancels near eta = 1 even in f64.
    let k1 = 2.0 * (1.0 - c.eta().wide()) / c.eta().wide();
    let kappa = c.kappa().wide();
    let e = r * nbar;
    let delta = (r - 1.0) * nbar * k1;
    let (n_hat, scale) = match c.policy() {
        CountPolicy::Spvg => (
            kappa * delta + e,
            e.abs() + kappa * (r.abs() + 1.0) * nbar.abs() * k1,
        ),
        CountPolicy::TwoPhase => (e, e.abs()),
        CountPolicy::UnrealClamp => (r, r.abs()),
        CountPolicy::Fixed(_) => return None,
    };
    let limit = T::max_value().wide() / 16.0;
    // The intermediates too: the library evaluates `nbar (kappa (r - 1) k1 + r)`, and
    // `(r - 1) k1` or that bracket can overflow in T (and saturate there) where `nbar`
    // is tiny.
    let spvg_intermediate = match c.policy() {
        CountPolicy::Spvg => ((r - 1.0) * k1)
            .abs()
            .max((kappa * (r - 1.0) * k1 + r).abs()),
        _ => 0.0,
    };
    if !(scale.is_finite()
        && scale < limit
        && n_hat.abs() < limit
        && e.abs() < limit
        && spvg_intermediate < limit)
    {
        return None;
    }
    // Each operation rounds once in T; 8 eps_T of every term's magnitude bounds the sum.
    // f64's own rounding is far below that.
    // Underflow in T (a subnormal `r`) adds an absolute error of one subnormal step,
    // amplified by the count terms.
    let step = T::min_positive_value().wide() * T::epsilon().wide();
    let tol = 8.0 * T::epsilon().wide() * (scale + n_hat.abs())
        + 4.0 * f64::EPSILON * scale
        + 4.0 * step * (1.0 + nbar.abs() * (1.0 + kappa * k1));
    let round = |x: f64| -> u32 {
        let (lo, hi) = (f64::from(c.min_samples()), f64::from(c.max_samples()));
        x.clamp(lo, hi).ceil() as u32
    };
    Some((round(n_hat - tol), round(n_hat + tol)))
}
