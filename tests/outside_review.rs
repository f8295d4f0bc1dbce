//! The reproducers an outside review found, each checked against the count
//! formula of docs/algorithms.md §2.1 evaluated independently in `f64`, plus the API
//! additions it asked for.

use spvg::cv::{As, Ocv, PixelController};
use spvg::texel::{
    FrameInputs, Layout, Rounding, SpvgTexel32, TexelEncoding, check_config_precision,
    check_precision, estimate_frame, update_frame, update_frame_ocv, update_frame_ocv_parallel,
    update_frame_parallel,
};
use spvg::{Float, SpvgConfig, SpvgHistory};

/// docs/algorithms.md §2.1 in `f64`: `n_hat = kappa (r - 1) nbar (k - 1) + r nbar` with
/// `r = var / sigma0^2` and `k - 1 = 2/eta - 2`, clamped to the budget and rounded up
/// (NaN to the minimum). The history is read as texel decode reads it.
fn formula(c: &SpvgConfig<f32>, h: &SpvgHistory<f32>) -> u32 {
    let read = |v: f32| -> f64 {
        if v > 0.0 {
            f64::from(v.min(f32::MAX))
        } else {
            0.0
        }
    };
    let (var, nbar) = (read(h.variance), read(h.mean_count));
    let r = var / f64::from(c.target_variance());
    let k1 = 2.0 / f64::from(c.eta()) - 2.0;
    let n_hat = f64::from(c.kappa()) * (r - 1.0) * nbar * k1 + r * nbar;
    let (lo, hi) = (f64::from(c.min_samples()), f64::from(c.max_samples()));
    if n_hat.is_nan() {
        return c.min_samples();
    }
    n_hat.clamp(lo, hi).ceil() as u32
}

fn config(eta: f32, kappa: f32, target: f32) -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .eta(eta)
        .kappa(kappa)
        .target_variance(target)
        .budget(8, 64)
        .build()
        .expect("a valid configuration")
}

/// The review's reproducer: with `eta = 1e-7`, `kappa = 1`, `sigma0^2 = 1.1e-8` the count
/// right after a disocclusion with 32 samples was 8 (from `var * fl(1/sigma0^2) != 1`).
#[test]
fn count_after_disocclusion_is_the_formulas() {
    let c = config(1e-7, 1.0, 1.1e-8);
    let mut h = SpvgHistory::default();
    assert!(c.update(&mut h, 0.5, 32, false), "the seed is absorbed");
    let want = formula(&c, &h);
    assert_eq!(want, 32, "the f64 formula at var == sigma0^2 keeps nbar");
    assert_eq!(
        c.estimate(&h, 1.0),
        want,
        "estimate after disocclusion, {h:?}"
    );
}

/// The same for many targets and counts: at `var == sigma0^2` the count is `nbar`
/// whatever the rounding of `1 / sigma0^2` would have been.
#[test]
fn seeded_history_keeps_its_count_for_every_target() {
    for i in 0..2000 {
        // Log-spaced targets from 1e-8 to 1e2.
        let target = 10f64.powf(-8.0 + 10.0 * f64::from(i) / 2000.0) as f32;
        let c = config(1e-7, 1.0, target);
        for count in [8_u32, 9, 31, 32, 33, 63, 64] {
            let h = SpvgHistory::seeded(0.25, &c, count);
            assert_eq!(formula(&c, &h), count, "formula at {target:e}");
            assert_eq!(
                c.estimate(&h, 1.0),
                count,
                "sigma0^2 = {target:e}, n = {count}"
            );
        }
    }
}

