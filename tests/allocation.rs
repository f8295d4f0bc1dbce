//! The allocation exponent (`SpvgConfigBuilder::allocation_exponent`, docs/algorithms.md
//! §8.2): validation naming the parameter, `p = 1` unchanged, the raw count raised to
//! `p` against `f64` closed forms, and under the frame budget's feed-forward counts
//! proportional to `v^p` (the Neyman allocation at `p = 1/2`).

use spvg::budget::{BudgetConfig, DemandCurve, Governor, allocate};
use spvg::{Error, SpvgConfig, SpvgHistory};

fn with_p(p: f64) -> SpvgConfig<f64> {
    SpvgConfig::<f64>::builder()
        .allocation_exponent(p)
        .build()
        .expect("valid")
}

#[test]
fn out_of_range_exponents_are_refused_by_name() {
    for bad in [0.0, -0.5, 1.0 + 1e-12, 2.0, f64::NAN, f64::INFINITY] {
        let err = SpvgConfig::<f64>::builder()
            .allocation_exponent(bad)
            .build()
            .unwrap_err();
        assert!(
            matches!(
                err,
                Error::InvalidParameter {
                    name: "allocation_exponent",
                    ..
                }
            ),
            "{bad}: {err}"
        );
    }
    // Fractional counts do not pass through the allocation: p < 1 is refused with them.
    let err = SpvgConfig::<f64>::builder()
        .fractional_floor(Some(0.5))
        .allocation_exponent(0.5)
        .build()
        .unwrap_err();
    assert!(err.to_string().contains("allocation_exponent"), "{err}");
    assert_eq!(SpvgConfig::<f32>::published().allocation_exponent(), 1.0);
    assert_eq!(
        with_p(0.75).to_builder().build().expect("valid"),
        with_p(0.75)
    );
}

#[test]
fn the_raw_count_is_raised_to_p() {
    for p in [0.5, 0.75, 1.0] {
        let c = with_p(p);
        let base = with_p(1.0);
        for (var, nbar) in [(1e-4, 8.0), (3.7e-3, 21.0), (2e-6, 64.0), (0.4, 13.0)] {
            let h = SpvgHistory {
                mean: 0.5,
                variance: var,
                mean_count: nbar,
            };
            let e = base.raw_estimate(&h);
            let got = c.raw_estimate(&h);
            // The closed form in f64 (powf, an independent route from exp(p ln e)).
            let want = if e > 0.0 { e.powf(p) } else { e };
            assert!(
                (got - want).abs() <= 1e-12 * want.abs(),
                "p {p}: {got} vs {want}"
            );
            if p == 1.0 {
                assert_eq!(got.to_bits(), e.to_bits());
            }
        }
    }
    // Non-positive and non-finite counts pass unchanged.
    for x in [0.0, -3.0, f64::INFINITY, f64::NAN] {
        assert_eq!(allocate(0.5, x).to_bits(), x.to_bits());
    }
}

#[test]
fn under_the_budget_counts_follow_v_to_the_p() {
    // kappa = 0 and a wide per-pixel budget: the raw count is E = var nbar / sigma0^2, the
    // per-sample variance v = var nbar over the target. Pixels with v in ratio 1 : 4 :
    // 16 : 64 take counts in ratio v^p once the feed-forward has met the budget.
    let v = [1e-3, 4e-3, 1.6e-2, 6.4e-2];
    let hist: Vec<SpvgHistory<f64>> = v
        .iter()
        .map(|&v| SpvgHistory {
            mean: 0.5,
            variance: v / 16.0,
            mean_count: 16.0,
        })
        .collect();
    for p in [0.5, 0.75, 1.0] {
        let c = SpvgConfig::<f64>::builder()
            .kappa(0.0)
            .budget(1, spvg::controller::MAX_BUDGET)
            .allocation_exponent(p)
            .build()
            .expect("valid");
        let budget = 4000.0;
        let mut g = Governor::new(BudgetConfig::builder(budget).build().expect("valid"), 1e-4)
            .expect("valid");
        let mut target = g.target();
        for _ in 0..6 {
            let curve = DemandCurve::from_pixels(
                &c,
                g.curve_targets(),
                hist.iter().map(|h| (h, 1.0, true)),
            );
            target = g.plan_curve(&curve);
        }
        let cfg = c
            .to_builder()
            .target_variance(target)
            .build()
            .expect("valid");
        let n: Vec<f64> = hist.iter().map(|h| cfg.raw_estimate(h)).collect();
        let total: f64 = n.iter().sum();
        assert!(
            (total - budget).abs() < 0.02 * budget,
            "p {p}: total {total}"
        );
        for i in 1..v.len() {
            let want = (v[i] / v[0]).powf(p);
            let got = n[i] / n[0];
            assert!((got - want).abs() < 1e-9 * want, "p {p}: {got} vs {want}");
        }
    }
}
