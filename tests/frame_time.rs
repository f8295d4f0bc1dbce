//! The frame-time governor against closed forms and a simulated pass whose cost is known:
//! the exact line once the totals spread, the pure-rate start's error recursion, the
//! target band on a noisy pass under a step, a ramp and an oscillation of its cost, the
//! unreachable targets with their modelled floor and ceiling, and inputs that change
//! nothing.

use spvg::budget::{BudgetConfig, Governor};
use spvg::frame_time::{FrameTimeConfig, FrameTimeGovernor, Reach};

const PIXELS: f64 = 1920.0 * 1080.0;
const MIN: f64 = PIXELS; // beta_min = 1
const MAX: f64 = 64.0 * PIXELS;

fn governor(target_ms: f64, forgetting: f64, initial: f64) -> FrameTimeGovernor<f64> {
    let cfg = FrameTimeConfig::builder(target_ms, MIN, MAX)
        .forgetting(forgetting)
        .build()
        .expect("valid config");
    FrameTimeGovernor::new(cfg, initial).expect("initial budget in range")
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

#[test]
fn an_affine_cost_is_learnt_exactly_once_the_totals_spread() {
    let (a, b, target) = (0.4, 2e-7, 2.0);
    let cost = |n: f64| a + b * n;
    let mut g = governor(target, 0.75, 8.0 * PIXELS);
    assert_eq!(g.reach(), Reach::Unknown);
    let n0 = g.budget();
    assert!(g.observe(n0, cost(n0)));
    // One frame: a pure rate through it, so the budget scales by target / time.
    let expected = n0 * target / cost(n0);
    assert!(
        close(g.budget(), expected, 1e-12),
        "{} {expected}",
        g.budget()
    );
    let n1 = g.budget();
    assert!(g.observe(n1, cost(n1)));
    let m = g.model().expect("a model");
    assert!(close(m.fixed_ms, a, 1e-9), "fixed {}", m.fixed_ms);
    assert!(close(m.ms_per_sample, b, 1e-9), "rate {}", m.ms_per_sample);
    assert!(close(cost(g.budget()), target, 1e-9));
    assert_eq!(g.reach(), Reach::Reachable);
    // It stays exact while the totals stop moving (the spread fades with the forgetting).
    for _ in 0..50 {
        let n = g.budget();
        g.observe(n, cost(n));
    }
    assert!(close(cost(g.budget()), target, 1e-9));
}

#[test]
fn from_a_pure_rate_start_the_error_shrinks_by_the_fixed_share() {
    // Forgetting 0 remembers one frame: never a spread, always the pure-rate rule, whose
    // error obeys ms' - T = a (ms - T) / ms for a cost a + b n.
    let (a, b, target) = (0.5, 1e-7, 3.0);
    let cost = |n: f64| a + b * n;
    let mut g = governor(target, 0.0, 4.0 * PIXELS);
    let mut ms = cost(g.budget());
    for k in 0..8 {
        g.observe(g.budget(), ms);
        let next = cost(g.budget());
        let predicted = target + a * (ms - target) / ms;
        assert!(
            close(next, predicted, 1e-9),
            "frame {k}: {next} against {predicted}"
        );
        ms = next;
    }
    assert!((ms - target).abs() < 1e-6 * target);
}

/// A deterministic uniform number in [-1, 1) (splitmix64 of `i`).
fn noise(i: u64) -> f64 {
    let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Frames of a simulated pass after `warmup` whose time is within 10% of the target, as
/// a share: the pass takes `rate(t)` ms per sample plus a fixed 0.3 ms, its time has 3%
/// noise, and the budget governor meets a budget within 5%.
fn band(rate: impl Fn(u32) -> f64, target: f64, frames: u32, warmup: u32) -> f64 {
    let mut g = governor(target, 0.75, 8.0 * PIXELS);
    let mut inside = 0;
    for t in 0..frames {
        let n = g.budget() * (1.0 + 0.05 * noise(2 * u64::from(t)));
        let ms = (0.3 + rate(t) * n) * (1.0 + 0.03 * noise(2 * u64::from(t) + 1));
        assert!(g.observe(n, ms), "frame {t}: ({n}, {ms}) refused");
        if t >= warmup && (ms / target - 1.0).abs() <= 0.1 {
            inside += 1;
        }
    }
    f64::from(inside) / f64::from(frames - warmup)
}

#[test]
fn a_noisy_pass_stays_in_the_band() {
    let steady = band(|_| 1e-7, 1.5, 300, 10);
    assert!(steady >= 0.95, "steady: {steady}");
    // The cost per sample doubles at frame 100 and halves again at 200 (a light switched
    // on and off changes what a sample costs): a few frames out at each step.
    let switch = band(
        |t| if (100..200).contains(&t) { 2e-7 } else { 1e-7 },
        1.5,
        300,
        10,
    );
    assert!(switch >= 0.9, "switch: {switch}");
    // A slow drift: +0.5% per frame (a pan bringing costlier surface into view).
    let pan = band(|t| 1e-7 * 1.005_f64.powi(t as i32), 1.5, 300, 10);
    assert!(pan >= 0.9, "pan: {pan}");
}

#[test]
fn unreachable_targets_are_reported_with_the_modelled_bound() {
    let (a, b) = (2.0, 1e-7);
    let cost = |n: f64| a + b * n;
    // Below the fixed cost: no budget meets 1.5 ms.
    let mut g = governor(1.5, 0.75, 8.0 * PIXELS);
    for _ in 0..6 {
        let n = g.budget();
        g.observe(n, cost(n));
    }
    assert_eq!(g.budget(), MIN);
    match g.reach() {
        Reach::BelowFloor { floor_ms } => {
            let m = g.model().expect("a model");
            assert!(close(floor_ms, m.ms(MIN), 1e-12));
            assert!(floor_ms > 1.5);
        }
        r => panic!("expected BelowFloor, got {r:?}"),
    }
    // Above what the most samples cost: the budget is the largest.
    let mut g = governor(1e4, 0.75, 8.0 * PIXELS);
    for _ in 0..6 {
        let n = g.budget();
        g.observe(n, cost(n));
    }
    assert_eq!(g.budget(), MAX);
    match g.reach() {
        Reach::AboveCeiling { ceiling_ms } => {
            assert!(close(ceiling_ms, cost(MAX), 1e-6), "{ceiling_ms}");
        }
        r => panic!("expected AboveCeiling, got {r:?}"),
    }
    // A reachable target again: the learnt cost steers at once.
    g.set_target_ms(5.0).expect("valid target");
    assert_eq!(g.reach(), Reach::Reachable);
    assert!(close(cost(g.budget()), 5.0, 1e-6));
}

#[test]
fn bad_inputs_change_nothing_and_bad_parameters_are_named() {
    let mut g = governor(1.5, 0.75, 8.0 * PIXELS);
    g.observe(8.0 * PIXELS, 2.0);
    let before = g;
    for (n, ms) in [
        (f64::NAN, 1.0),
        (1e6, f64::NAN),
        (f64::INFINITY, 1.0),
        (1e6, f64::INFINITY),
        (-1.0, 1.0),
        (1e6, 0.0),
        (1e6, -1.0),
    ] {
        assert!(!g.observe(n, ms), "({n}, {ms}) accepted");
        assert_eq!(g, before);
    }
    assert!(g.set_target_ms(f64::NAN).is_err());
    assert_eq!(g, before);
    let named = |e: spvg::Error, name: &str| assert!(e.to_string().contains(name), "{e}");
    named(
        FrameTimeConfig::builder(0.0, MIN, MAX).build().unwrap_err(),
        "target_ms",
    );
    named(
        FrameTimeConfig::builder(1.0, f64::NAN, MAX)
            .build()
            .unwrap_err(),
        "min_budget",
    );
    named(
        FrameTimeConfig::builder(1.0, MIN, f64::INFINITY)
            .build()
            .unwrap_err(),
        "max_budget",
    );
    named(
        FrameTimeConfig::builder(1.0, MAX, MIN).build().unwrap_err(),
        "min_budget",
    );
    named(
        FrameTimeConfig::builder(1.0, MIN, MAX)
            .forgetting(1.0)
            .build()
            .unwrap_err(),
        "forgetting",
    );
    let cfg = FrameTimeConfig::builder(1.0, MIN, MAX)
        .build()
        .expect("valid");
    named(
        FrameTimeGovernor::new(cfg, 0.5 * MIN).unwrap_err(),
        "initial_budget",
    );
}

#[test]
fn the_budget_governor_takes_the_frame_time_budget() {
    let cfg = BudgetConfig::builder(8.0 * PIXELS).build().expect("valid");
    let mut spp = Governor::new(cfg, 1e-3).expect("valid");
    spp.set_budget(12.0 * PIXELS).expect("positive budget");
    assert_eq!(spp.config().budget(), 12.0 * PIXELS);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = spp.set_budget(bad).unwrap_err();
        assert!(e.to_string().contains("budget"), "{e}");
        assert_eq!(spp.config().budget(), 12.0 * PIXELS);
    }
    // Observing the new budget exactly leaves the correction where it was.
    let c = spp.correction();
    spp.observe(12.0 * PIXELS);
    assert_eq!(spp.correction(), c);
}

/// A simulated pass whose total follows the target variance, `N = K / sigma0^2` clamped
/// to the budget range: the chained governors bring its time to the target.
#[test]
fn the_chain_steers_the_target_variance_to_the_pass_time() {
    use spvg::frame_time::FrameTimeSteering;
    let (a, b, target, k) = (0.3, 1e-7, 1.2, 8.0 * PIXELS * 1e-3);
    let cost = |n: f64| a + b * n;
    let time = governor(target, 0.75, 8.0 * PIXELS);
    let spp = Governor::new(
        BudgetConfig::builder(8.0 * PIXELS).build().expect("valid"),
        1e-3,
    )
    .expect("valid");
    let mut s = FrameTimeSteering::new(time, spp).expect("chain");
    let mut last = 0.0;
    for _ in 0..60 {
        let n = (k / s.target()).clamp(MIN, MAX);
        last = cost(n);
        s.after_frame(n, last);
    }
    assert!(
        (last / target - 1.0).abs() < 0.01,
        "time {last} against {target}"
    );
    assert!(close(s.spp().config().budget(), s.time().budget(), 1e-12));
    let before = s;
    assert_eq!(s.after_frame(1e6, f64::NAN), before.target());
    assert_eq!(s, before);
}
