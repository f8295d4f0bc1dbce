// Burley normalized diffusion (SPEC 5), shape parameter d in mm.
// Rust twin: functions of the same names in `spvg_wgpu::twin`.
const PI: f32 = 3.14159265358979323846;

// gamma = 1 - cdf(r0) = e^{-r0/d}/4 + 3 e^{-r0/(3d)}/4, written without the cancellation
// of 1 - cdf.
fn burley_distant_ratio(r0: f32, d: f32) -> f32 {
    return 0.25 * exp(-r0 / d) + 0.75 * exp(-r0 / (3.0 * d));
}

// Radial pdf including the 2 pi r Jacobian: (e^{-r/d} + e^{-r/(3d)}) / (4 d).
fn burley_pdf(r: f32, d: f32) -> f32 {
    return (exp(-r / d) + exp(-r / (3.0 * d))) / (4.0 * d);
}

// r R(r) / A = (e^{-r/d} + e^{-r/(3d)}) / (8 pi d): the radial weight of the ratio
// estimator without the albedo, which cancels in the ratio.
fn burley_r_profile(r: f32, d: f32) -> f32 {
    return (exp(-r / d) + exp(-r / (3.0 * d))) / (8.0 * PI * d);
}

// Exact inverse cdf (Golubev 2019) written in the complementary cdf uc = 1 - cdf(r).
fn burley_inverse_ccdf(uc: f32, d: f32) -> f32 {
    let g = 1.0 + 4.0 * uc * (2.0 * uc + sqrt(1.0 + 4.0 * uc * uc));
    let c = pow(g, 1.0 / 3.0);
    return 3.0 * d * log((1.0 + 1.0 / c + c) / (4.0 * uc));
}

// Radius distributed as the profile truncated to r > r0 (SPEC 2.4):
// u = (1 - xi) cdf(r0) + xi, so 1 - u = (1 - xi) gamma exactly, never 0 for xi < 1.
fn burley_sample_distant(xi: f32, gamma: f32, d: f32) -> f32 {
    return burley_inverse_ccdf((1.0 - xi) * gamma, d);
}
