// The reusable adaptive-sampling component (`spvg_wgpu::adaptive::AdaptivePass`): two
// compute steps a renderer records around its own sampling pass.
// - adaptive_estimate: reprojects the history (the library's `spvg_reproject_*`),
//   decides validity once per pixel, writes the count and the reprojection link.
// - adaptive_dilate (only with a dilation radius): each covered pixel takes the largest
//   count of its neighbourhood (`spvg::dilation::dilated_count`).
// - adaptive_update (AS, CCV) / adaptive_update_ocv: reads the same history through the
//   link and writes the new history.
// Rust twin: `spvg_wgpu::adaptive::AdaptiveTwin` (`estimate`, `update`).
// Every controller call goes through the `ctl_*` wrappers below, and nothing else here
// knows the controller's texel or parameter layout.

// Rust twin: `spvg_wgpu::adaptive::AdaptiveParams`; same field order and types.
struct AdaptiveParams {
    width: u32,
    height: u32,
    depth_tolerance: f32,
    // Bit 0: the mask textures are bound (else every pixel is covered). Bit 1: the
    // distant-energy ratio is bound (else gamma = 1). Bit 2: the model monitors
    // fbar - alpha G with a constant alpha (CCV) instead of fbar (AS). Bit 3: the border
    // prior (pixels entering the frame estimate from spvg_reproject_border_texel). Bit 4:
    // the footprint search (spvg_reproject_footprint_texel where the nearest texel fails).
    // Bit 5: pixels entering under the border prior take beta_max (BorderCount::Maximum).
    flags: u32,
    // Radius of the count dilation; 0 = off (adaptive_dilate is not run).
    dilation: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

const FLAG_MASKS: u32 = 1u;
const FLAG_GAMMA: u32 = 2u;
const FLAG_CONTROL: u32 = 4u;
const FLAG_BORDER_PRIOR: u32 = 8u;
const FLAG_FOOTPRINT: u32 = 16u;
const FLAG_BORDER_MAXIMUM: u32 = 32u;
// spvg::dilation::KEEP: the pixel keeps its count (no history).
const DILATION_KEEP: u32 = 0x80000000u;

@group(0) @binding(0) var<uniform> controller: spvg_Params;
@group(0) @binding(1) var<uniform> adaptive: AdaptiveParams;
@group(0) @binding(2) var hist_in: texture_2d<f32>;
// estimate
@group(0) @binding(3) var motion: texture_2d<f32>;
@group(0) @binding(4) var depth: texture_2d<f32>;
@group(0) @binding(5) var prev_depth: texture_2d<f32>;
@group(0) @binding(6) var mask: texture_2d<u32>;
@group(0) @binding(7) var prev_mask: texture_2d<u32>;
@group(0) @binding(8) var gamma_in: texture_2d<f32>;
@group(0) @binding(9) var count_out: texture_storage_2d<r32uint, write>;
@group(0) @binding(10) var link_out: texture_storage_2d<r32uint, write>;
// update
@group(0) @binding(11) var value_in: texture_2d<f32>;
@group(0) @binding(12) var control_in: texture_2d<f32>;
@group(0) @binding(13) var count_in: texture_2d<u32>;
@group(0) @binding(14) var link_in: texture_2d<u32>;
@group(0) @binding(15) var hist_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(16) var cv_in: texture_2d<f32>;
@group(0) @binding(17) var cv_out: texture_storage_2d<rgba16float, write>;

// ---- the controller (spvg_shaders::WGSL), behind one wrapper per call ----
// The H texel is the library's history encoding in r, g, b and a "written" flag in the
// spare channel; an invalid history arrives here as all zeros (flag 0).

fn ctl_valid(h: vec4<f32>) -> bool {
    return h.w >= 0.5;
}

// Count from the reprojected H texel.
fn ctl_estimate(h: vec4<f32>, gamma: f32) -> u32 {
    return spvg_estimate_count(controller, spvg_decode_history(controller, h), gamma, ctl_valid(h));
}

// New H texel, ready for the rgba16float store; a refused frame keeps a valid texel and
// clears an invalid one.
fn ctl_update(h: vec4<f32>, s: f32, n: u32) -> vec4<f32> {
    let valid = ctl_valid(h);
    let u = spvg_update_history(controller, spvg_decode_history(controller, h), s, n, valid);
    if (!u.accepted) {
        return select(vec4<f32>(0.0), h, valid);
    }
    var t = spvg_encode_history(controller, u.history, 0u);
    t.w = 1.0;
    return t;
}

// The control-variate coefficient: AS 0, CCV 1, OCV from the reprojected J texel (the
// cold state when invalid).
fn ctl_alpha(j: vec4<f32>, valid: bool, f: f32, g: f32) -> f32 {
    var js = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid) {
        js = spvg_decode_cv(controller, j);
    }
    return spvg_cv_coefficient(controller, js, f, g);
}

