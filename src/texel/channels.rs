//! What the four channels of a texel hold and how one channel value is stored and loaded.
//!
//! Every texel encoding is one rule per channel: a channel is signed or non-negative,
//! and stored as it is or over one of the encoding's two scales ([`Channel`]). A history lists its channels once ([`Channels`]), a storage type
//! (`f16`, `f32`) says how far it reaches and how it rounds ([`Element`]), and the
//! per-pixel `encode`/`decode` and the frame functions' lanes all apply the same two
//! per-channel steps ([`Channel::store`], [`Channel::load`]), so the texel layouts and
//! the frame functions cannot drift apart.

use half::f16;

use super::chunk::{CHUNK, Chunked};
use super::rounding::{F16_MAX, Rounding, channel_bits, clamp_signed, to_f16};
use super::types::Layout;
use crate::stats::rules::saturate as sat;
use crate::{CvHistory, SpvgHistory};

/// A non-negative stored value (variance, count): NaN and anything not positive to 0,
/// clamped to `max`.
#[inline(always)]
#[must_use]
fn clamp_non_negative(v: f32, max: f32) -> f32 {
    let v = if v > 0.0 { v } else { 0.0 };
    v.min(max)
}

/// The sign a channel may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// Means and covariances: any sign.
    Signed,
    /// Variances and counts: never negative.
    NonNegative,
}

/// The scale a channel is stored over (see [`TexelEncoding`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scale {
    /// Stored as it is.
    One,
    /// Over `2^k`, the power of two nearest `sigma0^2`.
    Variance,
    /// Over `2^c`, the CV scale.
    Cv,
}

/// How one texel channel is stored: its sign and its scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Channel {
    kind: Kind,
    scale: Scale,
}

impl Channel {
    const SIGNED: Self = Self::new(Kind::Signed, Scale::One);
    const NON_NEGATIVE: Self = Self::new(Kind::NonNegative, Scale::One);

    #[inline]
    #[must_use]
    const fn new(kind: Kind, scale: Scale) -> Self {
        Self { kind, scale }
    }

    #[inline(always)]
    #[must_use]
    fn clamp(self, v: f32, max: f32) -> f32 {
        match self.kind {
            Kind::Signed => clamp_signed(v, max),
            Kind::NonNegative => clamp_non_negative(v, max),
        }
    }

    /// The value to store for `v` in a layout whose largest finite value is `max`:
    /// divided by the channel's scale (an exact multiply by a power of two), then
    /// sanitised for the channel's sign and clamped to `[-max, max]`. `f16` layouts
    /// round the result ([`Element::narrow`]).
    #[inline(always)]
    #[must_use]
    pub(super) fn store(self, v: f32, max: f32, scales: &Scales) -> f32 {
        let v = match self.scale {
            Scale::One => v,
            Scale::Variance => v * scales.inv_var,
            Scale::Cv => v * scales.inv_cv,
        };
        self.clamp(v, max)
    }

    /// The value a stored channel (widened to `f32`, any bits) stands for: sanitised as
    /// on store, so a corrupt texel cannot inject NaN, infinities or negative variances,
    /// then multiplied by the channel's scale. The sanitised value times a positive
    /// normal power of two is never NaN and keeps its sign, so saturating it restores
    /// the `f32` range without another sign test.
    #[inline(always)]
    #[must_use]
    pub(super) fn load(self, stored: f32, max: f32, scales: &Scales) -> f32 {
        let v = self.clamp(stored, max);
        match self.scale {
            Scale::One => v,
            Scale::Variance => sat(v * scales.var),
            Scale::Cv => sat(v * scales.cv),
        }
    }
}

/// The scales of a [`TexelEncoding`](super::TexelEncoding) and their reciprocals (all powers of two, so the
/// reciprocals are exact), computed once per texel or per frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scales {
    var: f32,
    inv_var: f32,
    cv: f32,
    inv_cv: f32,
}

impl Scales {
    #[inline]
    #[must_use]
    pub(super) fn new(var: f32, cv: f32) -> Self {
        Self {
            var,
            inv_var: 1.0 / var,
            cv,
            inv_cv: 1.0 / cv,
        }
    }
}

/// A history stored in the four channels of a texel (channel order as in the module
/// docs' table).
pub(super) trait Channels: Copy {
    /// How each channel is stored.
    const CHANNELS: [Channel; 4];
    /// The channel values, in texel order.
    fn to_channels(&self) -> [f32; 4];
    /// The history from decoded channel values.
    fn from_channels(values: [f32; 4]) -> Self;
}

impl Channels for SpvgHistory<f32> {
    const CHANNELS: [Channel; 4] = [
        Channel::SIGNED,
        Channel::new(Kind::NonNegative, Scale::Variance),
        Channel::NON_NEGATIVE,
        // The spare channel: always stored as 0.
        Channel::SIGNED,
    ];

    #[inline(always)]
    fn to_channels(&self) -> [f32; 4] {
        [self.mean, self.variance, self.mean_count, 0.0]
    }

    #[inline(always)]
    fn from_channels([mean, variance, mean_count, _]: [f32; 4]) -> Self {
        Self {
            mean,
            variance,
            mean_count,
        }
    }
}

