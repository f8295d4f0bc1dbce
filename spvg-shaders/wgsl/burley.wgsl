// spvg::burley: Burley's normalized diffusion profile (docs/algorithms.md §2.4, §5):
// pdf, cdf, exact and approximate inverse cdf, truncated distant sampling, the
// depth-aware ratio estimator and the AFIS mip level. Radii in the unit of d.
// Depends on: float.
// Rust twins: `spvg::burley::{BurleyProfile, RatioEstimator, footprint_radius,
// filtered_mip_level}`, the same operation order; exp/log/asinh/sinh/cosh are the
// device's (not correctly rounded), see the crate README for the measured bounds.

const spvg_PI: f32 = 3.14159265358979323846;

// BurleyProfile<f32>: the albedo A, the shape d and 1 / d as the core computes them
// (`albedo()`, `shape()`, `inv_shape()`).
struct spvg_BurleyProfile {
    albedo: f32,
    d: f32,
    inv_d: f32,
}

// A radius drawn by spvg_burley_sample_distant and its truncated pdf
// (spvg::burley::DistantSample).
struct spvg_DistantSample {
    radius: f32,
    pdf: f32,
}

// exp(x) - 1 without cancellation (WGSL has no expm1): a degree-7 Taylor polynomial for
// |x| < 1/16 (truncation below 2^-37 relative), exp(x) - 1 above (the subtraction loses
// at most 4 bits there). Not Kahan's u - 1 trick: it needs a correctly rounded log near
// 1, which devices do not have.
fn spvg_expm1(x: f32) -> f32 {
    if (abs(x) < 0.0625) {
        return x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0
            + x * (1.0 / 720.0 + x * (1.0 / 5040.0)))))));
    }
    return exp(x) - 1.0;
}

// ln(1 + x) without cancellation (WGSL has no log1p): a Taylor polynomial for
// |x| < 1/16 (truncation below 2^-35 relative), log(1 + x) above.
fn spvg_ln1p(x: f32) -> f32 {
    if (abs(x) < 0.0625) {
        return x * (1.0 + x * (-0.5 + x * (1.0 / 3.0 + x * (-0.25 + x * (0.2 + x * (-1.0 / 6.0
            + x * (1.0 / 7.0 + x * (-0.125 + x * (1.0 / 9.0)))))))));
    }
    return log(1.0 + x);
}

// asinh without the cancellation of the built-in near 0 (devices evaluate it as
// log(x + sqrt(x^2 + 1)), which gives 0 for tiny x): Taylor polynomial for |x| < 1/16,
// the log form above (|x| < 2^64, all the inverse cdf needs).
fn spvg_asinh(x: f32) -> f32 {
    if (abs(x) < 0.0625) {
        let x2 = x * x;
        return x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (3.0 / 40.0 + x2 * (-5.0 / 112.0))));
    }
    let a = abs(x);
    return sign(x) * log(a + sqrt(a * a + 1.0));
}

// sinh without the cancellation of (e^x - e^-x) / 2 near 0: Taylor polynomial for
// |x| < 1/16, the exponential form above.
fn spvg_sinh(x: f32) -> f32 {
    if (abs(x) < 0.0625) {
        let x2 = x * x;
        return x * (1.0 + x2 * (1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (1.0 / 5040.0))));
    }
    return (exp(x) - exp(-x)) * 0.5;
}

// BurleyProfile::pdf: (e^{-x} + e^{-x/3}) / (4 d), x = r / d; NaN passes, r < 0 gives 0.
fn spvg_burley_pdf(b: spvg_BurleyProfile, r: f32) -> f32 {
    if (spvg_is_nan(r)) {
        return r;
    }
    if (r < 0.0) {
        return 0.0;
    }
    let x = r * b.inv_d;
    return (exp(-x) + exp(-x / 3.0)) * b.inv_d * 0.25;
}

