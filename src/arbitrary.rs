//! Hard-case float generators shared by property tests and fuzz targets.
//!
//! Uniformly random bits almost never produce the floats that break numerical code:
//! zeros, subnormals, the extremes of the range, values a few ulps from 1, and pairs a few
//! ulps apart. The functions here map raw bits (a `u64`, or fuzzer bytes through
//! [`bits_from_bytes`]) to floats biased to those cases; they are pure, so a fuzz input
//! or a failing property-test case replays exactly. The proptest [`Strategy`]
//! constructors are built on the same mappers.
//!
//! Class selection uses the low 4 bits of the input, so every class is reachable from a
//! single byte of fuzz input.
//!
//! # Examples
//!
//! ```
//! use spvg::arbitrary::{finite_f64_from_bits, hard_f64_from_bits, weight_f64_from_bits};
//! assert_eq!(hard_f64_from_bits(0), 0.0);
//! assert!(hard_f64_from_bits(14).is_nan());
//! assert!((0..4096_u64).all(|b| finite_f64_from_bits(b.wrapping_mul(0x9e37_79b9_7f4a_7c15)).is_finite()));
//! assert!((0..4096_u64).all(|b| {
//!     let eta = weight_f64_from_bits(b.wrapping_mul(0x9e37_79b9_7f4a_7c15));
//!     eta > 0.0 && eta <= 1.0
//! }));
//! ```

use num_traits::Float;
use proptest::collection::{SizeRange, vec};
use proptest::prelude::{Strategy, any};

/// Bit-level access to an IEEE binary float, for building hard cases field by field.
trait IeeeBits: Float {
    /// Explicit mantissa bits.
    const MANT: u32;
    /// The all-ones (inf/NaN) biased exponent.
    const EXP_MAX: u64;
    /// The biased exponent of 1.0.
    const BIAS: u64;
    fn from_raw(bits: u64) -> Self;
    fn to_raw(self) -> u64;
    /// The weight `1e-7`, rounded in this type.
    fn small_weight() -> Self;
}

impl IeeeBits for f64 {
    const MANT: u32 = 52;
    const EXP_MAX: u64 = 0x7ff;
    const BIAS: u64 = 1023;
    #[inline]
    fn from_raw(bits: u64) -> Self {
        f64::from_bits(bits)
    }
    #[inline]
    fn to_raw(self) -> u64 {
        self.to_bits()
    }
    #[inline]
    fn small_weight() -> Self {
        1e-7
    }
}

impl IeeeBits for f32 {
    const MANT: u32 = 23;
    const EXP_MAX: u64 = 0xff;
    const BIAS: u64 = 127;
    #[inline]
    fn from_raw(bits: u64) -> Self {
        // Only the low 32 bits are meaningful; callers build them field by field.
        f32::from_bits(u32::try_from(bits & 0xffff_ffff).unwrap_or(0))
    }
    #[inline]
    fn to_raw(self) -> u64 {
        u64::from(self.to_bits())
    }
    #[inline]
    fn small_weight() -> Self {
        1e-7
    }
}

/// Assembles a float from sign, biased exponent and mantissa fields.
#[inline]
fn compose<F: IeeeBits>(negative: bool, exp: u64, mant: u64) -> F {
    let exp_bits = 64 - (F::EXP_MAX.leading_zeros());
    let sign = u64::from(negative) << (F::MANT + exp_bits);
    F::from_raw(sign | ((exp & F::EXP_MAX) << F::MANT) | (mant & ((1 << F::MANT) - 1)))
}

fn hard<F: IeeeBits>(bits: u64) -> F {
    let class = bits & 0xf;
    let negative = (bits >> 4) & 1 == 1;
    let r = bits >> 5;
    let mant = r & ((1 << F::MANT) - 1);
    let pick = |lo: u64, width: u64| lo + (r >> F::MANT) % width;
    match class {
        0 => compose(negative, 0, 0),
        1 => compose(negative, F::EXP_MAX - 1, u64::MAX),
        2 => compose(negative, 1, 0),
        3 => compose(negative, 0, 1),
        4 | 5 => compose(negative, 0, mant.max(1)),
        6 => compose(negative, pick(1, 64), mant),
        7 => compose(negative, pick(F::EXP_MAX - 64, 64), mant),
        8 | 9 => {
            // 1 +- k ulps, k in 0..16.
            let k = r & 0xf;
            let one = F::one().to_raw();
            let v = F::from_raw(if negative { one - k } else { one + k });
            if class == 9 { -v } else { v }
        }
        10 | 11 => compose(negative, pick(F::BIAS - 20, 41), mant),
        12 | 13 => F::from_raw(r ^ (r << 17)),
        14 => F::nan(),
        _ => {
            if negative {
                F::neg_infinity()
            } else {
                F::infinity()
            }
        }
    }
}

