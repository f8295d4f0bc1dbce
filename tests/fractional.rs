//! Fractional counts (`spvg::controller::fractional`, docs/algorithms.md §8.6) against
//! independent references: the real count itself for the mean of the realised counts,
//! the integer rule where the feature is off or the count is at least one, the
//! per-sample variance over the target for a simulated pixel's steady count, and the
//! stored history's finiteness on hard inputs.

mod common;

use common::splitmix::SplitMix64;
use proptest::prelude::*;
use spvg::controller::CountPolicy;
use spvg::controller::fractional::{
    REVISIT_COUNT, REVISIT_FRAMES, fractional_raw_count, realise_count, recorded_count,
};
use spvg::controller::rules::EstimateUniforms;
use spvg::sequence::dither_threshold;
use spvg::{Error, SpvgConfig, SpvgHistory};

/// The realised counts of `c` summed over `frames` frames at one pixel, or over a
/// `k x k` window in one frame, or both, starting at `(px, py, t)`.
fn realised_sum(c: f32, [px, py, t]: [u32; 3], k: u32, frames: u32) -> u64 {
    let mut sum = 0_u64;
    for f in 0..frames {
        for y in 0..k {
            for x in 0..k {
                let xi =
                    dither_threshold(px.wrapping_add(x), py.wrapping_add(y), t.wrapping_add(f));
                sum += u64::from(realise_count(c, xi));
            }
        }
    }
    sum
}

