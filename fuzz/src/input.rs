//! Decoding fuzz bytes: a cursor that never fails (missing bytes read as zero) and the
//! float types the checks run in.
//!
//! Every check decodes the same bytes once per float type, so one input exercises `f32`
//! and `f64` alike; the hard-case mappers of `spvg::arbitrary` turn 8 bytes into a float
//! biased to zeros, subnormals, extremes, values next to 1, NaN and infinities.

use core::fmt::Debug;

use num_traits::Float;
use spvg::arbitrary::{
    bits_from_bytes, finite_f32_from_bits, finite_f64_from_bits, hard_f32_from_bits,
    hard_f64_from_bits, weight_f32_from_bits, weight_f64_from_bits,
};

/// A cursor over fuzz input. Reading past the end yields zero bytes, so every input (the
/// empty one included) decodes to something.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Input<'a> {
    data: &'a [u8],
}

impl<'a> Input<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Self { data }
    }

    /// Whether every byte was consumed.
    pub(crate) fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The next byte, 0 past the end.
    pub(crate) fn byte(&mut self) -> u8 {
        let (head, rest) = self.data.split_at(self.data.len().min(1));
        self.data = rest;
        head.first().copied().unwrap_or(0)
    }

    /// The next 8 bytes as a little-endian `u64` (zero-padded past the end).
    pub(crate) fn bits(&mut self) -> u64 {
        let (head, rest) = self.data.split_at(self.data.len().min(8));
        self.data = rest;
        bits_from_bytes(head)
    }

    /// A hard-case float (NaN and infinities included).
    pub(crate) fn hard<T: Real>(&mut self) -> T {
        T::hard(self.bits())
    }

    /// A hard-case finite float.
    pub(crate) fn finite<T: Real>(&mut self) -> T {
        T::finite(self.bits())
    }

    /// A valid exponential weight in `(0, 1]`.
    pub(crate) fn weight<T: Real>(&mut self) -> T {
        T::weight(self.bits())
    }

    /// A value in `[0, 1]`, biased to 0, 1 and `special`; uniform on a 2^-24 grid
    /// otherwise (exact in both float types).
    pub(crate) fn unit<T: Real>(&mut self, special: T) -> T {
        let bits = self.bits();
        match bits & 7 {
            0 => T::zero(),
            1 => T::one(),
            2 => special,
            _ => T::from_f64(((bits >> 8) & 0xff_ffff) as f64 / f64::from(1 << 24)),
        }
    }
}

/// The float types the checks run in.
pub(crate) trait Real: Float + Debug + Default + 'static {
    /// `f32` or `f64`, for messages.
    const NAME: &'static str;
    fn hard(bits: u64) -> Self;
    fn finite(bits: u64) -> Self;
    fn weight(bits: u64) -> Self;
    /// Rounds an `f64` to this type (exact for the constants the checks use).
    fn from_f64(v: f64) -> Self;
    /// Widens to `f64` (exact).
    fn wide(self) -> f64;
    /// The raw bits, for comparisons that must treat NaN as equal to itself.
    fn raw(self) -> u64;
}

/// `Real` for a primitive float type, from the `spvg::arbitrary` mappers named for it.
/// The conversions are written once for both: for `f64` they are identities, for `f32`
/// `as` rounds to nearest and the two `from` widen exactly.
macro_rules! real {
    ($t:ident, $hard:ident, $finite:ident, $weight:ident) => {
        impl Real for $t {
            const NAME: &'static str = stringify!($t);
            fn hard(bits: u64) -> Self {
                $hard(bits)
            }
            fn finite(bits: u64) -> Self {
                $finite(bits)
            }
            fn weight(bits: u64) -> Self {
                $weight(bits)
            }
            fn from_f64(v: f64) -> Self {
                v as $t
            }
            fn wide(self) -> f64 {
                f64::from(self)
            }
            fn raw(self) -> u64 {
                u64::from(self.to_bits())
            }
        }
    };
}

real!(
    f64,
    hard_f64_from_bits,
    finite_f64_from_bits,
    weight_f64_from_bits
);
real!(
    f32,
    hard_f32_from_bits,
    finite_f32_from_bits,
    weight_f32_from_bits
);

/// Bitwise equality of float tuples (NaN equal to the same NaN), for "state unchanged".
pub(crate) fn same<T: Real, const N: usize>(a: [T; N], b: [T; N]) -> bool {
    a.iter().zip(b.iter()).all(|(x, y)| x.raw() == y.raw())
}

/// `min(v, MAX)` with `-inf` to `-MAX`: the crate's overflow policy, for references.
pub(crate) fn sat<T: Real>(v: T) -> T {
    if v.is_infinite() {
        v.signum() * T::max_value()
    } else {
        v
    }
}
