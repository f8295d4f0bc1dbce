//! Tests of the SPVG controller (docs/algorithms.md §2) against references written here: docs/algorithms.md §2.1 and
//! 2.2 evaluated literally in f64, the documented f32 operation order, and the docs/algorithms.md §7
//! circle scenario with its closed-form per-sample variance.

mod common;

use common::circle;
use common::splitmix::SplitMix64;
use proptest::prelude::*;
use spvg::controller::CountPolicy;
use spvg::{Error, SpvgConfig, SpvgHistory};

/// docs/algorithms.md §2.1 literally, in f64: `n_hat = kappa Delta + E`.
fn spec_n_hat(eta: f64, target: f64, kappa: f64, var: f64, nbar: f64) -> f64 {
    let k = 2.0 / eta - 1.0;
    let e = var / target * nbar;
    let delta = (var - target) / target * nbar * (k - 1.0);
    kappa * delta + e
}

/// `ceil(clamp(n_hat, min, max))`.
fn spec_round(n_hat: f64, min: u32, max: u32) -> u32 {
    n_hat.clamp(f64::from(min), f64::from(max)).ceil() as u32
}

/// Whether a reference `n_hat` is so close to an integer that the implementation's
/// different (but equally valid) rounding of the intermediate steps may round it to the
/// neighbouring count.
fn near_integer(n_hat: f64, rel: f64) -> bool {
    (n_hat - n_hat.round()).abs() <= rel * n_hat.abs().max(1.0)
}

fn config(eta: f64, target: f64, kappa: f64, min: u32, max: u32) -> SpvgConfig<f64> {
    SpvgConfig::builder()
        .eta(eta)
        .target_variance(target)
        .kappa(kappa)
        .budget(min, max)
        .build()
        .expect("valid test configuration")
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1e3..1e3_f64,
        2 => 0.0..1e-2_f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MAX),
        1 => Just(-0.0),
        1 => Just(f64::MIN_POSITIVE),
    ]
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -1e3..1e3_f32,
        2 => 0.0..1e-2_f32,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(f32::MAX),
        1 => Just(f32::MIN_POSITIVE),
    ]
}

