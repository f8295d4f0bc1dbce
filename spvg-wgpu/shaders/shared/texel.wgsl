// Finite checks and f16 storage guards (docs/algorithms.md §4). Rust twin: `spvg_wgpu::twin::sanitize_texel`.
const F16_MAX: f32 = 65504.0;

// Exponent all ones means inf or NaN; tested on the bits so no compiler fast-math can fold it.
fn is_finite_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_finite_vec3(v: vec3<f32>) -> bool {
    return is_finite_f32(v.x) && is_finite_f32(v.y) && is_finite_f32(v.z);
}

// Saturates to the f16 range so that the rgba16float store cannot round to infinity.
fn sanitize_texel(t: vec4<f32>) -> vec4<f32> {
    return clamp(t, vec4<f32>(-F16_MAX), vec4<f32>(F16_MAX));
}

// Rounds an f32 in the f16 range to the nearest f16 (ties to even) and returns it as f32,
// so the rgba16float store is exact whatever rounding the driver's conversion uses
// (lavapipe truncates). Rust twin: `half::f16::from_f32` (round to nearest even).
fn round_to_f16(x: f32) -> f32 {
    if (abs(x) < 6.103515625e-5) {
        // f16 subnormals: multiples of 2^-24; round() is ties-to-even in WGSL.
        return round(x * 16777216.0) * (1.0 / 16777216.0);
    }
    let b = bitcast<u32>(x);
    let lsb = (b >> 13u) & 1u;
    return bitcast<f32>((b + 0xfffu + lsb) & 0xffffe000u);
}

fn round_texel(t: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(round_to_f16(t.x), round_to_f16(t.y), round_to_f16(t.z), round_to_f16(t.w));
}

// What every rgba16float store goes through: finite, in range, exactly representable.
fn store_texel(t: vec4<f32>) -> vec4<f32> {
    return round_texel(sanitize_texel(t));
}

// spvg::texel store16_signed before rounding: NaN -> 0, then the f16 range.
fn store_signed(x: f32) -> f32 {
    if (!is_finite_f32(x) && (bitcast<u32>(x) & 0x007fffffu) != 0u) {
        return 0.0;
    }
    return clamp(x, -F16_MAX, F16_MAX);
}

// spvg::texel store16_non_negative before rounding: NaN and negatives -> 0.
fn store_non_negative(x: f32) -> f32 {
    if (x > 0.0) {
        return min(x, F16_MAX);
    }
    return 0.0;
}

// spvg::stats::saturate: an infinity from overflow becomes the largest finite f32.
fn saturate_f32(x: f32) -> f32 {
    if (bitcast<u32>(x) == 0x7f800000u) {
        return 3.40282347e+38;
    }
    if (bitcast<u32>(x) == 0xff800000u) {
        return -3.40282347e+38;
    }
    return x;
}
