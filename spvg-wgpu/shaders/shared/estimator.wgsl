// Unified subsurface estimator (docs/algorithms.md §2.4, §5): near part from the pre-integrated lighting,
// distant part by Burley sampling with the depth-aware ratio estimator (one streaming
// RatioEstimator per channel, as `spvg::burley::RatioEstimator::add`).
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
    return burley_distant_ratio(footprint_radius(z), params.inv_d_s);
}

// One channel of RatioEstimator::add: streaming weighted mean, non-finite input refused.
struct Ratio {
    sum: f32,
    mean: f32,
}

fn ratio_add(acc: Ratio, r: f32, dz: f32, pdf: f32, l: f32, inv_d: f32) -> Ratio {
    let finite = is_finite_f32(r) && is_finite_f32(dz) && is_finite_f32(pdf) && is_finite_f32(l);
    if (!finite || r < 0.0 || pdf <= 0.0) {
        return acc;
    }
    let w = burley_ratio_weight(r, dz, pdf, inv_d);
    if (!is_finite_f32(w) || w == 0.0) {
        return acc;
    }
    var out: Ratio;
    out.sum = saturate_f32(acc.sum + w);
    out.mean = saturate_f32(acc.mean + (w / out.sum) * saturate_f32(l - acc.mean));
    return out;
}

// n distant samples at pixel p. With n = 0 the result is the near part alone.
fn estimate_pixel(p: vec2<i32>, n: u32) -> PixelEstimate {
    let b = textureLoad(lighting, p, 0).xyz;
    let z = textureLoad(depth, p, 0).x;
    let r0 = footprint_radius(z);
    let gamma = vec3<f32>(
        burley_distant_ratio(r0, params.inv_d_r),
        burley_distant_ratio(r0, params.inv_d_g),
        burley_distant_ratio(r0, params.inv_d_b),
    );
    let gamma_s = burley_distant_ratio(r0, params.inv_d_s);
    let seed16 = pcg3d16(vec3<u32>(u32(p.x), u32(p.y), params.frame));
    let seed = vec2<u32>(seed16.x << 16u, seed16.y << 16u);
    // Millimetres per pixel at this depth.
    let mm_x = z * params.w_px;
    let mm_y = z * params.h_px;
    var er = Ratio(0.0, 0.0);
    var eg = Ratio(0.0, 0.0);
    var eb = Ratio(0.0, 0.0);
    for (var m = 0u; m < n; m++) {
        let u = r2_fixed(seed, m);
        let s = burley_sample_distant(unit_from_fixed(u.x), r0, params.d_s, params.inv_d_s);
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
            let li = filtered_mip_index(s.pdf, n, params.lmax, area, params.max_mip);
            // Clamp to the level's size: with sizes that are not powers of two the last
            // texels of a row have no parent (40 >> 4 = 2 texels cover x < 32 only).
            let dims = vec2<i32>(vec2<u32>(max(params.width >> li, 1u), max(params.height >> li, 1u)));
            let ql = min(vec2<i32>(q.x >> li, q.y >> li), dims - vec2<i32>(1));
            lq = textureLoad(lighting, ql, i32(li)).xyz;
        } else {
            lq = textureLoad(lighting, q, 0).xyz;
        }
        er = ratio_add(er, s.radius, dz, s.pdf, lq.x, params.inv_d_r);
        eg = ratio_add(eg, s.radius, dz, s.pdf, lq.y, params.inv_d_g);
        eb = ratio_add(eb, s.radius, dz, s.pdf, lq.z, params.inv_d_b);
    }
    // Where no sample landed on the surface the distant part falls back to B(p).
    var ls = b;
    if (er.sum > 0.0) { ls.x = er.mean; }
    if (eg.sum > 0.0) { ls.y = eg.mean; }
    if (eb.sum > 0.0) { ls.z = eb.mean; }
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
