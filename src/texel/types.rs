//! GPU-visible texel layouts of the per-pixel histories (RGBA16F and RGBA32F).
//!
//! Each struct is the twin of a WGSL `vec4<f32>` read from an `rgba16float` or
//! `rgba32float` texture; the channel order below is part of the contract with the shader.

use bytemuck::{Pod, Zeroable};
use half::f16;

/// Storage precision of a history texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// RGBA16F: 8 bytes per texel, 11 significant bits.
    F16,
    /// RGBA32F: 16 bytes per texel, 24 significant bits.
    F32,
}

/// The SPVG history `H` in one RGBA16F texel (8 bytes).
///
/// WGSL twin: the `vec4<f32>` read from the `rgba16float` SPVG history texture.
/// Channels (see [`TexelEncoding`](super::TexelEncoding) for the exact encodings):
/// - `r` (0): `mu`, the EMA of the monitored luminance, stored as is;
/// - `g` (1): `var * 2^-k`, the variance over the power of two nearest `sigma0^2`;
/// - `b` (2): `nbar`, the EMA of the sample count, stored as is;
/// - `a` (3): spare, written as `0`.
///
/// `Zeroable::zeroed()` (all bits zero) is the cold history.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct SpvgTexel16(pub [f16; 4]);

/// The SPVG history `H` in one RGBA32F texel (16 bytes): same channels and encodings as
/// [`SpvgTexel16`], in `f32`.
///
/// WGSL twin: the `vec4<f32>` read from the `rgba32float` SPVG history texture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct SpvgTexel32(pub [f32; 4]);

/// The online control variate's history `J` in one RGBA16F texel (8 bytes).
///
/// WGSL twin: the `vec4<f32>` read from the `rgba16float` CV history texture.
/// Channels (see [`TexelEncoding`](super::TexelEncoding)):
/// - `r` (0): `Sigma_xy * 2^-c`, the covariance of `fbar` and `G` over the CV scale;
/// - `g` (1): `Sigma_yy * 2^-c`, the variance of `G` over the CV scale;
/// - `b` (2): `zeta_f`, the EMA of `fbar`, stored as is;
/// - `a` (3): `zeta_g`, the EMA of `G`, stored as is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct CvTexel16(pub [f16; 4]);

/// The online control variate's history `J` in one RGBA32F texel (16 bytes): same
/// channels and encodings as [`CvTexel16`], in `f32`.
///
/// WGSL twin: the `vec4<f32>` read from the `rgba32float` CV history texture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct CvTexel32(pub [f32; 4]);

const _: () = assert!(
    size_of::<SpvgTexel16>() == 8,
    "SpvgTexel16 size is part of the GPU layout"
);
const _: () = assert!(
    size_of::<CvTexel16>() == 8,
    "CvTexel16 size is part of the GPU layout"
);
const _: () = assert!(
    size_of::<SpvgTexel32>() == 16,
    "SpvgTexel32 size is part of the GPU layout"
);
const _: () = assert!(
    size_of::<CvTexel32>() == 16,
    "CvTexel32 size is part of the GPU layout"
);
const _: () = assert!(
    align_of::<SpvgTexel16>() == 2,
    "SpvgTexel16 align is part of the GPU layout"
);
const _: () = assert!(
    align_of::<SpvgTexel32>() == 4,
    "SpvgTexel32 align is part of the GPU layout"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytemuck_round_trip_keeps_channel_order() {
        let t = SpvgTexel16([
            f16::from_f32(1.5),
            f16::from_f32(2.0),
            f16::from_f32(8.0),
            f16::ZERO,
        ]);
        let bits: [u16; 4] = bytemuck::cast(t);
        assert_eq!(bits[0], 0x3E00, "channel 0 must hold the mean's f16 bits");
        assert_eq!(
            bits[1], 0x4000,
            "channel 1 must hold the variance's f16 bits"
        );
        assert_eq!(bits[2], 0x4800, "channel 2 must hold the count's f16 bits");
        let back: SpvgTexel16 = bytemuck::cast(bits);
        assert_eq!(back, t, "bytemuck round trip must be the identity");

        let c = CvTexel32([1.0, -2.0, 3.0, 4.0]);
        let bytes = bytemuck::bytes_of(&c);
        assert_eq!(bytes.len(), 16, "CvTexel32 is 16 bytes");
        assert_eq!(
            bytes[4..8],
            (-2.0_f32).to_ne_bytes(),
            "channel 1 sits at byte offset 4"
        );
        assert_eq!(
            *bytemuck::from_bytes::<CvTexel32>(bytes),
            c,
            "bytemuck round trip must be the identity"
        );
    }

    #[test]
    fn zeroed_texels_are_zero() {
        let z: SpvgTexel16 = Zeroable::zeroed();
        assert_eq!(z, SpvgTexel16::default(), "zeroed is the default texel");
        assert!(
            z.0.iter().all(|v| v.to_f32() == 0.0),
            "zeroed f16 texel is all zero"
        );
    }
}
