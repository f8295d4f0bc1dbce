//! The TAA-guided update (`SpvgConfig::update_guided`, the dissertation's Eq. 4.4,
//! docs/algorithms.md §8.5) against the unguided rule and closed forms: with the guide
//! equal to the history's mean it is `update` bit for bit; a non-finite guide is `update`;
//! a constant guide gives the geometric sum of the squared deviations from it; the mean
//! and the mean count never depend on the guide; the seed and refused frames are
//! `update`'s; and the stationary variance is `(1 - eta) s^2` about the true mean against
//! `2 (1 - eta) / (2 - eta) s^2` about the pixel's own EMA.

mod common;

use common::splitmix::SplitMix64;
use spvg::{SpvgConfig, SpvgHistory};

fn config(eta: f64, firefly: Option<f64>) -> SpvgConfig<f64> {
    SpvgConfig::<f64>::builder()
        .eta(eta)
        .target_variance(1e-4)
        .firefly_clamp(firefly)
        .build()
        .expect("valid")
}

fn random_history(g: &mut SplitMix64) -> SpvgHistory<f64> {
    SpvgHistory {
        mean: g.next_f64() * 4.0 - 1.0,
        variance: g.next_f64() * 0.1,
        mean_count: 8.0 + g.next_f64() * 56.0,
    }
}

#[test]
fn guide_at_the_mean_is_the_unguided_update_bit_for_bit() {
    let mut g = SplitMix64(7);
    for firefly in [None, Some(4.0)] {
        for eta in [0.05, 0.2, 0.5, 1.0] {
            let c = config(eta, firefly);
            let cf = SpvgConfig::<f32>::builder()
                .eta(eta as f32)
                .target_variance(1e-4)
                .firefly_clamp(firefly.map(|k| k as f32))
                .build()
                .expect("valid");
            for _ in 0..2000 {
                let h0 = random_history(&mut g);
                let s = h0.mean + g.normal() * 0.3;
                let count = (g.next_u64() % 65) as u32;
                let valid = !g.next_u64().is_multiple_of(4);
                let (mut a, mut b) = (h0, h0);
                let ra = c.update(&mut a, s, count, valid);
                let rb = c.update_guided(&mut b, s, h0.mean, count, valid);
                assert_eq!((a, ra), (b, rb), "f64 {h0:?} s={s} n={count} valid={valid}");
                let hf = SpvgHistory {
                    mean: h0.mean as f32,
                    variance: h0.variance as f32,
                    mean_count: h0.mean_count as f32,
                };
                let (mut a, mut b) = (hf, hf);
                let ra = cf.update(&mut a, s as f32, count, valid);
                let rb = cf.update_guided(&mut b, s as f32, hf.mean, count, valid);
                assert_eq!((a, ra), (b, rb), "f32 {hf:?} s={s} n={count} valid={valid}");
            }
        }
    }
}

#[test]
fn non_finite_guide_falls_back_to_the_unguided_update() {
    let mut g = SplitMix64(11);
    let c = config(0.2, None);
    for _ in 0..500 {
        let h0 = random_history(&mut g);
        let s = h0.mean + g.normal() * 0.3;
        for guide in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (mut a, mut b) = (h0, h0);
            assert!(c.update(&mut a, s, 16, true));
            assert!(c.update_guided(&mut b, s, guide, 16, true));
            assert_eq!(a, b, "guide {guide}");
            assert!(b.variance.is_finite() && b.mean.is_finite());
        }
    }
}

#[test]
fn constant_guide_gives_the_geometric_sum_of_squared_deviations() {
    // var_t = (1 - eta)^t var_0 + sum_k eta (1 - eta) (x_k - C)^2 (1 - eta)^(t - 1 - k),
    // evaluated here as a sum rather than the recurrence.
    let (eta, centre) = (0.2_f64, 0.75_f64);
    let c = config(eta, None);
    let mut g = SplitMix64(3);
    let xs: Vec<f64> = (0..60).map(|_| centre + 0.1 * g.normal() + 0.02).collect();
    let var0 = 3e-3;
    let mut h = SpvgHistory {
        mean: 0.5,
        variance: var0,
        mean_count: 16.0,
    };
    for (t, &x) in xs.iter().enumerate() {
        assert!(c.update_guided(&mut h, x, centre, 16, true));
        let steps = t as i32 + 1;
        let mut want = (1.0 - eta).powi(steps) * var0;
        for (k, &xk) in xs[..=t].iter().enumerate() {
            want +=
                eta * (1.0 - eta) * (xk - centre).powi(2) * (1.0 - eta).powi(t as i32 - k as i32);
        }
        assert!(
            (h.variance - want).abs() <= 1e-12 * want,
            "frame {t}: {} != {want}",
            h.variance
        );
    }
}

