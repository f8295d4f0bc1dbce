//! `f32 -> f16` conversion for storage: saturating, NaN-free, with optional stochastic
//! rounding.
//!
//! Round-to-nearest freezes a slowly updated state: an EMA step `eta (x - mu)` under half
//! an ulp of `mu` is rounded away every frame (docs/algorithms.md §4). Stochastic rounding rounds to one
//! of the two neighbouring `f16` values with probability proportional to the distance to
//! the other one, so the stored value equals the exact one in expectation and small steps
//! accumulate.

use half::f16;

/// A signed stored value: NaN to 0, clamped to `[-max, max]`.
#[inline(always)]
#[must_use]
pub(super) fn clamp_signed(v: f32, max: f32) -> f32 {
    // `max`/`min` return the non-NaN operand, so NaN would become -max; test it first.
    if v.is_nan() { 0.0 } else { v.clamp(-max, max) }
}

/// Largest finite `f16` value, as `f32`.
pub(crate) const F16_MAX: f32 = 65504.0;

/// How an `f32` is rounded to `f16` when a texel is stored. `f32` texels ignore it: they
/// store the `f32` value exactly.
///
/// # Examples
///
/// ```
/// use spvg::texel::{Rounding, to_f16};
/// // 1 + 2^-12 lies a quarter ulp above 1.0: nearest always gives 1.0 ...
/// let x = 1.0 + 2.0_f32.powi(-12);
/// assert_eq!(to_f16(x, Rounding::Nearest).to_f32(), 1.0);
/// // ... stochastic rounding gives 1 + 2^-10 for a quarter of the random words.
/// let ups = (0..1024_u32)
///     .filter(|i| to_f16(x, Rounding::Stochastic(i << 22)).to_f32() > 1.0)
///     .count();
/// assert_eq!(ups, 256);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rounding {
    /// IEEE round-to-nearest-even (`half::f16::from_f32`), what a GPU store does.
    Nearest,
    /// Stochastic rounding driven by a caller-supplied uniformly random `u32` (for
    /// example a hash of pixel and frame). See [`to_f16`] for which bits are used.
    Stochastic(u32),
}

/// Converts an `f32` to `f16` for storage.
///
/// - NaN becomes `+0`; values beyond `+-65504` (infinities included) saturate to
///   `+-65504`. The result is always finite.
/// - [`Rounding::Nearest`]: `half::f16::from_f32` of the clamped value.
/// - [`Rounding::Stochastic(r)`](Rounding::Stochastic): the result is `lo` or `hi`, the
///   two `f16` values that bracket `x` (equal when `x` is representable), and it is `hi`
///   with probability `(|x| - |lo|) / (|hi| - |lo|)` over a uniformly random `r`, so
///   `E[result] = x` exactly. Rounding is on the magnitude, so the sign is kept and zero
///   crossings cannot happen. For `|x| >= 2^-14` (normal `f16`) the top 13 bits of `r`
///   decide (`x`'s 13 discarded significand bits are an exact fraction of 2^13). Below,
///   the `f16` grid is the multiples of `2^-24`: with `s` discarded bits the top `s` bits
///   of `r` decide, exact while `s <= 32` (`|x| >= 2^-33`); for smaller `|x|` the
///   probability is truncated to a multiple of `2^-32`, a bias under `2^-56` in absolute
///   value.
///
/// A WGSL mirror: clamp as above, then with `a = bits & 0x7fffffff` of the `f32`:
/// if `a >= 0x38800000` the `f16` bits are `(((a + (r >> 19)) & ~0x1fffu) >> 13) -
/// 0x1c000u`; otherwise `q = floor(|x| 2^24)`, `rem = |x| 2^24 - q` and the result is
/// `(q + select(0, 1, r < floor(rem 2^32))) 2^-24` (exact in integers as in the code).
/// The sign is copied from `x`.
///
/// # Examples
///
/// ```
/// use spvg::texel::{Rounding, to_f16};
/// assert_eq!(to_f16(f32::NAN, Rounding::Nearest).to_f32(), 0.0);
/// assert_eq!(to_f16(1e9, Rounding::Stochastic(7)).to_f32(), 65504.0);
/// assert_eq!(to_f16(-0.5, Rounding::Stochastic(u32::MAX)).to_f32(), -0.5);
/// ```
#[inline]
#[must_use]
pub fn to_f16(x: f32, rounding: Rounding) -> f16 {
    // The value every `f16` store starts from, so that nothing non-finite is stored.
    let x = clamp_signed(x, F16_MAX);
    match rounding {
        Rounding::Nearest => f16::from_f32(x),
        Rounding::Stochastic(r) => f16::from_bits(stochastic_bits(x, r)),
    }
}

