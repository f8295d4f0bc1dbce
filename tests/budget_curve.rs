//! The clamp-aware feed-forward of the frame budget governor (docs/algorithms.md §8.2):
//! `count_at` against the estimate of a rebuilt configuration, its monotonicity in the
//! target, and `Governor::plan_curve` against a brute-force f64 bisection of the clamped
//! total over random pixel sets, with its edge cases and non-finite input.

mod common;

use common::splitmix::SplitMix64;
use proptest::prelude::*;
use spvg::budget::{BudgetConfig, CURVE_POINTS, DemandCurve, Governor, count_at};
use spvg::controller::CountPolicy;
use spvg::{SpvgConfig, SpvgHistory};

fn governor(budget: f64, initial: f64) -> Governor<f64> {
    let c = BudgetConfig::builder(budget).build().expect("valid budget");
    Governor::new(c, initial).expect("valid initial target")
}

fn history(var: f64, nbar: f64) -> SpvgHistory<f64> {
    SpvgHistory {
        mean: 1.0,
        variance: var,
        mean_count: nbar,
    }
}

fn policy(k: u8, lo: u32) -> CountPolicy {
    match k % 5 {
        1 => CountPolicy::TwoPhase,
        2 => CountPolicy::UnrealClamp,
        3 => CountPolicy::Fixed(lo),
        _ => CountPolicy::Spvg,
    }
}

proptest! {
    /// `count_at(config, s, ..)` is the estimate of the configuration rebuilt with target
    /// `s` (an independent path: the builder and `estimate_with_validity`), and never
    /// rises with the target.
    #[test]
    fn count_at_is_the_estimate_at_that_target_and_falls_with_it(
        var in prop_oneof![Just(0.0), Just(f64::NAN), Just(f64::INFINITY), 1e-12_f64..1e3],
        nbar in prop_oneof![Just(0.0), Just(f64::NAN), 0.0_f64..200.0],
        target in 1e-9_f64..1e2,
        factor in 1.0_f64..1e3,
        kappa in prop_oneof![Just(0.0), Just(1.0), 0.0_f64..=1.0],
        damped in prop_oneof![Just(None), (0.01_f64..2.0).prop_map(Some)],
        k in 0_u8..5,
        gamma in prop_oneof![Just(1.0), Just(0.0), Just(0.005), 0.0_f64..1.0],
        valid in any::<bool>(),
    ) {
        let base = SpvgConfig::<f64>::builder()
            .kappa(kappa)
            .budget(8, 64)
            .max_change(damped)
            .policy(policy(k, 8))
            .build()
            .expect("valid");
        let h = history(var, nbar);
        let mut previous = u32::MAX;
        for s in [target, target * factor.sqrt(), target * factor] {
            let rebuilt = base.to_builder().target_variance(s).build().expect("valid target");
            let got = count_at(&base, s, &h, gamma, valid);
            prop_assert_eq!(got, rebuilt.estimate_with_validity(&h, gamma, valid), "target {}", s);
            prop_assert!(got <= previous, "count {} at {} above {} at a smaller target", got, s, previous);
            previous = got;
        }
    }
}

/// Non-positive and NaN targets read as the smallest positive normal value.
#[test]
fn count_at_reads_a_bad_target_as_the_smallest_positive() {
    let c = SpvgConfig::<f32>::builder().build().expect("valid");
    let h = SpvgHistory {
        mean: 1.0,
        variance: 1e-30,
        mean_count: 20.0,
    };
    let at_min = count_at(&c, f32::MIN_POSITIVE, &h, 1.0, true);
    for bad in [0.0, -0.0, -1.0, f32::NAN, -f32::INFINITY] {
        assert_eq!(count_at(&c, bad, &h, 1.0, true), at_min, "target {bad}");
    }
}

/// A pixel of the continuous clamped model `clamp(a / s - o, lo, hi)`.
#[derive(Clone, Copy, Debug)]
struct Px {
    a: f64,
    o: f64,
}

const LO: f64 = 8.0;
const HI: f64 = 64.0;

fn clamped_total(pixels: &[Px], s: f64) -> f64 {
    pixels.iter().map(|p| (p.a / s - p.o).clamp(LO, HI)).sum()
}

/// The target at which the (non-increasing) clamped total crosses `budget`, by bisection
/// on `ln s` in f64 (the reference).
fn bisect(pixels: &[Px], budget: f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = (0.5 * (lo.ln() + hi.ln())).exp();
        if clamped_total(pixels, mid) >= budget {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo * hi).sqrt()
}

