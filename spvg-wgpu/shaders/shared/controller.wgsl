// SPVG sample-count controller (SPEC 2) on the history texel (mu, var / sigma0^2, nbar, valid).
// Rust twin: `spvg_wgpu::twin::estimate_count` / `update_history`.

// n_hat = kappa * Delta + E with E = v nbar, Delta = (v - 1) nbar (k - 1), v = var / sigma0^2;
// n = ceil(clamp(n_hat, beta_min, beta_max)). An invalid history (disocclusion) counts as
// zero, so n = beta_min. A non-finite n_hat (impossible from a finite history) gives beta_min.
fn estimate_count(h: vec4<f32>) -> u32 {
    if (h.w < 0.5) {
        return u32(ceil(params.beta_min));
    }
    let e = h.y * h.z;
    let delta = ((h.y - 1.0) * h.z) * params.k_minus_1;
    let n_hat = params.kappa * delta + e;
    if (!is_finite_f32(n_hat)) {
        return u32(ceil(params.beta_min));
    }
    return u32(ceil(min(max(n_hat, params.beta_min), params.beta_max)));
}

// History update with the monitored value s and the count n (SPEC 2.2, 2.3). Returns the
// new texel; a non-finite s keeps a valid history unchanged and leaves an invalid one cold.
fn update_history(h: vec4<f32>, s: f32, n: u32) -> vec4<f32> {
    if (!is_finite_f32(s)) {
        if (h.w < 0.5) {
            return vec4<f32>(0.0);
        }
        return h;
    }
    if (h.w < 0.5) {
        // Disocclusion: weight 1, variance sigma0^2 (stored relative: 1).
        return sanitize_texel(vec4<f32>(s, 1.0, f32(n), 1.0));
    }
    // EMV (Finch) on absolute variance, then EMA of the count; same op order as spvg::stats.
    let var_old = h.y * params.sigma0_sq;
    let d = s - h.x;
    let var_new = params.retain * var_old + params.eta_retain * (d * d);
    let mu_new = params.retain * h.x + params.eta * s;
    let nbar_new = params.retain * h.z + params.eta * f32(n);
    return sanitize_texel(vec4<f32>(mu_new, var_new / params.sigma0_sq, nbar_new, 1.0));
}
