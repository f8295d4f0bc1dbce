//! The firefly clamp (`SpvgConfigBuilder::firefly_clamp`, docs/algorithms.md §8.3)
//! against closed forms: the clamped value `mean +- k sqrt(max(variance, sigma0^2))`, the
//! variance a single outlier leaves, its geometric decay and the recovery time that
//! follows from it, the growth of the interval under a real step, the refused frames
//! (NaN, infinities), the unclamped disocclusion seed, and the clamp off equal to the
//! published update bit for bit.

use spvg::{Error, SpvgConfig, SpvgHistory};

fn config(k: Option<f64>) -> SpvgConfig<f64> {
    SpvgConfig::<f64>::builder()
        .firefly_clamp(k)
        .build()
        .expect("valid")
}

/// Relative closeness for the f64 closed forms (a few roundings each).
fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12 * want.abs().max(1e-300),
        "{what}: {got} != {want}"
    );
}

/// A steady pixel: mean 0.5, variance 4 sigma0^2 (sigma = 0.02).
const STEADY: SpvgHistory<f64> = SpvgHistory {
    mean: 0.5,
    variance: 4e-4,
    mean_count: 16.0,
};

#[test]
fn one_outlier_adds_k_sigma_squared_then_decays_by_retain() {
    for k in [4.0, 6.0, 8.0] {
        let c = config(Some(k));
        let (eta, retain) = (0.2, 0.8);
        let sigma = STEADY.variance.sqrt();
        let mut h = STEADY;
        // A 100x outlier: far outside mean + k sigma, so it is absorbed as that bound.
        assert!(c.update(&mut h, 50.0, 16, true));
        let var1 = retain * STEADY.variance + eta * retain * (k * sigma) * (k * sigma);
        close(h.variance, var1, "variance after the outlier");
        close(h.mean, retain * 0.5 + eta * (0.5 + k * sigma), "mean after");
        // The same in closed form: the variance is multiplied by (1 - eta)(1 + eta k^2).
        close(
            h.variance / STEADY.variance,
            retain * (1.0 + eta * k * k),
            "factor",
        );
        // Frames at the current mean (d = 0) leave retain^t of it.
        for t in 1..=40 {
            let m = h.mean;
            assert!(c.update(&mut h, m, 16, true));
            close(h.variance, var1 * retain.powi(t), "decay");
        }
    }
}

#[test]
fn recovery_time_follows_the_closed_form() {
    // Frames after one outlier until the variance is back within 10% of the steady
    // variance, when later frames add nothing (d = 0): the smallest t with
    // retain^t var1 <= 1.1 var0, t = ceil(ln(var1 / (1.1 var0)) / ln(1 / retain)).
    let retain: f64 = 0.8;
    let var0 = STEADY.variance;
    let frames = |c: &SpvgConfig<f64>| {
        let mut h = STEADY;
        c.update(&mut h, 50.0, 16, true);
        let mut t = 0;
        while h.variance > 1.1 * var0 {
            let m = h.mean;
            c.update(&mut h, m, 16, true);
            t += 1;
        }
        (t, h)
    };
    let d = 50.0 - STEADY.mean;
    let off_var1 = retain * var0 + 0.2 * retain * d * d;
    let want_off = ((off_var1 / (1.1 * var0)).ln() / (1.0 / retain).ln()).ceil() as usize;
    assert_eq!(frames(&config(None)).0, want_off, "clamp off");
    assert!(
        want_off > 40,
        "unclamped the outlier holds the pixel for {want_off} frames"
    );
    for k in [4.0, 6.0, 8.0] {
        let var1 = retain * var0 * (1.0 + 0.2 * k * k);
        let want = ((var1 / (1.1 * var0)).ln() / (1.0 / retain).ln()).ceil() as usize;
        assert_eq!(frames(&config(Some(k))).0, want, "k = {k}");
        assert!(want <= 12, "k = {k}: {want} frames");
    }
}

#[test]
fn variance_is_floored_at_the_target() {
    // A history whose variance is 0 (a constant pixel) still lets a value through up
    // to k sigma0: the interval never collapses to the mean.
    let c = config(Some(8.0));
    let sigma0 = c.target_variance().sqrt();
    let mut h = SpvgHistory {
        mean: 1.0,
        variance: 0.0,
        mean_count: 8.0,
    };
    assert!(c.update(&mut h, 5.0, 8, true));
    close(h.mean, 0.8 + 0.2 * (1.0 + 8.0 * sigma0), "mean");
    close(
        h.variance,
        0.16 * (8.0 * sigma0) * (8.0 * sigma0),
        "variance",
    );
    // Below the mean the same.
    let mut h = SpvgHistory {
        mean: 1.0,
        variance: 0.0,
        mean_count: 8.0,
    };
    assert!(c.update(&mut h, -5.0, 8, true));
    close(h.mean, 0.8 + 0.2 * (1.0 - 8.0 * sigma0), "mean below");
}

#[test]
fn a_real_step_is_tracked() {
    // A scene change from 0.5 to 5.0 (450 sigma0) at a pixel whose variance is
    // sigma0^2: while the step is clamped the variance grows geometrically (by
    // (1 - eta)(1 + eta k^2) on a fixed mean), so the mean reaches the new level a few
    // frames after the plain EMA does (the f64 recurrence of the rule, evaluated by
    // hand: 17, 15 and 14 frames for k = 4, 6, 8).
    for (k, within) in [(4.0, 17), (6.0, 15), (8.0, 14)] {
        let c = config(Some(k));
        let mut h = SpvgHistory {
            mean: 0.5,
            variance: c.target_variance(),
            mean_count: 8.0,
        };
        let mut t = 0;
        while (h.mean - 5.0).abs() > 0.45 {
            c.update(&mut h, 5.0, 8, true);
            t += 1;
            assert!(
                t <= within,
                "k = {k}: not within 10% after {t} frames: {h:?}"
            );
        }
        // Unclamped the EMA alone takes ceil(ln(10) / ln(1.25)) = 11 frames; the clamp
        // costs a few more at most.
        assert!(t >= 11, "k = {k}: {t} frames, faster than the EMA");
    }
}

