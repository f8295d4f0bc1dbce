//! The young-history rules (`spvg::controller::young`, `SpvgConfig::update_young`) against
//! independent references: the plain mean and the two-pass sample variance computed here
//! in f64, the published update where the rules are off, and the count a seeded history
//! asks on its next frame.

use spvg::controller::young::{AGE_CAP, SpatialMoments, next_age, read_age};
use spvg::{SpvgConfig, SpvgHistory};

fn config(age_weight: bool, spatial: u32) -> SpvgConfig<f64> {
    SpvgConfig::<f64>::builder()
        .target_variance(1e-3)
        .age_weight(age_weight)
        .spatial_variance(spatial)
        .build()
        .expect("valid")
}

/// With both rules off the history is bit for bit the published update's, whatever the
/// age and the spatial variance passed.
#[test]
fn off_is_the_published_update() {
    // The spatial variance is on by default: switched off here.
    let c = SpvgConfig::<f32>::builder()
        .target_variance(1e-3)
        .spatial_variance(0)
        .build()
        .expect("valid");
    let mut g = 1u32;
    let mut next = || {
        g = g.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (g >> 8) as f32 / 16_777_216.0
    };
    for k in 0..2000u32 {
        let start = SpvgHistory {
            mean: next(),
            variance: next() * 1e-2,
            mean_count: next() * 64.0,
        };
        let (s, n, valid) = (next(), k % 70, k % 3 != 0);
        let (mut a, mut b) = (start, start);
        let mut age = k % 9;
        let ok_a = c.update(&mut a, s, n, valid);
        let ok_b = c.update_young(&mut b, &mut age, s, n, valid, Some(next()));
        assert_eq!((a, ok_a), (b, ok_b), "case {k}");
        assert_eq!(age, next_age(k % 9, valid, ok_a));
    }
}

/// With the age-aware weight a seeded history's mean is the plain mean of its frames
/// while `1 / age > eta` (the first 1/eta - 1 = 4 frames at eta = 0.2), then the EMA.
#[test]
fn age_weight_averages_the_first_frames() {
    let c = config(true, 0);
    let samples = [0.3, 0.9, 0.1, 0.5, 0.7, 0.2];
    let (mut h, mut age) = (SpvgHistory::default(), 0);
    for (k, &s) in samples.iter().enumerate() {
        assert!(c.update_young(&mut h, &mut age, s, 8, k > 0, None));
        assert_eq!(age, k as u32 + 1);
        if k < 5 {
            let mean: f64 = samples[..=k].iter().sum::<f64>() / (k + 1) as f64;
            assert!(
                (h.mean - mean).abs() < 1e-12,
                "frame {k}: {} vs {mean}",
                h.mean
            );
        }
    }
    // Frame 6 weighs eta = 0.2 (1/6 < 0.2): the EMA of the fifth frame's mean.
    let mean5: f64 = samples[..5].iter().sum::<f64>() / 5.0;
    assert!((h.mean - (0.8 * mean5 + 0.2 * samples[5])).abs() < 1e-12);
}

/// The seed's variance fades by the factor of the age weight on the second frame: half of
/// `sigma0^2` is left instead of `1 - eta = 0.8` of it.
#[test]
fn age_weight_forgets_the_seed_in_two_frames() {
    for (on, kept) in [(true, 0.5), (false, 0.8)] {
        let c = config(on, 0);
        let (mut h, mut age) = (SpvgHistory::default(), 0);
        c.update_young(&mut h, &mut age, 0.5, 8, false, None);
        c.update_young(&mut h, &mut age, 0.5, 8, true, None);
        assert!(
            (h.variance - kept * 1e-3).abs() < 1e-15,
            "{on}: {}",
            h.variance
        );
    }
}

/// The spatial moments give the two-pass sample variance of the finite values pushed,
/// computed here in f64, on random neighbourhoods (NaN and infinities skipped).
#[test]
fn spatial_variance_is_the_sample_variance() {
    let mut g = 7u64;
    let mut next = || {
        g = g
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (g >> 11) as f64 / (1u64 << 53) as f64
    };
    for k in 0..500 {
        let centre = next();
        let values: Vec<f32> = (0..9)
            .map(|j| match (k + j) % 7 {
                0 => f32::NAN,
                1 => f32::INFINITY,
                _ => (centre + (next() - 0.5) * 0.2) as f32,
            })
            .collect();
        let m = values
            .iter()
            .fold(SpatialMoments::default(), |m, &v| m.push(centre as f32, v));
        let finite: Vec<f64> = values
            .iter()
            .filter(|v| v.is_finite())
            .map(|&v| f64::from(v))
            .collect();
        assert_eq!(m.count as usize, finite.len());
        let n = finite.len() as f64;
        let mean = finite.iter().sum::<f64>() / n;
        let var = finite.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let got = f64::from(m.variance().expect("two values or more"));
        assert!(
            (got - var).abs() <= 1e-5 * var + 1e-9,
            "case {k}: {got} vs {var}"
        );
    }
    assert_eq!(SpatialMoments::<f32>::default().variance(), None);
}

/// A seed that takes its neighbourhood's variance asks, on its next frame, the count of
/// a steady history with that variance: with the sampler's noise `sigma^2` per sample
/// and `n` samples the neighbourhood's variance is about `sigma^2 / n`, and the next
/// count is `nbar r = sigma^2 / sigma0^2`, not `nbar` as from the seed's `sigma0^2`.
#[test]
fn spatial_seed_asks_the_steady_count() {
    let c = config(false, 1);
    // sigma^2 = 0.032, 8 samples: fbar's variance 0.004, steady count 32 at sigma0^2 = 1e-3.
    let (mut h, mut age) = (SpvgHistory::default(), 0);
    c.update_young(&mut h, &mut age, 0.5, 8, false, Some(0.004));
    let with_spatial = c.estimate_with_validity(&h, 1.0, true);
    let (mut s, mut age) = (SpvgHistory::default(), 0);
    c.update_young(&mut s, &mut age, 0.5, 8, false, None);
    let seeded = c.estimate_with_validity(&s, 1.0, true);
    assert_eq!(seeded, 8);
    // n_hat = nbar (kappa (r - 1)(k - 1) + r) with r = 4, k - 1 = 8, kappa = 0.2.
    assert_eq!(
        with_spatial,
        (8.0 * (0.2 * 3.0 * 8.0 + 4.0_f64)).ceil().min(64.0) as u32
    );
    // From the second frame on the temporal variance takes over (limit 1 frame).
    let before = h.variance;
    c.update_young(&mut h, &mut age, 0.5, 8, true, Some(1.0));
    assert!((h.variance - 0.8 * before).abs() < 1e-15);
}

/// The age channel: read, advance and saturate.
#[test]
fn ages_saturate_at_the_cap() {
    assert_eq!(read_age(1e9_f32), AGE_CAP);
    assert_eq!(read_age(-1.0_f32), 0);
    let mut age = 0;
    for _ in 0..400 {
        age = next_age(age, age > 0, true);
    }
    assert_eq!(age, AGE_CAP);
    let err = SpvgConfig::<f32>::builder()
        .spatial_variance(AGE_CAP + 1)
        .build()
        .unwrap_err();
    assert!(err.to_string().contains("spatial_variance"));
}