fn any_policy() -> impl Strategy<Value = CountPolicy> {
    prop_oneof![
        Just(CountPolicy::Spvg),
        Just(CountPolicy::TwoPhase),
        Just(CountPolicy::UnrealClamp),
        (0_u32..8).prop_map(CountPolicy::Fixed),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn estimate_matches_spec_formula(
        eta in 0.01..=1.0_f64,
        target in 1e-5..1e-1_f64,
        kappa in 0.0..=1.0_f64,
        r in 0.0..20.0_f64,
        nbar in 0.0..80.0_f64,
        min in 1_u32..16,
        extra in 0_u32..100,
    ) {
        let max = min + extra;
        let c = config(eta, target, kappa, min, max);
        let var = r * target;
        let h = SpvgHistory { mean: 0.3, variance: var, mean_count: nbar };
        let n_hat = spec_n_hat(eta, target, kappa, var, nbar);
        prop_assume!(!near_integer(n_hat, 1e-9));
        let want = spec_round(n_hat, min, max);
        let got = c.estimate(&h, 1.0);
        prop_assert_eq!(got, want, "n_hat {} (var {}, nbar {})", n_hat, var, nbar);
    }

    #[test]
    fn f32_estimate_matches_spec_formula_away_from_integers(
        kappa in 0.0..=1.0_f32,
        r in 0.0..20.0_f32,
        nbar in 0.0..80.0_f32,
    ) {
        let c = SpvgConfig::<f32>::builder().kappa(kappa).build().expect("valid");
        let var = r * 1e-4;
        let h = SpvgHistory { mean: 0.3, variance: var, mean_count: nbar };
        let n_hat = spec_n_hat(0.2, 1e-4, f64::from(kappa), f64::from(var), f64::from(nbar));
        // f32 keeps ~7 digits; Delta can be ~10^4, so stay 1e-3 away from integers.
        prop_assume!((n_hat - n_hat.round()).abs() > 1e-3);
        prop_assert_eq!(c.estimate(&h, 1.0), spec_round(n_hat, 8, 64), "n_hat {}", n_hat);
    }

    /// The operation order documented on `raw_estimate` and `round_count`, written out in
    /// f32 here: the GPU port's contract, so it must hold bit for bit.
    #[test]
    fn f32_estimate_follows_documented_operation_order(
        eta in 0.01..=1.0_f32,
        target in 1e-5..1e-1_f32,
        kappa in 0.0..=1.0_f32,
        var_stored in any_f32(),
        nbar_stored in any_f32(),
    ) {
        let (var, nbar) = (var_stored, nbar_stored);
        let c = SpvgConfig::<f32>::builder()
            .eta(eta).target_variance(target).kappa(kappa).build().expect("valid");
        let inv_target = 1.0 / target;
        let k_minus_1 = 2.0 * (1.0 - eta) / eta;
        prop_assert_eq!(c.inv_target().to_bits(), inv_target.to_bits(), "inv_target");
        prop_assert_eq!(c.k_minus_1().to_bits(), k_minus_1.to_bits(), "k_minus_1");
        let sat = |x: f32| x.clamp(-f32::MAX, f32::MAX);
        // The texel decode read: NaN and anything not > 0 to 0, +inf to MAX.
        let read = |x: f32| if x > 0.0 { x.min(f32::MAX) } else { 0.0 };
        let (var, nbar) = (read(var), read(nbar));
        let r = sat(var / target);
        let t = sat((kappa * sat((r - 1.0) * k_minus_1)) + r);
        let n_hat = sat(t * nbar);
        let want = if n_hat >= 8.0 {
            if n_hat < 64.0 { (n_hat.ceil() as u32).min(64) } else { 64 }
        } else {
            8
        };
        let h = SpvgHistory { mean: 0.0, variance: var_stored, mean_count: nbar_stored };
        prop_assert_eq!(c.raw_estimate(&h).to_bits(), n_hat.to_bits(), "n_hat");
        prop_assert_eq!(c.estimate(&h, 1.0), want, "count");
    }

    #[test]
    fn counts_stay_in_budget_for_any_history(
        mean in any_f64(),
        var in any_f64(),
        nbar in any_f64(),
        kappa in 0.0..=1.0_f64,
        policy in any_policy(),
        valid in any::<bool>(),
        min in 1_u32..8,
        extra in 0_u32..70,
    ) {
        let max = min + extra;
        let policy = match policy {
            CountPolicy::Fixed(n) => CountPolicy::Fixed((min + n).min(max)),
            p => p,
        };
        let c = config(0.2, 1e-4, kappa, min, max).with_policy(policy).expect("valid");
        let h = SpvgHistory { mean, variance: var, mean_count: nbar };
        let n = c.estimate_with_validity(&h, 0.5, valid);
        prop_assert!((min..=max).contains(&n), "{n} outside [{min}, {max}] for {h:?}");
    }

    #[test]
    fn f32_counts_stay_in_budget_for_any_history(
        var in any_f32(), nbar in any_f32(), kappa in 0.0..=1.0_f32, policy in any_policy(),
    ) {
        let policy = match policy {
            CountPolicy::Fixed(n) => CountPolicy::Fixed(8 + n),
            p => p,
        };
        let c = SpvgConfig::<f32>::builder().kappa(kappa).policy(policy).build().expect("valid");
        let h = SpvgHistory { mean: 0.0, variance: var, mean_count: nbar };
        let n = c.estimate(&h, 1.0);
        prop_assert!((8..=64).contains(&n), "{n} outside [8, 64] for {h:?}");
    }

    #[test]
    fn update_matches_spec_formula(
        mean in -10.0..10.0_f64,
        var in 0.0..10.0_f64,
        nbar in 0.0..64.0_f64,
        sample in -10.0..10.0_f64,
        count in 1_u32..64,
        eta in 0.01..=1.0_f64,
        two_phase in any::<bool>(),
    ) {
        let policy = if two_phase { CountPolicy::TwoPhase } else { CountPolicy::Spvg };
        let c = SpvgConfig::<f64>::builder().eta(eta).policy(policy).build().expect("valid");
        let mut h = SpvgHistory { mean, variance: var, mean_count: nbar };
        prop_assert!(c.update(&mut h, sample, count, true), "finite sample refused");
        let want_var = (1.0 - eta) * var + eta * (1.0 - eta) * (sample - mean).powi(2);
        let want_mean = (1.0 - eta) * mean + eta * sample;
        let want_nbar = if two_phase {
            f64::from(count)
        } else {
            (1.0 - eta) * nbar + eta * f64::from(count)
        };
        for (got, want, what) in [
            (h.variance, want_var, "variance"),
            (h.mean, want_mean, "mean"),
            (h.mean_count, want_nbar, "mean_count"),
        ] {
            let tol = 1e-12 * want.abs().max(1.0);
            prop_assert!((got - want).abs() <= tol, "{what}: {got} != {want} (tol {tol})");
        }
    }

    #[test]
    fn update_never_stores_non_finite(
        mean in any_f64(), var in any_f64(), nbar in any_f64(),
        sample in any_f64(), count in 0_u32..100, valid in any::<bool>(),
    ) {
        let c = SpvgConfig::<f64>::published();
        let mut h = SpvgHistory { mean, variance: var, mean_count: nbar };
        c.update(&mut h, sample, count, valid);
        if valid && (count == 0 || !sample.is_finite()) {
            // Refused frames leave a valid history exactly as it was.
            prop_assert!(
                h.mean.to_bits() == mean.to_bits() && h.variance.to_bits() == var.to_bits(),
                "refused frame changed the history: {h:?}"
            );
        } else {
            prop_assert!(
                h.mean.is_finite() && h.variance.is_finite() && h.mean_count.is_finite(),
                "non-finite state {h:?}"
            );
            prop_assert!(h.variance >= 0.0 && h.mean_count >= 0.0, "negative moment {h:?}");
        }
    }
}

/// Near `eta = 1` the correction's gain `2/eta - 2` is a small difference of large terms;
/// the f32 configuration must still hold it to a few ulps of the f64 value, or the
/// estimate's two terms (which nearly cancel there) flip sign. The history and
/// configuration are one that `cargo fuzz` found (f32 gave 36, the f64 formula 72).
#[test]
fn gain_near_eta_one_is_accurate_in_f32() {
    for ulps in 1..=64_u32 {
        let eta = 1.0 - f32::EPSILON / 2.0 * ulps as f32;
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .build()
            .expect("valid");
        let exact = 2.0 / f64::from(eta) - 2.0;
        let rel = (f64::from(c.k_minus_1()) - exact).abs() / exact;
        assert!(
            rel < 4.0 * f64::from(f32::EPSILON),
            "eta {eta}: k - 1 off by {rel:e}"
        );
    }
    let eta = f32::from_bits(0x3f7f_fff7); // 0.99999946 = 1 - 9 * 2^-24
    let c = SpvgConfig::<f32>::builder()
        .eta(eta)
        .target_variance(3.872_216e-39)
        .kappa(1.0)
        .eps_u(0.0)
        .budget(36, 72)
        .build()
        .expect("valid");
    let h = SpvgHistory {
        mean: 3.872_216e-39,
        variance: 4e-45,
        mean_count: 1.825_416_7e32,
    };
    let n_hat = spec_n_hat(
        f64::from(eta),
        f64::from(c.target_variance()),
        1.0,
        f64::from(h.variance),
        f64::from(h.mean_count),
    );
    assert_eq!(spec_round(n_hat, 36, 72), 72, "f64 formula");
    assert_eq!(c.estimate(&h, 1.0), 72);
}

#[test]
fn zero_sample_rule() {
    let c = SpvgConfig::<f32>::published();
    let h = SpvgHistory {
        mean: 1.0,
        variance: 1.0,
        mean_count: 64.0,
    };
    for gamma in [0.0, 0.009_999, -1.0, f32::NAN, f32::NEG_INFINITY] {
        assert_eq!(
            c.estimate(&h, gamma),
            0,
            "gamma {gamma} must take 0 samples"
        );
        assert_eq!(
            c.estimate_with_validity(&h, gamma, false),
            0,
            "gamma {gamma}"
        );
    }
    for gamma in [0.01, 0.5, 1.0] {
        assert_eq!(c.estimate(&h, gamma), 64, "gamma {gamma} samples");
    }
    // eps_u = 0 keeps every pixel with distant energy, but gamma = 0 has none.
    let unbiased = c.to_builder().eps_u(0.0).build().expect("valid");
    assert_eq!(unbiased.estimate(&h, 1e-30), 64, "tiny gamma must sample");
    assert_eq!(
        unbiased.estimate(&h, 0.0),
        0,
        "gamma = 0 has no distant energy"
    );
}

#[test]
fn cold_history_gives_min_samples() {
    for kappa in [0.0, 0.2, 1.0] {
        for policy in [
            CountPolicy::Spvg,
            CountPolicy::TwoPhase,
            CountPolicy::UnrealClamp,
        ] {
            let c = config(0.2, 1e-4, kappa, 5, 40)
                .with_policy(policy)
                .expect("valid");
            let n = c.estimate(&SpvgHistory::default(), 1.0);
            assert_eq!(n, 5, "cold history with kappa {kappa} {policy:?}");
        }
    }
}

#[test]
fn disocclusion_gives_min_samples_and_seeds_target_variance() {
    let c = config(0.2, 0.0064, 1.0, 8, 64);
    let stale = SpvgHistory {
        mean: 5.0,
        variance: 3.0,
        mean_count: 64.0,
    };
    assert_eq!(
        c.estimate(&stale, 1.0),
        64,
        "the stale history asks for more"
    );
    assert_eq!(
        c.estimate_with_validity(&stale, 1.0, false),
        8,
        "an invalid history is treated as zero (docs/algorithms.md §2.3)"
    );
    let mut h = stale;
    assert!(c.update(&mut h, 0.7, 8, false), "seeding update accepted");
    assert_eq!(
        h,
        SpvgHistory {
            mean: 0.7,
            variance: 0.0064,
            mean_count: 8.0
        },
        "w = 1 and var = sigma0^2"
    );
    // The next frame at the target variance keeps the count (r = 1, Delta = 0).
    assert_eq!(c.estimate(&h, 1.0), 8, "seeded history keeps min_samples");
    // A refused frame on an invalid history drops the stale numbers.
    let mut h = stale;
    assert!(!c.update(&mut h, f64::NAN, 8, false), "NaN refused");
    assert_eq!(h, SpvgHistory::default(), "stale history dropped");
    let mut h = stale;
    assert!(!c.update(&mut h, 1.0, 0, true), "zero-sample frame refused");
    assert_eq!(h, stale, "valid history kept on a zero-sample frame");
}

#[test]
fn published_parameters() {
    let c = SpvgConfig::<f64>::published();
    assert_eq!(c.eta(), 0.2, "eta");
    assert_eq!(c.target_variance(), 1e-4, "sigma0^2");
    assert_eq!(c.kappa(), 0.2, "kappa");
    assert_eq!((c.min_samples(), c.max_samples()), (8, 64), "budget");
    assert_eq!(c.eps_u(), 0.01, "eps_u");
    assert_eq!(c.policy(), CountPolicy::Spvg, "policy");
    let k_minus_1 = c.k_minus_1();
    assert!((k_minus_1 - 8.0).abs() < 1e-12, "k - 1 = {k_minus_1}");
    assert_eq!(
        SpvgConfig::<f64>::builder().build(),
        Ok(c),
        "builder defaults"
    );
}

fn invalid_name<T: std::fmt::Debug>(r: Result<T, Error>) -> &'static str {
    match r {
        Err(Error::InvalidParameter { name, .. }) => name,
        Err(Error::InconsistentParameters { names, .. }) => names,
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn validation_names_the_field() {
    let b = SpvgConfig::<f64>::builder;
    for eta in [0.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
        assert_eq!(invalid_name(b().eta(eta).build()), "eta", "eta {eta}");
    }
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-320] {
        let name = invalid_name(b().target_variance(t).build());
        assert_eq!(name, "target_variance", "target {t}");
    }
    for k in [-0.1, 1.1, f64::NAN] {
        assert_eq!(invalid_name(b().kappa(k).build()), "kappa", "kappa {k}");
    }
    for e in [-0.1, 1.1, f64::NAN] {
        assert_eq!(invalid_name(b().eps_u(e).build()), "eps_u", "eps_u {e}");
    }
    assert_eq!(
        invalid_name(b().budget(0, 0).build()),
        "max_samples",
        "zero budget"
    );
    assert_eq!(
        invalid_name(b().min_samples(0).build()),
        "min_samples",
        "zero min"
    );
    // The budget's upper bound: MAX_BUDGET itself is accepted, one above is refused.
    assert_eq!(spvg::controller::MAX_BUDGET, 4096);
    assert!(b().budget(8, 4096).build().is_ok(), "MAX_BUDGET accepted");
    for max in [4097, 100_000, u32::MAX] {
        assert_eq!(
            invalid_name(b().budget(8, max).build()),
            "max_samples",
            "max {max}"
        );
    }
    assert!(
        invalid_name(b().budget(9, 8).build()).contains("min_samples"),
        "min > max"
    );
    assert!(
        invalid_name(b().policy(CountPolicy::Fixed(65)).build()).contains("policy"),
        "fixed count outside the budget"
    );
    assert!(
        b().budget(1, 1)
            .kappa(0.0)
            .eta(1.0)
            .eps_u(1.0)
            .build()
            .is_ok(),
        "range ends are valid"
    );
    let msg = b().kappa(2.0).build().unwrap_err().to_string();
    assert!(msg.contains("kappa"), "message names the field: {msg}");
}

#[test]
fn baselines_follow_their_formulas() {
    let c = config(0.2, 0.25, 0.2, 8, 64);
    // r = 4 exactly (0.25 and 1.0 are binary fractions), nbar = 12.
    let h = SpvgHistory {
        mean: 0.0,
        variance: 1.0,
        mean_count: 12.0,
    };
    let two_phase = c.with_policy(CountPolicy::TwoPhase).expect("valid");
    assert_eq!(two_phase.estimate(&h, 1.0), 48, "max(r n_prev, min) = 48");
    let unreal = c.with_policy(CountPolicy::UnrealClamp).expect("valid");
    assert_eq!(unreal.estimate(&h, 1.0), 8, "clamp(4, 8, 64) = 8");
    let fixed = c.with_policy(CountPolicy::Fixed(20)).expect("valid");
    assert_eq!(fixed.estimate(&h, 1.0), 20, "fixed");
    assert_eq!(
        fixed.estimate(&h, 0.0),
        0,
        "fixed still obeys the zero rule"
    );
    assert_eq!(
        fixed.estimate_with_validity(&h, 1.0, false),
        20,
        "fixed ignores history"
    );
    // SPVG: E = 48, Delta = 3 * 12 * 8 = 288, n_hat = 0.2 * 288 + 48 = 105.6 -> 64.
    assert_eq!(c.estimate(&h, 1.0), 64, "spvg");
}

// ---------------------------------------------------------------------------------------
// docs/algorithms.md §7 circle scenario (the scenario itself is `common::circle`, shared with
// examples/circle.rs).

struct Ensemble {
    /// Mean count over pixels, per frame.
    mean_counts: Vec<f64>,
    /// Mean squared error of the frame estimate over pixels, per frame.
    mean_sq_err: Vec<f64>,
}

/// Runs `pixels` independent circle pixels for `frames` frames.
fn circle_ensemble(kappa: f64, seeded: bool, pixels: u64, frames: usize) -> Ensemble {
    let c = circle::config(kappa).expect("valid test configuration");
    let mut counts = vec![0.0; frames];
    let mut sq = vec![0.0; frames];
    for p in 0..pixels {
        let mut rng = SplitMix64(0x5eed ^ (p * 0x9e37));
        let mut h = SpvgHistory::default();
        for t in 0..frames {
            let f = circle::frame(&c, &mut h, &mut rng, t, seeded);
            assert!(f.accepted, "finite sample accepted");
            counts[t] += f64::from(f.count);
            sq[t] += (f.sample - 1.0) * (f.sample - 1.0);
        }
    }
    let scale = 1.0 / pixels as f64;
    Ensemble {
        mean_counts: counts.iter().map(|v| v * scale).collect(),
        mean_sq_err: sq.iter().map(|v| v * scale).collect(),
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// First frame from which the ensemble mean count stays within `band` (relative) of
/// `settled` for `hold` consecutive frames.
fn settle_frame(counts: &[f64], settled: f64, band: f64, hold: usize) -> Option<usize> {
    (0..counts.len().saturating_sub(hold)).find(|&t| {
        counts[t..t + hold]
            .iter()
            .all(|c| (c - settled).abs() <= band * settled)
    })
}

#[test]
fn circle_converges_to_the_closed_form_count() {
    let ideal = circle::per_sample_variance() / circle::TARGET; // ~42.7
    let (pixels, frames, burn_in) = (120, 160, 60);
    let mut settle = [[0_usize; 2]; 2];
    for (ki, kappa) in [0.0, 1.0].into_iter().enumerate() {
        for (si, seeded) in [false, true].into_iter().enumerate() {
            let e = circle_ensemble(kappa, seeded, pixels, frames);
            let settled = mean(&e.mean_counts[burn_in..]);
            let mse = mean(&e.mean_sq_err[burn_in..]);
            let at = settle_frame(&e.mean_counts, settled, 0.2, 10).unwrap_or(frames);
            settle[ki][si] = at;
            println!(
                "circle kappa {kappa} {}: settled mean count {settled:.2} (ideal {ideal:.2}), \
                 squared error {:.3} x target, settles (20% band, 10 frames) at frame {at}",
                if seeded { "seeded" } else { "zero-history" },
                mse / circle::TARGET
            );
            // kappa = 0: the EMV's bias 2(1-eta)/(2-eta) = 0.89 (docs/algorithms.md §1) and the +0.5 of
            // ceil and Jensen's E[1/n] >= 1/E[n] move the fixed point by a few percent in
            // opposite directions; the ensemble mean of 120 x 100 frames has a standard
            // error under 1%. 10% holds with margin.
            // kappa = 1: the estimate amplifies the EMV's noise by 1 + (k - 1) = 9, so
            // counts hit the budget ends most frames (docs/algorithms.md §2.1's "one-frame spikes") and the
            // clamped, rectified series settles above the ideal; 25% bounds it.
            let tol = if kappa == 0.0 { 0.10 } else { 0.25 };
            let rel = (settled - ideal).abs() / ideal;
            assert!(
                rel <= tol,
                "settled {settled} != ideal {ideal} (rel {rel}, tol {tol})"
            );
            // The achieved variance of the frame estimate stays near the target.
            let ratio = mse / circle::TARGET;
            let tol = if kappa == 0.0 { 1.5 } else { 2.0 };
            assert!(ratio <= tol, "squared error {ratio} x target exceeds {tol}");
        }
    }
    for (start, (k1, k0)) in ["zero-history", "seeded"]
        .into_iter()
        .zip(settle[1].iter().zip(&settle[0]))
    {
        assert!(
            k1 < k0,
            "{start}: kappa = 1 settles at frame {k1} but kappa = 0 at {k0}"
        );
    }
}

#[test]
fn f16_configuration_keeps_the_budget() {
    use half::f16;
    let c = SpvgConfig::<f16>::published();
    let target = c.target_variance().to_f64();
    assert!(
        (target - 1e-4).abs() <= 1e-4 * 1e-3,
        "f16 target {target} != 1e-4 (tol 1e-7)"
    );
    for (var, nbar) in [(0.0, 0.0), (1e-4, 20.0), (1.0, 64.0), (f64::NAN, 8.0)] {
        let h = SpvgHistory {
            mean: f16::ZERO,
            variance: f16::from_f64(var),
            mean_count: f16::from_f64(nbar),
        };
        let n = c.estimate(&h, f16::ONE);
        assert!(
            (8..=64).contains(&n),
            "f16 count {n} for var {var}, nbar {nbar}"
        );
    }
    // The widest budget (MAX_BUDGET) still clamps a saturated f16 history, and the
    // update keeps the count finite. (A budget beyond f16's range, 65504, is refused.)
    let wide = SpvgConfig::<f16>::builder()
        .budget(8, spvg::controller::MAX_BUDGET)
        .build()
        .expect("valid");
    let h = SpvgHistory {
        mean: f16::ZERO,
        variance: f16::MAX,
        mean_count: f16::MAX,
    };
    assert_eq!(wide.estimate(&h, f16::ONE), 4096, "saturated history");
    let mut h = SpvgHistory::default();
    assert!(wide.update(&mut h, f16::ONE, 4096, true), "update accepted");
    assert!(
        h.mean_count.is_finite(),
        "count saturates: {:?}",
        h.mean_count
    );
}
