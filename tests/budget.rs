//! The frame budget governor (docs/algorithms.md §8.2): closed forms of the loop, its
//! non-finite policy and validation, and a simulation of many pixels under changing
//! light in which the governor holds each frame's total to the budget.

mod common;

use std::f64::consts::PI;

use common::splitmix::SplitMix64;
use proptest::prelude::*;
use spvg::budget::{BudgetConfig, DemandCurve, FrameDemand, Governor};
use spvg::cv::{Ccv, PixelController, PixelFrame};
use spvg::{Error, SpvgConfig, SpvgHistory};

fn governor(budget: f64, gain: f64, initial: f64) -> Governor<f64> {
    let c = BudgetConfig::builder(budget)
        .gain(gain)
        .build()
        .expect("valid budget");
    Governor::new(c, initial).expect("valid initial target")
}

/// Feedback alone on the plant `N = K / sigma0^2` (no clamps): with the total of each
/// frame observed before the next (latency 1), `ln(N / B)` shrinks by `1 - g` per frame,
/// the closed form of docs/algorithms.md §8.2.
#[test]
fn feedback_error_decays_by_one_minus_gain() {
    let (k, b) = (50.0, 1000.0);
    for g in [0.25, 0.5, 1.0] {
        let mut gov = governor(b, g, 1e-3);
        let mut err = (k / gov.target() / b).ln();
        for t in 0..12 {
            assert!(gov.observe(k / gov.target()), "finite total");
            let next = (k / gov.target() / b).ln();
            let want = (1.0 - g) * err;
            assert!(
                (next - want).abs() <= 1e-12 * err.abs().max(1.0),
                "g {g} frame {t}: error {next} != (1 - g) * {err} = {want}"
            );
            err = next;
        }
    }
}

/// With the total observed two frames late (a CPU read-back), the default gain 1/4 is
/// the critically damped one: the error goes to zero without changing sign, while
/// g = 1/2 overshoots.
#[test]
fn default_gain_does_not_overshoot_with_two_frames_of_latency() {
    let (k, b) = (50.0, 1000.0);
    let run = |g: f64| {
        let mut gov = governor(b, g, 1e-3);
        let mut used = vec![gov.target(), gov.target()];
        let mut errors = Vec::new();
        for t in 2..60 {
            // Frame t - 2's total arrives now; frame t renders with the new target.
            gov.observe(k / used[t - 2]);
            used.push(gov.target());
            errors.push((k / gov.target() / b).ln());
        }
        errors
    };
    let default = BudgetConfig::<f64>::builder(1.0)
        .build()
        .expect("valid")
        .gain();
    assert_eq!(default, 0.25, "default gain");
    let errors = run(default);
    assert!(
        errors.iter().all(|e| *e >= -1e-12),
        "the error changed sign: {errors:?}"
    );
    assert!(
        errors.last().expect("frames").abs() < 1e-6,
        "converged: {errors:?}"
    );
    let errors = run(0.5);
    assert!(
        errors.iter().any(|e| *e < -1e-3),
        "g = 0.5 should overshoot: {errors:?}"
    );
}

/// Feed-forward: with kappa = 0 and every pixel inside the budget clamp, the planned
/// target puts the summed raw counts exactly on the budget.
#[test]
fn plan_solves_the_unclamped_total() {
    for kappa in [0.0, 0.2, 1.0] {
        let controller = SpvgConfig::<f64>::builder()
            .kappa(kappa)
            .budget(1, spvg::controller::MAX_BUDGET)
            .build()
            .expect("valid");
        let histories: Vec<SpvgHistory<f64>> = (0..50)
            .map(|i| SpvgHistory {
                mean: 1.0,
                variance: 1e-3 * (1.0 + f64::from(i)),
                mean_count: 10.0 + f64::from(i % 7),
            })
            .collect();
        let demand = histories
            .iter()
            .map(|h| FrameDemand::pixel(&controller, h, 1.0, true))
            .fold(FrameDemand::default(), |a, b| a + b);
        let budget = 50.0 * 30.0;
        let mut gov = governor(budget, 0.25, 1e-4);
        let target = gov.plan(&demand);
        let config = controller
            .to_builder()
            .target_variance(target)
            .build()
            .expect("valid");
        let raw: f64 = histories.iter().map(|h| config.raw_estimate(h)).sum();
        assert!(
            (raw - budget).abs() <= 1e-9 * budget,
            "kappa {kappa}: summed raw count {raw} != budget {budget}"
        );
        assert!(
            (demand.unclamped_total(target) - budget).abs() <= 1e-9 * budget,
            "unclamped_total"
        );
    }
}

