//! Shared helpers of the effects' GPU tests.
#![allow(dead_code, reason = "each test file uses a subset")]

/// The largest distance between two texel slices, channel by channel, in `f16` units in the
/// last place (0 where they are bit-identical; adjacent finite values are 1 apart, +0 and
/// -0 are 0 apart).
pub(crate) fn max_f16_ulps(a: &[[half::f16; 4]], b: &[[half::f16; 4]]) -> u32 {
    // f16 bits as a line of integers: the order of the values they encode.
    let key = |x: half::f16| {
        let bits = x.to_bits();
        let magnitude = i32::from(bits & 0x7fff);
        if bits & 0x8000 == 0 {
            magnitude
        } else {
            -magnitude
        }
    };
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(&x, &y)| key(x).abs_diff(key(y))))
        .max()
        .unwrap_or(0)
}

/// How far apart (in f16 ulp, [`max_f16_ulps`]) a subsurface H texel of the GPU may be
/// from its twin's: the Burley sampling is within 2e-5 of the core's, not bit-identical
/// (device `exp`/`log`; spvg-shaders README), and a monitored value that differs by that
/// moves a stored channel by a rounding step or a few (at most 6 measured on lavapipe).
/// The OCV J texels hold moments near zero, where ulps say nothing; their layout is
/// compared, their values are not (the counts they lead to are, exactly).
pub(crate) const SAMPLING_ULPS: u32 = 16;

/// A `w x h` frame of the subsurface effect from one rule per pixel: `texel(x, y)` gives the
/// lighting's red, green and blue (alpha 1), the depth in millimetres and whether the pixel
/// is in the mask. The test files differ in their scenes, not in how a frame is laid out.
pub(crate) fn frame(
    w: u32,
    h: u32,
    texel: impl Fn(u32, u32) -> ([f32; 3], f32, bool),
) -> spvg_effects::sss::FrameInputs {
    let n = (w * h) as usize;
    let mut f = spvg_effects::sss::FrameInputs {
        width: w,
        height: h,
        lighting: Vec::with_capacity(n),
        depth: Vec::with_capacity(n),
        mask: Vec::with_capacity(n),
    };
    for y in 0..h {
        for x in 0..w {
            let ([r, g, b], depth, inside) = texel(x, y);
            let v = half::f16::from_f32;
            f.lighting.push([v(r), v(g), v(b), half::f16::ONE]);
            f.depth.push(depth);
            f.mask.push(u8::from(inside));
        }
    }
    f
}

/// The bits of each channel of `f16` texels, for bit-identity (`==` on the values would
/// let NaN payloads and the sign of zero pass).
pub(crate) fn f16_bits(v: &[[half::f16; 4]]) -> Vec<[u16; 4]> {
    v.iter().map(|t| t.map(half::f16::to_bits)).collect()
}
