//! The encodings that map per-pixel histories to texels and back.

use half::f16;

use super::channels::{Element, Scales, decode_channels, encode_channels};
pub(crate) use super::chunk::CHUNK;
use super::rounding::Rounding;
pub use super::types::Layout;
use super::types::{CvTexel16, CvTexel32, SpvgTexel16, SpvgTexel32};
use crate::cv::Ocv;
use crate::{CvHistory, Error, SpvgConfig, SpvgHistory};

/// The scales shared by every pixel that turn histories into texels and back.
///
/// Encodings (channel order in [`SpvgTexel16`] and [`CvTexel16`]):
/// - `mu`, `nbar`, `zeta_f`, `zeta_g` are stored as they are.
/// - `var` is stored as `var * 2^-k`, where `2^k` is the power of two nearest
///   `sigma0^2` (`k` = the exponent of `sigma0^2`, plus one when its significand
///   exceeds `sqrt 2`), so the stored value is `var / sigma0^2` within a factor `sqrt 2`.
/// - `Sigma_xy` and `Sigma_yy` are stored as `Sigma * 2^-c`; `2^c` defaults to `2^k` and
///   can be set with [`TexelEncoding::with_cv_scale`].
///
/// Scaling by powers of two is exact (no rounding, barring `f32` overflow or underflow),
/// so `f32` texels round-trip bit for bit and a shader mirrors decoding with one exact
/// multiply by `2^k` or `2^c` (uniforms computed on the CPU by
/// [`variance_scale`](Self::variance_scale) and [`cv_scale`](Self::cv_scale)).
/// `f16`'s relative step is the same in every binade, so a non-power-of-two scale
/// (`1 / sigma0^2` exactly) would buy no accuracy, only an extra rounding.
///
/// Store (`encode`), per channel, in this order: multiply by the scale's reciprocal; map
/// NaN to 0; for `var`, `nbar` and `Sigma_yy` map anything not `> 0` to 0; clamp to
/// `+-65504` (`f16`) or `+-f32::MAX` (`f32`); round (`f16` only, see
/// [`to_f16`](super::to_f16)). Load (`decode`): apply the same sanitising to the stored
/// value (a corrupt texel cannot inject NaN, infinities or negative variances), then
/// multiply by the scale.
///
/// # Examples
///
/// ```
/// use spvg::texel::{Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::SpvgHistory;
/// let enc = TexelEncoding::new(1e-4).unwrap();
/// let h = SpvgHistory { mean: 0.75, variance: 3e-4, mean_count: 24.0 };
/// let t: SpvgTexel16 = enc.encode(&h, Rounding::Nearest);
/// // The variance is stored relative to 2^-13 (the power of two nearest 1e-4).
/// assert_eq!(t.0[1].to_f32(), half::f16::from_f32(3e-4 * 8192.0).to_f32());
/// let back = enc.decode(t);
/// assert_eq!((back.mean, back.mean_count), (0.75, 24.0));
/// assert!((back.variance - 3e-4).abs() <= 3e-4 * 2f32.powi(-11));
/// assert!(TexelEncoding::new(-1.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelEncoding {
    var_exp: i32,
    cv_exp: i32,
}

/// Exponents are kept in this range so that `2^e` and `2^-e` are normal `f32` values and
/// every decoded `f16` (at most `2^16`, at least `2^-24`) stays normal in `f32`.
const MIN_EXP: i32 = -100;
const MAX_EXP: i32 = 100;

/// The power of two nearest `v` (in log scale) as an exponent, if `v` is a positive
/// normal `f32` whose exponent lies in `[MIN_EXP, MAX_EXP]`.
fn nearest_pow2_exp(v: f32) -> Option<i32> {
    if !(v.is_finite() && v.is_normal() && v > 0.0) {
        return None;
    }
    let bits = v.to_bits();
    // Exponent field is 8 bits, so the cast cannot truncate.
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    // sqrt 2 = 1.0110101000001001111001100...b: significand field 0x3504f3 (and a bit).
    if bits & 0x7f_ffff > 0x35_04f3 {
        e += 1;
    }
    (MIN_EXP..=MAX_EXP).contains(&e).then_some(e)
}