/// Real counts from 0 to 64: uniform, and next to the integers (the fraction near 0 or
/// 1, where a rounding mistake shows).
fn real_counts() -> impl Strategy<Value = f32> {
    prop_oneof![
        0.0_f32..64.0,
        (0_u32..64, 0_u32..4).prop_map(|(w, k)| w as f32 + f32::EPSILON * (k as f32 + 1.0)),
        (1_u32..64).prop_map(|w| w as f32 - 1e-4),
        (0_u32..64).prop_map(|w| w as f32),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The mean of the realised counts converges to the real count over frames at one
    /// pixel, over the pixels of a window in one frame, and over both: the total differs
    /// from `N c` by a few samples at most whatever `N` (an i.i.d. threshold's would grow
    /// as `sqrt(N c (1 - c))`, 8 at `N = 256`), so the mean is within `3 / N` of `c`.
    #[test]
    fn realised_counts_converge_to_the_real_count(
        c in real_counts(),
        origin in any::<[u32; 3]>(),
    ) {
        let want = f64::from(c);
        for frames in [4_u32, 16, 64, 256, 1024] {
            let n = realised_sum(c, origin, 1, frames) as f64;
            let err = (n - want * f64::from(frames)).abs();
            prop_assert!(err <= 3.0, "{frames} frames: {n} samples for c = {c} (err {err})");
        }
        for k in [2_u32, 3, 4, 8] {
            let n = realised_sum(c, origin, k, 1) as f64;
            let err = (n - want * f64::from(k * k)).abs();
            prop_assert!(err <= 3.0, "{k}x{k}: {n} samples for c = {c} (err {err})");
        }
        let n = realised_sum(c, origin, 4, 16) as f64;
        let err = (n - want * 256.0).abs();
        prop_assert!(err <= 7.0, "4x4x16: {n} samples for c = {c} (err {err})");
    }

    /// Each realised count is `floor(c)` or `floor(c) + 1`, and an integer `c` is
    /// realised as itself whatever the threshold.
    #[test]
    fn realised_count_brackets_the_real_count(c in real_counts(), xi in any::<u32>()) {
        let n = realise_count(c, xi);
        let floor = c.floor() as u32;
        prop_assert!(n == floor || n == floor + 1, "{n} for c = {c}");
        if c.fract() == 0.0 {
            prop_assert_eq!(n, floor);
        }
        prop_assert_eq!(realise_count(f64::from(c), xi), n, "f64 and f32 agree");
    }
}

/// Non-finite and out-of-range real counts never panic: NaN and anything not above 0
/// realise 0 samples, anything at or above `2^32` the largest count.
#[test]
fn realise_is_total() {
    for xi in [0, 1 << 31, u32::MAX] {
        assert_eq!(realise_count(f32::NAN, xi), 0);
        assert_eq!(realise_count(-1.0_f32, xi), 0);
        assert_eq!(realise_count(-0.0_f32, xi), 0);
        assert_eq!(realise_count(f32::INFINITY, xi), u32::MAX);
        assert_eq!(realise_count(4_294_967_296.0_f32, xi), u32::MAX);
        assert_eq!(realise_count(f32::MAX, xi), u32::MAX);
    }
}

fn fractional(floor: f32) -> SpvgConfig<f32> {
    SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .fractional_floor(Some(floor))
        .build()
        .expect("valid")
}

/// A deterministic stream of histories, samples and counts covering the budget.
fn histories(k: u32) -> (SpvgHistory<f32>, f32, u32, bool) {
    let mut g = SplitMix64(u64::from(k) * 7919 + 1);
    let h = SpvgHistory {
        mean: g.next_f64() as f32,
        variance: (g.next_f64() * 1e-2) as f32,
        mean_count: (g.next_f64() * 70.0) as f32,
    };
    (
        h,
        g.next_f64() as f32,
        (g.next_u64() % 70) as u32,
        !k.is_multiple_of(3),
    )
}

/// Without a fractional floor, the fractional estimate and update are the integer
/// rules bit for bit.
#[test]
fn off_is_the_integer_rule() {
    let c = SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .build()
        .expect("valid");
    for k in 0..4000 {
        let (h, s, n, valid) = histories(k);
        let xi = dither_threshold(k, k / 7, k / 3);
        let f = c.estimate_fractional(&h, 1.0, valid, xi);
        assert_eq!(f.count, c.estimate_with_validity(&h, 1.0, valid), "{h:?}");
        assert_eq!(f.real, None);
        let (mut a, mut b, mut age_a, mut age_b) = (h, h, k % 5, k % 5);
        let guide = if k.is_multiple_of(2) {
            f32::NAN
        } else {
            s * 0.9
        };
        let ra = c.update_fractional(&mut a, &mut age_a, s, guide, n, None, valid, None);
        let rb = c.update_young_guided(&mut b, &mut age_b, s, guide, n, valid, None);
        assert_eq!((ra, age_a), (rb, age_b));
        assert_eq!(
            [a.mean, a.variance, a.mean_count].map(f32::to_bits),
            [b.mean, b.variance, b.mean_count].map(f32::to_bits),
            "{h:?}, s = {s}, n = {n}"
        );
    }
}

/// At or above one sample a frame the fractional raw count is the published SPVG count
/// with `kappa = 0` (the expected count `E = r nbar`) bit for bit; below one it is `r`,
/// the count of a sampled frame being one; continuous across one sample.
#[test]
fn fractional_count_is_the_expected_count() {
    let c = fractional(0.0);
    let u = EstimateUniforms::new(&c);
    let no_lag = c
        .to_builder()
        .kappa(0.0)
        .fractional_floor(None)
        .build()
        .expect("valid");
    for k in 0..20_000 {
        let (h, ..) = histories(k);
        let got = fractional_raw_count(&u, h.variance, h.mean_count, 1.0);
        let sampled = SpvgHistory {
            mean_count: h.mean_count.max(1.0),
            ..h
        };
        assert_eq!(
            got.to_bits(),
            no_lag.raw_estimate(&sampled).to_bits(),
            "{h:?}"
        );
    }
    let below = fractional_raw_count(&u, 0.7e-3, 1.0 - 1e-6, 1.0);
    let above = fractional_raw_count(&u, 0.7e-3, 1.0 + 1e-6, 1.0);
    assert!((below - above).abs() < 1e-5, "{below} vs {above}");
}

/// One simulated pixel: the monitored value of a frame is the mean of its `n` samples,
/// each normal with variance `v1`; the count follows `config`'s rule from a seed. Returns
/// each frame's realised count and its real-valued count (`None` where the rule is integer).
fn simulated_counts(
    config: &SpvgConfig<f64>,
    v1: f64,
    frames: u32,
    seed: u64,
) -> Vec<(u32, Option<f64>)> {
    let mut g = SplitMix64(seed);
    let (mut h, mut age, mut valid) = (SpvgHistory::default(), 0, false);
    let mut out = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let xi = (g.next_u64() >> 32) as u32;
        let fc = config.estimate_fractional(&h, 1.0, valid, xi);
        let s = if fc.count == 0 {
            f64::NAN
        } else {
            0.5 + (v1 / f64::from(fc.count)).sqrt() * g.normal()
        };
        config.update_fractional(
            &mut h,
            &mut age,
            s,
            f64::NAN,
            fc.count,
            fc.real,
            valid,
            None,
        );
        valid = true;
        out.push((fc.count, fc.real));
    }
    out
}