/// Hand-built histories are read as texel decode reads them: the per-pixel estimate of
/// a history equals the frame estimate of its `f32` texel, and the f64 formula on the
/// decoded values.
#[test]
fn hand_built_histories_are_clamped_as_decode_does() {
    let c = config(0.2, 0.2, 1e-4);
    let enc = TexelEncoding::new(c.target_variance()).expect("encoding");
    let odd = [
        0.0,
        -1.0,
        -1e-3,
        1e-4,
        2e-4,
        5e-5,
        16.0,
        1e38,
        f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -0.0,
    ];
    for &variance in &odd {
        for &mean_count in &odd {
            let h = SpvgHistory {
                mean: 0.5,
                variance,
                mean_count,
            };
            let texel = [enc.encode::<SpvgTexel32>(&h, Rounding::Nearest)];
            let mut frame = [0_u32];
            estimate_frame(&c, &enc, &texel, &[1.0], &[1], &mut frame).expect("lengths match");
            let n = c.estimate(&h, 1.0);
            assert_eq!(n, frame[0], "per pixel vs decoded texel for {h:?}");
            assert_eq!(n, formula(&c, &h), "formula for {h:?}");
        }
    }
    // The review's cases: a negative variance, a negative or infinite mean count gave
    // the maximum.
    let h = SpvgHistory {
        mean: 0.5,
        variance: -1.0,
        mean_count: 32.0,
    };
    assert_eq!(c.estimate(&h, 1.0), 8, "negative variance reads as 0");
    let h = SpvgHistory {
        mean: 0.5,
        variance: 1e-4,
        mean_count: -32.0,
    };
    assert_eq!(c.estimate(&h, 1.0), 8, "negative mean count reads as 0");
}

/// `(r - 1) nbar (k - 1)` overflowing `f32` gave the maximum where exact math gives the
/// minimum (a large mean count, `r < 1`, a small `eta` and `kappa`).
#[test]
fn overflowing_correction_gives_the_formulas_count() {
    for (eta, kappa, variance, mean_count) in [
        (1e-7_f32, 1e-3_f32, 0.9e-4_f32, 1e38_f32),
        (1e-7, 1e-3, 0.9e-4, f32::MAX),
        (1e-7, 1e-3, 0.9e-4, f32::INFINITY),
        (1e-6, 0.5, 0.5e-4, 3e37),
        (1e-7, 1e-6, 1.5e-4, 1e38),
        (0.2, 1.0, 2e-4, 1e38),
    ] {
        let c = config(eta, kappa, 1e-4);
        let h = SpvgHistory {
            mean: 0.0,
            variance,
            mean_count,
        };
        let want = formula(&c, &h);
        assert_eq!(c.estimate(&h, 1.0), want, "{c:?} {h:?}");
    }
    // The first case by hand: nbar (kappa (r - 1)(k - 1) + r) < 0, so the minimum.
    let c = config(1e-7, 1e-3, 1e-4);
    let h = SpvgHistory {
        mean: 0.0,
        variance: 0.9e-4,
        mean_count: 1e38,
    };
    assert_eq!(c.estimate(&h, 1.0), 8, "exact math gives a negative n_hat");
}

/// Error messages print numbers compactly.
#[test]
fn error_messages_are_short() {
    let err = SpvgConfig::<f64>::builder()
        .target_variance(1e-320)
        .build()
        .expect_err("a subnormal target has no finite reciprocal");
    let msg = err.to_string();
    assert!(msg.len() < 120, "{} characters: {msg}", msg.len());
    assert!(msg.contains("1e-320"), "the value is readable: {msg}");
    let msg = SpvgConfig::<f64>::builder()
        .eta(0.5e300)
        .build()
        .expect_err("eta > 1")
        .to_string();
    assert!(msg.contains("5e299"), "{msg}");
    let msg = SpvgConfig::<f64>::builder()
        .kappa(1.5)
        .build()
        .expect_err("kappa > 1")
        .to_string();
    assert!(msg.contains("= 1.5:"), "plain numbers stay plain: {msg}");
}

