// SPVG sample-count controller (docs/algorithms.md §2) on the history texel
// (mu, var * 2^-k, nbar, valid): the `spvg::texel::SpvgTexel16` layout and encoding, with
// the spare channel holding the validity flag (1 where the pixel was subsurface and
// sampled last frame, so identity reprojection finds valid history). Mirrors
// `spvg::SpvgConfig::{samples_distant, raw_estimate, round_count, estimate_with_validity,
// update}` and `TexelEncoding::{decode, encode}`.
// Rust twin: `spvg_wgpu::twin::estimate_count` / `update_history`.

fn samples_distant(gamma: f32) -> bool {
    return gamma >= params.eps_u && gamma > 0.0;
}

// SpvgConfig::round_count: ceil into [beta_min, beta_max]; NaN gives beta_min.
fn round_count(n_hat: f32) -> u32 {
    if (n_hat >= params.beta_min) {
        if (n_hat < params.beta_max) {
            return clamp(u32(ceil(n_hat)), params.beta_min_u, params.beta_max_u);
        }
        return params.beta_max_u;
    }
    return params.beta_min_u;
}

// SpvgConfig::estimate_with_validity with the Spvg policy: n_hat = kappa Delta + E,
// E = r nbar, Delta = (r - 1) nbar (k - 1), r = var / sigma0^2. An invalid history counts
// as zero, so n = beta_min.
fn estimate_count(h: vec4<f32>, gamma: f32) -> u32 {
    if (!samples_distant(gamma)) {
        return 0u;
    }
    var var_abs = 0.0;
    var nbar = 0.0;
    if (h.w >= 0.5) {
        var_abs = h.y * params.var_scale;
        nbar = h.z;
    }
    let r = var_abs * params.inv_target;
    let e = r * nbar;
    let delta = (r - 1.0) * nbar * params.k_minus_1;
    return round_count(params.kappa * delta + e);
}

// SpvgConfig::update with the monitored value s and the count n (docs/algorithms.md §2.2, §2.3). A zero
// count or a non-finite s keeps a valid history and leaves an invalid one cold.
fn update_history(h: vec4<f32>, s: f32, n: u32) -> vec4<f32> {
    let valid = h.w >= 0.5;
    if (n == 0u || !is_finite_f32(s)) {
        if (!valid) {
            return vec4<f32>(0.0);
        }
        return h;
    }
    let nf = f32(n);
    if (!valid) {
        // Disocclusion: weight 1, variance sigma0^2.
        return encode_history(s, params.sigma0_sq, nf);
    }
    // Emv::from_parts then Emv::update (Finch), then the EMA of the count.
    var mean = h.x;
    var var_abs = h.y * params.var_scale;
    if (!is_finite_f32(mean)) { mean = 0.0; }
    if (!(is_finite_f32(var_abs) && var_abs > 0.0)) { var_abs = 0.0; }
    let d = saturate_f32(s - mean);
    let var_new = saturate_f32(params.retain * var_abs + params.eta_retain * saturate_f32(d * d));
    let mean_new = saturate_f32(params.retain * mean + params.eta * s);
    var old_count = 0.0;
    if (is_finite_f32(h.z) && h.z > 0.0) { old_count = h.z; }
    let nbar = saturate_f32(params.retain * old_count + params.eta * nf);
    return encode_history(mean_new, var_new, nbar);
}

// TexelEncoding::encode for SpvgTexel16 (before the f16 rounding of store_texel), flag 1.
fn encode_history(mean: f32, var_abs: f32, nbar: f32) -> vec4<f32> {
    return vec4<f32>(
        store_signed(mean),
        store_non_negative(var_abs * params.inv_var_scale),
        store_non_negative(nbar),
        1.0,
    );
}