fn finite<F: IeeeBits>(bits: u64) -> F {
    let v = hard::<F>(bits);
    if v.is_nan() {
        F::zero()
    } else if v.is_infinite() {
        v.signum() * F::max_value()
    } else {
        v
    }
}

fn weight<F: IeeeBits>(bits: u64) -> F {
    let r = bits >> 3;
    match bits & 7 {
        0 | 1 => F::one(),
        2 | 3 => F::small_weight(),
        // Tiny positive, down to the smallest subnormal.
        4 => {
            let mant = r & ((1 << F::MANT) - 1);
            let exp = (r >> F::MANT) % 65;
            compose(false, exp, if exp == 0 { mant.max(1) } else { mant })
        }
        // 1 - k ulps.
        5 => F::from_raw(F::one().to_raw() - 1 - (r & 0xf)),
        _ => {
            // Uniform in (0, 1] on a 2^-24 grid (exact in both types); 0 maps to 1.
            let u = F::from(r & 0xff_ffff).unwrap_or_else(F::one)
                / F::from(1 << 24).unwrap_or_else(F::one);
            if u > F::zero() { u } else { F::one() }
        }
    }
}

fn near_pair<F: IeeeBits>(bits: u64) -> (F, F) {
    let x = finite::<F>(bits);
    let k = (bits >> 59) & 0x7;
    let y = F::from_raw(x.to_raw().wrapping_add(k));
    // Stepping the bits can cross into inf/NaN at the top of the range or flip sign
    // through zero; fall back to the pair (x, x) then.
    if y.is_finite() && (y.is_sign_negative() == x.is_sign_negative()) {
        (x, y)
    } else {
        (x, x)
    }
}

/// Little-endian `u64` from up to 8 bytes (missing bytes are zero), for decoding fuzz
/// input.
///
/// # Examples
///
/// ```
/// assert_eq!(spvg::arbitrary::bits_from_bytes(&[1, 2]), 0x0201);
/// ```
#[inline]
#[must_use]
pub fn bits_from_bytes(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .take(8)
        .enumerate()
        .fold(0, |acc, (i, &b)| acc | (u64::from(b) << (8 * i)))
}

macro_rules! float_api {
    ($t:ident, $chunk:literal, $hard:ident, $finite:ident, $weight:ident, $near:ident,
     $stream_bytes:ident, $s_hard:ident, $s_finite:ident, $s_weight:ident, $s_near:ident,
     $s_stream:ident, $s_hard_stream:ident) => {
        #[doc = concat!("An `", stringify!($t), "` biased to hard cases: +-0, +-max, the smallest")]
        /// normal and subnormal, random subnormals, tiny and huge magnitudes, values within
        /// 16 ulps of +-1, moderate magnitudes, raw bit patterns, NaN and +-inf.
        #[inline]
        #[must_use]
        pub fn $hard(bits: u64) -> $t {
            hard::<$t>(bits)
        }

        #[doc = concat!("Like [`", stringify!($hard), "`] but always finite (NaN becomes 0, +-inf becomes")]
        /// +-max).
        #[inline]
        #[must_use]
        pub fn $finite(bits: u64) -> $t {
            finite::<$t>(bits)
        }

        /// A valid exponential weight in `(0, 1]`, biased to exactly 1, to `1e-7`, to tiny
        /// values down to subnormals, and to a few ulps below 1.
        #[inline]
        #[must_use]
        pub fn $weight(bits: u64) -> $t {
            weight::<$t>(bits)
        }

        /// A finite pair at most 7 ulps apart (same sign), for cancellation cases.
        #[inline]
        #[must_use]
        pub fn $near(bits: u64) -> ($t, $t) {
            near_pair::<$t>(bits)
        }

        #[doc = concat!("Decodes fuzz bytes into a stream: each ", stringify!($chunk), "-byte chunk through [`", stringify!($hard), "`]")]
        /// (so NaN and infinities occur).
        #[must_use]
        pub fn $stream_bytes(bytes: &[u8]) -> Vec<$t> {
            bytes.chunks($chunk).map(|c| $hard(bits_from_bytes(c))).collect()
        }

        #[doc = concat!("Strategy over [`", stringify!($hard), "`] (non-finite values included).")]
        pub fn $s_hard() -> impl Strategy<Value = $t> {
            any::<u64>().prop_map($hard)
        }

        #[doc = concat!("Strategy over [`", stringify!($finite), "`].")]
        pub fn $s_finite() -> impl Strategy<Value = $t> {
            any::<u64>().prop_map($finite)
        }

        #[doc = concat!("Strategy over [`", stringify!($weight), "`].")]
        pub fn $s_weight() -> impl Strategy<Value = $t> {
            any::<u64>().prop_map($weight)
        }

        #[doc = concat!("Strategy over [`", stringify!($near), "`].")]
        pub fn $s_near() -> impl Strategy<Value = ($t, $t)> {
            any::<u64>().prop_map($near)
        }

        /// Strategy over finite streams whose length lies in `len`.
        pub fn $s_stream(len: impl Into<SizeRange>) -> impl Strategy<Value = Vec<$t>> {
            vec($s_finite(), len)
        }

        /// Strategy over streams with non-finite values mixed in, length in `len`.
        pub fn $s_hard_stream(len: impl Into<SizeRange>) -> impl Strategy<Value = Vec<$t>> {
            vec($s_hard(), len)
        }
    };
}