// New J texel, ready for the rgba16float store.
fn ctl_update_cv(j: vec4<f32>, valid: bool, f: f32, g: f32) -> vec4<f32> {
    var js = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid) {
        js = spvg_decode_cv(controller, j);
    }
    let u = spvg_update_cv(controller, js, f, g, valid);
    if (!u.accepted && valid) {
        return j;
    }
    return spvg_encode_cv(controller, u.cv, 0u);
}

// ---- the component ----

fn in_frame(gid: vec3<u32>) -> bool {
    return gid.x < adaptive.width && gid.y < adaptive.height;
}

fn covered(m: texture_2d<u32>, p: vec2<i32>) -> bool {
    if ((adaptive.flags & FLAG_MASKS) == 0u) {
        return true;
    }
    return textureLoad(m, p, 0).x != 0u;
}

// Whether the previous frame's texel `q` continues a pixel at depth `d`: its mask is set
// and the relative depth test passes (spvg::reproject::Reprojection::accepts).
fn continues(q: vec2<u32>, d: f32) -> bool {
    let qi = vec2<i32>(q);
    return covered(prev_mask, qi)
        && spvg_reproject_depth_agrees(textureLoad(prev_depth, qi, 0).x, d, adaptive.depth_tolerance);
}

// The link: 0 where the history is invalid, else 1 + the previous frame's texel index.
fn link_texel(link: u32) -> vec2<i32> {
    let k = link - 1u;
    return vec2<i32>(i32(k % adaptive.width), i32(k / adaptive.width));
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_estimate(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    var n = 0u;
    var link = 0u;
    if (covered(mask, p)) {
        let size = vec2<u32>(adaptive.width, adaptive.height);
        let v = textureLoad(motion, p, 0).xy;
        var q = spvg_reproject_texel(gid.xy, v, size);
        // 1: a reprojected history (estimate and update); 2: the border prior (estimate
        // only, the update seeds); 0: none.
        var source = q.z;
        if (q.z == 0u && (adaptive.flags & FLAG_BORDER_PRIOR) != 0u) {
            q = spvg_reproject_border_texel(gid.xy, v, size);
            source = 2u * q.z;
        }
        var h = vec4<f32>(0.0);
        var history = false;
        if (source != 0u) {
            let d = textureLoad(depth, p, 0).x;
            var ok = continues(q.xy, d);
            // The footprint search (spvg::reproject::Reprojection::locate): the other
            // texels of the 2x2 footprint, for a reprojected position only.
            if (!ok && source == 1u && (adaptive.flags & FLAG_FOOTPRINT) != 0u) {
                for (var k = 1u; k <= 3u; k++) {
                    let alt = spvg_reproject_footprint_texel(gid.xy, v, size, k);
                    if (alt.z != 0u && continues(alt.xy, d)) {
                        q = alt;
                        ok = true;
                        break;
                    }
                }
            }
            if (ok) {
                let qi = vec2<i32>(q.xy);
                let stored = textureLoad(hist_in, qi, 0);
                // A texel the previous frame did not write (flag 0) is no history either.
                if (stored.w >= 0.5) {
                    h = stored;
                    history = true;
                    if (source == 1u) {
                        link = 1u + q.y * adaptive.width + q.x;
                    }
                }
            }
        }
        var gamma = 1.0;
        if ((adaptive.flags & FLAG_GAMMA) != 0u) {
            gamma = textureLoad(gamma_in, p, 0).x;
        }
        n = ctl_estimate(h, gamma);
        // Entered the frame under the border prior, count rule BorderCount::Maximum
        // (spvg::reproject::Reprojection::entering_count).
        if (history && link == 0u && (adaptive.flags & FLAG_BORDER_MAXIMUM) != 0u && n != 0u) {
            n = controller.max_samples;
        }
        // A pixel without history keeps its first-observation count under dilation.
        if (adaptive.dilation != 0u && !history) {
            n = n | DILATION_KEEP;
        }
    }
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
    textureStore(link_out, p, vec4<u32>(link, 0u, 0u, 0u));
}

// Twin: `spvg::dilation::dilated_count`. Reads the estimate's counts (bound as count_in),
// writes the dilated ones (count_out).
@compute @workgroup_size(8, 8, 1)
fn adaptive_dilate(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    let own = textureLoad(count_in, p, 0).x;
    var m = own & ~DILATION_KEEP;
    if (own != 0u && (own & DILATION_KEEP) == 0u) {
        let r = vec2<i32>(i32(adaptive.dilation));
        let lo = max(p - r, vec2<i32>(0));
        let hi = min(p + r, vec2<i32>(i32(adaptive.width) - 1, i32(adaptive.height) - 1));
        for (var y = lo.y; y <= hi.y; y++) {
            for (var x = lo.x; x <= hi.x; x++) {
                m = max(m, textureLoad(count_in, vec2<i32>(x, y), 0).x & ~DILATION_KEEP);
            }
        }
    }
    textureStore(count_out, p, vec4<u32>(m, 0u, 0u, 0u));
}

// What both update entry points read: the count, the link and the reprojected H texel.
struct UpdatePixel {
    p: vec2<i32>,
    n: u32,
    link: u32,
    h: vec4<f32>,
}

fn update_pixel(gid: vec3<u32>) -> UpdatePixel {
    var u: UpdatePixel;
    u.p = vec2<i32>(gid.xy);
    u.n = textureLoad(count_in, u.p, 0).x;
    u.link = textureLoad(link_in, u.p, 0).x;
    u.h = vec4<f32>(0.0);
    if (u.link != 0u) {
        u.h = textureLoad(hist_in, link_texel(u.link), 0);
    }
    return u;
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let u = update_pixel(gid);
    if (u.n == 0u) {
        textureStore(hist_out, u.p, vec4<f32>(0.0));
        return;
    }
    var s = textureLoad(value_in, u.p, 0).x;
    if ((adaptive.flags & FLAG_CONTROL) != 0u) {
        let g = textureLoad(control_in, u.p, 0).x;
        s = s - ctl_alpha(vec4<f32>(0.0), false, s, g) * g;
    }
    textureStore(hist_out, u.p, ctl_update(u.h, s, u.n));
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update_ocv(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let u = update_pixel(gid);
    if (u.n == 0u) {
        textureStore(hist_out, u.p, vec4<f32>(0.0));
        textureStore(cv_out, u.p, vec4<f32>(0.0));
        return;
    }
    let valid = u.link != 0u;
    var j = vec4<f32>(0.0);
    if (valid) {
        j = textureLoad(cv_in, link_texel(u.link), 0);
    }
    let f = textureLoad(value_in, u.p, 0).x;
    let g = textureLoad(control_in, u.p, 0).x;
    let alpha = ctl_alpha(j, valid, f, g);
    textureStore(hist_out, u.p, ctl_update(u.h, f - alpha * g, u.n));
    textureStore(cv_out, u.p, ctl_update_cv(j, valid, f, g));
}