#[test]
fn non_finite_input_never_poisons_the_state() {
    let mut gov = governor(1000.0, 0.5, 1e-3);
    let before = gov;
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY, 0.0, -5.0] {
        assert!(!gov.observe(bad), "total {bad} refused");
        assert_eq!(gov, before, "total {bad} left the state unchanged");
    }
    for bad in [
        FrameDemand {
            scaled: f64::NAN,
            offset: 0.0,
            fixed: 0.0,
        },
        FrameDemand {
            scaled: 1.0,
            offset: f64::INFINITY,
            fixed: 0.0,
        },
        FrameDemand {
            scaled: 1.0,
            offset: 0.0,
            fixed: -1.0,
        },
        FrameDemand::default(),
    ] {
        assert_eq!(gov.plan(&bad), before.target(), "demand {bad:?} ignored");
        assert_eq!(gov, before, "demand {bad:?} left the state unchanged");
    }
    // A budget spent on fixed counts asks for the largest target.
    let all_fixed = FrameDemand {
        scaled: 1.0,
        offset: 0.0,
        fixed: 2000.0,
    };
    assert_eq!(gov.plan(&all_fixed), 1e2, "max_target");
}

#[test]
fn parameters_are_validated_by_name() {
    let name = |r: Result<BudgetConfig<f64>, Error>| match r {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an invalid parameter, got {other:?}"),
    };
    let b = BudgetConfig::<f64>::builder;
    assert_eq!(name(b(0.0).build()), "budget");
    assert_eq!(name(b(f64::NAN).build()), "budget");
    assert_eq!(name(b(f64::INFINITY).build()), "budget");
    assert_eq!(name(b(1.0).gain(0.0).build()), "gain");
    assert_eq!(name(b(1.0).gain(1.5).build()), "gain");
    assert_eq!(name(b(1.0).target_range(0.0, 1.0).build()), "min_target");
    assert_eq!(name(b(1.0).target_range(1e-320, 1.0).build()), "min_target");
    assert_eq!(
        name(b(1.0).target_range(1e-3, f64::NAN).build()),
        "max_target"
    );
    assert!(
        matches!(
            b(1.0).target_range(1.0, 1e-3).build(),
            Err(Error::InconsistentParameters { .. })
        ),
        "min > max"
    );
    let c = b(1.0).target_range(1e-4, 1e-2).build().expect("valid");
    let err = Governor::new(c, 1.0).unwrap_err();
    assert!(err.to_string().contains("initial_target"), "{err}");
}

proptest! {
    /// Whatever the totals and demands, the target stays within its range and the state
    /// finite, in f64 and f32.
    #[test]
    fn target_stays_in_range(
        steps in prop::collection::vec(
            (prop_oneof![Just(f64::NAN), Just(0.0), Just(f64::INFINITY), 1e-30_f64..1e30],
             prop_oneof![Just(f64::NAN), Just(0.0), 1e-30_f64..1e30],
             0.0_f64..1e6, 0.0_f64..1e6), 1..40),
        gain in 0.01_f64..=1.0,
    ) {
        let mut g64 = governor(1e5, gain, 1e-3);
        let c32 = BudgetConfig::<f32>::builder(1e5).gain(gain as f32).build().expect("valid");
        let mut g32 = Governor::new(c32, 1e-3).expect("valid");
        for (total, scaled, offset, fixed) in steps {
            let d = FrameDemand { scaled, offset, fixed };
            g64.plan(&d);
            g64.observe(total);
            prop_assert!((1e-8..=1e2).contains(&g64.target()), "f64 target {}", g64.target());
            prop_assert!(g64.correction().is_finite(), "f64 correction");
            let d = FrameDemand { scaled: scaled as f32, offset: offset as f32, fixed: fixed as f32 };
            g32.plan(&d);
            g32.observe(total as f32);
            prop_assert!((1e-8..=1e2).contains(&g32.target()), "f32 target {}", g32.target());
            prop_assert!(g32.correction().is_finite(), "f32 correction");
        }
    }
}

// ---------------------------------------------------------------------------------------
// Simulation: many pixels under changing light.

/// The lighting of a frame (60 frames per second).
#[derive(Clone, Copy, Debug)]
enum Light {
    /// `sin(2 pi 5 t / 60) + 1`.
    Flash,
    /// On (1) and off (0.1) every 3 s, with a 4% flicker at 7 Hz.
    Switch,
}

impl Light {
    fn intensity(self, t: usize) -> f64 {
        let t = t as f64;
        match self {
            Self::Flash => (2.0 * PI * 5.0 * t / 60.0).sin() + 1.0,
            Self::Switch => {
                let on = if ((t / 180.0).floor() as u64).is_multiple_of(2) {
                    1.0
                } else {
                    0.1
                };
                on * (1.0 + 0.04 * (2.0 * PI * 7.0 * t / 60.0).sin())
            }
        }
    }
}