#[test]
fn mean_and_mean_count_do_not_depend_on_the_guide() {
    let mut g = SplitMix64(5);
    let c = config(0.2, None);
    for _ in 0..500 {
        let h0 = random_history(&mut g);
        let s = h0.mean + g.normal() * 0.3;
        let count = 1 + (g.next_u64() % 64) as u32;
        let (mut a, mut b) = (h0, h0);
        c.update(&mut a, s, count, true);
        c.update_guided(&mut b, s, g.next_f64() * 10.0 - 5.0, count, true);
        assert_eq!((a.mean, a.mean_count), (b.mean, b.mean_count));
        // Closed form of the variance with the guide's deviation: one step.
        let want_a = 0.8 * h0.variance + 0.16 * (s - h0.mean) * (s - h0.mean);
        assert!((a.variance - want_a).abs() <= 1e-14 * want_a.max(1e-300));
    }
}

#[test]
fn seed_and_refused_frames_are_the_unguided_ones() {
    let c = config(0.2, None);
    let h0 = SpvgHistory {
        mean: 0.3,
        variance: 0.01,
        mean_count: 20.0,
    };
    // Disocclusion: the guide has nothing to say about a new surface.
    let mut h = h0;
    assert!(c.update_guided(&mut h, 2.0, 9.0, 8, false));
    assert_eq!(
        h,
        SpvgHistory {
            mean: 2.0,
            variance: 1e-4,
            mean_count: 8.0
        }
    );
    // A NaN sample or zero count is refused and keeps a valid history.
    let mut h = h0;
    assert!(!c.update_guided(&mut h, f64::NAN, 0.3, 8, true));
    assert!(!c.update_guided(&mut h, 0.5, 0.3, 0, true));
    assert_eq!(h, h0);
}

#[test]
fn stationary_variance_about_the_true_mean_is_retain_times_the_noise() {
    // i.i.d. noise of variance s^2 about m. About the exact mean, E[(x - m)^2] = s^2 and
    // the EMV settles at eta (1 - eta) s^2 / eta = (1 - eta) s^2. About the pixel's own EMA
    // the deviation also carries the EMA's variance eta / (2 - eta) s^2, so it settles at
    // 2 (1 - eta) / (2 - eta) s^2: the guided form, with a perfect guide, reads the noise
    // (2 - eta) / 2 times lower.
    let (eta, m, s) = (0.2_f64, 0.5_f64, 0.05_f64);
    let c = config(eta, None);
    let mut g = SplitMix64(13);
    let seed = SpvgHistory {
        mean: m,
        variance: s * s,
        mean_count: 16.0,
    };
    let (mut own, mut guided) = (seed, seed);
    let (mut sum_own, mut sum_guided, mut frames) = (0.0, 0.0, 0.0);
    for t in 0..200_000 {
        let x = m + s * g.normal();
        c.update(&mut own, x, 16, true);
        c.update_guided(&mut guided, x, m, 16, true);
        if t >= 100 {
            sum_own += own.variance;
            sum_guided += guided.variance;
            frames += 1.0;
        }
    }
    let (mean_own, mean_guided) = (sum_own / frames, sum_guided / frames);
    let want_own = 2.0 * (1.0 - eta) / (2.0 - eta) * s * s;
    let want_guided = (1.0 - eta) * s * s;
    // 200k correlated frames (correlation time ~ 1/eta): a 2% band is ~ 10 standard errors.
    assert!(
        (mean_own / want_own - 1.0).abs() < 0.02,
        "own {mean_own} vs {want_own}"
    );
    assert!(
        (mean_guided / want_guided - 1.0).abs() < 0.02,
        "guided {mean_guided} vs {want_guided}"
    );
}