/// The mean real count of one simulated pixel over the frames after `warm`.
fn steady_count(config: &SpvgConfig<f64>, v1: f64, frames: u32, warm: u32, seed: u64) -> f64 {
    let counts = simulated_counts(config, v1, frames, seed);
    let steady = &counts[warm as usize..];
    let sum: f64 = steady
        .iter()
        .map(|&(n, real)| real.unwrap_or(f64::from(n)))
        .sum();
    sum / steady.len() as f64
}

/// The rule's steady count is the per-sample variance over the target, below one sample
/// as above it, within 15% (the EMV's own bias, its steady variance about the moving
/// mean being `2 (1 - w) / (2 - w)` of the true one, and the noise of a finite run): the
/// count neither collapses to the floor (as it does with the mean count read as `c < 1`)
/// nor sticks at one sample, nor is it inflated by an oscillation.
#[test]
fn steady_count_follows_the_per_sample_variance() {
    let target = 1e-3;
    let config = SpvgConfig::<f64>::builder()
        .target_variance(target)
        .spatial_variance(0)
        .fractional_floor(Some(0.0))
        .build()
        .expect("valid");
    for ratio in [0.15, 0.3, 0.6, 3.0, 12.0] {
        let got = steady_count(&config, ratio * target, 20_000, 500, 7);
        let rel = got / ratio;
        assert!(
            (0.85..1.15).contains(&rel),
            "ratio {ratio}: steady count {got} (rel {rel})"
        );
    }
}

/// A skipped frame keeps the mean, the variance and the age, moves the mean count
/// towards the real count with the history's weight, and absorbs nothing; a sampled
/// frame records the real count, or the count where the dither cannot have given it.
#[test]
fn skipped_frame_keeps_the_statistics() {
    let c = SpvgConfig::<f64>::builder()
        .eta(0.25)
        .target_variance(1e-3)
        .spatial_variance(0)
        .fractional_floor(Some(0.0))
        .build()
        .expect("valid");
    let h0 = SpvgHistory {
        mean: 0.4,
        variance: 2e-3,
        mean_count: 2.0,
    };
    let (mut h, mut age) = (h0, 6);
    assert!(!c.update_fractional(&mut h, &mut age, 9.0, 0.1, 0, Some(0.4), true, None));
    assert_eq!((h.mean, h.variance, age), (h0.mean, h0.variance, 6));
    assert_eq!(h.mean_count, 0.75 * 2.0 + 0.25 * 0.4);
    // The dither's outcome (0 or 1 for c = 0.4) records c ...
    let mut one = h0;
    assert!(c.update_fractional(&mut one, &mut age, 0.5, f64::NAN, 1, Some(0.4), true, None));
    assert_eq!(one.mean_count, 0.75 * 2.0 + 0.25 * 0.4);
    // ... a count the dither cannot give (dilated to 5) records the count.
    let mut five = h0;
    assert!(c.update_fractional(&mut five, &mut age, 0.5, f64::NAN, 5, Some(0.4), true, None));
    assert_eq!(five.mean_count, 0.75 * 2.0 + 0.25 * 5.0);
    assert_eq!(recorded_count(1.5_f64, 2), 1.5);
    assert_eq!(recorded_count(1.5_f64, 3), 3.0);
    assert_eq!(recorded_count(-1.0_f64, 3), 3.0);
    assert_eq!(recorded_count(f64::NAN, 3), 3.0);
    // Without history the frame seeds from its samples as ever; no sample, no seed.
    let mut fresh = SpvgHistory::default();
    assert!(!c.update_fractional(
        &mut fresh,
        &mut age,
        0.5,
        f64::NAN,
        0,
        Some(0.4),
        false,
        None
    ));
    assert_eq!((fresh, age), (SpvgHistory::default(), 0));
}