/// Stochastic rounding of a value already inside `[-65504, 65504]` (not NaN) to `f16`
/// bits. Branch-free, in 32-bit integers (both ranges computed, one selected), so that
/// the frame functions' chunk stores vectorise it.
#[inline(always)]
#[must_use]
pub(crate) fn stochastic_bits(x: f32, r: u32) -> u16 {
    let bits = x.to_bits();
    let sign = (bits >> 16) & 0x8000;
    let a = bits & 0x7fff_ffff;
    // Normal f16 range. Adding a uniform 13-bit integer to the bit pattern carries into
    // bit 13 with probability (discarded bits) / 2^13; a carry out of the significand
    // bumps the exponent, which is the next f16 as well. `a` is at most 65504's pattern,
    // whose discarded bits are zero, so no carry can leave the range. Rebias the
    // exponent from 127 to 15: subtract (127 - 15) << 10 after the shift.
    let normal = (((a + (r >> 19)) & !0x1fff) >> 13).wrapping_sub(112 << 10);
    // Subnormal f16 range: the grid is k 2^-24. Write |x| = m 2^(e - 150) with the 24-bit
    // significand m; in units of 2^-24 that is m / 2^s with s = 126 - e >= 14 (wrapping
    // where `a` is in the normal range, whose result is not selected). An f32 zero or
    // subnormal (e = 0, s = 126) and every s >= 56 (m / 2^s < 2^-32) give q = 0 and an
    // up probability truncated to 0 through the shifts below, as they should.
    let s = 126_u32.wrapping_sub(a >> 23);
    let m = (a & 0x7f_ffff) | 0x80_0000;
    let q = m.checked_shr(s).unwrap_or(0);
    // The s discarded bits (all of m once s >= 24).
    let rem = m & 1_u32.checked_shl(s).unwrap_or(0).wrapping_sub(1);
    // P(up) = rem / 2^s = k / 2^32 with k = floor(rem 2^(32 - s)) < 2^32, exact while
    // s <= 32. (The shifts are checked: s wraps for normal values.)
    let k = if s <= 32 {
        rem.checked_shl(32 - s).unwrap_or(0)
    } else {
        rem.checked_shr(s - 32).unwrap_or(0)
    };
    // q + up <= 1024: 1024 is 2^-14's pattern, the smallest normal, as it should be.
    let sub = q + u32::from(r < k);
    let magnitude = if a >= 0x3880_0000 { normal } else { sub };
    // Both parts fit in 16 bits (the largest is 65504's pattern, 0x7bff).
    (sign | magnitude) as u16
}

/// The random word used for channel `channel` (0..4) of a texel stored with
/// [`Rounding::Stochastic(random)`](Rounding::Stochastic): the channels of a texel need
/// independent bits, so each one hashes `random + channel * 0x9e3779b9` with a 32-bit
/// integer finaliser (`x ^= x >> 16; x *= 0x7feb352d; x ^= x >> 15; x *= 0x846ca68b;
/// x ^= x >> 16`, wrapping), which a shader can mirror.
///
/// # Examples
///
/// ```
/// use spvg::texel::channel_bits;
/// assert_ne!(channel_bits(5, 0), channel_bits(5, 1));
/// ```
#[inline]
#[must_use]
pub fn channel_bits(random: u32, channel: u32) -> u32 {
    let mut x = random.wrapping_add(channel.wrapping_mul(0x9e37_79b9));
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// `f16` bits to `f32`, exact, branch-free (so that slice loops vectorise without F16C).
/// Infinities and NaN come out as infinities and (quiet) NaN.
#[inline(always)]
#[must_use]
#[cfg_attr(
    all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "f16c"
    ),
    allow(
        dead_code,
        reason = "F16C compiled in: only `Portable` (tests) converts by bits"
    )
)]
pub(crate) fn widen_bits(h: u16) -> f32 {
    let h = u32::from(h);
    let sign = (h & 0x8000) << 16;
    let em = h & 0x7fff;
    // Normal: shift the exponent and significand into place and rebias 15 -> 127.
    let normal = (em << 13) + 0x3800_0000;
    // Subnormal (and zero): the significand counts units of 2^-24, exactly.
    let sub = (em as f32 * 5.960_464_5e-8).to_bits();
    // Infinity and NaN: all-ones exponent, significand kept (NaN stays NaN).
    let special = (em << 13) | 0x7f80_0000;
    let bits = if em < 0x0400 {
        sub
    } else if em >= 0x7c00 {
        special
    } else {
        normal
    };
    f32::from_bits(sign | bits)
}