/// Random bimodal pixel sets like the report's scenes: most pixels' unclamped counts far
/// below `beta_min`, a few far above `beta_max`, some in between; with the SPVG offset of
/// `kappa = 0.2` (`o = b nbar`, `a = (1 + b) var nbar`).
fn pixel_set(rng: &mut SplitMix64, n: usize, target: f64) -> Vec<Px> {
    (0..n)
        .map(|_| {
            let nbar = 8.0 + 56.0 * rng.next_f64();
            // r = var / target: log-uniform over [1e-3, 1e3] with extra mass at the ends.
            let u = rng.next_f64();
            let r = match (u * 10.0) as u32 {
                0..=5 => 10f64.powf(-3.0 + 2.5 * rng.next_f64()),
                6 => 10f64.powf(1.5 + 1.5 * rng.next_f64()),
                _ => 10f64.powf(-0.7 + 1.5 * rng.next_f64()),
            };
            let b = 0.2 * 8.0;
            Px {
                a: (1.0 + b) * r * target * nbar,
                o: b * nbar,
            }
        })
        .collect()
}

/// `plan_curve` against the bisection: the planned target lies in the same pair of
/// candidates as the exact crossing, and the total there misses the budget by no more
/// than the pixels that change between clamped and unclamped inside that pair can
/// account for (the interpolation in `1 / s` is exact for the others). Where the
/// crossing lies outside the candidates, the plan takes the nearest end.
#[test]
fn plan_curve_matches_a_bisection_of_the_clamped_total() {
    let mut rng = SplitMix64(0x5eed_b0d9);
    let (mut inside, mut below, mut above) = (0, 0, 0);
    for case in 0..400 {
        let n = 50 + (rng.next_f64() * 2000.0) as usize;
        let center = 10f64.powf(-7.0 + 4.0 * rng.next_f64());
        let spread = 10f64.powf(2.0 * rng.next_f64() - 1.0);
        let pixels = pixel_set(&mut rng, n, center * spread);
        let budget = n as f64 * (LO + (HI - LO) * rng.next_f64() * 0.5);
        let mut gov = governor(budget, center);
        let targets = gov.curve_targets();
        let curve = DemandCurve {
            targets,
            totals: targets.map(|s| clamped_total(&pixels, s)),
        };
        let planned = gov.plan_curve(&curve);
        let exact = bisect(&pixels, budget, 1e-12, 1e6);
        let (first, last) = (targets[0], targets[CURVE_POINTS - 1]);
        if exact <= first {
            assert_eq!(
                planned, first,
                "case {case}: crossing {exact} below the candidates"
            );
            below += 1;
            continue;
        }
        if exact >= last {
            assert_eq!(
                planned, last,
                "case {case}: crossing {exact} above the candidates"
            );
            above += 1;
            continue;
        }
        inside += 1;
        let j = targets
            .windows(2)
            .position(|w| w[0] <= exact && exact <= w[1])
            .expect("bracketed");
        let (s0, s1) = (targets[j], targets[j + 1]);
        assert!(
            (s0..=s1).contains(&planned),
            "case {case}: planned {planned} outside the bracket [{s0}, {s1}] of {exact}"
        );
        // The pixels whose count is not linear in 1/s over the whole bracket.
        let slack: f64 = pixels
            .iter()
            .filter(|p| {
                let (c0, c1) = (p.a / s0 - p.o, p.a / s1 - p.o);
                let unclamped = |c: f64| (LO..=HI).contains(&c);
                let linear = unclamped(c0) && unclamped(c1);
                let constant = (c0 <= LO && c1 <= LO) || (c0 >= HI && c1 >= HI);
                !(linear || constant)
            })
            .map(|p| (p.a / s0 - p.o).clamp(LO, HI) - (p.a / s1 - p.o).clamp(LO, HI))
            .sum();
        let miss = (clamped_total(&pixels, planned) - budget).abs();
        assert!(
            miss <= slack + 1e-9 * budget,
            "case {case}: total at the plan misses the budget {budget} by {miss} (tol {slack})"
        );
    }
    assert!(
        inside > 200 && below > 10 && above > 10,
        "every case kind covered: {inside} inside, {below} below, {above} above"
    );
}