/// `2^e` for `e` in `[MIN_EXP, MAX_EXP]`.
#[inline]
fn pow2(e: i32) -> f32 {
    // In range the biased exponent is in 27..=227: a normal f32.
    f32::from_bits(((e + 127) as u32) << 23)
}

impl TexelEncoding {
    /// The encoding for the target variance `sigma0^2`; the CV scale equals the variance
    /// scale.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `target_variance` unless it is finite and in
    /// about `[1e-30, 1e30]` (its nearest power of two within `2^-100..=2^100`).
    pub fn new(target_variance: f32) -> Result<Self, Error> {
        let var_exp = nearest_pow2_exp(target_variance).ok_or(Error::invalid(
            "target_variance",
            f64::from(target_variance),
            "must be finite and in [1e-30, 1e30]",
        ))?;
        Ok(Self {
            var_exp,
            cv_exp: var_exp,
        })
    }

    /// Sets the scale of `Sigma_xy` and `Sigma_yy` to the power of two nearest `scale`.
    ///
    /// The coefficient `alpha = (Sigma_xy + eps_a) / (Sigma_yy + eps_a)` is unchanged by
    /// the encoding: decoding restores absolute covariances, and `eps_a` applies to them.
    /// A shader that works on stored values directly must add `eps_a * 2^-c` instead; as
    /// the scale is a power of two, that gives a bit-identical `alpha` (barring
    /// underflow). Choose `scale` so that `eps_a * 2^-c` stays a normal `f16` with room
    /// below it: `eps_a * 4096` puts `eps_a` at `2^-12` in stored units and lets
    /// covariances up to `65504 * 4096 * eps_a` (268 for `eps_a = 1e-6`) be stored,
    /// where the default (`sigma0^2 = 1e-4`) saturates at 6.6.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `cv_scale` unless it is finite and in about
    /// `[1e-30, 1e30]`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::texel::TexelEncoding;
    /// let enc = TexelEncoding::new(1e-4).unwrap().with_cv_scale(1e-6 * 4096.0).unwrap();
    /// assert_eq!(enc.cv_scale(), 2f32.powi(-8));
    /// assert_eq!(enc.variance_scale(), 2f32.powi(-13));
    /// ```
    pub fn with_cv_scale(self, cv_scale: f32) -> Result<Self, Error> {
        let cv_exp = nearest_pow2_exp(cv_scale).ok_or(Error::invalid(
            "cv_scale",
            f64::from(cv_scale),
            "must be finite and in [1e-30, 1e30]",
        ))?;
        Ok(Self { cv_exp, ..self })
    }

    /// The encoding for a controller configuration (its target variance).
    ///
    /// # Errors
    ///
    /// As [`TexelEncoding::new`].
    pub fn for_config(config: &SpvgConfig<f32>) -> Result<Self, Error> {
        Self::new(config.target_variance())
    }

    /// Sets the CV scale for an OCV model: `eps_a * 4096` (see
    /// [`with_cv_scale`](Self::with_cv_scale)); unchanged when `eps_a = 0`.
    ///
    /// # Errors
    ///
    /// As [`with_cv_scale`](Self::with_cv_scale), when `eps_a * 4096` is outside about
    /// `[1e-30, 1e30]`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::SpvgConfig;
    /// use spvg::cv::Ocv;
    /// use spvg::texel::TexelEncoding;
    /// let enc = TexelEncoding::for_config(&SpvgConfig::published())
    ///     .unwrap()
    ///     .for_ocv(&Ocv::with_weight(0.05).unwrap())
    ///     .unwrap();
    /// // eps_a = 1e-6 sits at about 2^-12 in stored units.
    /// assert_eq!(enc.cv_scale(), 2f32.powi(-8));
    /// ```
    pub fn for_ocv(self, ocv: &Ocv<f32>) -> Result<Self, Error> {
        if ocv.eps_a() > 0.0 {
            self.with_cv_scale(ocv.eps_a() * 4096.0)
        } else {
            Ok(self)
        }
    }

