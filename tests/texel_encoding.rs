//! Encodings: exact f32 round trips, f16 round trips within half an ulp, sanitising of
//! every stored or loaded value, and the `eps_a` semantics of the CV scale.

use half::f16;
use proptest::prelude::*;
use spvg::cv::Ocv;
use spvg::texel::{CvTexel16, CvTexel32, Rounding, SpvgTexel16, SpvgTexel32, TexelEncoding};
use spvg::{CvHistory, SpvgHistory};

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        -1e4_f32..1e4,
        any::<u32>().prop_map(|b| {
            let x = f32::from_bits(b);
            if x.is_finite() { x } else { 0.0 }
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn f32_round_trip_is_exact_in_normal_range(
        mean in finite(), var in 1e-30_f32..1e30, count in 0.0_f32..1e6,
        cov in -1e20_f32..1e20, vg in 1e-20_f32..1e20, mf in finite(), mg in finite(),
        target in 1e-8_f32..1e3,
    ) {
        let enc = TexelEncoding::new(target).unwrap();
        let h = SpvgHistory { mean, variance: var, mean_count: count };
        let back = enc.decode(enc.encode::<SpvgTexel32>(&h, Rounding::Nearest));
        prop_assert_eq!(back, h, "SPVG f32 round trip");
        let j = CvHistory { cov_fg: cov, var_g: vg, mean_f: mf, mean_g: mg };
        let back = enc.decode(enc.encode::<CvTexel32>(&j, Rounding::Nearest));
        prop_assert_eq!(back, j, "CV f32 round trip");
    }

    #[test]
    fn f16_round_trip_within_half_ulp(
        mean in -6e4_f32..6e4, ratio in 6.2e-5_f32..6e4, count in 0.0_f32..64.0,
        target in 1e-6_f32..1e-1, r in any::<u32>(),
    ) {
        let enc = TexelEncoding::new(target).unwrap();
        let var = ratio * enc.variance_scale();
        let h = SpvgHistory { mean, variance: var, mean_count: count };
        let rn = enc.decode(enc.encode::<SpvgTexel16>(&h, Rounding::Nearest));
        let sr = enc.decode(enc.encode::<SpvgTexel16>(&h, Rounding::Stochastic(r)));
        // Independent oracle: f16 step at |x| (normal range) is 2^(floor(log2|x|) - 10),
        // subnormals 2^-24.
        let ulp = |x: f32| 2f64.powi((f64::from(x.abs()).log2().floor() as i32).max(-14) - 10);
        for (got, want, scale) in [
            (rn.mean, mean, 1.0), (rn.variance, var, enc.variance_scale()),
            (rn.mean_count, count, 1.0),
        ] {
            let u = ulp(want / scale) * f64::from(scale);
            let err = f64::from(got - want).abs();
            prop_assert!(err <= 0.5 * u, "{} != {} (tol {})", got, want, 0.5 * u);
        }
        for (got, want, scale) in [
            (sr.mean, mean, 1.0), (sr.variance, var, enc.variance_scale()),
            (sr.mean_count, count, 1.0),
        ] {
            let u = ulp(want / scale) * f64::from(scale);
            let err = f64::from(got - want).abs();
            prop_assert!(err < u, "{} != {} (tol {})", got, want, u);
        }
    }

    #[test]
    fn every_stored_texel_is_finite_and_sane(
        mean in any::<u32>(), var in any::<u32>(), count in any::<u32>(), r in any::<u32>(),
        stochastic in any::<bool>(),
    ) {
        let enc = TexelEncoding::new(1e-4).unwrap();
        let h = SpvgHistory {
            mean: f32::from_bits(mean), variance: f32::from_bits(var),
            mean_count: f32::from_bits(count),
        };
        let rounding = if stochastic { Rounding::Stochastic(r) } else { Rounding::Nearest };
        let t16: SpvgTexel16 = enc.encode(&h, rounding);
        let t32: SpvgTexel32 = enc.encode(&h, rounding);
        prop_assert!(t16.0.iter().all(|v| v.is_finite()), "{:?}", t16);
        prop_assert!(t32.0.iter().all(|v| v.is_finite()), "{:?}", t32);
        prop_assert!(t16.0[1].to_f32() >= 0.0 && t16.0[2].to_f32() >= 0.0, "{:?}", t16);
        prop_assert!(t32.0[1] >= 0.0 && t32.0[2] >= 0.0, "{:?}", t32);
        if h.mean.is_nan() {
            prop_assert_eq!(t16.0[0].to_f32(), 0.0, "NaN mean stores 0");
        }
        // Loading arbitrary bits gives finite, non-negative variance and count.
        let bits = [mean as u16, var as u16, count as u16, 0];
        let any16: SpvgTexel16 = bytemuck::cast(bits);
        let d = enc.decode(any16);
        prop_assert!(d.mean.is_finite() && d.variance >= 0.0 && d.variance.is_finite(), "{:?}", d);
        prop_assert!(d.mean_count >= 0.0 && d.mean_count <= 65504.0, "{:?}", d);
        let any32: SpvgTexel32 = bytemuck::cast([mean, var, count, 0]);
        let d = enc.decode(any32);
        prop_assert!(d.mean.is_finite() && d.variance >= 0.0 && d.variance.is_finite(), "{:?}", d);
        let j: CvTexel16 = bytemuck::cast(bits);
        let d = enc.decode(j);
        prop_assert!(d.cov_fg.is_finite() && d.var_g >= 0.0 && d.mean_f.is_finite(), "{:?}", d);
    }
}

#[test]
fn saturation_and_special_values() {
    let enc = TexelEncoding::new(1e-4).unwrap();
    let h = SpvgHistory {
        mean: f32::INFINITY,
        variance: 1e9,
        mean_count: f32::NAN,
    };
    let t: SpvgTexel16 = enc.encode(&h, Rounding::Nearest);
    assert_eq!(t.0[0].to_f32(), 65504.0, "infinite mean saturates");
    assert_eq!(t.0[1].to_f32(), 65504.0, "huge variance saturates");
    assert_eq!(t.0[2].to_f32(), 0.0, "NaN count stores 0");
    let h = SpvgHistory {
        mean: -f32::INFINITY,
        variance: -3.0,
        mean_count: -1.0,
    };
    let t: SpvgTexel32 = enc.encode(&h, Rounding::Nearest);
    assert_eq!(
        t.0,
        [f32::MIN, 0.0, 0.0, 0.0],
        "f32: saturate, negatives to 0"
    );
    let inf = SpvgTexel16([f16::INFINITY, f16::NAN, f16::NEG_INFINITY, f16::NAN]);
    let d = enc.decode(inf);
    assert_eq!(
        (d.mean, d.variance, d.mean_count),
        (65504.0, 0.0, 0.0),
        "sanitised load"
    );
    assert!(TexelEncoding::new(0.0).is_err(), "zero target variance");
    assert!(TexelEncoding::new(f32::NAN).is_err(), "NaN target variance");
    assert!(
        TexelEncoding::new(1e-4)
            .unwrap()
            .with_cv_scale(-1.0)
            .is_err(),
        "negative cv scale"
    );
}

#[test]
fn scales_are_nearest_powers_of_two() {
    for target in [1e-4_f32, 1e-3, 0.08 * 0.08, 1.0, 3.0, 1e-6] {
        let s = TexelEncoding::new(target).unwrap().variance_scale();
        let ratio = f64::from(target) / f64::from(s);
        assert!(
            (std::f64::consts::FRAC_1_SQRT_2..=std::f64::consts::SQRT_2).contains(&ratio),
            "{target}: scale {s}, ratio {ratio}"
        );
        assert_eq!(s.to_bits() & 0x7f_ffff, 0, "{s} is a power of two");
    }
}

#[test]
fn alpha_in_stored_units_is_bit_identical() {
    // With power-of-two scales, (c' + eps') / (g' + eps') on stored values with
    // eps' = eps_a 2^-c is the coefficient of the decoded values with eps_a.
    let eps_a = 1e-6_f32;
    let ocv = Ocv::with_weight(0.05_f32).unwrap();
    for scale in [1e-4_f32, 4.096e-3, 1.0] {
        let enc = TexelEncoding::new(1e-4)
            .unwrap()
            .with_cv_scale(scale)
            .unwrap();
        let inv = 1.0 / enc.cv_scale();
        let mut state = 7_u32;
        for _ in 0..1000 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let c = (state >> 8) as f32 / 16_777_216.0 * 2e-5 - 5e-6;
            let g = (state & 0xffff) as f32 / 65536.0 * 1e-5;
            let j = CvHistory {
                cov_fg: c,
                var_g: g,
                mean_f: 1.0,
                mean_g: 1.0,
            };
            let t: CvTexel32 = enc.encode(&j, Rounding::Nearest);
            let decoded = enc.decode(t);
            let want = ocv.raw_coefficient(&decoded);
            let stored = (t.0[0] + eps_a * inv) / (t.0[1] + eps_a * inv);
            assert_eq!(
                stored.to_bits(),
                want.to_bits(),
                "{stored} != {want} at scale {scale}"
            );
        }
    }
}