/// Threads are capped and the results are the serial ones, with absurd thread counts.
#[test]
fn absurd_thread_counts_give_the_serial_bits() {
    let n = 70_000;
    let radiance: Vec<f32> = (0..n).map(|i| (i % 13) as f32 * 0.07).collect();
    let ones = vec![1.0_f32; n];
    let gamma = vec![0.5_f32; n];
    let (count, valid) = (vec![16_u32; n], vec![1_u8; n]);
    let inputs = FrameInputs {
        radiance: &radiance,
        preintegrated: &ones,
        gamma: &gamma,
        count: &count,
        valid: &valid,
    };
    let c = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(c.target_variance()).expect("encoding");
    let rounding = Rounding::Stochastic(99);
    let pixel = PixelController::new(c, As);
    let mut serial = vec![spvg::texel::SpvgTexel16::default(); n];
    update_frame(&pixel, &enc, rounding, &inputs, &mut serial).expect("lengths");
    let ocv = PixelController::new(c, Ocv::with_weight(0.05).expect("eta_cv"));
    let mut h_serial = vec![spvg::texel::SpvgTexel16::default(); n];
    let mut j_serial = vec![spvg::texel::CvTexel16::default(); n];
    update_frame_ocv(&ocv, &enc, rounding, &inputs, &mut h_serial, &mut j_serial).expect("lengths");
    for threads in [0, 1, 3, 1000, usize::MAX] {
        let mut threaded = vec![spvg::texel::SpvgTexel16::default(); n];
        update_frame_parallel(&pixel, &enc, rounding, &inputs, &mut threaded, threads)
            .expect("lengths");
        assert_eq!(serial, threaded, "AS with {threads} threads");
        let mut h = vec![spvg::texel::SpvgTexel16::default(); n];
        let mut j = vec![spvg::texel::CvTexel16::default(); n];
        update_frame_ocv_parallel(&ocv, &enc, rounding, &inputs, &mut h, &mut j, threads)
            .expect("lengths");
        assert_eq!(
            (&h_serial, &j_serial),
            (&h, &j),
            "OCV with {threads} threads"
        );
    }
}

/// `spvg::Float` is enough to write generic code over the crate's types.
fn generic_count<T: Float>(c: &SpvgConfig<T>, h: &SpvgHistory<T>) -> u32 {
    c.estimate(h, T::one())
}

#[test]
fn float_is_reexported() {
    let h = SpvgHistory {
        mean: 0.0_f64,
        variance: 1e-4,
        mean_count: 20.0,
    };
    let c = SpvgConfig::<f64>::builder()
        .target_variance(1e-4)
        .build()
        .expect("config");
    assert_eq!(generic_count(&c, &h), 20, "r = 1 keeps nbar");
}

/// `check_precision` takes numbers and `check_config_precision` any float type; both give
/// the same verdicts as the thresholds `2^-11 / eta` (f16) they document.
#[test]
fn precision_checks_take_numbers_in_any_float_type() {
    let eta = 0.005;
    let r64 = check_precision(eta, None, Layout::F16, Rounding::Nearest, 0.09_f64)
        .expect("valid numbers");
    let r32 = check_precision(eta as f32, None, Layout::F16, Rounding::Nearest, 0.09_f32)
        .expect("valid numbers");
    assert_eq!(r64, r32, "f64 and f32 numbers give the same report");
    let t = f64::from(r64.history[0].nearest_threshold);
    let want = 2f64.powi(-11) / eta;
    assert!((t - want).abs() <= 1e-6 * want, "{t} != {want}");
    assert!(
        check_precision(1.5_f64, None, Layout::F16, Rounding::Nearest, 0.1).is_err(),
        "eta > 1"
    );
    let err = check_precision(0.2_f64, Some(-1.0), Layout::F16, Rounding::Nearest, 0.1)
        .expect_err("negative eta_cv");
    assert!(err.to_string().contains("eta_cv"), "{err}");
    let c = SpvgConfig::<f64>::published();
    let ocv = Ocv::with_weight(1e-6_f64).expect("eta_cv");
    let r =
        check_config_precision(&c, Some(&ocv), Layout::F32, Rounding::Nearest, 0.1).expect("valid");
    // f32 moves eta_cv 1e-6 only from deviations of 2^-24 / 1e-6 = 6%: 10% moves.
    assert!(r.all_move(), "{r:?}");
}
