// The two-pass form of the component (`spvg_wgpu::adaptive::AdaptivePass::record_estimate`
// and `record_update`): compute steps a renderer records around its own sampling pass,
// exchanging the count, the link and the real count through textures. The per-pixel work
// is component.wgsl's, which the one-pass form (one_pass.wgsl) runs too.
// - adaptive_estimate: the estimate of each pixel (spvg_ad_estimate_pixel); writes the
//   count, the reprojection link, the real count and this frame's depth where the
//   neighbourhood rules need them.
// - adaptive_dilate (only with a dilation radius): each covered pixel takes the largest
//   count of its neighbourhood (the library's `spvg_dilation_window`/`_take`, with the
//   neighbour prior `spvg_dilation_prior_*`), from the estimate's counts.
// - adaptive_update: reads the same history through the link and writes the new history
//   (and for OCV the control-variate history).
// Rust twin: `spvg_wgpu::adaptive::AdaptiveTwin` (`estimate`, `update`).

// estimate
@group(0) @binding(10) var spvg_ad_link_out: texture_storage_2d<r32uint, write>;
// update
@group(0) @binding(11) var spvg_ad_value_in: texture_2d<f32>;
@group(0) @binding(12) var spvg_ad_control_in: texture_2d<f32>;
@group(0) @binding(13) var spvg_ad_count_in: texture_2d<u32>;
@group(0) @binding(14) var spvg_ad_link_in: texture_2d<u32>;
// This frame's depth, written by the estimate (19) and read by the dilation and the
// update (20) for the same-surface tests of the neighbour prior and of the spatial
// variance; bound 1x1 and untouched while both are off.
@group(0) @binding(19) var spvg_ad_surface_out: texture_storage_2d<r32float, write>;
@group(0) @binding(20) var spvg_ad_surface_in: texture_2d<f32>;
// update: the renderer's resolved TAA history C_t, in the monitored value's space
@group(0) @binding(21) var spvg_ad_guide_in: texture_2d<f32>;
// update: the mean of the squares of the samples whose mean is the value (docs/algorithms.md
// §8.8), read where spvg_AD_FLAG_MOMENT is set
@group(0) @binding(26) var spvg_ad_moment_in: texture_2d<f32>;
// Fractional counts: each pixel's real count, written by the estimate (23) and read by
// the update (24), -1 where the integer rule decided; bound 1x1 and untouched while
// fractional counts are off.
@group(0) @binding(23) var spvg_ad_real_out: texture_storage_2d<r32float, write>;
@group(0) @binding(24) var spvg_ad_real_in: texture_2d<f32>;

@compute @workgroup_size(8, 8, 1)
fn adaptive_estimate(@builtin(global_invocation_id) gid: vec3<u32>) {
    adaptive_estimate_at(gid);
}

