// R2 low-discrepancy sequence in u32 fixed point (docs/algorithms.md §6), bit-identical on CPU and GPU.
// Rust twin: `spvg_wgpu::twin::r2_fixed` and `spvg_wgpu::twin::unit_from_fixed`.
// The steps are round(2^32 / phi2) and round(2^32 / phi2^2), phi2 = 1.32471795724474602596.
const R2_STEP: vec2<u32> = vec2<u32>(3242174889u, 2447445414u);

// Point m of the sequence started at `seed` (fixed point, wrapping).
fn r2_fixed(seed: vec2<u32>, m: u32) -> vec2<u32> {
    return seed + m * R2_STEP;
}

// The top 24 bits as a float in [0, 1): exact in f32, never 1.
fn unit_from_fixed(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

// Unit vector at angle 2 pi x / 2^32 for a fixed-point angle x. The quadrant comes from the
// top 2 bits and the angle inside it from the next 24 (exact in f32); sin and cos are
// Taylor polynomials (error < 6e-8 on [0, pi/2]) rather than the built-ins, whose accuracy
// varies between drivers (Vulkan allows 2^-11 absolute), so CPU and GPU agree.
fn unit_dir(x: u32) -> vec2<f32> {
    let t = f32((x >> 6u) & 0xffffffu) * (1.0 / 16777216.0) * 1.57079632679489661923;
    let t2 = t * t;
    let s = t * (1.0 + t2 * (-1.0 / 6.0 + t2 * (1.0 / 120.0 + t2 * (-1.0 / 5040.0
        + t2 * (1.0 / 362880.0 + t2 * (-1.0 / 39916800.0))))));
    let c = 1.0 + t2 * (-0.5 + t2 * (1.0 / 24.0 + t2 * (-1.0 / 720.0
        + t2 * (1.0 / 40320.0 + t2 * (-1.0 / 3628800.0 + t2 * (1.0 / 479001600.0))))));
    switch (x >> 30u) {
        case 0u: { return vec2<f32>(c, s); }
        case 1u: { return vec2<f32>(-s, c); }
        case 2u: { return vec2<f32>(-c, -s); }
        default: { return vec2<f32>(s, -c); }
    }
}