/// Hard inputs (non-finite and negative samples, guides and real counts; saturated and
/// tiny stored numbers) never turn a history the update can store into a non-finite one
/// or a negative mean count, and the real count of any stored history (NaN, infinite and
/// negative included) is finite and at least the floor. (A history already out of range
/// is what a refused frame keeps as it is; the estimate reads it defensively.)
#[test]
fn nothing_non_finite_is_stored() {
    let hard = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        -f32::MAX,
        0.0,
        -0.0,
        1e-45,
        1e30,
        -1.0,
        0.5,
        3.0,
    ];
    for floor in [0.0, 0.3, 8.0] {
        let c = fractional(floor);
        for &m in &hard {
            for &v in &hard {
                for &nbar in &hard {
                    let h = SpvgHistory {
                        mean: m,
                        variance: v,
                        mean_count: nbar,
                    };
                    let real = c.real_count(&h);
                    assert!(real.is_finite() && real >= floor, "{real} from {h:?}");
                    // What the update can have stored: finite, with a variance and a mean
                    // count that are not negative.
                    if !(m.is_finite()
                        && v.is_finite()
                        && nbar.is_finite()
                        && v >= 0.0
                        && nbar >= 0.0)
                    {
                        continue;
                    }
                    for &s in &hard {
                        for &r in &hard {
                            for n in [0, 1, 7] {
                                let (mut x, mut age) = (h, 3);
                                c.update_fractional(&mut x, &mut age, s, r, n, Some(r), true, None);
                                let ok = [x.mean, x.variance, x.mean_count]
                                    .iter()
                                    .all(|v| v.is_finite());
                                assert!(
                                    ok && x.mean_count >= 0.0,
                                    "{x:?} from {h:?}, s {s}, real {r}, n {n}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The floor is validated with errors naming it; NaN and infinities are refused.
#[test]
fn floor_is_validated() {
    let build = |f: f32| {
        SpvgConfig::<f32>::builder()
            .fractional_floor(Some(f))
            .build()
    };
    for bad in [f32::NAN, f32::INFINITY, -f32::INFINITY, -0.1, 8.01, 100.0] {
        match build(bad) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "fractional_floor"),
            other => panic!("{bad}: {other:?}"),
        }
    }
    for good in [0.0, 0.25, 1.0, 8.0] {
        let c = build(good).expect("valid");
        // The floor in use is never below the revisit count, 1/32.
        assert_eq!(
            (c.fractional_floor(), c.floor_f()),
            (Some(good), good.max(1.0 / 32.0))
        );
    }
    let e = SpvgConfig::<f32>::builder()
        .budget(1, 2)
        .fractional_floor(Some(3.0))
        .build()
        .unwrap_err();
    assert!(e.to_string().contains("fractional_floor"), "{e}");
    let e = SpvgConfig::<f32>::builder()
        .max_change(Some(0.35))
        .fractional_floor(Some(0.5))
        .build()
        .unwrap_err();
    assert!(e.to_string().contains("max_change"), "{e}");
    // Off: the floor of a real count is the integer floor.
    assert_eq!(SpvgConfig::<f32>::published().floor_f(), 8.0);
}

/// `Fixed(n)` takes `n` samples with or without fractional counts, and its real count
/// is `n`.
#[test]
fn fixed_policy_takes_its_count() {
    let c = SpvgConfig::<f32>::builder()
        .budget(1, 64)
        .policy(CountPolicy::Fixed(5))
        .fractional_floor(Some(0.5))
        .build()
        .expect("valid");
    for xi in [0, 1 << 31, u32::MAX] {
        let f = c.estimate_fractional(&SpvgHistory::default(), 1.0, true, xi);
        assert_eq!((f.count, f.real), (5, Some(5.0)));
    }
}

/// Mean count and mean `|n_t - n_(t-1)|` of one simulated pixel ([`simulated_counts`])
/// over the frames after the 500th, under `config`'s integer estimate (fractional counts
/// off) or fractional one (on).
fn count_series(config: &SpvgConfig<f64>, v1: f64, frames: u32, seed: u64) -> (f64, f64) {
    let counts: Vec<f64> = simulated_counts(config, v1, frames, seed)[500..]
        .iter()
        .map(|&(n, _)| f64::from(n))
        .collect();
    let k = counts.len() as f64;
    let steps: f64 = counts.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
    (counts.iter().sum::<f64>() / k, steps / (k - 1.0))
}

/// Why fractional counts drop the lag correction: with the published rule and an integer
/// floor of 1, a pixel whose per-sample variance asks for 3 samples spends far more
/// (the correction amplifies the moving variance's noise into counts that swing by more
/// than their mean, and the swings cost more samples than they save); the fractional rule
/// spends about the per-sample ratio and changes its realised count by a fraction of it.
#[test]
fn the_lag_correction_oscillates_at_low_counts() {
    let target = 1e-3;
    let published = SpvgConfig::<f64>::builder()
        .target_variance(target)
        .budget(1, 64)
        .spatial_variance(0)
        .build()
        .expect("valid");
    let fractional = published
        .to_builder()
        .fractional_floor(Some(0.0))
        .build()
        .expect("valid");
    let (np, sp) = count_series(&published, 3.0 * target, 20_000, 11);
    let (nf, sf) = count_series(&fractional, 3.0 * target, 20_000, 11);
    eprintln!(
        "published [1, 64]: mean {np:.2}, |dn| {sp:.2}; fractional: mean {nf:.2}, |dn| {sf:.2}"
    );
    assert!(np > 2.0 * nf, "published mean count {np} against {nf}");
    assert!(sp > 3.0 * sf, "published oscillation {sp} against {sf}");
    assert!((2.5..3.5).contains(&nf), "fractional mean count {nf}");
}

/// The longest run of frames between two frames whose dither threshold at `(px, py)` lies
/// below `limit` (in units of 2^-24, as the realised count compares it), over `frames`
/// frames from `t0`: walked frame by frame, independent of the three-gap argument that
/// gives [`REVISIT_FRAMES`].
fn longest_gap(px: u32, py: u32, t0: u32, frames: u32, limit: u32) -> u32 {
    let (mut last, mut longest) = (None, 0);
    for t in 0..frames {
        if dither_threshold(px, py, t0.wrapping_add(t)) >> 8 < limit {
            if let Some(l) = last {
                longest = longest.max(t - l);
            }
            last = Some(t);
        }
    }
    longest
}

/// Floor 0 never stalls: the revisit count is 1/32 and, at 1/32, the dither's thresholds
/// come below it at least once in every [`REVISIT_FRAMES`] frames at every pixel, a bound
/// that some pixel meets exactly; and a simulated frame of converged pixels (variance 0,
/// floor 0) samples every pixel within the bound, at about 1/32 sample per pixel a frame.
#[test]
fn floor_zero_revisits_every_pixel_within_the_bound() {
    assert_eq!(REVISIT_COUNT, 1.0 / 32.0);
    let limit = 1 << 19; // 1/32 in units of 2^-24.
    let mut worst = 0;
    for (px, py) in (0..64).flat_map(|y| (0..64).map(move |x| (x * 37, y * 11))) {
        worst = worst.max(longest_gap(px, py, px ^ py, 600, limit));
    }
    assert_eq!(worst, REVISIT_FRAMES, "the bound is exact over 4096 pixels");

    let c = SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .fractional_floor(Some(0.0))
        .build()
        .expect("valid");
    // A converged pixel: its variance reads 0, so only the floor keeps it sampling.
    let h = SpvgHistory {
        mean: 0.5,
        variance: 0.0,
        mean_count: 0.05,
    };
    let (w, frames) = (48_u32, 400_u32);
    let mut last = vec![0_u32; (w * w) as usize];
    let mut samples = 0_u64;
    for t in 1..=frames {
        for y in 0..w {
            for x in 0..w {
                let f = c.estimate_fractional(&h, 1.0, true, dither_threshold(x, y, t));
                assert_eq!(f.real, Some(1.0 / 32.0));
                let i = (y * w + x) as usize;
                if f.count > 0 {
                    last[i] = t;
                    samples += u64::from(f.count);
                }
                assert!(
                    t - last[i] <= REVISIT_FRAMES,
                    "pixel ({x}, {y}) went {} frames without a sample",
                    t - last[i]
                );
            }
        }
    }
    let mean = samples as f64 / f64::from(w * w * frames);
    assert!((mean - 1.0 / 32.0).abs() < 0.002, "mean count {mean}");
}

/// The resolve weight is validated with errors naming it, and needs fractional counts.
#[test]
fn resolve_weight_is_validated() {
    let build = |a: f32| {
        SpvgConfig::<f32>::builder()
            .fractional_floor(Some(0.0))
            .resolve_weight(Some(a))
            .build()
    };
    for bad in [f32::NAN, f32::INFINITY, 0.0, -0.1, 1.01] {
        match build(bad) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "resolve_weight"),
            other => panic!("{bad}: {other:?}"),
        }
    }
    for good in [0.01, 0.1, 1.0] {
        assert_eq!(build(good).expect("valid").resolve_weight(), Some(good));
    }
    let e = SpvgConfig::<f32>::builder()
        .resolve_weight(Some(0.1))
        .build()
        .unwrap_err();
    assert!(e.to_string().contains("fractional_floor"), "{e}");
}

/// The resolved-image rule gives the *resolved* image the target variance: a simulated
/// pixel (each sample normal with variance `v1`) whose frames a resolve blends with the
/// weight `a` onto its history (`y = (1 - a) y + a S`, every frame sampled: `v1` asks
/// for about two samples a frame after the resolve) ends with the resolved value's
/// variance at `sigma0^2` as closely as the per-frame rule's resolved variance is at
/// `a / (2 - a) sigma0^2` (both overshoot by the moving variance's bias), at about
/// `a / (2 - a)` of the per-frame rule's samples. The variance is measured over
/// independent pixels, not read from the controller.
#[test]
fn resolved_rule_meets_the_target_after_the_resolve() {
    let (target, alpha, v1) = (1e-3, 0.1, 0.04);
    let base = SpvgConfig::<f64>::builder()
        .target_variance(target)
        .budget(1, 64)
        .spatial_variance(0)
        .fractional_floor(Some(0.0));
    let per_frame = base.build().expect("valid");
    let resolved = base.resolve_weight(Some(alpha)).build().expect("valid");
    let run = |config: &SpvgConfig<f64>| {
        let (pixels, frames) = (1000_u32, 300_u32);
        let (mut sum, mut sum2, mut spp) = (0.0, 0.0, 0.0);
        for p in 0..pixels {
            let mut g = SplitMix64(u64::from(p) * 7919 + 3);
            let (mut h, mut age, mut valid) = (SpvgHistory::default(), 0_u32, false);
            let mut y = 0.0;
            for t in 0..frames {
                let xi = dither_threshold(p, 0, t);
                let fc = config.estimate_resolved(&h, age, 1.0, valid, xi, f64::NAN);
                let n = fc.count.max(1);
                let s = 0.5 + (v1 / f64::from(n)).sqrt() * g.normal();
                let a = if t == 0 {
                    1.0
                } else {
                    alpha.max(1.0 / f64::from(t + 1))
                };
                y = (1.0 - a) * y + a * s;
                config.update_fractional(&mut h, &mut age, s, f64::NAN, n, fc.real, valid, None);
                valid = true;
                if t + 1 == frames {
                    sum += y;
                    sum2 += y * y;
                }
                if t >= frames - 100 {
                    spp += f64::from(n) / 100.0;
                }
            }
        }
        let k = f64::from(pixels);
        let mean = sum / k;
        ((sum2 / k - mean * mean) * k / (k - 1.0), spp / k)
    };
    let (var_r, spp_r) = run(&resolved);
    let (var_f, spp_f) = run(&per_frame);
    let factor = alpha / (2.0 - alpha);
    eprintln!(
        "resolved: variance {var_r:.3e} at {spp_r:.2} spp; per frame: {var_f:.3e} at {spp_f:.2} spp"
    );
    // Both rules overshoot their aim alike: the moving variance reads about
    // 2 (1 - eta) / (2 - eta) = 0.89 of the true one, and the count's noise costs more
    // variance than it saves (E[1/n] > 1/E[n]). The resolved rule's resolved variance
    // against its target matches the per-frame rule's against the variance the resolve
    // leaves it.
    let (rel_r, rel_f) = (var_r / target, var_f / (factor * target));
    assert!((0.9..1.4).contains(&rel_r), "resolved variance {var_r}");
    assert!(
        (rel_r / rel_f - 1.0).abs() < 0.15,
        "resolved rule {rel_r} of its target, per-frame rule {rel_f}"
    );
    assert!(
        (spp_r / spp_f / factor - 1.0).abs() < 0.25,
        "spp {spp_r} against {spp_f}"
    );
}
