// The subsurface-scattering pass: one invocation per pixel, three entry points.
// - sss_fixed: a fixed count per pixel, no history (baseline).
// - sss_adaptive: SPVG count control on one history texel; alpha_const 0 is AS, 1 is CCV.
// - sss_ocv: SPVG with the online control variate, two history texels.
// CPU twins: `spvg_wgpu::twin::{sss_fixed, sss_adaptive, sss_ocv}`, one per entry point.
// Textures read at the pixel itself (identity reprojection: the camera is static).

@group(0) @binding(0) var<uniform> params: PassParams;
@group(0) @binding(1) var lighting: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<u32>;
@group(0) @binding(4) var result_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var count_out: texture_storage_2d<r32uint, write>;
@group(0) @binding(6) var hist_in: texture_2d<f32>;
@group(0) @binding(7) var hist_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var cv_in: texture_2d<f32>;
@group(0) @binding(9) var cv_out: texture_storage_2d<rgba16float, write>;

fn in_bounds(gid: vec3<u32>) -> bool {
    return gid.x < params.width && gid.y < params.height;
}

fn write_outputs(p: vec2<i32>, e: PixelEstimate, n: u32) {
    textureStore(result_out, p, store_texel(vec4<f32>(e.result, 1.0)));
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
}

fn write_empty(p: vec2<i32>) {
    textureStore(result_out, p, vec4<f32>(0.0));
    textureStore(count_out, p, vec4<u32>(0u));
}

// Zero-sample rule (docs/algorithms.md §2.4): nothing scatters far enough to need samples.
fn distant_count(p: vec2<i32>, n: u32) -> u32 {
    if (!samples_distant(pixel_gamma_s(p))) {
        return 0u;
    }
    return n;
}

@compute @workgroup_size(8, 8, 1)
fn sss_fixed(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_bounds(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    if (textureLoad(mask, p, 0).x == 0u) {
        write_empty(p);
        return;
    }
    let n = distant_count(p, params.fixed_count);
    write_outputs(p, estimate_pixel(p, n), n);
}

// What the adaptive entry points share: the count from the SPVG history, the samples and
// the result. `live` is false where the pixel has no history to update (not subsurface,
// or zero samples): then the SPVG history is cleared here and the caller clears its own
// extra history where `in_bounds` holds.
struct AdaptivePixel {
    in_bounds: bool,
    live: bool,
    p: vec2<i32>,
    h: vec4<f32>,
    n: u32,
    e: PixelEstimate,
}

fn adaptive_pixel(gid: vec3<u32>) -> AdaptivePixel {
    var a: AdaptivePixel;
    a.in_bounds = in_bounds(gid);
    a.live = false;
    if (!a.in_bounds) {
        return a;
    }
    a.p = vec2<i32>(gid.xy);
    if (textureLoad(mask, a.p, 0).x == 0u) {
        write_empty(a.p);
        textureStore(hist_out, a.p, vec4<f32>(0.0));
        return a;
    }
    a.h = textureLoad(hist_in, a.p, 0);
    a.n = estimate_count(a.h, pixel_gamma_s(a.p));
    a.e = estimate_pixel(a.p, a.n);
    write_outputs(a.p, a.e, a.n);
    if (a.n == 0u) {
        textureStore(hist_out, a.p, vec4<f32>(0.0));
        return a;
    }
    a.live = true;
    return a;
}

@compute @workgroup_size(8, 8, 1)
fn sss_adaptive(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = adaptive_pixel(gid);
    if (!a.live) {
        return;
    }
    let s = dot(LUMA, a.e.fbar) - params.alpha_const * dot(LUMA, a.e.g);
    textureStore(hist_out, a.p, store_texel(update_history(a.h, s, a.n)));
}

@compute @workgroup_size(8, 8, 1)
fn sss_ocv(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = adaptive_pixel(gid);
    if (!a.live) {
        if (a.in_bounds) {
            textureStore(cv_out, a.p, vec4<f32>(0.0));
        }
        return;
    }
    let j = textureLoad(cv_in, a.p, 0);
    let valid = a.h.w >= 0.5;
    let f = dot(LUMA, a.e.fbar);
    let g = dot(LUMA, a.e.g);
    let alpha = ocv_alpha(j, valid, f, g);
    let s = f - alpha * g;
    textureStore(hist_out, a.p, store_texel(update_history(a.h, s, a.n)));
    textureStore(cv_out, a.p, store_texel(update_cv(j, valid, f, g)));
}