    /// `2^k`: stored variance times this is the variance.
    #[inline]
    #[must_use]
    pub fn variance_scale(&self) -> f32 {
        pow2(self.var_exp)
    }

    /// `2^c`: stored `Sigma_xy`, `Sigma_yy` times this are the covariances.
    #[inline]
    #[must_use]
    pub fn cv_scale(&self) -> f32 {
        pow2(self.cv_exp)
    }

    /// The scales and their reciprocals, for the per-channel rules.
    #[inline]
    #[must_use]
    pub(super) fn scales(&self) -> Scales {
        Scales::new(self.variance_scale(), self.cv_scale())
    }

    /// The largest variance not above `variance` (positive) that the variance channel of
    /// `layout` stores exactly: `decode(encode(v)) == v` under any rounding, since `v` is a
    /// stored value times the power-of-two scale. For [`Layout::F32`] that is `variance`
    /// itself (barring underflow of `variance * 2^-k`); for [`Layout::F16`] it rounds
    /// `variance * 2^-k` down to an `f16`, at most one `f16` step (`2^-10` relative in the
    /// normal range) below. Where `variance` lies above the largest stored value
    /// (`65504 * 2^k`) that is the result; where it lies below the smallest positive one
    /// (`2^-24 * 2^k`), the smallest positive one (for f32, where `variance * 2^-k`
    /// underflows to 0, `variance` itself: nothing smaller is a usable target).
    ///
    /// Why: a disoccluded pixel is seeded with `var = sigma0^2` (docs/algorithms.md §2.3)
    /// so that its next estimate asks exactly its seeded count `nbar` (`var / sigma0^2 =
    /// 1`). An `f16` texel stores `sigma0^2` rounded, and the estimate multiplies that
    /// rounding error by `nbar (1 + kappa (2 / eta - 2))`: a target of `1e-3` read back as
    /// `1.0004e-3` asked 9 samples instead of 8. With the target replaced by this value
    /// ([`storable_config`](Self::storable_config)) the seed is stored exactly, and its
    /// estimate is `nbar` exactly.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::texel::{Layout, TexelEncoding};
    /// let enc = TexelEncoding::new(1e-3).unwrap();
    /// let t = enc.stored_variance(1e-3, Layout::F16);
    /// assert!(t <= 1e-3 && t > 1e-3 * (1.0 - 2f32.powi(-10)));
    /// assert_eq!(enc.stored_variance(t, Layout::F16), t);
    /// assert_eq!(enc.stored_variance(1e-3, Layout::F32), 1e-3);
    /// ```
    #[must_use]
    pub fn stored_variance(&self, variance: f32, layout: Layout) -> f32 {
        let (scale, inv) = (self.variance_scale(), 1.0 / self.variance_scale());
        match layout {
            Layout::F32 => {
                // Exact unless `variance * 2^-k` is subnormal: then step its stored value
                // down to one whose decode is not above `variance`.
                let mut x = variance * inv;
                if x * scale > variance && x > 0.0 {
                    x = f32::from_bits(x.to_bits() - 1);
                }
                if x > 0.0 { x * scale } else { variance }
            }
            Layout::F16 => {
                let s = variance * inv;
                let mut h = f16::from_f32(s.min(f16::MAX.to_f32()));
                if h.to_f32() > s && h > f16::ZERO {
                    // Positive f16 bits are ordered: one step down.
                    h = f16::from_bits(h.to_bits() - 1);
                }
                if h <= f16::ZERO || h.is_nan() {
                    h = f16::from_bits(1);
                }
                h.to_f32() * scale
            }
        }
    }