float_api!(
    f64,
    8,
    hard_f64_from_bits,
    finite_f64_from_bits,
    weight_f64_from_bits,
    near_pair_f64_from_bits,
    stream_f64_from_bytes,
    hard_f64,
    finite_f64,
    weight_f64,
    near_pair_f64,
    stream_f64,
    hard_stream_f64
);
float_api!(
    f32,
    4,
    hard_f32_from_bits,
    finite_f32_from_bits,
    weight_f32_from_bits,
    near_pair_f32_from_bits,
    stream_f32_from_bytes,
    hard_f32,
    finite_f32,
    weight_f32,
    near_pair_f32,
    stream_f32,
    hard_stream_f32
);

#[cfg(test)]
mod tests {
    use super::*;

    fn mix(i: u64) -> u64 {
        // splitmix64 finaliser: spreads consecutive integers over all bits.
        let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    #[test]
    fn every_hard_class_is_hit() {
        let xs: Vec<f64> = (0..20_000).map(|i| hard_f64_from_bits(mix(i))).collect();
        let has = |p: &dyn Fn(f64) -> bool, what: &str| {
            assert!(xs.iter().any(|&x| p(x)), "no {what} generated");
        };
        has(&|x| x == 0.0, "zero");
        has(&|x| x.abs() == f64::MAX, "max");
        has(&|x| x != 0.0 && x.is_subnormal(), "subnormal");
        has(&|x| x.is_finite() && x.abs() < 1e-290 && x != 0.0, "tiny");
        has(&|x| x.is_finite() && x.abs() > 1e290, "huge");
        has(&|x| x != 1.0 && (x - 1.0).abs() < 1e-14, "near 1");
        has(&f64::is_nan, "NaN");
        has(&f64::is_infinite, "inf");
        let ys: Vec<f32> = (0..20_000).map(|i| hard_f32_from_bits(mix(i))).collect();
        assert!(ys.iter().any(|x| x.is_subnormal()), "no f32 subnormal");
        assert!(ys.iter().any(|x| x.abs() == f32::MAX), "no f32 max");
    }

    #[test]
    fn weights_are_valid_and_biased() {
        for ty in 0..2 {
            let mut ones = 0;
            let mut small = 0;
            let mut subnormal = 0;
            for i in 0..20_000 {
                let (eta, is_one, is_small, is_sub) = if ty == 0 {
                    let e = weight_f64_from_bits(mix(i));
                    (e, e == 1.0, e == 1e-7, e.is_subnormal())
                } else {
                    let e = weight_f32_from_bits(mix(i));
                    (f64::from(e), e == 1.0, e == 1e-7_f32, e.is_subnormal())
                };
                assert!(eta > 0.0 && eta <= 1.0, "weight {eta} outside (0, 1]");
                ones += usize::from(is_one);
                small += usize::from(is_small);
                subnormal += usize::from(is_sub);
            }
            assert!(
                ones > 2000 && small > 2000,
                "bias: {ones} ones, {small} 1e-7"
            );
            assert!(subnormal > 0, "no subnormal weight (type {ty})");
        }
    }

    #[test]
    fn near_pairs_are_close_and_finite() {
        for i in 0..20_000 {
            let (x, y) = near_pair_f64_from_bits(mix(i));
            assert!(x.is_finite() && y.is_finite(), "{x} {y}");
            let gap = y.to_bits().abs_diff(x.to_bits());
            assert!(gap <= 7, "{x} and {y} are {gap} ulps apart");
            let (a, b) = near_pair_f32_from_bits(mix(i));
            assert!(b.to_bits().abs_diff(a.to_bits()) <= 7, "{a} {b}");
        }
    }
}
