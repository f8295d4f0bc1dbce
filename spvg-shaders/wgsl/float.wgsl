// spvg::float: finite tests and the overflow policy, on the bits so that no compiler
// fast-math rewrite can fold them. Depends on nothing.
// Rust twins: `f32::is_finite`, `f32::is_nan`, `spvg::stats` saturation (private
// `saturate`: an infinity from overflow becomes the largest finite value, NaN passes).

// The largest finite f32 (f32::MAX), as an exact hexadecimal literal: Tint (the WGSL
// compiler of Chrome's WebGPU) refuses the decimal 3.40282347e+38, whose exact value lies
// above f32::MAX before rounding.
const spvg_F32_MAX: f32 = 0x1.fffffep+127f;
// The largest finite f16 (65504), as f32.
const spvg_F16_MAX: f32 = 65504.0;

// f32::is_finite: the exponent is not all ones.
fn spvg_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// f32::is_nan: all-ones exponent and a non-zero significand.
fn spvg_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// The f32 whose bits are `bits`, made at run time: WGSL makes a constant expression whose
// value is not finite a shader-creation error (Tint, Chrome's WGSL compiler, refuses
// `bitcast<f32>(0x7f800000u)`), and a call of a function is never a constant expression.
fn spvg_f32_from_bits(bits: u32) -> f32 {
    return bitcast<f32>(bits);
}

// f32::INFINITY.
fn spvg_inf() -> f32 {
    return spvg_f32_from_bits(0x7f800000u);
}

// A quiet NaN (the bits of f32::NAN).
fn spvg_nan() -> f32 {
    return spvg_f32_from_bits(0x7fc00000u);
}

// The overflow policy: +-inf becomes +-f32::MAX; NaN and finite values pass unchanged.
fn spvg_saturate(x: f32) -> f32 {
    let b = bitcast<u32>(x);
    if (b == 0x7f800000u) {
        return spvg_F32_MAX;
    }
    if (b == 0xff800000u) {
        return -spvg_F32_MAX;
    }
    return x;
}

// f32::max(a, b) as the core computes it: the other operand when one is NaN, and `a`
// unless b > a (so max(-0, +0) = -0, as Rust's max gives on x86-64; WGSL's max leaves
// both NaN and the sign of zero open).
fn spvg_max(a: f32, b: f32) -> f32 {
    if (spvg_is_nan(a)) {
        return b;
    }
    if (spvg_is_nan(b)) {
        return a;
    }
    return select(a, b, b > a);
}

// f32::min(a, b) as the core computes it: the other operand when one is NaN, and `a`
// unless b < a.
fn spvg_min(a: f32, b: f32) -> f32 {
    if (spvg_is_nan(a)) {
        return b;
    }
    if (spvg_is_nan(b)) {
        return a;
    }
    return select(a, b, b < a);
}
