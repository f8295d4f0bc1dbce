// The sample direction both consumers use (sss, ao). Rust twin: `spvg_wgpu::common::unit_dir`.
// (The R2 points themselves come from the library: spvg_r2_point, spvg_to_unit_f32.)

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