/// How the governor is fed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feed {
    /// Clamp-aware feed-forward (the demand curve at the governor's candidate targets)
    /// from the history the frame reads, the frame's total observed before the next
    /// frame (the order of `spvg_wgpu::sss::reduce` and of the report).
    Curve,
    /// Feed-forward from the unclamped sums of the history the frame reads, the frame's
    /// total observed before the next frame.
    InFrame,
    /// Totals only, observed before the next frame (no demand reduction).
    FeedbackOnly,
    /// Both sums read back one frame late on the CPU: the demand of the history before
    /// last and the total of the frame before last.
    ReadBack,
}

struct Outcome {
    within: f64,
    worst: f64,
    mean_abs: f64,
    mean_spp: f64,
}

/// The per-sample standard deviations of the pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Population {
    /// Log-uniform in [0.02, 1].
    Smooth,
    /// Like the report's pass scenes at 16 spp: 85% of the pixels with standard
    /// deviations log-uniform in [0.001, 0.01] (their counts sit at `beta_min`), 10% in
    /// [0.5, 2] (at `beta_max`), 5% in [0.02, 0.2].
    Bimodal,
}

/// `pixels` pixels with per-sample standard deviations drawn from `population`, mean
/// luminance 1, under CCV (the residual keeps the Monte Carlo noise, which scales with
/// the light), each frame's estimate drawn as the mean of `n` samples (a normal with
/// standard deviation `I sigma_p / sqrt(n)`), kappa 0.2, budget [8, 64] per pixel, and a
/// frame budget of 16 samples per pixel; returns the share of frames after a 10-frame
/// warm-up whose total lies within 10% of the budget.
fn simulate(
    light: Light,
    population: Population,
    feed: Feed,
    max_change: Option<f64>,
    frames: usize,
) -> Outcome {
    let pixels = 2000_usize;
    let mut rng = SplitMix64(0xb0d9e7);
    let log_uniform = |lo: f64, hi: f64, u: f64| (lo.ln() + u * (hi.ln() - lo.ln())).exp();
    let sigma: Vec<f64> = (0..pixels)
        .map(|i| match population {
            Population::Smooth => log_uniform(0.02, 1.0, rng.next_f64()),
            Population::Bimodal => match i % 20 {
                0 | 1 => log_uniform(0.5, 2.0, rng.next_f64()),
                2 => log_uniform(0.02, 0.2, rng.next_f64()),
                _ => log_uniform(0.001, 0.01, rng.next_f64()),
            },
        })
        .collect();
    let controller = SpvgConfig::<f64>::builder()
        .kappa(0.2)
        .budget(8, 64)
        .max_change(max_change)
        .build()
        .expect("valid");
    let budget = 16.0 * pixels as f64;
    let mut gov = governor(budget, 0.25, 1e-3);
    let mut histories = vec![SpvgHistory::default(); pixels];
    let (mut totals, mut demands) = (Vec::new(), Vec::new());
    for t in 0..frames {
        let demand = histories
            .iter()
            .map(|h| FrameDemand::pixel(&controller, h, 1.0, true))
            .fold(FrameDemand::default(), |a, b| a + b);
        demands.push(demand);
        match feed {
            Feed::Curve => {
                if let Some(&n) = totals.last() {
                    gov.observe(n);
                }
                let curve = DemandCurve::from_pixels(
                    &controller,
                    gov.curve_targets(),
                    histories.iter().map(|h| (h, 1.0, true)),
                );
                gov.plan_curve(&curve);
            }
            Feed::InFrame => {
                if let Some(&n) = totals.last() {
                    gov.observe(n);
                }
                gov.plan(&demand);
            }
            Feed::FeedbackOnly => {
                if let Some(&n) = totals.last() {
                    gov.observe(n);
                }
            }
            Feed::ReadBack => {
                if t >= 2 {
                    gov.observe(totals[t - 2]);
                    gov.plan(&demands[t - 1]);
                }
            }
        }
        let config = controller
            .to_builder()
            .target_variance(gov.target())
            .build()
            .expect("the governor's target is a valid target");
        let pixel = PixelController::new(config, Ccv);
        let light_t = light.intensity(t);
        let mut total = 0_u64;
        for (h, s) in histories.iter_mut().zip(&sigma) {
            let n = pixel.count(h, 1.0, true);
            total += u64::from(n);
            let noise = rng.normal() * s / f64::from(n).sqrt();
            let frame = PixelFrame {
                radiance: light_t * (1.0 + noise),
                preintegrated: light_t,
                gamma: 1.0,
            };
            pixel.update(h, &mut (), frame, n, true);
        }
        totals.push(total as f64);
    }
    let rel: Vec<f64> = totals[10..].iter().map(|n| n / budget - 1.0).collect();
    Outcome {
        within: rel.iter().filter(|r| r.abs() <= 0.1).count() as f64 / rel.len() as f64,
        worst: rel.iter().fold(0.0_f64, |m, r| m.max(r.abs())),
        mean_abs: rel.iter().map(|r| r.abs()).sum::<f64>() / rel.len() as f64,
        mean_spp: totals[10..].iter().sum::<f64>() / (rel.len() * pixels) as f64,
    }
}

