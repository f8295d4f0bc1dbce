// Unified subsurface estimator (docs/algorithms.md §2.4, §5): near part from the pre-integrated lighting,
// distant part by Burley sampling with the depth-aware ratio estimator (one streaming
// RatioEstimator per channel, as `spvg::burley::RatioEstimator::add`).
// Rust twin: `spvg_effects::sss::twin::PixelEstimate` and `spvg_effects::sss::twin::estimate_pixel`.
// Needs the bindings `lighting`, `depth`, `mask` and the uniform `params`; the Burley
// sampling, the ratio estimator, the seeds and the R2 points are the library's
// (spvg_shaders::WGSL).

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

// The per-channel profiles (albedo 1: it cancels in the ratio estimator) and the
// sampling profile, as the core crate's BurleyProfile::from_shape(1, d).
fn profile_r() -> spvg_BurleyProfile { return spvg_BurleyProfile(1.0, params.d_r, params.inv_d_r); }
fn profile_g() -> spvg_BurleyProfile { return spvg_BurleyProfile(1.0, params.d_g, params.inv_d_g); }
fn profile_b() -> spvg_BurleyProfile { return spvg_BurleyProfile(1.0, params.d_b, params.inv_d_b); }
fn profile_s() -> spvg_BurleyProfile { return spvg_BurleyProfile(1.0, params.d_s, params.inv_d_s); }

fn pixel_gamma_s(p: vec2<i32>) -> f32 {
    let z = textureLoad(depth, p, 0).x;
    return spvg_burley_distant_ratio(profile_s(), spvg_footprint_radius(z, params.texel_diag));
}

// n distant samples at pixel p. With n = 0 the result is the near part alone.
fn estimate_pixel(p: vec2<i32>, n: u32) -> PixelEstimate {
    let b = textureLoad(lighting, p, 0).xyz;
    let z = textureLoad(depth, p, 0).x;
    let r0 = spvg_footprint_radius(z, params.texel_diag);
    let gamma = vec3<f32>(
        spvg_burley_distant_ratio(profile_r(), r0),
        spvg_burley_distant_ratio(profile_g(), r0),
        spvg_burley_distant_ratio(profile_b(), r0),
    );
    let gamma_s = spvg_burley_distant_ratio(profile_s(), r0);
    let seed = spvg_r2_offset_from_seed(spvg_pixel_seed(u32(p.x), u32(p.y), params.frame));
    // Millimetres per pixel at this depth.
    let mm_x = z * params.w_px;
    let mm_y = z * params.h_px;
    var er = spvg_RatioEstimator(0.0, 0.0);
    var eg = spvg_RatioEstimator(0.0, 0.0);
    var eb = spvg_RatioEstimator(0.0, 0.0);
    for (var m = 0u; m < n; m++) {
        let u = spvg_r2_point(seed, m);
        let s = spvg_burley_sample_distant(profile_s(), spvg_to_unit_f32(u.x), r0);
        let dir = unit_dir(u.y);
        let qf = vec2<f32>(p) + vec2<f32>(0.5) + vec2<f32>(s.radius * dir.x / mm_x, s.radius * dir.y / mm_y);
        let q = vec2<i32>(floor(qf));
        // Off screen or off the material: weight 0 (RatioEstimator::weight's 1_s).
        if (q.x < 0 || q.y < 0 || q.x >= i32(params.width) || q.y >= i32(params.height)) {
            continue;
        }
        if (textureLoad(mask, q, 0).x == 0u) {
            continue;
        }
        let dz = textureLoad(depth, q, 0).x - z;
        var lq: vec3<f32>;
        if (params.afis != 0u) {
            // Filtered sampling: the mip level for this sample's density at its depth.
            let zq = z + dz;
            let area = (zq * params.w_px) * (zq * params.h_px);
            let li = spvg_filtered_mip_index(s.pdf, n, params.lmax, area, params.max_mip);
            // Clamp to the level's size: with sizes that are not powers of two the last
            // texels of a row have no parent (40 >> 4 = 2 texels cover x < 32 only).
            let dims = vec2<i32>(vec2<u32>(max(params.width >> li, 1u), max(params.height >> li, 1u)));
            let ql = min(vec2<i32>(q.x >> li, q.y >> li), dims - vec2<i32>(1));
            lq = textureLoad(lighting, ql, i32(li)).xyz;
        } else {
            lq = textureLoad(lighting, q, 0).xyz;
        }
        er = spvg_burley_ratio_add(profile_r(), er, s.radius, dz, s.pdf, lq.x);
        eg = spvg_burley_ratio_add(profile_g(), eg, s.radius, dz, s.pdf, lq.y);
        eb = spvg_burley_ratio_add(profile_b(), eb, s.radius, dz, s.pdf, lq.z);
    }
    // Where no sample landed on the surface the distant part falls back to B(p).
    var ls = b;
    if (er.sum_weights > 0.0) { ls.x = er.mean; }
    if (eg.sum_weights > 0.0) { ls.y = eg.mean; }
    if (eb.sum_weights > 0.0) { ls.z = eb.mean; }
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