impl Channels for CvHistory<f32> {
    const CHANNELS: [Channel; 4] = [
        Channel::new(Kind::Signed, Scale::Cv),
        Channel::new(Kind::NonNegative, Scale::Cv),
        Channel::SIGNED,
        Channel::SIGNED,
    ];

    #[inline(always)]
    fn to_channels(&self) -> [f32; 4] {
        [self.cov_fg, self.var_g, self.mean_f, self.mean_g]
    }

    #[inline(always)]
    fn from_channels([cov_fg, var_g, mean_f, mean_g]: [f32; 4]) -> Self {
        Self {
            cov_fg,
            var_g,
            mean_f,
            mean_g,
        }
    }
}

/// The storage type of a texel's channels: `f16` (RGBA16F) or `f32` (RGBA32F).
#[allow(
    unreachable_pub,
    reason = "a sealed bound of the public frame functions: public so it may bound them, unnameable outside"
)]
pub trait Element: bytemuck::Pod + Chunked {
    /// The layout of texels of this type.
    const LAYOUT: Layout;
    /// Largest finite stored value.
    const MAX: f32;
    /// Stores a value already clamped to `[-MAX, MAX]` (not NaN): `f16` rounds it.
    fn narrow(v: f32, rounding: Rounding) -> Self;
    /// The stored value as `f32`, exactly.
    fn widen(self) -> f32;
}

impl Element for f16 {
    const LAYOUT: Layout = Layout::F16;
    const MAX: f32 = F16_MAX;

    #[inline(always)]
    fn narrow(v: f32, rounding: Rounding) -> Self {
        to_f16(v, rounding)
    }

    #[inline(always)]
    fn widen(self) -> f32 {
        self.to_f32()
    }
}

impl Element for f32 {
    const LAYOUT: Layout = Layout::F32;
    const MAX: f32 = f32::MAX;

    /// `f32` texels store the `f32` value exactly: the rounding mode does not apply.
    #[inline(always)]
    fn narrow(v: f32, _rounding: Rounding) -> Self {
        v
    }

    #[inline(always)]
    fn widen(self) -> f32 {
        self
    }
}

/// Rounding for channel `c` of a texel: independent random words per channel.
#[inline]
#[must_use]
fn channel_rounding(rounding: Rounding, c: u32) -> Rounding {
    match rounding {
        Rounding::Nearest => Rounding::Nearest,
        Rounding::Stochastic(r) => Rounding::Stochastic(channel_bits(r, c)),
    }
}

/// `[f(0, channel 0, v0), .., f(3, channel 3, v3)]` over the channels of `H`: the one
/// loop over channels that the per-pixel and the lane encodings share (written out, so
/// that it inlines into straight-line lane code).
#[inline(always)]
fn each<H: Channels, T>(values: [f32; 4], f: impl Fn(u32, Channel, f32) -> T) -> [T; 4] {
    let [a, b, c, d] = H::CHANNELS;
    let [va, vb, vc, vd] = values;
    [f(0, a, va), f(1, b, vb), f(2, c, vc), f(3, d, vd)]
}

/// Stores a history in the channels of one texel (see [`TexelEncoding`]).
#[inline]
#[must_use]
pub(super) fn encode_channels<E: Element, H: Channels>(
    scales: &Scales,
    history: &H,
    rounding: Rounding,
) -> [E; 4] {
    each::<H, _>(history.to_channels(), |c, channel, v| {
        E::narrow(
            channel.store(v, E::MAX, scales),
            channel_rounding(rounding, c),
        )
    })
}

/// Loads a history from the channels of one texel (see [`TexelEncoding`]).
#[inline]
#[must_use]
pub(super) fn decode_channels<E: Element, H: Channels>(scales: &Scales, texel: [E; 4]) -> H {
    H::from_channels(each::<H, _>(texel.map(E::widen), |_, channel, v| {
        channel.load(v, E::MAX, scales)
    }))
}

/// Loads lane `i` of a chunk of raw (widened, unsanitised) channels of `E` texels
/// holding an `H`: [`decode_channels`] on the lane, before `from_channels`.
#[inline(always)]
#[must_use]
pub(super) fn load_lane<E: Element, H: Channels>(
    raw: &[[f32; CHUNK]; 4],
    i: usize,
    scales: &Scales,
) -> [f32; 4] {
    let lane = [raw[0][i], raw[1][i], raw[2][i], raw[3][i]];
    each::<H, _>(lane, |_, channel, v| channel.load(v, E::MAX, scales))
}

/// Writes the channel values of an `H` to lane `i` of a chunk of `E` texels as they are
/// to be stored, before rounding: [`encode_channels`] on the lane.
#[inline(always)]
pub(super) fn store_lane<E: Element, H: Channels>(
    out: &mut [[f32; CHUNK]; 4],
    i: usize,
    values: [f32; 4],
    scales: &Scales,
) {
    let stored = each::<H, _>(values, |_, channel, v| channel.store(v, E::MAX, scales));
    for (o, s) in out.iter_mut().zip(stored) {
        o[i] = s;
    }
}