    /// `config` with its target variance replaced by
    /// [`stored_variance`](Self::stored_variance)`(target, layout)`: the configuration a
    /// history stored in `layout` texels runs with, so that a disocclusion seed decodes
    /// to the target exactly and its next estimate is its seeded count. The adaptive
    /// component of `spvg-wgpu` builds its parameter block from it.
    ///
    /// # Errors
    ///
    /// As [`SpvgConfig::builder`]'s `build` (not for a valid `config`).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::texel::{Layout, Rounding, SpvgTexel16, TexelEncoding};
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let config = SpvgConfig::<f32>::builder().target_variance(1e-3).build().unwrap();
    /// let enc = TexelEncoding::for_config(&config).unwrap();
    /// let stored = enc.storable_config(&config, Layout::F16).unwrap();
    /// let seed = SpvgHistory::seeded(0.5, &stored, 8);
    /// let back = enc.decode(enc.encode::<SpvgTexel16>(&seed, Rounding::Nearest));
    /// assert_eq!(back.variance, stored.target_variance());
    /// assert_eq!(stored.estimate(&back, 1.0), 8);
    /// ```
    pub fn storable_config(
        &self,
        config: &SpvgConfig<f32>,
        layout: Layout,
    ) -> Result<SpvgConfig<f32>, Error> {
        let target = self.stored_variance(config.target_variance(), layout);
        if target == config.target_variance() {
            return Ok(*config);
        }
        config.to_builder().target_variance(target).build()
    }

    /// Stores a history in a texel (see the type docs for the exact steps).
    #[inline]
    #[must_use]
    pub fn encode<T: Texel>(&self, history: &T::History, rounding: Rounding) -> T {
        T::encode(self, history, rounding)
    }

    /// Loads a history from a texel; the result is always finite, with non-negative
    /// variances and count.
    #[inline]
    #[must_use]
    pub fn decode<T: Texel>(&self, texel: T) -> T::History {
        texel.decode(self)
    }
}

mod sealed {
    /// The crate's side of a texel type. `Element` and `Chunked` are `pub` traits in
    /// private modules (nameable only inside the crate) because they bound this one.
    pub trait Sealed: bytemuck::Pod {
        /// The storage type of its four channels (`f16` or `f32`).
        type Element: super::Element;
    }
}

/// A texel type that stores one per-pixel history; implemented by the four layouts of
/// this module (sealed).
pub trait Texel: bytemuck::Pod + core::fmt::Debug + sealed::Sealed {
    /// The history stored in it, in `f32`.
    type History: Copy;
    /// Its storage precision.
    const LAYOUT: Layout;
    /// Stores `history` with the scales of `enc`.
    #[must_use]
    fn encode(enc: &TexelEncoding, history: &Self::History, rounding: Rounding) -> Self;
    /// Loads the history with the scales of `enc`.
    #[must_use]
    fn decode(self, enc: &TexelEncoding) -> Self::History;
}

/// The channels of a slice of texels, for the chunk loads and stores of the frame
/// functions. Every texel type is `#[repr(C)]` four channels of its element type (same
/// alignment), so the cast cannot fail.
#[inline(always)]
pub(super) fn channels<T: Texel>(texels: &[T]) -> &[T::Element] {
    bytemuck::cast_slice(texels)
}

/// [`channels`], mutable.
#[inline(always)]
pub(super) fn channels_mut<T: Texel>(texels: &mut [T]) -> &mut [T::Element] {
    bytemuck::cast_slice_mut(texels)
}

/// Implements [`Texel`] for a layout: a history (`Channels`) in four channels of an
/// `Element` type (`f16` or `f32`). The four layouts differ only in these two types; the
/// per-channel rules live in `channels.rs`.
macro_rules! texel {
    ($texel:ident, $element:ty, $history:ty) => {
        impl sealed::Sealed for $texel {
            type Element = $element;
        }

        impl Texel for $texel {
            type History = $history;
            const LAYOUT: Layout = <$element as Element>::LAYOUT;

            #[inline]
            fn encode(enc: &TexelEncoding, history: &$history, rounding: Rounding) -> Self {
                Self(encode_channels(&enc.scales(), history, rounding))
            }

            #[inline]
            fn decode(self, enc: &TexelEncoding) -> $history {
                decode_channels(&enc.scales(), self.0)
            }
        }
    };
}

texel!(SpvgTexel16, f16, SpvgHistory<f32>);
texel!(SpvgTexel32, f32, SpvgHistory<f32>);
texel!(CvTexel16, f16, CvHistory<f32>);
texel!(CvTexel32, f32, CvHistory<f32>);