#[test]
fn frame_total_tracks_the_budget_under_changing_light() {
    let frames = 240;
    for population in [Population::Smooth, Population::Bimodal] {
        for light in [Light::Flash, Light::Switch] {
            for (feed, damped) in [
                (Feed::Curve, None),
                (Feed::InFrame, None),
                (Feed::Curve, Some(0.35)),
                (Feed::InFrame, Some(0.35)),
                (Feed::FeedbackOnly, None),
                (Feed::ReadBack, None),
            ] {
                let o = simulate(light, population, feed, damped, frames);
                println!(
                    "{population:?} {light:?} {feed:?} damped {damped:?}: {:.1}% of frames \
                     within 10% of the budget after a 10-frame warm-up, worst |error| {:.1}%, \
                     mean |error| {:.2}%, mean {:.2} spp (budget 16)",
                    100.0 * o.within,
                    100.0 * o.worst,
                    100.0 * o.mean_abs,
                    o.mean_spp
                );
                // The clamp-aware feed-forward holds the band on both populations; the
                // unclamped one only where few pixels clamp.
                let must = damped.is_none()
                    && (feed == Feed::Curve
                        || (feed == Feed::InFrame && population == Population::Smooth));
                if must {
                    assert!(
                        o.within >= 0.95,
                        "{population:?} {light:?} {feed:?}: only {} of frames within 10% of \
                         the budget",
                        o.within
                    );
                }
            }
        }
    }
}

/// The frame functions take the configuration and the texel encoding separately: with
/// the encoding built once and the target moved by the governor across several powers of
/// two, `estimate_frame` still gives each pixel the count of the per-pixel estimate of the
/// decoded history, and a demand reduced over the decoded texels plans the target that
/// puts the frame's raw counts on the budget.
#[test]
fn frame_functions_read_a_fixed_encoding_under_a_moving_target() {
    use spvg::texel::{Rounding, SpvgTexel16, TexelEncoding, estimate_frame};
    let enc = TexelEncoding::new(1e-3).expect("valid");
    let mut rng = SplitMix64(7);
    let texels: Vec<SpvgTexel16> = (0..500)
        .map(|_| {
            let h = SpvgHistory {
                mean: 1.0_f32,
                variance: (1e-5 * (1e4_f64).powf(rng.next_f64())) as f32,
                mean_count: (8.0 + 56.0 * rng.next_f64()) as f32,
            };
            enc.encode(&h, Rounding::Nearest)
        })
        .collect();
    let decoded: Vec<SpvgHistory<f32>> = texels.iter().map(|t| enc.decode(*t)).collect();
    let (gamma, valid) = (vec![1.0_f32; texels.len()], vec![1_u8; texels.len()]);
    for (kappa, max_change) in [(0.0, None), (0.2, None), (0.0, Some(0.35))] {
        let controller = SpvgConfig::<f32>::builder()
            .kappa(kappa)
            .max_change(max_change)
            .budget(1, spvg::controller::MAX_BUDGET)
            .build()
            .expect("valid");
        for target in [3e-5_f32, 2.5e-4, 1e-3, 7e-3, 4e-2] {
            let config = controller
                .to_builder()
                .target_variance(target)
                .build()
                .expect("valid");
            let mut counts = vec![0_u32; texels.len()];
            estimate_frame(&config, &enc, &texels, &gamma, &valid, &mut counts)
                .expect("matching lengths");
            for (i, (n, h)) in counts.iter().zip(&decoded).enumerate() {
                assert_eq!(
                    *n,
                    config.estimate(h, 1.0),
                    "pixel {i}, target {target}, kappa {kappa}, max_change {max_change:?}"
                );
            }
        }
        if max_change.is_none() {
            let demand = decoded
                .iter()
                .map(|h| FrameDemand::pixel(&controller, h, 1.0, true))
                .fold(FrameDemand::default(), |a, b| a + b);
            let budget = 20.0 * texels.len() as f32;
            let mut gov =
                Governor::new(BudgetConfig::builder(budget).build().expect("valid"), 1e-3)
                    .expect("valid");
            let target = gov.plan(&demand);
            let config = controller
                .to_builder()
                .target_variance(target)
                .build()
                .expect("valid");
            let raw: f64 = decoded
                .iter()
                .map(|h| f64::from(config.raw_estimate(h)))
                .sum();
            let rel = (raw / f64::from(budget) - 1.0).abs();
            assert!(
                rel <= 1e-3,
                "kappa {kappa}: raw total {raw} != budget {budget} (rel {rel}, tol 1e-3, f32 sums)"
            );
        }
    }
}