#[test]
fn stochastic_texel_store_is_unbiased() {
    // Values between f16 neighbours; the mean over many pixel words must converge to the
    // exact value, per channel (each channel draws its own word from the pixel's).
    let enc = TexelEncoding::new(1e-4).unwrap();
    let h = SpvgHistory {
        mean: 1.000_3,
        variance: 1.7e-4,
        mean_count: 37.01,
    };
    let n = 20_000_u32;
    let mut sum = [0.0_f64; 3];
    for i in 0..n {
        let r = i.wrapping_mul(0x9e37_79b9) ^ 0x5bd1_e995;
        let d = enc.decode(enc.encode::<SpvgTexel16>(&h, Rounding::Stochastic(r)));
        sum[0] += f64::from(d.mean);
        sum[1] += f64::from(d.variance);
        sum[2] += f64::from(d.mean_count);
    }
    let ulp16 = |x: f64| 2f64.powi(x.abs().log2().floor() as i32 - 10);
    let want = [
        f64::from(h.mean),
        f64::from(h.variance),
        f64::from(h.mean_count),
    ];
    let scale = [1.0, f64::from(enc.variance_scale()), 1.0];
    for c in 0..3 {
        let got = sum[c] / f64::from(n);
        // Standard deviation of one store is at most half an ulp.
        let tol = 5.0 * 0.5 * ulp16(want[c] / scale[c]) * scale[c] / f64::from(n).sqrt();
        assert!(
            (got - want[c]).abs() <= tol,
            "channel {c}: {got} != {} (tol {tol})",
            want[c]
        );
    }
}
