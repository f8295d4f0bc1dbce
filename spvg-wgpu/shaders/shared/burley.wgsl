// Burley normalized diffusion (docs/algorithms.md §5), radii in mm. Mirrors `spvg::burley` operation by
// operation (BurleyProfile::{pdf, cdf, distant_ratio, sample_distant}, the private
// inverse_split, RatioEstimator::weight, footprint_radius); a profile is (d, 1/d) as the
// core crate stores it. Rust twin of this file: those functions, called by
// `spvg_wgpu::twin`.
const PI: f32 = 3.14159265358979323846;

// exp(x) - 1 without cancellation (Kahan's trick; WGSL has no expm1).
fn expm1_f32(x: f32) -> f32 {
    let u = exp(x);
    if (u == 1.0) {
        return x;
    }
    let um1 = u - 1.0;
    if (um1 == -1.0) {
        return -1.0;
    }
    return um1 * x / log(u);
}

// ln(1 + x) without cancellation (same trick; WGSL has no log1p).
fn ln1p_f32(x: f32) -> f32 {
    let u = 1.0 + x;
    if (u == 1.0) {
        return x;
    }
    return log(u) * x / (u - 1.0);
}

// BurleyProfile::pdf: (e^{-x} + e^{-x/3}) / (4 d), x = r / d.
fn burley_pdf(r: f32, inv_d: f32) -> f32 {
    let x = r * inv_d;
    return (exp(-x) + exp(-x / 3.0)) * inv_d * 0.25;
}

// BurleyProfile::cdf: 1 - e^{-x}/4 - 3 e^{-x/3}/4 through expm1.
fn burley_cdf(r: f32, inv_d: f32) -> f32 {
    if (r <= 0.0) {
        return 0.0;
    }
    let x = r * inv_d;
    return -(expm1_f32(-x) + 3.0 * expm1_f32(-x / 3.0)) * 0.25;
}

// BurleyProfile::distant_ratio: gamma = 1 - cdf(r0).
fn burley_distant_ratio(r0: f32, inv_d: f32) -> f32 {
    if (r0 <= 0.0) {
        return 1.0;
    }
    let x = r0 * inv_d;
    return (exp(-x) + 3.0 * exp(-x / 3.0)) * 0.25;
}

// The core crate's inverse_split: the exact inverse cdf at xi with u = 1 - xi given
// separately (head branch through asinh/cosh/sinh, tail through asinh/sinh).
fn burley_inverse_split(xi: f32, u: f32, d: f32) -> f32 {
    var x: f32;
    if (xi <= u) {
        let theta1 = 0.48121182505960347;
        let sqrt5 = 2.23606797749979;
        let q = 2.0 * xi * (1.0 + u) / (sqrt(1.0 + 4.0 * u * u) + sqrt5 * u);
        let h = asinh(q) / 6.0;
        let e = 4.0 * cosh(theta1 - h) * sinh(h);
        x = -3.0 * ln1p_f32(-e);
    } else {
        let y = 2.0 * sinh(asinh(u + u) / 3.0);
        x = -3.0 * log(y);
    }
    return x * d;
}

struct DistantSample {
    radius: f32,
    pdf: f32,
}

// BurleyProfile::sample_distant: radius of the profile truncated to r > r0 (docs/algorithms.md §2.4) and
// its truncated pdf.
fn burley_sample_distant(xi_in: f32, r0_in: f32, d: f32, inv_d: f32) -> DistantSample {
    var s: DistantSample;
    let r0 = max(r0_in, 0.0);
    let gamma = burley_distant_ratio(r0, inv_d);
    if (gamma <= 0.0) {
        s.radius = r0;
        s.pdf = 0.0;
        return s;
    }
    let xi = max(xi_in, 0.0);
    let target_cdf = burley_cdf(r0, inv_d) + xi * gamma;
    let complement = (1.0 - xi) * gamma;
    var radius = 0.0;
    if (target_cdf > 0.0) {
        radius = burley_inverse_split(target_cdf, complement, d);
    }
    radius = max(radius, r0);
    s.radius = radius;
    s.pdf = burley_pdf(radius, inv_d) / gamma;
    return s;
}

// RatioEstimator::weight for a subsurface sample: r' R(r') / A / pdf with r' = hypot(r, dz).
fn burley_ratio_weight(r: f32, dz: f32, pdf: f32, inv_d: f32) -> f32 {
    let x = sqrt(r * r + dz * dz) * inv_d;
    let kernel = (exp(-x) + exp(-x / 3.0)) * inv_d / (8.0 * PI);
    return kernel / pdf;
}

// footprint_radius: |z| hypot(w, h) / 2 (texel_diag = hypot(w_px, h_px) from the host).
fn footprint_radius(z: f32) -> f32 {
    return abs(z) * params.texel_diag * 0.5;
}

// AFIS mip index: floor of spvg::burley::filtered_mip_level's level
// 0.5 max(-log2(q), 0), q = pdf n / (16 lmax^2 t), clamped to max_mip. The floor is found by
// exact comparisons with powers of two (floor(0.5 (-log2 q)) >= k  <=>  q <= 2^-2k), not
// through log2, whose accuracy differs between drivers and would flip levels at integer
// boundaries. NaN q gives 0 (as the core crate), q <= 0 the coarsest level.
fn filtered_mip_index(pdf: f32, n: u32, lmax: f32, area: f32, max_mip: u32) -> u32 {
    let q = pdf * f32(n) / (16.0 * lmax * lmax * area);
    if ((bitcast<u32>(q) & 0x7fffffffu) > 0x7f800000u) {
        return 0u;
    }
    var k = 0u;
    // 2^-2(k+1) is a normal f32 while 2(k+1) <= 126.
    while (k < max_mip && k < 62u && q <= bitcast<f32>((125u - 2u * k) << 23u)) {
        k += 1u;
    }
    return k;
}