/// Pixels that stay unclamped, or clamped, over the bracket: the interpolation in
/// `1 / s` is exact, the total at the plan is the budget.
#[test]
fn plan_curve_is_exact_where_no_pixel_changes_clamp() {
    let target = 1e-4;
    // Two clamped at the top, three at the bottom, four unclamped near 20..40.
    let mut pixels = vec![Px { a: 1.0, o: 0.0 }; 2];
    pixels.extend([Px { a: 1e-12, o: 0.0 }; 3]);
    for k in 0..4 {
        pixels.push(Px {
            a: target * (20.0 + 5.0 * f64::from(k)),
            o: 0.0,
        });
    }
    // At `target` the unclamped ones sum to 110; the budget asks for 100 from them.
    let budget = 2.0 * HI + 3.0 * LO + 100.0;
    let mut gov = governor(budget, target);
    let targets = gov.curve_targets();
    let curve = DemandCurve {
        targets,
        totals: targets.map(|s| clamped_total(&pixels, s)),
    };
    let planned = gov.plan_curve(&curve);
    let want = target * 110.0 / 100.0;
    assert!(
        (planned / want - 1.0).abs() < 1e-12,
        "planned {planned} != {want}"
    );
    assert!(
        (curve.total_at(planned) - budget).abs() < 1e-9,
        "total_at the plan"
    );
}

/// The ends, a flat curve and unusable curves.
#[test]
fn plan_curve_edge_cases_and_non_finite_input() {
    let budget = 1000.0;
    let mut gov = governor(budget, 1e-3);
    let targets = gov.curve_targets();
    assert!(
        targets.windows(2).all(|w| w[0] < w[1]),
        "candidates increase: {targets:?}"
    );
    assert!(
        (targets[8] - 1e-3).abs() < 1e-18 && (targets[0] - 1e-3 / 16.0).abs() < 1e-18,
        "candidates around the base: {targets:?}"
    );
    let falling = |hi: f64, lo: f64| DemandCurve {
        targets,
        totals: core::array::from_fn(|j| hi + (lo - hi) * j as f64 / (CURVE_POINTS - 1) as f64),
    };
    // Above the budget everywhere: the largest candidate.
    assert_eq!(gov.plan_curve(&falling(5000.0, 2000.0)), targets[15]);
    // Below it everywhere: the smallest candidate of the new base.
    let mut gov = governor(budget, 1e-3);
    assert_eq!(gov.plan_curve(&falling(900.0, 100.0)), targets[0]);
    // Flat below the budget (a zero history): the previous base.
    let mut gov = governor(budget, 1e-3);
    let before = gov;
    assert_eq!(gov.plan_curve(&falling(500.0, 500.0)), 1e-3);
    assert_eq!(gov, before, "flat curve");
    // Unusable curves leave the state unchanged.
    let bad_total = |v: f64| {
        let mut c = falling(2000.0, 100.0);
        c.totals[3] = v;
        c
    };
    let bad_target = |v: f64| {
        let mut c = falling(2000.0, 100.0);
        c.targets[5] = v;
        c
    };
    for c in [
        bad_total(f64::NAN),
        bad_total(f64::INFINITY),
        bad_total(-1.0),
        bad_target(f64::NAN),
        bad_target(0.0),
        bad_target(-1e-3),
        bad_target(f64::INFINITY),
        bad_target(1.0), // not non-decreasing
    ] {
        assert_eq!(gov.plan_curve(&c), before.target(), "curve {c:?}");
        assert_eq!(gov, before, "curve {c:?} left the state unchanged");
        assert!(c.total_at(1e-3).is_nan(), "total_at of {c:?}");
    }
}

proptest! {
    /// Whatever the curves and totals, the candidates stay in range and increase, the
    /// target stays within its range and the state finite.
    #[test]
    fn curve_governor_stays_in_range(
        steps in prop::collection::vec(
            (prop_oneof![Just(f64::NAN), Just(0.0), Just(f64::INFINITY), 1e-30_f64..1e30],
             prop::array::uniform16(prop_oneof![Just(f64::NAN), Just(-1.0), 0.0_f64..1e7]),
             any::<bool>()), 1..30),
        budget in 1.0_f64..1e6,
    ) {
        let mut gov = governor(budget, 1e-3);
        for (total, mut totals, sorted) in steps {
            let targets = gov.curve_targets();
            prop_assert!(targets.iter().all(|t| (1e-8..=1e2).contains(t)), "{:?}", targets);
            prop_assert!(targets.windows(2).all(|w| w[0] <= w[1]), "{:?}", targets);
            if sorted {
                totals.sort_by(|a, b| b.total_cmp(a));
            }
            gov.plan_curve(&DemandCurve { targets, totals });
            gov.observe(total);
            prop_assert!((1e-8..=1e2).contains(&gov.target()), "target {}", gov.target());
            prop_assert!(gov.correction().is_finite(), "correction");
        }
    }
}