// The body of `adaptive_estimate` for the pixel `gid`: the whole-frame entry above and the
// tile-list entry of tiles.wgsl run the same code.
fn adaptive_estimate_at(gid: vec3<u32>) {
    if (!spvg_ad_in_frame(gid.xy)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    if (spvg_ad_keeps_depth()) {
        textureStore(spvg_ad_surface_out, p, vec4<f32>(textureLoad(spvg_ad_depth, p, 0).x, 0.0, 0.0, 0.0));
    }
    let e = spvg_ad_estimate_pixel(gid.xy);
    textureStore(spvg_ad_count_out, p, vec4<u32>(e.count, 0u, 0u, 0u));
    textureStore(spvg_ad_link_out, p, vec4<u32>(e.link, 0u, 0u, 0u));
    if (spvg_ad_ctl_fractional()) {
        textureStore(spvg_ad_real_out, p, vec4<f32>(e.real, 0.0, 0.0, 0.0));
    }
}

// Twin: `spvg::dilation::dilated_count` (`dilated_count_with_prior` with the neighbour
// prior). Reads the estimate's counts (bound as spvg_ad_count_in), writes the dilated ones
// (spvg_ad_count_out).
@compute @workgroup_size(8, 8, 1)
fn adaptive_dilate(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!spvg_ad_in_frame(gid.xy)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let own = textureLoad(spvg_ad_count_in, p, 0).x;
    let size = spvg_ad_size();
    let radius = spvg_ad_params.dilation;
    if ((spvg_ad_params.flags & spvg_AD_FLAG_NEIGHBOUR_PRIOR) != 0u) {
        // Same surface by the reprojection's depth test of the neighbour's depth against
        // this pixel's.
        var m = spvg_dilation_prior_window(own, gid.xy, size, radius);
        let d = textureLoad(spvg_ad_surface_in, p, 0).x;
        for (var y = m.lo.y; y <= m.hi.y; y++) {
            for (var x = m.lo.x; x <= m.hi.x; x++) {
                let q = vec2<u32>(x, y);
                let same = spvg_reproject_depth_agrees(textureLoad(spvg_ad_surface_in, q, 0).x, d, spvg_ad_params.depth_tolerance);
                m = spvg_dilation_prior_take(m, own, textureLoad(spvg_ad_count_in, q, 0).x, same);
            }
        }
        textureStore(spvg_ad_count_out, p, vec4<u32>(spvg_dilation_prior_count(m, own), 0u, 0u, 0u));
        return;
    }
    var m = spvg_dilation_window(own, gid.xy, size, radius);
    for (var y = m.lo.y; y <= m.hi.y; y++) {
        for (var x = m.lo.x; x <= m.hi.x; x++) {
            m.count = spvg_dilation_take(m.count, textureLoad(spvg_ad_count_in, vec2<u32>(x, y), 0).x);
        }
    }
    textureStore(spvg_ad_count_out, p, vec4<u32>(m.count, 0u, 0u, 0u));
}

// The control value of pixel `q` where the model reads one (CCV, OCV), else 0.
fn adaptive_control(q: vec2<u32>) -> f32 {
    if (spvg_ad_reads_control()) {
        return textureLoad(spvg_ad_control_in, q, 0).x;
    }
    return 0.0;
}

// The spatial moments (spvg::controller::young::SpatialMoments) of pixel `p` with the
// monitored value `centre` and coefficient `alpha`: the pixels of its spatial window
// (spvg_spatial_window: 3x3 clipped to its tile), itself included, in row-major order,
// that took samples this frame and pass the reprojection's depth test against its depth.
// Twin: the neighbourhood of `AdaptiveTwin::update`.
fn adaptive_spatial_moments(p: vec2<u32>, centre: f32, alpha: f32) -> spvg_SpatialMoments {
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    let d = textureLoad(spvg_ad_surface_in, p, 0).x;
    let w = spvg_spatial_window(p, spvg_ad_size());
    for (var y = w.lo.y; y <= w.hi.y; y++) {
        for (var x = w.lo.x; x <= w.hi.x; x++) {
            let q = vec2<u32>(x, y);
            let same = spvg_reproject_depth_agrees(textureLoad(spvg_ad_surface_in, q, 0).x, d, spvg_ad_params.depth_tolerance);
            if (textureLoad(spvg_ad_count_in, q, 0).x != 0u && same) {
                m = spvg_spatial_push(m, centre, spvg_ad_monitored(textureLoad(spvg_ad_value_in, q, 0).x, adaptive_control(q), alpha));
            }
        }
    }
    return m;
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update(@builtin(global_invocation_id) gid: vec3<u32>) {
    adaptive_update_at(gid);
}

// The body of `adaptive_update` for the pixel `gid`: the whole-frame entry above and the
// tile-list entry of tiles.wgsl run the same code.
fn adaptive_update_at(gid: vec3<u32>) {
    if (!spvg_ad_in_frame(gid.xy)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let n = textureLoad(spvg_ad_count_in, p, 0).x;
    let link = textureLoad(spvg_ad_link_in, p, 0).x;
    var h = vec4<f32>(0.0);
    if (link != 0u) {
        h = textureLoad(spvg_ad_hist_in, spvg_ad_link_texel(link), 0);
    }
    var real = -1.0;
    if (spvg_ad_ctl_fractional()) {
        real = textureLoad(spvg_ad_real_in, p, 0).x;
    }
    let j = spvg_ad_load_cv(link);
    let f = textureLoad(spvg_ad_value_in, p, 0).x;
    let g = adaptive_control(gid.xy);
    var s = 0.0;
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    if (n != 0u) {
        let alpha = spvg_ad_alpha(j, link, f, g);
        s = spvg_ad_monitored(f, g, alpha);
        if (spvg_ad_young(h)) {
            m = adaptive_spatial_moments(gid.xy, s, alpha);
        }
    }
    let guided = (spvg_ad_params.flags & spvg_AD_FLAG_GUIDE) != 0u;
    var guide = 0.0;
    if (guided) {
        guide = textureLoad(spvg_ad_guide_in, p, 0).x;
    }
    var frame_var = -1.0;
    if ((spvg_ad_params.flags & spvg_AD_FLAG_MOMENT) != 0u && !spvg_ad_controlled()) {
        frame_var = spvg_per_sample_variance(s, textureLoad(spvg_ad_moment_in, p, 0).x, n);
    }
    let t = spvg_ad_update_texels(n, link, real, h, j, f, g, s, m, guided, guide, frame_var);
    textureStore(spvg_ad_hist_out, p, t.h);
    if (spvg_AD_OCV) {
        spvg_ad_store_cv(p, t.j);
    }
}
