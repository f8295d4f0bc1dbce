// Online control variate (SPEC 3) on the J texel (Sigma_xy, Sigma_yy, zeta_f, zeta_g).
// Rust twin: `spvg_wgpu::twin::ocv_alpha` / `update_cv`.

// alpha = (Sigma_xy + eps_a) / (Sigma_yy + eps_a) from J_{t-1} (an invalid J counts as zero,
// so alpha = 1), clamped to [0, a0 + f / g] (no upper bound when g <= 0).
fn ocv_alpha(j: vec4<f32>, valid: bool, f: f32, g: f32) -> f32 {
    var alpha = 1.0;
    if (valid) {
        alpha = (j.x + params.eps_a) / (j.y + params.eps_a);
    }
    if (g > 0.0) {
        alpha = min(alpha, params.a0 + f / g);
    }
    return max(alpha, 0.0);
}

// EMCM update of Z = [f, g] with weight eta_cv; an invalid J is seeded with the first sample.
// f and g enter at storage (f16) precision: the stored means are f16, so a constant control
// must round to exactly its stored mean, or the rounding error g - q(zeta_g) becomes a fixed
// deviation that correlates with the noise of f and sends alpha far from 1 (seen on the
// static scene: alpha off by up to 0.4 with eps_a = 1e-6).
fn update_cv(j: vec4<f32>, valid: bool, f_in: f32, g_in: f32) -> vec4<f32> {
    let f = round_to_f16(clamp(f_in, -F16_MAX, F16_MAX));
    let g = round_to_f16(clamp(g_in, -F16_MAX, F16_MAX));
    if (!(is_finite_f32(f_in) && is_finite_f32(g_in))) {
        if (valid) {
            return j;
        }
        return vec4<f32>(0.0);
    }
    if (!valid) {
        return sanitize_texel(vec4<f32>(0.0, 0.0, f, g));
    }
    let dx = f - j.z;
    let dy = g - j.w;
    let sxy = params.retain_cv * j.x + params.eta_retain_cv * (dx * dy);
    let syy = params.retain_cv * j.y + params.eta_retain_cv * (dy * dy);
    let zf = params.retain_cv * j.z + params.eta_cv * f;
    let zg = params.retain_cv * j.w + params.eta_cv * g;
    return sanitize_texel(vec4<f32>(sxy, syy, zf, zg));
}
