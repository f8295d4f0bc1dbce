//! pcg3d16 and the fixed-point R2 sequence against second implementations, exact
//! integer proofs of the R2 constants, and discrepancy.

use proptest::prelude::*;
use spvg::sequence::{
    PHI2, R2_STEP, pcg3d16, pixel_seed, r2_offset_from_seed, r2_point, to_unit_f32, to_unit_f64,
};

// ---------------------------------------------------------------- pcg3d16

/// pcg3d16 in `u64` arithmetic masked to 32 bits, written from docs/algorithms.md §6: each of the six
/// updates uses the lanes as already updated.
fn pcg3d16_u64(v: [u32; 3]) -> [u32; 3] {
    const M: u64 = 0xFFFF_FFFF;
    let mut w = v.map(|x| (u64::from(x) * 12829 + 47989) & M);
    for _ in 0..2 {
        w[0] = (w[0] + w[1] * w[2]) & M;
        w[1] = (w[1] + w[2] * w[0]) & M;
        w[2] = (w[2] + w[0] * w[1]) & M;
    }
    w.map(|x| (x >> 16) as u32)
}

#[test]
fn pcg3d16_matches_u64_reference() {
    for x in 0..64 {
        for y in 0..64 {
            for f in [0, 1, 2, 1000, u32::MAX] {
                let v = [x, y, f];
                assert_eq!(pcg3d16(v), pcg3d16_u64(v), "pcg3d16({v:?})");
            }
        }
    }
    for v in [[u32::MAX; 3], [0; 3], [1 << 31, 12345, 0xDEAD_BEEF]] {
        assert_eq!(pcg3d16(v), pcg3d16_u64(v), "pcg3d16({v:?})");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn pcg3d16_matches_u64_reference_random(x: u32, y: u32, z: u32) {
        let v = [x, y, z];
        let h = pcg3d16(v);
        prop_assert_eq!(h, pcg3d16_u64(v), "pcg3d16({:?})", v);
        prop_assert!(h.iter().all(|&lane| lane < 1 << 16), "16-bit lanes {:?}", h);
        prop_assert_eq!(pixel_seed(x, y, z), h, "pixel_seed is pcg3d16");
    }

    #[test]
    fn r2_point_matches_u64_reference(ox: u32, oy: u32, m: u32) {
        let want = [(ox, R2_STEP[0]), (oy, R2_STEP[1])]
            .map(|(o, s)| ((u64::from(o) + u64::from(m) * u64::from(s)) % (1 << 32)) as u32);
        prop_assert_eq!(r2_point([ox, oy], m), want, "r2_point({}, {}, {})", ox, oy, m);
    }
}

#[test]
fn pcg3d16_lanes_are_roughly_uniform() {
    // Chi-square of the top 4 bits of each lane over a 64 x 64 pixel block: 16 bins, 15
    // degrees of freedom, 0.1% critical value 37.7.
    for lane in 0..3 {
        let mut bins = [0u32; 16];
        for x in 0..64 {
            for y in 0..64 {
                let h = pixel_seed(x, y, 5);
                bins[(h[lane] >> 12) as usize] += 1;
            }
        }
        let expect = 4096.0 / 16.0;
        let chi2: f64 = bins
            .iter()
            .map(|&b| (f64::from(b) - expect).powi(2) / expect)
            .sum();
        assert!(chi2 < 37.7, "lane {lane}: chi^2 {chi2} over bins {bins:?}");
    }
}

// ---------------------------------------------------------------- R2 constants

/// `phi2` by Newton's iteration on `x^3 - x - 1` in `f64`.
fn phi2_newton() -> f64 {
    let mut x = 1.3_f64;
    for _ in 0..50 {
        x -= (x * x * x - x - 1.0) / (3.0 * x * x - 1.0);
    }
    x
}

#[test]
fn phi2_is_the_plastic_number() {
    let x = phi2_newton();
    assert_eq!(PHI2, x, "PHI2 {PHI2} != Newton {x}");
    // docs/algorithms.md §6 gives 1.32471795724474602596; the nearest f64 must parse from those digits.
    let spec: f64 = "1.32471795724474602596".parse().expect("a float literal");
    assert_eq!(PHI2, spec, "PHI2 vs the digits of docs/algorithms.md §6");
    let residual = PHI2 * PHI2 * PHI2 - PHI2 - 1.0;
    assert!(
        residual.abs() <= 4.0 * f64::EPSILON,
        "x^3 - x - 1 = {residual:e}"
    );
}

#[test]
fn r2_step_rounds_correctly_in_f64() {
    let phi = phi2_newton();
    let two32 = 4_294_967_296.0_f64;
    let want = [(two32 / phi).round(), (two32 / (phi * phi)).round()];
    assert_eq!(R2_STEP.map(f64::from), want, "round(2^32 / phi2^k)");
}

#[test]
fn r2_step_rounds_correctly_exactly() {
    // N = round(2^32 / phi) iff phi lies strictly between 2^33 / (2N + 1) and
    // 2^33 / (2N - 1). As f(x) = x^3 - x - 1 increases past 1/sqrt(3) and f(phi) = 0,
    // `phi > P / Q` iff f(P / Q) < 0 iff P^3 - P Q^2 - Q^3 < 0 (times Q^3 > 0): exact in
    // i128 (P, Q < 2^34, cubes < 2^102).
    let p: i128 = 1 << 33;
    let phi_above = |q: i128| p * p * p - p * q * q - q * q * q < 0;
    let n = i128::from(R2_STEP[0]);
    assert!(phi_above(2 * n + 1), "2^32 / phi >= N + 1/2");
    assert!(!phi_above(2 * n - 1), "2^32 / phi <= N - 1/2");
    // N = round(2^32 / phi^2) iff phi^2 lies between P / (2N + 1) and P / (2N - 1).
    // `phi^2 > P / Q` iff phi > sqrt(P / Q) = x iff f(x) = x (x^2 - 1) - 1 < 0
    // iff x (P - Q) / Q < 1 iff (P > Q here) P (P - Q)^2 < Q^3.
    let phi2_above = |q: i128| {
        assert!(p > q, "P > Q");
        p * (p - q) * (p - q) < q * q * q
    };
    let n = i128::from(R2_STEP[1]);
    assert!(phi2_above(2 * n + 1), "2^32 / phi^2 >= N + 1/2");
    assert!(!phi2_above(2 * n - 1), "2^32 / phi^2 <= N - 1/2");
}

// ---------------------------------------------------------------- R2 points

/// Circular distance on the unit torus.
fn circular(a: f64, b: f64) -> f64 {
    let e = (a - b).rem_euclid(1.0);
    e.min(1.0 - e)
}

#[test]
fn r2_points_track_the_irrational_sequence() {
    // Point m differs from frac(s + m alpha) by m |delta| 2^-32, delta = R2_STEP -
    // 2^32 alpha (the constant's rounding residual), plus the f64 evaluation of the
    // reference, 2 units of 2^-32 below: up to m = 1e6, m alpha < 2^20 rounds to half a
    // unit, and delta itself (from 2^32 alpha near 2^32) is known to 2^-21, i.e. another
    // half unit after multiplying by m. Beyond ~1e7 an f64 reference is too coarse.
    let phi = phi2_newton();
    let two32 = 4_294_967_296.0_f64;
    let alpha = [1.0 / phi, 1.0 / (phi * phi)];
    let delta = [0, 1].map(|k| f64::from(R2_STEP[k]) - two32 * alpha[k]);
    println!("rounding residuals delta = {delta:?} (units of 2^-32)");
    let offset = r2_offset_from_seed(pixel_seed(17, 3, 9));
    let s = offset.map(to_unit_f64);
    let ms = (0..=4096u32).chain([100_000, 999_999, 1_000_000]);
    for m in ms {
        let got = r2_point(offset, m);
        for k in 0..2 {
            let want = (s[k] + f64::from(m) * alpha[k]).fract();
            let bound = (f64::from(m) * delta[k].abs() + 2.0) / two32;
            let err = circular(to_unit_f64(got[k]), want);
            assert!(
                err <= bound,
                "m {m} k {k}: {} != {want} (tol {bound:e})",
                got[k]
            );
            // The f32 view truncates to 24 bits: 2^-24 more, below, never above.
            let err32 = circular(f64::from(to_unit_f32(got[k])), want);
            assert!(
                err32 <= bound + 1.0 / 16_777_216.0,
                "f32 m {m} k {k}: err {err32:e}"
            );
            // Within 2^-24 of the irrational sequence as long as m |delta| stays below
            // 2^8 - 2 units (x: m <= 24_000, y: m <= 1_150).
            if f64::from(m) * delta[k].abs() + 2.0 <= 256.0 {
                assert!(
                    err <= 1.0 / 16_777_216.0,
                    "m {m} k {k}: err {err:e} > 2^-24"
                );
            }
        }
    }
}

#[test]
fn unit_conversions_are_exact() {
    let probes = [
        0,
        1,
        255,
        256,
        257,
        1 << 31,
        u32::MAX - 255,
        u32::MAX - 1,
        u32::MAX,
    ];
    for u in probes
        .into_iter()
        .chain((0..10_000u32).map(|i| i.wrapping_mul(2_654_435_761)))
    {
        let want32 = f64::from(u >> 8) / 16_777_216.0;
        assert_eq!(f64::from(to_unit_f32(u)), want32, "to_unit_f32({u})");
        let want64 = f64::from(u) / 4_294_967_296.0;
        assert_eq!(to_unit_f64(u), want64, "to_unit_f64({u})");
        assert!(
            to_unit_f32(u) < 1.0 && to_unit_f64(u) < 1.0,
            "below 1 for {u}"
        );
    }
    assert_eq!(
        r2_offset_from_seed([0xFFFF, 1, 2]),
        [0xFFFF_0000, 0x0001_0000],
        "top bits"
    );
    assert_eq!(
        r2_offset_from_seed([0x1_0001, 0, 0]),
        [0x0001_0000, 0],
        "high bits dropped"
    );
}

// ---------------------------------------------------------------- discrepancy

/// Squared L2-star discrepancy of points in [0, 1)^2 by Warnock's formula:
/// `1/9 - (1/(2N)) sum_i prod_k (1 - x_ik^2) + (1/N^2) sum_ij prod_k (1 - max(x_ik, x_jk))`.
fn l2_star_discrepancy_sq(points: &[[f64; 2]]) -> f64 {
    let n = points.len() as f64;
    let single: f64 = points
        .iter()
        .map(|p| (1.0 - p[0] * p[0]) * (1.0 - p[1] * p[1]))
        .sum();
    let mut pairs = 0.0;
    for a in points {
        for b in points {
            pairs += (1.0 - a[0].max(b[0])) * (1.0 - a[1].max(b[1]));
        }
    }
    1.0 / 9.0 - single / (2.0 * n) + pairs / (n * n)
}

#[test]
fn warnock_formula_reference_value() {
    // Direct integrals of the squared discrepancy function (count / N - x y)^2.
    // One point at the origin lies in every box [0, x) x [0, y):
    // int (1 - x y)^2 = 1 - 1/2 + 1/9.
    let d2 = l2_star_discrepancy_sq(&[[0.0, 0.0]]);
    assert!((d2 - (1.0 - 0.5 + 1.0 / 9.0)).abs() < 1e-15, "D^2 {d2}");
    // One point at the centre lies in the boxes with x, y > 1/2:
    // int (1[x, y > 1/2] - x y)^2 = 1/4 - 2 (3/8)^2 + 1/9.
    let d2 = l2_star_discrepancy_sq(&[[0.5, 0.5]]);
    let want = 0.25 - 2.0 * (3.0 / 8.0) * (3.0 / 8.0) + 1.0 / 9.0;
    assert!((d2 - want).abs() < 1e-15, "D^2 {d2} != {want}");
}

#[test]
fn r2_discrepancy_is_far_below_random() {
    let n = 4096u32;
    let offset = r2_offset_from_seed(pixel_seed(8, 8, 1));
    let r2: Vec<[f64; 2]> = (0..n)
        .map(|m| r2_point(offset, m).map(to_unit_f64))
        .collect();
    // Independent uniform points from pcg3d16 (16-bit lanes).
    let random: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let h = pcg3d16([i, 77, 1]);
            [f64::from(h[0]) + 0.5, f64::from(h[1]) + 0.5].map(|x| x / 65_536.0)
        })
        .collect();
    let d_r2 = l2_star_discrepancy_sq(&r2).sqrt();
    let d_random = l2_star_discrepancy_sq(&random).sqrt();
    let expected_random = ((0.25 - 1.0 / 9.0) / f64::from(n)).sqrt();
    println!(
        "L2-star discrepancy of 4096 points: R2 {d_r2:.3e}, pcg3d16 {d_random:.3e} \
         (i.i.d. expectation {expected_random:.3e})"
    );
    assert!(
        d_r2 < 0.25 * d_random,
        "R2 {d_r2} not far below random {d_random}"
    );
    assert!(
        d_random > 0.3 * expected_random,
        "pcg points look too regular: {d_random}"
    );
}
