// spvg::texel: the history texels (docs/algorithms.md §4) in RGBA16F and RGBA32F, and the
// f32 -> f16 store with round-to-nearest-even or stochastic rounding.
// Depends on: float, params, sequence.
// Rust twins: `spvg::texel::{to_f16, TexelEncoding}` through `Texel::{encode, decode}` of
// `SpvgTexel16`, `SpvgTexel32`, `CvTexel16`, `CvTexel32`.
//
// Channel order: H = (mu, var * 2^-k, nbar, spare 0), J = (Sigma_xy * 2^-c,
// Sigma_yy * 2^-c, zeta_f, zeta_g). An encoded f16 texel holds f32 values that are
// exactly f16 values, so an rgba16float store is exact whatever rounding the driver's own
// conversion uses (lavapipe truncates).

// An f32 in [-65504, 65504] (not NaN) rounded to the nearest f16, ties to even, returned
// as f32: half::f16::from_f32, then to_f32.
fn spvg_round_f16_nearest(x: f32) -> f32 {
    let b = bitcast<u32>(x);
    let sign = b & 0x80000000u;
    let a = b & 0x7fffffffu;
    if (a >= 0x38800000u) {
        // Normal f16: round the 13 discarded bits to nearest, ties to even; a carry bumps
        // the exponent. 65504 has no discarded bits, so nothing rounds to infinity.
        return bitcast<f32>(sign | ((a + 0xfffu + ((a >> 13u) & 1u)) & 0xffffe000u));
    }
    // Subnormal f16 (multiples of 2^-24): adding 0.5 makes the FPU round |x| to a multiple
    // of 2^-24 (ties to even); the low bits of the sum count them (0..=1024).
    let q = bitcast<u32>(bitcast<f32>(a) + 0.5) - 0x3f000000u;
    return bitcast<f32>(sign | bitcast<u32>(f32(q) * (1.0 / 16777216.0)));
}

// Stochastic rounding of an f32 in [-65504, 65504] (not NaN) to f16 driven by the random
// word r, returned as f32: spvg::texel::to_f16 with Rounding::Stochastic(r) (the private
// `stochastic_bits`), in u32 arithmetic (the core uses u64 below the normal range).
fn spvg_round_f16_stochastic(x: f32, r: u32) -> f32 {
    let b = bitcast<u32>(x);
    let sign = b & 0x80000000u;
    let a = b & 0x7fffffffu;
    if (a >= 0x38800000u) {
        // A uniform 13-bit integer added to the pattern carries into bit 13 with
        // probability (discarded bits) / 2^13.
        return bitcast<f32>(sign | ((a + (r >> 19u)) & 0xffffe000u));
    }
    // |x| = m 2^(e - 150) = (m / 2^s) units of 2^-24 with s = 126 - e >= 14.
    let e = a >> 23u;
    if (e == 0u) {
        return bitcast<f32>(sign);
    }
    let s = 126u - e;
    if (s >= 56u) {
        return bitcast<f32>(sign);
    }
    let m = (a & 0x7fffffu) | 0x800000u;
    // q = m >> s and rem = m mod 2^s; m < 2^24, so q = 0 and rem = m from s = 24 on.
    var q = 0u;
    var rem = m;
    if (s < 24u) {
        q = m >> s;
        rem = m & ((1u << s) - 1u);
    }
    // P(up) = rem / 2^s = k / 2^32, k = floor(rem 2^(32 - s)).
    var k: u32;
    if (s <= 32u) {
        k = rem << (32u - s);
    } else {
        k = rem >> (s - 32u);
    }
    let up = select(0u, 1u, r < k);
    return bitcast<f32>(sign | bitcast<u32>(f32(q + up) * (1.0 / 16777216.0)));
}

// A signed stored value: NaN to 0, then clamped to [-max, max].
fn spvg_store_signed(v: f32, max_value: f32) -> f32 {
    if (spvg_is_nan(v)) {
        return 0.0;
    }
    if (v < -max_value) {
        return -max_value;
    }
    if (v > max_value) {
        return max_value;
    }
    return v;
}

// A non-negative stored value (variance, count): NaN and anything not > 0 to 0, then
// clamped to max.
fn spvg_store_non_negative(v: f32, max_value: f32) -> f32 {
    if (v > 0.0) {
        return min(v, max_value);
    }
    return 0.0;
}

// spvg::texel::to_f16 then to_f32: clamp to the f16 range (NaN to 0), then round.
fn spvg_to_f16(x: f32, rounding: u32, random: u32) -> f32 {
    let v = spvg_store_signed(x, spvg_F16_MAX);
    if (rounding == spvg_ROUNDING_STOCHASTIC) {
        return spvg_round_f16_stochastic(v, random);
    }
    return spvg_round_f16_nearest(v);
}

