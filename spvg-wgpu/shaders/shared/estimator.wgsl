// Unified subsurface estimator (SPEC 2.4, 5): near part from the pre-integrated lighting,
// distant part by Burley sampling with the depth-aware ratio estimator.
// Rust twin: `spvg_wgpu::twin::PixelEstimate` and `spvg_wgpu::twin::estimate_pixel`.
// Needs the bindings `lighting`, `depth`, `mask` and the uniform `params`.

const LUMA: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

struct PixelEstimate {
    // (1 - gamma) B + gamma L_s per channel.
    result: vec3<f32>,
    // fbar = gamma L_s, the distant part.
    fbar: vec3<f32>,
    // G = gamma B, the control.
    g: vec3<f32>,
    // Distant ratio of the sampling (widest) profile; below eps_u the pixel takes 0 samples.
    gamma_s: f32,
}

fn pixel_gamma_s(p: vec2<i32>) -> f32 {
    let z = textureLoad(depth, p, 0).x;
    let r0 = z * params.half_diag;
    return burley_distant_ratio(r0, params.d_s);
}

// n distant samples at pixel p. With n = 0 the result is the near part alone.
fn estimate_pixel(p: vec2<i32>, n: u32) -> PixelEstimate {
    let b = textureLoad(lighting, p, 0).xyz;
    let z = textureLoad(depth, p, 0).x;
    let r0 = z * params.half_diag;
    let d_rgb = vec3<f32>(params.d_r, params.d_g, params.d_b);
    let gamma = vec3<f32>(
        burley_distant_ratio(r0, params.d_r),
        burley_distant_ratio(r0, params.d_g),
        burley_distant_ratio(r0, params.d_b),
    );
    let gamma_s = burley_distant_ratio(r0, params.d_s);
    let seed16 = pcg3d16(vec3<u32>(u32(p.x), u32(p.y), params.frame));
    let seed = vec2<u32>(seed16.x << 16u, seed16.y << 16u);
    // Millimetres per pixel at this depth.
    let mm_x = z * params.w_px;
    let mm_y = z * params.h_px;
    var sum_wl = vec3<f32>(0.0);
    var sum_w = vec3<f32>(0.0);
    for (var m = 0u; m < n; m++) {
        let u = r2_fixed(seed, m);
        let xi_r = unit_from_fixed(u.x);
        let dir = unit_dir(u.y);
        let r = burley_sample_distant(xi_r, gamma_s, params.d_s);
        let qf = vec2<f32>(p) + vec2<f32>(0.5) + vec2<f32>(r * dir.x / mm_x, r * dir.y / mm_y);
        let q = vec2<i32>(floor(qf));
        if (q.x < 0 || q.y < 0 || q.x >= i32(params.width) || q.y >= i32(params.height)) {
            continue;
        }
        if (textureLoad(mask, q, 0).x == 0u) {
            continue;
        }
        let lq = textureLoad(lighting, q, 0).xyz;
        if (!is_finite_vec3(lq)) {
            continue;
        }
        let dz = textureLoad(depth, q, 0).x - z;
        let rp = sqrt(r * r + dz * dz);
        let inv_pdf = 1.0 / burley_pdf(r, params.d_s);
        let w = vec3<f32>(
            burley_r_profile(rp, d_rgb.x),
            burley_r_profile(rp, d_rgb.y),
            burley_r_profile(rp, d_rgb.z),
        ) * inv_pdf;
        sum_wl += w * lq;
        sum_w += w;
    }
    // Where no sample landed on the surface the distant part falls back to B(p).
    var ls = b;
    if (sum_w.x > 0.0) { ls.x = sum_wl.x / sum_w.x; }
    if (sum_w.y > 0.0) { ls.y = sum_wl.y / sum_w.y; }
    if (sum_w.z > 0.0) { ls.z = sum_wl.z / sum_w.z; }
    if (n == 0u) {
        ls = vec3<f32>(0.0);
    }
    var e: PixelEstimate;
    e.fbar = gamma * ls;
    e.g = gamma * b;
    e.result = (vec3<f32>(1.0) - gamma) * b + e.fbar;
    e.gamma_s = gamma_s;
    return e;
}
