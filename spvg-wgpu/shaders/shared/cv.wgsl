// Online control variate (docs/algorithms.md §3) on the J texel (Sigma_xy 2^-c, Sigma_yy 2^-c, zeta_f,
// zeta_g): the `spvg::texel::CvTexel16` layout and encoding. Mirrors
// `spvg::cv::Ocv::{raw_coefficient, clamp_to_bound, update_state}` on the decoded state.

// TexelEncoding::decode for CvTexel16.
fn decode_cv(j: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(j.x * params.cv_scale, j.y * params.cv_scale, j.z, j.w);
}

// TexelEncoding::encode for CvTexel16 (before the f16 rounding of store_texel).
fn encode_cv(j: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        store_signed(j.x * params.inv_cv_scale),
        store_non_negative(j.y * params.inv_cv_scale),
        store_signed(j.z),
        store_signed(j.w),
    );
}
// Rust twin: `spvg_wgpu::twin::ocv_alpha` / `update_cv`.

// alpha = (Sigma_xy + eps_a) / (Sigma_yy + eps_a) from J_{t-1} (an invalid J is the cold
// zero state, so alpha = 1), clamped to [0, a0 + f / g] (no upper bound when g <= 0).
fn ocv_alpha(j_in: vec4<f32>, valid: bool, f: f32, g: f32) -> f32 {
    var j = vec4<f32>(0.0);
    if (valid) {
        j = decode_cv(j_in);
    }
    var a = (j.x + params.eps_a) / (j.y + params.eps_a);
    if (!is_finite_f32(a)) {
        a = 1.0;
    }
    if (g > 0.0) {
        let upper = params.a0 + f / g;
        if (is_finite_f32(upper)) {
            a = min(a, upper);
        }
    }
    return max(a, 0.0);
}

fn finite_or_zero(v: f32) -> f32 {
    if (is_finite_f32(v)) {
        return v;
    }
    return 0.0;
}

// EMCM update of Z = [f, g] with weight eta_cv (Ocv::update_state of the model built with
// Ocv::with_f16_inputs); an invalid J is seeded with the first sample. f and g enter at
// storage (f16) precision: the stored means are f16, so a constant control must round to
// exactly its stored mean, or the rounding error g - q(zeta_g) becomes a fixed deviation
// that correlates with the noise of f and moves alpha far from 1 (seen on the static
// scene: alpha off by up to 0.4 with eps_a = 1e-6).
fn update_cv(j_stored: vec4<f32>, valid: bool, f_in: f32, g_in: f32) -> vec4<f32> {
    let j = decode_cv(j_stored);
    if (!(is_finite_f32(f_in) && is_finite_f32(g_in))) {
        if (valid) {
            return j_stored;
        }
        return vec4<f32>(0.0);
    }
    let f = round_to_f16(clamp(f_in, -F16_MAX, F16_MAX));
    let g = round_to_f16(clamp(g_in, -F16_MAX, F16_MAX));
    if (!valid) {
        return encode_cv(vec4<f32>(0.0, 0.0, f, g));
    }
    let mean_f = finite_or_zero(j.z);
    let mean_g = finite_or_zero(j.w);
    let cov_fg = finite_or_zero(j.x);
    let var_g = max(finite_or_zero(j.y), 0.0);
    let df = saturate_f32(f - mean_f);
    let dg = saturate_f32(g - mean_g);
    return encode_cv(vec4<f32>(
        saturate_f32(params.retain_cv * cov_fg + params.eta_retain_cv * saturate_f32(df * dg)),
        saturate_f32(params.retain_cv * var_g + params.eta_retain_cv * saturate_f32(dg * dg)),
        saturate_f32(params.retain_cv * mean_f + params.eta_cv * f),
        saturate_f32(params.retain_cv * mean_g + params.eta_cv * g),
    ));
}