// The largest finite stored value of the layout (65504 or f32::MAX).
fn spvg_texel_max(p: spvg_Params) -> f32 {
    if (p.texel_layout == spvg_LAYOUT_F32) {
        return spvg_F32_MAX;
    }
    return spvg_F16_MAX;
}

// Element::narrow: f16 layouts round channel `channel` (stochastically with its own
// random word); f32 layouts store the value as it is.
fn spvg_narrow(p: spvg_Params, v: f32, channel: u32, random: u32) -> f32 {
    if (p.texel_layout == spvg_LAYOUT_F32) {
        return v;
    }
    return spvg_to_f16(v, p.rounding, spvg_channel_bits(random, channel));
}

// Channel::load of a signed channel stored over `scale` (1 when unscaled).
fn spvg_load_signed(stored: f32, max_value: f32, scale: f32) -> f32 {
    return spvg_saturate(spvg_store_signed(stored, max_value) * scale);
}

// Channel::load of a non-negative channel stored over `scale`.
fn spvg_load_non_negative(stored: f32, max_value: f32, scale: f32) -> f32 {
    return spvg_saturate(spvg_store_non_negative(stored, max_value) * scale);
}

// TexelEncoding::decode of an SPVG history texel (any bits: a corrupt texel cannot
// inject NaN, infinities or a negative variance). The spare channel is not read.
fn spvg_decode_history(p: spvg_Params, t: vec4<f32>) -> spvg_History {
    let m = spvg_texel_max(p);
    return spvg_History(
        spvg_store_signed(t.x, m),
        spvg_load_non_negative(t.y, m, p.var_scale),
        spvg_store_non_negative(t.z, m),
    );
}

// TexelEncoding::encode of an SPVG history, as the core stores it: spare channel 0;
// `random` is used only with stochastic rounding. A history that reprojection reads back
// (spvg_reproject_locate, the written check) must be stored with
// spvg_encode_written_history instead, or a zeroed (never written) texture reads as a
// valid history.
fn spvg_encode_history(p: spvg_Params, h: spvg_History, random: u32) -> vec4<f32> {
    let m = spvg_texel_max(p);
    return vec4<f32>(
        spvg_narrow(p, spvg_store_signed(h.mean, m), 0u, random),
        spvg_narrow(p, spvg_store_non_negative(h.variance * p.inv_var_scale, m), 1u, random),
        spvg_narrow(p, spvg_store_non_negative(h.mean_count, m), 2u, random),
        spvg_narrow(p, 0.0, 3u, random),
    );
}

// The history texel as a store with reprojection keeps it: spvg_encode_history with the
// written mark (spare channel 1.0, exact in f16 and f32), so that spvg_history_written
// tells a texel the previous frame wrote from a zeroed or cleared one.
fn spvg_encode_written_history(p: spvg_Params, h: spvg_History, random: u32) -> vec4<f32> {
    var t = spvg_encode_history(p, h, random);
    t.w = 1.0;
    return t;
}

// Whether a history texel carries the written mark (spare channel >= 0.5; a zeroed
// texel, or one cleared for a pixel without samples, does not).
fn spvg_history_written(t: vec4<f32>) -> bool {
    return t.w >= 0.5;
}

// TexelEncoding::decode of a CV history texel.
fn spvg_decode_cv(p: spvg_Params, t: vec4<f32>) -> spvg_CvHistory {
    let m = spvg_texel_max(p);
    return spvg_CvHistory(
        spvg_load_signed(t.x, m, p.cv_scale),
        spvg_load_non_negative(t.y, m, p.cv_scale),
        spvg_store_signed(t.z, m),
        spvg_store_signed(t.w, m),
    );
}

// TexelEncoding::encode of a CV history.
fn spvg_encode_cv(p: spvg_Params, j: spvg_CvHistory, random: u32) -> vec4<f32> {
    let m = spvg_texel_max(p);
    return vec4<f32>(
        spvg_narrow(p, spvg_store_signed(j.cov_fg * p.inv_cv_scale, m), 0u, random),
        spvg_narrow(p, spvg_store_non_negative(j.var_g * p.inv_cv_scale, m), 1u, random),
        spvg_narrow(p, spvg_store_signed(j.mean_f, m), 2u, random),
        spvg_narrow(p, spvg_store_signed(j.mean_g, m), 3u, random),
    );
}

// ---- the history's age in the spare channel (spvg::controller::young) ----

// The largest age stored (spvg::controller::young::AGE_CAP).
const spvg_AGE_CAP: u32 = 255u;

// young::read_age: the age a stored spare channel reads as; 0 (never written) unless it is
// >= 0.5, else its integer part, at least 1 and at most the cap.
fn spvg_read_age(stored: f32) -> u32 {
    if (!(stored >= 0.5)) {
        return 0u;
    }
    if (stored >= f32(spvg_AGE_CAP)) {
        return spvg_AGE_CAP;
    }
    return max(u32(stored), 1u);
}
