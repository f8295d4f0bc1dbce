// The subsurface-scattering pass: one invocation per pixel, three entry points.
// - sss_fixed: a fixed count per pixel, no history (baseline).
// - sss_adaptive: SPVG count control on one history texel; AS or CCV (the model in params.spvg).
// - sss_ocv: SPVG with the online control variate, two history texels.
// CPU twins: `spvg_wgpu::twin::{sss_fixed, sss_adaptive, sss_ocv}`, one per entry point.
// Textures read at the pixel itself (identity reprojection: the camera is static).
// Every controller, control-variate and texel rule is the WGSL library's
// (spvg_shaders::WGSL, the `spvg_` functions, with `params.spvg` as their parameters);
// this file keeps the bindings, the validity flag in the H texel's spare channel and the
// order of the calls.

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

// The result texel as the library stores an f16 value (NaN to 0, clamped, rounded to
// nearest even: exact in the rgba16float store).
fn result_texel(v: vec3<f32>) -> vec4<f32> {
    let r = spvg_ROUNDING_NEAREST;
    return vec4<f32>(spvg_to_f16(v.x, r, 0u), spvg_to_f16(v.y, r, 0u), spvg_to_f16(v.z, r, 0u), 1.0);
}

fn write_outputs(p: vec2<i32>, e: PixelEstimate, n: u32) {
    textureStore(result_out, p, result_texel(e.result));
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
}

// The H texel holds the library's history encoding in r, g, b and the validity flag in
// the spare channel (1 where the pixel was subsurface and sampled last frame, so identity
// reprojection finds valid history).
fn history_valid(h: vec4<f32>) -> bool {
    return h.w >= 0.5;
}

// spvg_update_history on the decoded H texel; a refused frame keeps a valid texel as it is
// and clears an invalid one.
fn next_history(h: vec4<f32>, s: f32, n: u32) -> vec4<f32> {
    let valid = history_valid(h);
    let u = spvg_update_history(params.spvg, spvg_decode_history(params.spvg, h), s, n, valid);
    if (!u.accepted) {
        return select(vec4<f32>(0.0), h, valid);
    }
    var t = spvg_encode_history(params.spvg, u.history, 0u);
    t.w = 1.0;
    return t;
}

fn write_empty(p: vec2<i32>) {
    textureStore(result_out, p, vec4<f32>(0.0));
    textureStore(count_out, p, vec4<u32>(0u));
}

// Zero-sample rule (docs/algorithms.md §2.4): nothing scatters far enough to need samples.
fn distant_count(p: vec2<i32>, n: u32) -> u32 {
    if (!spvg_samples_distant(params.spvg, pixel_gamma_s(p))) {
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
    a.n = spvg_estimate_count(params.spvg, spvg_decode_history(params.spvg, a.h), pixel_gamma_s(a.p), history_valid(a.h));
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
    // AS (alpha 0) or CCV (alpha 1): the model in params.spvg; they keep no CV state.
    let f = dot(LUMA, a.e.fbar);
    let g = dot(LUMA, a.e.g);
    let alpha = spvg_cv_coefficient(params.spvg, spvg_CvHistory(0.0, 0.0, 0.0, 0.0), f, g);
    textureStore(hist_out, a.p, next_history(a.h, f - alpha * g, a.n));
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
    let jt = textureLoad(cv_in, a.p, 0);
    let valid = history_valid(a.h);
    // An invalid J is the cold state: its coefficient is 1, and the update reseeds it.
    var j = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid) {
        j = spvg_decode_cv(params.spvg, jt);
    }
    let f = dot(LUMA, a.e.fbar);
    let g = dot(LUMA, a.e.g);
    let alpha = spvg_cv_coefficient(params.spvg, j, f, g);
    textureStore(hist_out, a.p, next_history(a.h, f - alpha * g, a.n));
    let u = spvg_update_cv(params.spvg, j, f, g, valid);
    var jn = spvg_encode_cv(params.spvg, u.cv, 0u);
    if (!u.accepted && valid) {
        jn = jt;
    }
    textureStore(cv_out, a.p, jn);
}