/// `f32` in `[-65504, 65504]` (not NaN) to `f16` bits, round-to-nearest-even, branch-free:
/// the same bits as `half::f16::from_f32` on that domain.
#[inline(always)]
#[must_use]
#[cfg_attr(
    all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "f16c"
    ),
    allow(
        dead_code,
        reason = "F16C compiled in: only `Portable` (tests) converts by bits"
    )
)]
pub(crate) fn narrow_bits(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = (b >> 16) & 0x8000;
    let a = b & 0x7fff_ffff;
    // Normal f16: round the 13 discarded bits to nearest, ties to even (adding 0xfff plus
    // the kept lsb carries exactly when above half, or at half with an odd lsb); a carry
    // out of the significand bumps the exponent, as it should. 65504 has zero discarded
    // bits, so the clamped domain cannot round to infinity.
    let normal = ((a + 0x0fff + ((a >> 13) & 1)) >> 13).wrapping_sub(112 << 10);
    // Subnormal f16: adding 0.5 makes the FPU round |x| to a multiple of 2^-24 (ties to
    // even); the low bits of the sum are then the f16 significand (up to 0x400, the
    // smallest normal).
    let sub = (f32::from_bits(a) + 0.5)
        .to_bits()
        .wrapping_sub(0x3f00_0000);
    let bits = if a < 0x3880_0000 { sub } else { normal };
    (sign | bits) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The former `stochastic_bits`, with a branch per range, in 64-bit integers: a
    /// second implementation to hold the branch-free one to.
    fn stochastic_reference(x: f32, r: u32) -> u16 {
        let bits = x.to_bits();
        let sign = ((bits >> 16) & 0x8000) as u16;
        let a = bits & 0x7fff_ffff;
        if a >= 0x3880_0000 {
            let t = (a + (r >> 19)) & !0x1fff;
            return sign | ((t >> 13) - (112 << 10)) as u16;
        }
        let e = a >> 23;
        if e == 0 {
            return sign;
        }
        let s = 126 - e;
        if s >= 56 {
            return sign;
        }
        let m = u64::from((a & 0x7f_ffff) | 0x80_0000);
        let q = m >> s;
        let rem = m & ((1_u64 << s) - 1);
        let k = (rem << 32) >> s;
        let up = u64::from(u64::from(r) < k);
        sign | (q + up) as u16
    }

    /// Words that hit the edges of the comparison `r < k` and of the normal range's
    /// 13-bit carry, and hashed ones.
    fn words(x: f32) -> impl Iterator<Item = u32> {
        let b = x.to_bits();
        [
            0,
            1,
            u32::MAX,
            u32::MAX - 1,
            1 << 31,
            (1 << 19) - 1,
            1 << 19,
        ]
        .into_iter()
        .chain((0..8).map(move |c| channel_bits(b, c)))
        .chain((0..64_u32).map(|k| (k << 26) | 0x3ff_ffff))
    }

    #[test]
    fn stochastic_bits_match_the_reference() {
        let mut values = Vec::new();
        // Every f16 value, its neighbours in f32 and the midpoints.
        for h in 0..0x7bff_u16 {
            let v = f16::from_bits(h).to_f32();
            let next = f16::from_bits(h + 1).to_f32();
            let mid = ((f64::from(v) + f64::from(next)) / 2.0) as f32;
            for x in [v, mid, next] {
                for d in [-1_i32, 0, 1] {
                    values.push(f32::from_bits(x.to_bits().wrapping_add_signed(d)));
                }
            }
        }
        // A stride through every f32 exponent below the f16 range (s from 14 to 126).
        values.extend((0..0x3880_0000_u32).step_by(4099).map(f32::from_bits));
        values.extend([0.0, 65504.0, 65503.0, 1e-45, 1e-40, 2.0f32.powi(-133)]);
        for x in values {
            if x.is_nan() || x.abs() > 65504.0 {
                continue;
            }
            for x in [x, -x] {
                for r in words(x) {
                    let (got, want) = (stochastic_bits(x, r), stochastic_reference(x, r));
                    assert_eq!(got, want, "x = {x:e} ({:#x}), r = {r:#x}", x.to_bits());
                }
            }
        }
    }

    #[test]
    fn widen_matches_half_on_every_f16() {
        for h in 0..=u16::MAX {
            let want = f16::from_bits(h).to_f32();
            let got = widen_bits(h);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{h:#06x}: {got} != {want}"
            );
        }
    }

    #[test]
    fn narrow_matches_half_near_every_f16() {
        // Every f16 value, the f32 values around it and the exact midpoints (ties) and
        // their neighbours: where round-to-nearest-even can go wrong.
        for h in 0..0x7c00_u16 {
            let v = f16::from_bits(h).to_f32();
            let next = f16::from_bits(h + 1).to_f32();
            let mid = ((f64::from(v) + f64::from(next)) / 2.0) as f32;
            for x in [v, mid, next] {
                for d in [-2_i32, -1, 0, 1, 2] {
                    let y = f32::from_bits(x.to_bits().wrapping_add_signed(d));
                    for y in [y, -y] {
                        if y.is_nan() || y.abs() > 65504.0 {
                            continue;
                        }
                        let want = f16::from_f32(y).to_bits();
                        assert_eq!(narrow_bits(y), want, "{y:e}");
                    }
                }
            }
        }
        // Tiny f32 values, f32 subnormals and zero.
        for y in [
            0.0_f32,
            -0.0,
            1e-45,
            1e-40,
            1e-30,
            2.98e-8,
            2.9802322e-8,
            2.9802326e-8,
        ] {
            assert_eq!(narrow_bits(y), f16::from_f32(y).to_bits(), "{y:e}");
        }
    }
}