// BurleyProfile::cdf: 1 - e^{-x}/4 - 3 e^{-x/3}/4 through expm1; 0 for r <= 0.
fn spvg_burley_cdf(b: spvg_BurleyProfile, r: f32) -> f32 {
    if (spvg_is_nan(r)) {
        return r;
    }
    if (r <= 0.0) {
        return 0.0;
    }
    let x = r * b.inv_d;
    return -(spvg_expm1(-x) + 3.0 * spvg_expm1(-x / 3.0)) * 0.25;
}

// BurleyProfile::distant_ratio: gamma = 1 - cdf(r0); 1 for r0 <= 0.
fn spvg_burley_distant_ratio(b: spvg_BurleyProfile, r0: f32) -> f32 {
    if (spvg_is_nan(r0)) {
        return r0;
    }
    if (r0 <= 0.0) {
        return 1.0;
    }
    let x = r0 * b.inv_d;
    return (exp(-x) + 3.0 * exp(-x / 3.0)) * 0.25;
}

// The core's private inverse_split: the exact inverse cdf at xi with u = 1 - xi given
// separately (Golubev 2019 through asinh/cosh/sinh without cancellation).
fn spvg_burley_inverse_split(b: spvg_BurleyProfile, xi: f32, u: f32) -> f32 {
    var x: f32;
    if (xi <= u) {
        let theta1 = 0.48121182505960347;
        let sqrt5 = 2.23606797749979;
        let q = 2.0 * xi * (1.0 + u) / (sqrt(1.0 + 4.0 * u * u) + sqrt5 * u);
        let h = spvg_asinh(q) / 6.0;
        let e = 4.0 * cosh(theta1 - h) * spvg_sinh(h);
        x = -3.0 * spvg_ln1p(-e);
    } else {
        let y = 2.0 * spvg_sinh(spvg_asinh(u + u) / 3.0);
        x = -3.0 * log(y);
    }
    return x * b.d;
}

// BurleyProfile::inverse_cdf: the radius with cdf(r) = xi (0 for xi <= 0, +inf for
// xi >= 1, NaN passes).
fn spvg_burley_inverse_cdf(b: spvg_BurleyProfile, xi: f32) -> f32 {
    if (spvg_is_nan(xi)) {
        return xi;
    }
    if (xi <= 0.0) {
        return 0.0;
    }
    if (xi >= 1.0) {
        return spvg_inf();
    }
    return spvg_burley_inverse_split(b, xi, 1.0 - xi);
}

// BurleyProfile::approx_inverse_cdf: d ((2 - c) xi - 2) ln(1 - xi) (c = 2.5715 in the
// SPVG paper, 2.6 in Unreal Engine).
fn spvg_burley_approx_inverse_cdf(b: spvg_BurleyProfile, xi: f32, c: f32) -> f32 {
    if (spvg_is_nan(xi) || spvg_is_nan(c)) {
        return spvg_nan();
    }
    if (xi <= 0.0) {
        return 0.0;
    }
    if (xi >= 1.0) {
        return spvg_inf();
    }
    return b.d * ((2.0 - c) * xi - 2.0) * spvg_ln1p(-xi);
}

// BurleyProfile::sample_distant: a radius of the profile truncated to r > r0 and its
// truncated pdf, r = cdf^-1((1 - xi) cdf(r0) + xi).
fn spvg_burley_sample_distant(b: spvg_BurleyProfile, xi_in: f32, r0_in: f32) -> spvg_DistantSample {
    if (spvg_is_nan(xi_in) || spvg_is_nan(r0_in)) {
        let nan = spvg_nan();
        return spvg_DistantSample(nan, nan);
    }
    let r0 = spvg_max(r0_in, 0.0);
    let gamma = spvg_burley_distant_ratio(b, r0);
    if (gamma <= 0.0) {
        return spvg_DistantSample(r0, 0.0);
    }
    if (xi_in >= 1.0) {
        return spvg_DistantSample(spvg_inf(), 0.0);
    }
    let xi = spvg_max(xi_in, 0.0);
    let target_cdf = spvg_burley_cdf(b, r0) + xi * gamma;
    let complement = (1.0 - xi) * gamma;
    var radius = 0.0;
    if (target_cdf > 0.0) {
        radius = spvg_burley_inverse_split(b, target_cdf, complement);
    }
    radius = spvg_max(radius, r0);
    return spvg_DistantSample(radius, spvg_burley_pdf(b, radius) / gamma);
}

