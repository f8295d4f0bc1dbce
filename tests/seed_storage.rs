//! The disocclusion seed after an f16 store: `var == sigma0^2` read back from
//! the stored seed must give exactly the seeded count `nbar`, with no extra sample from the
//! f16 quantisation of the target. With the configuration a texel layout stores exactly
//! (`TexelEncoding::storable_config`) it does, for any target, weight, `kappa`, count and
//! rounding; with the raw target it does not (the defect, kept as evidence).

use proptest::prelude::*;
use spvg::texel::{Layout, Rounding, SpvgTexel16, SpvgTexel32, TexelEncoding};
use spvg::{SpvgConfig, SpvgHistory};

fn config(target: f32, eta: f32, kappa: f32) -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(target)
        .eta(eta)
        .kappa(kappa)
        .budget(1, 2048)
        .build()
        .expect("valid config")
}

/// A log-uniform value in [lo, hi].
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f32> {
    (0.0..=1.0_f64).prop_map(move |u| (lo.ln() + u * (hi.ln() - lo.ln())).exp() as f32)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn a_stored_seed_estimates_its_count(
        target in log_uniform(1e-12, 1e6),
        // The encoding's target: the configuration's, or one a governor moved away from.
        moved in prop_oneof![Just(1.0_f64), 1e-3..1e3_f64],
        eta in prop_oneof![Just(0.2_f32), log_uniform(1e-6, 1.0)],
        kappa in prop_oneof![Just(0.5_f32), Just(1.0_f32), 0.0..=1.0_f32],
        nbar in 1..=2048_u32,
        sample in -10.0..10.0_f32,
        random in any::<u32>(),
    ) {
        let c = config(target, eta, kappa);
        let enc = TexelEncoding::new((f64::from(target) * moved) as f32)
            .map_err(|e| TestCaseError::reject(e.to_string()))?;
        let stored = enc.storable_config(&c, Layout::F16).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let t = stored.target_variance();
        prop_assert!(t > 0.0 && t.is_finite());
        // The scale keeps the target's stored value in the normal f16 range here: at most
        // one f16 step (2^-10 relative) below the requested target.
        if moved > 1e-3 * 4.0 && moved < 1e3 / 4.0 {
            prop_assert!(t <= target && f64::from(t) >= f64::from(target) * (1.0 - 2f64.powi(-10)), "{t} for {target}");
        }
        let seed = SpvgHistory::seeded(sample, &stored, nbar);
        for rounding in [Rounding::Nearest, Rounding::Stochastic(random)] {
            let back = enc.decode(enc.encode::<SpvgTexel16>(&seed, rounding));
            prop_assert_eq!(back.variance, t, "the seed's variance is stored exactly");
            prop_assert_eq!(back.mean_count, nbar as f32);
            prop_assert_eq!(stored.estimate(&back, 1.0), nbar, "eta {} kappa {} target {}", eta, kappa, target);
        }
        // f32 texels store every variance: the configuration is unchanged.
        prop_assert_eq!(enc.storable_config(&c, Layout::F32).ok(), Some(c));
        let back = enc.decode(enc.encode::<SpvgTexel32>(&SpvgHistory::seeded(sample, &c, nbar), Rounding::Nearest));
        prop_assert_eq!(c.estimate(&back, 1.0), nbar);
    }
}

/// The defect as reported: with the raw target, the f16 round trip of the seed changes
/// the estimate on a large share of targets at `eta = 0.2` (44% in the report); the
/// issue's own case, a target of `1e-3` and 8 samples, asked 9.
#[test]
fn the_raw_target_misses_the_count() {
    let c = SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        .build()
        .expect("valid config");
    let enc = TexelEncoding::for_config(&c).expect("encoding");
    let raw =
        enc.decode(enc.encode::<SpvgTexel16>(&SpvgHistory::seeded(0.5, &c, 8), Rounding::Nearest));
    assert_ne!(raw.variance, 1e-3, "1e-3 is not an f16 value at its scale");
    let fixed = enc.storable_config(&c, Layout::F16).expect("config");
    let back = enc
        .decode(enc.encode::<SpvgTexel16>(&SpvgHistory::seeded(0.5, &fixed, 8), Rounding::Nearest));
    assert_eq!(fixed.estimate(&back, 1.0), 8);
    let (mut missed, mut total) = (0, 0);
    for k in 0..2000 {
        let target = 1e-4 * (1.0 + k as f32 / 2000.0);
        let c = config(target, 0.2, 1.0);
        let enc = TexelEncoding::for_config(&c).expect("encoding");
        for nbar in [8, 16, 32, 64] {
            let h = SpvgHistory::seeded(0.5, &c, nbar);
            let back = enc.decode(enc.encode::<SpvgTexel16>(&h, Rounding::Nearest));
            total += 1;
            missed += usize::from(c.estimate(&back, 1.0) != nbar);
        }
    }
    eprintln!("raw target: {missed} of {total} seeds estimate another count");
    assert!(
        missed * 5 > total,
        "the defect this test documents: {missed} of {total}"
    );
}

proptest! {
    /// Any target against any encoding (a governor can move the target far from the
    /// scale): the stored target is positive, finite, stored exactly (so taking it again
    /// changes nothing), and not above the target unless the target is below the smallest
    /// stored value.
    #[test]
    fn stored_targets_are_exact_at_any_scale(
        target in log_uniform(1e-30, 1e30),
        scale in log_uniform(1e-30, 1e30),
    ) {
        let enc = TexelEncoding::new(scale).map_err(|e| TestCaseError::reject(e.to_string()))?;
        for layout in [Layout::F16, Layout::F32] {
            let t = enc.stored_variance(target, layout);
            prop_assert!(t > 0.0 && t.is_finite(), "{layout:?}: {t}");
            prop_assert_eq!(enc.stored_variance(t, layout), t, "{:?}", layout);
            let smallest = match layout {
                Layout::F16 => 2f32.powi(-24) * enc.variance_scale(),
                Layout::F32 => f32::MIN_POSITIVE,
            };
            if target >= smallest {
                prop_assert!(t <= target, "{layout:?}: {t} above {target}");
            }
        }
    }
}
