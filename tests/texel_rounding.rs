//! Properties of the f32 -> f16 store: saturation, NaN policy, and stochastic rounding
//! (always a neighbour, unbiased, exact probabilities).

use half::f16;
use proptest::prelude::*;
use spvg::texel::{Rounding, to_f16};

/// The two f16 values bracketing `x` (in range, not NaN), found by stepping the bits of
/// the round-to-nearest result: an oracle independent of the code under test.
fn neighbours(x: f32) -> (f64, f64) {
    let rn = f16::from_f32(x);
    let v = f64::from(rn.to_f32());
    let xd = f64::from(x);
    if v == xd {
        return (v, v);
    }
    // Step one ulp in magnitude away from or towards zero, keeping the sign bit.
    let bits = rn.to_bits();
    let (mag, sign) = (bits & 0x7fff, bits & 0x8000);
    let other = if v.abs() > xd.abs() { mag - 1 } else { mag + 1 };
    let w = f64::from(f16::from_bits(sign | other).to_f32());
    if v < w { (v, w) } else { (w, v) }
}

/// Hard cases: any f32 bit pattern inside the f16 range (so subnormals, tiny f32 values,
/// exact f16 values and both signs are all drawn), plus values at the top of the range.
fn in_range() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<u32>().prop_map(|b| {
            let x = f32::from_bits(b & 0xc7ff_ffff);
            if x.is_finite() && x.abs() <= 65504.0 {
                x
            } else {
                1.0
            }
        }),
        (0_u16..0x7c00, any::<bool>())
            .prop_map(|(b, s)| f16::from_bits(b | if s { 0x8000 } else { 0 }).to_f32()),
        (65000.0_f32..=65504.0).prop_map(|x| x),
        (-1e-6_f32..1e-6).prop_map(|x| x),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    #[test]
    fn stochastic_gives_a_neighbour(x in in_range(), r in any::<u32>()) {
        let got = f64::from(to_f16(x, Rounding::Stochastic(r)).to_f32());
        let (lo, hi) = neighbours(x);
        prop_assert!(got == lo || got == hi, "{x}: {got} not in {{{lo}, {hi}}}");
        if lo == hi {
            prop_assert!(got == lo, "exact {x} must stay exact, got {got}");
        }
        // The sign is kept: no zero crossing.
        prop_assert!(got == 0.0 || (got > 0.0) == (x > 0.0), "{x} changed sign to {got}");
    }

    #[test]
    fn nearest_is_ieee(x in in_range()) {
        let got = to_f16(x, Rounding::Nearest);
        prop_assert_eq!(got.to_bits(), f16::from_f32(x).to_bits(), "{}", x);
    }
}

/// Mean of the results over every value of the top `b` bits of the random word: the exact
/// expectation when the rounding uses at most `b` bits.
fn exact_mean(x: f32, b: u32) -> f64 {
    let n = 1_u64 << b;
    let sum: f64 = (0..n)
        .map(|i| {
            let r = (i << (32 - b)) as u32;
            f64::from(to_f16(x, Rounding::Stochastic(r)).to_f32())
        })
        .sum();
    sum / n as f64
}

#[test]
fn stochastic_expectation_is_exact_in_normal_range() {
    let mut state = 0x1234_5678_u32;
    for _ in 0..64 {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        // Magnitudes from 2^-14 to 2^15, both signs, arbitrary significand.
        let e = (state >> 27) % 29;
        let bits = ((113 + e) << 23) | (state & 0x7f_ffff) | (state & 0x8000_0000);
        let x = f32::from_bits(bits);
        let got = exact_mean(x, 13);
        // Sums of 8192 f16 values with at most 24 significant bits are exact in f64.
        assert!(got == f64::from(x), "E[sr({x})] = {got}");
    }
}

#[test]
fn stochastic_expectation_is_exact_in_subnormal_range() {
    // 2^-14 > |x| >= 2^-18: at most 17 discarded bits, so 2^17 words cover every case.
    for x in [6.0e-5_f32, -3.3e-5, 1.0e-5, 4.0e-6, 2.0e-5 + 1e-9] {
        let got = exact_mean(x, 17);
        assert!(got == f64::from(x), "E[sr({x})] = {got}");
    }
}

#[test]
fn stochastic_expectation_tiny_values_statistically() {
    // Far below the smallest subnormal 2^-24: up with probability x / 2^-24.
    let x = 1.0e-9_f32;
    let p = f64::from(x) / 2f64.powi(-24);
    let n = 200_000_u32;
    let mut state = 99_u32;
    let mut ups = 0_u32;
    for _ in 0..n {
        state = state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let r = state ^ (state >> 13);
        if to_f16(x, Rounding::Stochastic(r)).to_f32() > 0.0 {
            ups += 1;
        }
    }
    let got = f64::from(ups) / f64::from(n);
    let tol = 5.0 * (p * (1.0 - p) / f64::from(n)).sqrt();
    assert!((got - p).abs() <= tol, "{got} != {p} (tol {tol})");
}

#[test]
fn saturation_and_nan() {
    for rounding in [
        Rounding::Nearest,
        Rounding::Stochastic(0xffff_ffff),
        Rounding::Stochastic(0),
    ] {
        assert_eq!(to_f16(f32::NAN, rounding).to_f32(), 0.0, "NaN stores as 0");
        assert_eq!(
            to_f16(f32::INFINITY, rounding).to_f32(),
            65504.0,
            "inf saturates"
        );
        assert_eq!(
            to_f16(-f32::INFINITY, rounding).to_f32(),
            -65504.0,
            "-inf saturates"
        );
        assert_eq!(
            to_f16(65519.0, rounding).to_f32(),
            65504.0,
            "above max saturates"
        );
        assert_eq!(to_f16(1e30, rounding).to_f32(), 65504.0, "huge saturates");
        assert_eq!(to_f16(65504.0, rounding).to_f32(), 65504.0, "max is exact");
        assert!(
            to_f16(-1e-30, rounding).to_f32() == 0.0,
            "tiny negative rounds to zero"
        );
    }
    // The largest f16 below 65504 with almost a full ulp above rounds up to the max only.
    let x = 65503.9_f32;
    for i in 0..64_u32 {
        let v = to_f16(x, Rounding::Stochastic(i << 26)).to_f32();
        assert!(
            v == 65472.0 || v == 65504.0,
            "{v} is not a neighbour of {x}"
        );
    }
}