// RatioEstimator::weight of a subsurface sample: R(r') / A / pdf with r' = hypot(r, dz)
// (WGSL has no hypot: sqrt(r^2 + dz^2), which overflows above ~1.8e19 where hypot does
// not).
fn spvg_burley_ratio_weight(b: spvg_BurleyProfile, r: f32, dz: f32, pdf: f32) -> f32 {
    let x = sqrt(r * r + dz * dz) * b.inv_d;
    let kernel = (exp(-x) + exp(-x / 3.0)) * b.inv_d / (8.0 * spvg_PI);
    return kernel / pdf;
}

// A streaming depth-aware ratio estimator of one channel (spvg::burley::RatioEstimator).
struct spvg_RatioEstimator {
    sum_weights: f32,
    mean: f32,
}

// RatioEstimator::add for a subsurface sample (a sample off the surface has weight 0 and
// leaves the estimator unchanged): non-finite input, r < 0 or pdf <= 0 are refused.
fn spvg_burley_ratio_add(b: spvg_BurleyProfile, acc: spvg_RatioEstimator, r: f32, dz: f32, pdf: f32, lighting: f32) -> spvg_RatioEstimator {
    let finite = spvg_is_finite(r) && spvg_is_finite(dz) && spvg_is_finite(pdf) && spvg_is_finite(lighting);
    if (!finite || r < 0.0 || pdf <= 0.0) {
        return acc;
    }
    let w = spvg_burley_ratio_weight(b, r, dz, pdf);
    if (!spvg_is_finite(w) || w == 0.0) {
        return acc;
    }
    let sum = spvg_saturate(acc.sum_weights + w);
    let mean = spvg_saturate(acc.mean + (w / sum) * spvg_saturate(lighting - acc.mean));
    return spvg_RatioEstimator(sum, mean);
}

// spvg::burley::footprint_radius with texel_diag = hypot(texel_w, texel_h) computed on
// the host: |z| texel_diag / 2.
fn spvg_footprint_radius(depth: f32, texel_diag: f32) -> f32 {
    return abs(depth) * texel_diag * 0.5;
}

// spvg::burley::filtered_mip_level: 0.5 max(-log2 q, 0), q = pdf n / (16 lmax^2 t);
// NaN q gives 0, q <= 0 +inf.
fn spvg_filtered_mip_level(pdf: f32, n: u32, lmax: f32, texel_area: f32) -> f32 {
    let q = pdf * f32(n) / (16.0 * lmax * lmax * texel_area);
    if (spvg_is_nan(q)) {
        return 0.0;
    }
    if (q <= 0.0) {
        return spvg_inf();
    }
    return 0.5 * spvg_max(-log2(q), 0.0);
}

// floor(spvg_filtered_mip_level) clamped to max_mip, found by exact comparisons with
// powers of two (floor(0.5 (-log2 q)) >= k exactly when q <= 2^-2k) rather than through
// log2, whose accuracy differs between drivers and would flip levels at integer
// boundaries. NaN q gives 0, q <= 0 the coarsest level.
fn spvg_filtered_mip_index(pdf: f32, n: u32, lmax: f32, texel_area: f32, max_mip: u32) -> u32 {
    let q = pdf * f32(n) / (16.0 * lmax * lmax * texel_area);
    if (spvg_is_nan(q)) {
        return 0u;
    }
    var k = 0u;
    // 2^-2(k+1) is a normal f32 while 2(k+1) <= 126.
    while (k < max_mip && k < 62u && q <= bitcast<f32>((125u - 2u * k) << 23u)) {
        k += 1u;
    }
    return k;
}
