//! The second-moment update (docs/algorithms.md §8.8): variance that samples cannot
//! remove buys no samples, checked against the closed-form variance of a binary ray.

use spvg::controller::rules::per_sample_variance;
use spvg::{SpvgConfig, SpvgHistory};

/// A small deterministic generator (SplitMix64), independent of the crate's sequences.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Runs a pixel whose occlusion probability jumps between `p[0]` and `p[1]` from frame
/// to frame (a sub-pixel jitter across an edge: the frame's mean changes by
/// `p[1] - p[0]` whatever the count), each frame casting the controller's count of binary
/// rays. Returns the mean count over the second half of `frames`.
fn jittered_edge(config: &SpvgConfig<f32>, p: [f64; 2], with_moment: bool, frames: u32) -> f64 {
    let mut rng = Rng(7);
    let (mut h, mut age) = (SpvgHistory::<f32>::default(), 0u32);
    let mut total = 0.0;
    for frame in 0..frames {
        let valid = frame > 0;
        let n = config.estimate_with_validity(&h, 1.0, valid);
        let occlusion = p[(frame % 2) as usize];
        let hits = (0..n).filter(|_| rng.next() < occlusion).count() as f32;
        // Binary values: the mean of the squares is the mean.
        let mean = hits / n as f32;
        let moment = if with_moment { mean } else { f32::NAN };
        config.update_moment(
            &mut h,
            &mut age,
            mean,
            f32::NAN,
            moment,
            n,
            None,
            valid,
            None,
        );
        if frame >= frames / 2 {
            total += f64::from(n);
        }
    }
    total / f64::from(frames - frames / 2)
}

#[test]
fn jittered_edge_count_follows_the_per_sample_variance() {
    let target = 5e-4;
    let config = SpvgConfig::<f32>::builder()
        .target_variance(target)
        .budget(8, 4096)
        .build()
        .unwrap();
    let p = [0.1, 0.9];
    // The closed form: a binary ray's variance p (1 - p), the same on both sides.
    let required = p[0] * (1.0 - p[0]) / f64::from(target);
    let with = jittered_edge(&config, p, true, 600);
    let without = jittered_edge(&config, p, false, 600);
    eprintln!("required {required:.1}, with the moment {with:.1}, without {without:.1}");
    assert!(
        with > required / 1.1 && with < required * 1.1,
        "with the moment the mean count is {with}, required {required}"
    );
    // The temporal variance of the mean (0.16) never falls with n: the old rule runs to
    // the budget's maximum.
    assert!(without > 4000.0, "without the moment {without}");
}

#[test]
fn no_moment_or_one_sample_is_the_fractional_update() {
    let config = SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .firefly_clamp(Some(4.0))
        .build()
        .unwrap();
    let mut rng = Rng(11);
    for _ in 0..20_000 {
        let h0 = SpvgHistory {
            mean: rng.next() as f32,
            variance: (rng.next() * 0.01) as f32,
            mean_count: (rng.next() * 64.0) as f32,
        };
        let sample = (rng.next() * 2.0 - 0.5) as f32;
        let count = (rng.next() * 3.0) as u32; // 0, 1 or 2
        let (moment, count) = if count == 2 {
            (f32::NAN, 2 + (rng.next() * 60.0) as u32)
        } else {
            (rng.next() as f32, count)
        };
        let valid = rng.next() < 0.8;
        let (mut a, mut b, mut age_a, mut age_b) = (h0, h0, 3, 3);
        let ra = config.update_moment(
            &mut a,
            &mut age_a,
            sample,
            f32::NAN,
            moment,
            count,
            None,
            valid,
            None,
        );
        let rb = config.update_fractional(
            &mut b,
            &mut age_b,
            sample,
            f32::NAN,
            count,
            None,
            valid,
            None,
        );
        assert_eq!((a, age_a, ra), (b, age_b, rb));
    }
}

#[test]
fn per_sample_variance_matches_the_two_pass_variance() {
    let mut rng = Rng(3);
    for _ in 0..2000 {
        let n = 2 + (rng.next() * 30.0) as usize;
        let xs: Vec<f64> = (0..n).map(|_| rng.next() * 3.0 - 1.0).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let q = xs.iter().map(|x| x * x).sum::<f64>() / n as f64;
        // Two-pass sample variance about the mean, over n - 1.
        let two_pass = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let v = per_sample_variance(mean, q, n as u32);
        assert!(
            (v - two_pass).abs() <= 1e-12 * (1.0 + two_pass),
            "{v} {two_pass}"
        );
    }
}

#[test]
fn hostile_moments_store_only_finite_numbers() {
    let config = SpvgConfig::<f32>::builder()
        .target_variance(1e-4)
        .build()
        .unwrap();
    let clamped = SpvgConfig::<f32>::builder()
        .target_variance(1e-4)
        .firefly_clamp(Some(4.0))
        .build()
        .unwrap();
    let hostile = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        -f32::MAX,
        1e30,
        -1.0,
        0.0,
        1e-45,
    ];
    for c in [&config, &clamped] {
        for &sample in &hostile {
            for &moment in &hostile {
                for count in [0, 1, 2, 64, u32::MAX] {
                    let mut h = SpvgHistory {
                        mean: 0.5,
                        variance: 1e-4,
                        mean_count: 8.0,
                    };
                    let mut age = 2;
                    c.update_moment(
                        &mut h,
                        &mut age,
                        sample,
                        f32::NAN,
                        moment,
                        count,
                        None,
                        true,
                        None,
                    );
                    assert!(
                        h.mean.is_finite() && h.variance.is_finite() && h.mean_count.is_finite()
                    );
                    assert!(h.variance >= 0.0 && h.mean_count >= 0.0);
                }
            }
        }
    }
    // With the clamp the frame's per-sample variance is capped at k^2 max(variance nbar,
    // sigma0^2): a firefly's frame adds at most eta k^2 sigma0^2 / nbar to the variance.
    let mut h = SpvgHistory {
        mean: 0.5,
        variance: 0.0,
        mean_count: 8.0,
    };
    let mut age = 2;
    clamped.update_moment(&mut h, &mut age, 0.5, f32::NAN, 1e20, 8, None, true, None);
    assert!(
        h.variance <= 0.2 * 16.0 * 1e-4 * 1.000_001,
        "{}",
        h.variance
    );
}