#[test]
fn in_range_values_pass_unchanged() {
    // Within the interval the clamped update is the published one, bit for bit.
    let (on, off) = (config(Some(8.0)), config(None));
    for s in [0.5, 0.6, 0.4, 0.5 + 7.9 * 0.02, 0.5 - 7.9 * 0.02] {
        let (mut a, mut b) = (STEADY, STEADY);
        on.update(&mut a, s, 16, true);
        off.update(&mut b, s, 16, true);
        assert_eq!(a, b, "sample {s}");
    }
}

#[test]
fn off_is_the_published_update_bit_for_bit() {
    // The clamp off (None or +inf) computes the documented operations in f32, in order
    // (values whose squares stay in range: the saturation is not what is tested here).
    let published = SpvgConfig::<f32>::published();
    let inf = SpvgConfig::<f32>::builder()
        .firefly_clamp(Some(f32::INFINITY))
        .build()
        .expect("valid");
    assert_eq!(inf.firefly_clamp(), None, "+inf reads as off");
    assert_eq!(published.firefly_clamp(), None, "off by default");
    let w = published.weight();
    for (mean, var, s) in [
        (0.5_f32, 4e-4_f32, 50.0_f32),
        (0.5, 0.0, 1e4),
        (-3.0, 1e-9, 3e18),
        (1.0, 2.0, -7.5),
    ] {
        let h0 = SpvgHistory {
            mean,
            variance: var,
            mean_count: 12.0,
        };
        let d = s - mean;
        let want = SpvgHistory {
            mean: w.retain() * mean + w.eta() * s,
            variance: w.retain() * var + w.eta_retain() * (d * d),
            mean_count: w.retain() * 12.0 + w.eta() * 8.0,
        };
        for c in [published, inf] {
            let mut h = h0;
            assert!(c.update(&mut h, s, 8, true));
            assert_eq!(
                (
                    h.mean.to_bits(),
                    h.variance.to_bits(),
                    h.mean_count.to_bits()
                ),
                (
                    want.mean.to_bits(),
                    want.variance.to_bits(),
                    want.mean_count.to_bits()
                ),
                "{h0:?} with {s}"
            );
        }
    }
}

#[test]
fn refused_and_extreme_frames() {
    let c = SpvgConfig::<f32>::builder()
        .firefly_clamp(Some(6.0))
        .build()
        .expect("valid");
    let h0 = SpvgHistory {
        mean: 0.5_f32,
        variance: 4e-4,
        mean_count: 16.0,
    };
    // Non-finite samples are refused as without the clamp: the history is kept.
    for s in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut h = h0;
        assert!(!c.update(&mut h, s, 16, true), "{s}");
        assert_eq!(h, h0, "{s}");
    }
    // The largest finite values are clamped to the bound: a finite history.
    for s in [f32::MAX, f32::MIN] {
        let mut h = h0;
        assert!(c.update(&mut h, s, 16, true));
        let bound = 0.5 + s.signum() * 6.0 * 0.02;
        assert!(
            (h.mean - (0.8 * 0.5 + 0.2 * bound)).abs() < 1e-6,
            "{s}: {h:?}"
        );
        assert!(
            (h.variance - (0.8 * 4e-4 + 0.16 * 0.0144)).abs() < 1e-8,
            "{s}: {h:?}"
        );
    }
    // A stored history at the edge of the range: the bounds overflow to infinity,
    // which opens that side; nothing non-finite is stored.
    let edge = SpvgHistory {
        mean: f32::MAX,
        variance: f32::MAX,
        mean_count: 16.0,
    };
    for s in [f32::MAX, f32::MIN, 0.0] {
        let mut h = edge;
        assert!(c.update(&mut h, s, 16, true));
        assert!(
            h.mean.is_finite() && h.variance.is_finite() && h.variance >= 0.0,
            "{s}: {h:?}"
        );
    }
    // A corrupt stored history (NaN mean and variance) reads as zeros: the clamp is
    // against mean 0, sigma sigma0.
    let mut h = SpvgHistory {
        mean: f32::NAN,
        variance: f32::NAN,
        mean_count: 16.0,
    };
    assert!(c.update(&mut h, 1.0, 16, true));
    assert!((h.mean - 0.2 * 6.0 * 0.01).abs() < 1e-7, "{h:?}");
}

#[test]
fn disocclusion_seeds_are_not_clamped() {
    let c = config(Some(4.0));
    let mut h = STEADY;
    assert!(c.update(&mut h, 1e4, 32, false));
    assert_eq!(
        h,
        SpvgHistory {
            mean: 1e4,
            variance: c.target_variance(),
            mean_count: 32.0
        }
    );
}

#[test]
fn firefly_clamp_is_validated() {
    for bad in [0.0, -0.5, f64::NAN, f64::NEG_INFINITY] {
        let err = SpvgConfig::<f64>::builder()
            .firefly_clamp(Some(bad))
            .build()
            .unwrap_err();
        assert!(
            matches!(
                err,
                Error::InvalidParameter {
                    name: "firefly_clamp",
                    ..
                }
            ),
            "firefly_clamp {bad}: {err}"
        );
        assert!(err.to_string().contains("firefly_clamp"), "{err}");
    }
    let c = config(Some(8.0));
    assert_eq!(c.firefly_clamp(), Some(8.0));
    assert_eq!(c.to_builder().build().expect("valid"), c, "round trip");
}
