// The reusable adaptive-sampling component (`spvg_wgpu::adaptive::AdaptivePass`): two
// compute steps a renderer records around its own sampling pass.
// - adaptive_estimate: reprojects the history (the library's whole decision,
//   `spvg_reproject_locate`), decides validity once per pixel, writes the count and the
//   reprojection link.
// - adaptive_dilate (only with a dilation radius): each covered pixel takes the largest
//   count of its neighbourhood (the library's `spvg_dilation_window`/`_take`,
//   `spvg::dilation::dilated_count`).
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
    // fbar - alpha G with a constant alpha (CCV) instead of fbar (AS). Bits 3 to 5: the
    // library's spvg_Reprojection.flags shifted left by 3 (bit 3 the border prior,
    // spvg_REPROJECT_BORDER_PRIOR; bit 4 the footprint search, spvg_REPROJECT_FOOTPRINT;
    // bit 5 beta_max for pixels entering under the border prior,
    // spvg_REPROJECT_BORDER_MAXIMUM). Bit 6: the reprojected depth is bound; the depth
    // test compares it instead of this frame's depth. Bit 7: the dilation's depth-aware
    // neighbour prior (spvg_dilation_prior_*), this frame's depth kept in surface_out.
    // Bit 8: the update's TAA guide is bound; the variance follows value - guide
    // (spvg_update_young_texel_guided).
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
const FLAG_REPROJECTED_DEPTH: u32 = 64u;
const FLAG_NEIGHBOUR_PRIOR: u32 = 128u;
const FLAG_GUIDE: u32 = 256u;
// Where spvg_Reprojection.flags sit in AdaptiveParams.flags (bits 3 to 5).
const REPROJECT_SHIFT: u32 = 3u;
// Bits 3 to 5 only: the library's spvg_Reprojection.flags.
const REPROJECT_MASK: u32 = 7u;

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
// estimate: this pixel's surface point's depth as the previous camera saw it
@group(0) @binding(18) var reprojected_depth: texture_2d<f32>;
// This frame's depth, written by the estimate (19) and read by the update (20) for the
// same-surface test of the spatial variance; bound 1x1 and untouched while it is off.
@group(0) @binding(19) var surface_out: texture_storage_2d<r32float, write>;
@group(0) @binding(20) var surface_in: texture_2d<f32>;
// update: the renderer's resolved TAA history C_t, in the monitored value's space
@group(0) @binding(21) var guide_in: texture_2d<f32>;
// Fractional counts (controller.fractional != 0, docs/algorithms.md §8.6): the frame index
// of the dither threshold (x; the number of updates the component has recorded), and each
// pixel's real count, written by the estimate (23) and read by the update (24), -1 where
// the integer rule decided; bound 1x1 and untouched while fractional counts are off.
@group(0) @binding(22) var<uniform> frame_index: vec4<u32>;
@group(0) @binding(23) var real_out: texture_storage_2d<r32float, write>;
@group(0) @binding(24) var real_in: texture_2d<f32>;

// ---- the controller (spvg_shaders::WGSL), behind one wrapper per call ----
// The H texel is the library's history encoding in r, g, b and the history's age in the
// spare channel (spvg_update_young_texel; age >= 1 is the written mark that
// spvg_history_written reads); an invalid history arrives here as all zeros (age 0).

// Count from the reprojected H texel.
fn ctl_estimate(h: vec4<f32>, gamma: f32) -> u32 {
    return spvg_estimate_texel(controller, h, gamma);
}

// Whether fractional counts are on.
fn ctl_fractional() -> bool {
    return controller.fractional != 0u;
}

// Count and real count from a continued H texel under fractional counts, with the dither
// threshold of pixel `q` in this frame.
fn ctl_estimate_fractional(h: vec4<f32>, gamma: f32, q: vec2<u32>) -> spvg_FrameCount {
    return spvg_estimate_texel_fractional(controller, h, gamma, spvg_dither_threshold(q.x, q.y, frame_index.x));
}

// New H texel, ready for the rgba16float store, with the young-history rules the block
// switches on (`m`: the spatial moments of the pixel's neighbourhood); a refused frame
// keeps a valid texel and clears an invalid one. With the guide bound, the variance
// follows s - guide (a non-finite guide falls back to the unguided update inside the
// library). Under fractional counts the frame's real count `real` (-1 where the integer
// rule decided) selects the fractional update: a skipped frame (n = 0) keeps the
// statistics and moves the mean count.
fn ctl_update(h: vec4<f32>, s: f32, n: u32, real: f32, m: spvg_SpatialMoments, p: vec2<i32>) -> vec4<f32> {
    let guided = (adaptive.flags & FLAG_GUIDE) != 0u;
    if (ctl_fractional()) {
        var c = 0.0;
        if (guided) {
            c = textureLoad(guide_in, p, 0).x;
        }
        return spvg_update_fractional_texel_centred(controller, h, s, c, guided, n, real, m, 0u);
    }
    if (guided) {
        let c = textureLoad(guide_in, p, 0).x;
        return spvg_update_young_texel_guided(controller, h, s, c, n, m, 0u);
    }
    return spvg_update_young_texel(controller, h, s, n, m, 0u);
}

// The real count the estimate stored for pixel `p`, -1 without fractional counts.
fn ctl_real(p: vec2<i32>) -> f32 {
    if (ctl_fractional()) {
        return textureLoad(real_in, p, 0).x;
    }
    return -1.0;
}

// Whether pixel `u` skipped this frame under a fractional count: no sample, a continued
// history and a real count.
fn ctl_skipped(n: u32, link: u32, real: f32) -> bool {
    return n == 0u && link != 0u && spvg_is_real(real);
}

// Whether the spatial variance of young histories is on.
fn ctl_spatial() -> bool {
    return (controller.young & spvg_YOUNG_SPATIAL_MASK) != 0u;
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

// What the previous frame holds at texel `q`: its mask, its depth and its history texel.
fn previous_at(q: vec2<u32>) -> spvg_PreviousTexel {
    let qi = vec2<i32>(q);
    return spvg_PreviousTexel(
        covered(prev_mask, qi),
        textureLoad(prev_depth, qi, 0).x,
        spvg_history_written(textureLoad(hist_in, qi, 0)),
    );
}

// The link: 0 where the history is invalid, else 1 + the previous frame's texel index.
fn link_texel(link: u32) -> vec2<i32> {
    let k = link - 1u;
    return vec2<i32>(i32(k % adaptive.width), i32(k / adaptive.width));
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_estimate(@builtin(global_invocation_id) gid: vec3<u32>) {
    adaptive_estimate_at(gid);
}

// The body of `adaptive_estimate` for the pixel `gid`: the whole-frame entry above and the
// tile-list entry of tiles.wgsl run the same code.
fn adaptive_estimate_at(gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    var n = 0u;
    var link = 0u;
    var real = -1.0;
    if (ctl_spatial() || (adaptive.flags & FLAG_NEIGHBOUR_PRIOR) != 0u) {
        textureStore(surface_out, p, vec4<f32>(textureLoad(depth, p, 0).x, 0.0, 0.0, 0.0));
    }
    if (covered(mask, p)) {
        let size = vec2<u32>(adaptive.width, adaptive.height);
        let v = textureLoad(motion, p, 0).xy;
        // The depth the test compares with the previous frame's: the reprojected depth
        // where the renderer gives it (the surface point as the previous camera saw it, so
        // a dolly's own depth change is no disocclusion), else this frame's.
        var d = textureLoad(depth, p, 0).x;
        if ((adaptive.flags & FLAG_REPROJECTED_DEPTH) != 0u) {
            d = textureLoad(reprojected_depth, p, 0).x;
        }
        let rule = spvg_Reprojection(
            adaptive.depth_tolerance,
            (adaptive.flags >> REPROJECT_SHIFT) & REPROJECT_MASK,
        );
        // The whole rule (spvg::reproject::Reprojection::locate and the written check),
        // reading the previous frame only where it needs to.
        var l = spvg_reproject_locate_start(rule, gid.xy, v, size, size);
        while (l.source == spvg_SOURCE_PENDING) {
            l = spvg_reproject_locate(rule, gid.xy, v, size, d, l, previous_at(l.texel));
        }
        let history = l.source != spvg_SOURCE_DISOCCLUDED;
        var h = vec4<f32>(0.0);
        if (history) {
            h = textureLoad(hist_in, vec2<i32>(l.texel), 0);
        }
        if (l.source == spvg_SOURCE_HISTORY) {
            link = 1u + l.texel.y * adaptive.width + l.texel.x;
        }
        var gamma = 1.0;
        if ((adaptive.flags & FLAG_GAMMA) != 0u) {
            gamma = textureLoad(gamma_in, p, 0).x;
        }
        if (ctl_fractional() && link != 0u) {
            // A continued history under fractional counts: its real count, realised with
            // this pixel's and frame's dither threshold.
            let e = ctl_estimate_fractional(h, gamma, gid.xy);
            n = e.count;
            real = e.real;
        } else {
            n = ctl_estimate(h, gamma);
        }
        // Entered the frame under the border prior (Reprojection::entering_count).
        if (l.source == spvg_SOURCE_BORDER_PRIOR) {
            n = spvg_reproject_entering_count(rule, n, controller.max_samples);
        }
        // A pixel without history keeps its first-observation count under dilation.
        if (adaptive.dilation != 0u && !history) {
            n = n | spvg_DILATION_KEEP;
        }
    }
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
    textureStore(link_out, p, vec4<u32>(link, 0u, 0u, 0u));
    if (ctl_fractional()) {
        textureStore(real_out, p, vec4<f32>(real, 0.0, 0.0, 0.0));
    }
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
    let size = vec2<u32>(adaptive.width, adaptive.height);
    if ((adaptive.flags & FLAG_NEIGHBOUR_PRIOR) != 0u) {
        // Twin: `spvg::dilation::dilated_count_with_prior`, same surface by the
        // reprojection's depth test of the neighbour's depth against this pixel's.
        var m = spvg_dilation_prior_window(own, gid.xy, size, adaptive.dilation);
        let d = textureLoad(surface_in, p, 0).x;
        for (var y = m.lo.y; y <= m.hi.y; y++) {
            for (var x = m.lo.x; x <= m.hi.x; x++) {
                let q = vec2<u32>(x, y);
                let same = spvg_reproject_depth_agrees(textureLoad(surface_in, q, 0).x, d, adaptive.depth_tolerance);
                m = spvg_dilation_prior_take(m, own, textureLoad(count_in, q, 0).x, same);
            }
        }
        textureStore(count_out, p, vec4<u32>(spvg_dilation_prior_count(m, own), 0u, 0u, 0u));
        return;
    }
    var m = spvg_dilation_window(own, gid.xy, size, adaptive.dilation);
    for (var y = m.lo.y; y <= m.hi.y; y++) {
        for (var x = m.lo.x; x <= m.hi.x; x++) {
            m.count = spvg_dilation_take(m.count, textureLoad(count_in, vec2<u32>(x, y), 0).x);
        }
    }
    textureStore(count_out, p, vec4<u32>(m.count, 0u, 0u, 0u));
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

// The monitored value at pixel `q` for a neighbourhood whose centre uses the coefficient
// `alpha`: AS fbar, CCV each pixel's own constant coefficient, OCV (`ocv`) the centre's.
fn monitored_at(q: vec2<i32>, alpha: f32, ocv: bool) -> f32 {
    let f = textureLoad(value_in, q, 0).x;
    if ((adaptive.flags & FLAG_CONTROL) != 0u) {
        let g = textureLoad(control_in, q, 0).x;
        return f - ctl_alpha(vec4<f32>(0.0), false, f, g) * g;
    }
    if (ocv) {
        return f - alpha * textureLoad(control_in, q, 0).x;
    }
    return f;
}

// The spatial moments (spvg::controller::young::SpatialMoments) of pixel `p` with the
// monitored value `centre`: its 3x3 neighbours, itself included, in row-major order, that
// took samples this frame and pass the reprojection's depth test against its depth.
// Twin: the neighbourhood of `AdaptiveTwin::update`. Only a history that will be young
// after this frame reads it (spvg_update_young_texel uses the moments only for a new age
// of at most the spatial limit): a steady pixel skips the 3x3 gather, so the rule costs
// where histories are young and nowhere else.
fn spatial_moments(p: vec2<i32>, h: vec4<f32>, centre: f32, alpha: f32, ocv: bool) -> spvg_SpatialMoments {
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    if (!ctl_spatial()) {
        return m;
    }
    var next = 1u;
    if (spvg_history_written(h)) {
        next = min(spvg_read_age(h.w) + 1u, spvg_AGE_CAP);
    }
    if (next > (controller.young & spvg_YOUNG_SPATIAL_MASK)) {
        return m;
    }
    let d = textureLoad(surface_in, p, 0).x;
    let lo = max(p - vec2<i32>(1), vec2<i32>(0));
    let hi = min(p + vec2<i32>(1), vec2<i32>(i32(adaptive.width) - 1, i32(adaptive.height) - 1));
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            let q = vec2<i32>(x, y);
            let same = spvg_reproject_depth_agrees(textureLoad(surface_in, q, 0).x, d, adaptive.depth_tolerance);
            if (textureLoad(count_in, q, 0).x != 0u && same) {
                m = spvg_spatial_push(m, centre, monitored_at(q, alpha, ocv));
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
    if (!in_frame(gid)) {
        return;
    }
    let u = update_pixel(gid);
    let real = ctl_real(u.p);
    if (u.n == 0u) {
        var h = vec4<f32>(0.0);
        if (ctl_skipped(u.n, u.link, real)) {
            h = ctl_update(u.h, 0.0, 0u, real, spvg_SpatialMoments(0u, 0.0, 0.0), u.p);
        }
        textureStore(hist_out, u.p, h);
        return;
    }
    let s = monitored_at(u.p, 0.0, false);
    textureStore(hist_out, u.p, ctl_update(u.h, s, u.n, real, spatial_moments(u.p, u.h, s, 0.0, false), u.p));
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update_ocv(@builtin(global_invocation_id) gid: vec3<u32>) {
    adaptive_update_ocv_at(gid);
}

// The body of `adaptive_update_ocv` for the pixel `gid`: the whole-frame entry above and the
// tile-list entry of tiles.wgsl run the same code.
fn adaptive_update_ocv_at(gid: vec3<u32>) {
    if (!in_frame(gid)) {
        return;
    }
    let u = update_pixel(gid);
    let real = ctl_real(u.p);
    let valid = u.link != 0u;
    var j = vec4<f32>(0.0);
    if (valid) {
        j = textureLoad(cv_in, link_texel(u.link), 0);
    }
    if (u.n == 0u) {
        // A skipped frame carries both histories (the H texel's mean count updated).
        var h = vec4<f32>(0.0);
        var jc = vec4<f32>(0.0);
        if (ctl_skipped(u.n, u.link, real)) {
            h = ctl_update(u.h, 0.0, 0u, real, spvg_SpatialMoments(0u, 0.0, 0.0), u.p);
            jc = j;
        }
        textureStore(hist_out, u.p, h);
        textureStore(cv_out, u.p, jc);
        return;
    }
    let f = textureLoad(value_in, u.p, 0).x;
    let g = textureLoad(control_in, u.p, 0).x;
    let alpha = ctl_alpha(j, valid, f, g);
    let s = f - alpha * g;
    textureStore(hist_out, u.p, ctl_update(u.h, s, u.n, real, spatial_moments(u.p, u.h, s, alpha, true), u.p));
    textureStore(cv_out, u.p, ctl_update_cv(j, valid, f, g));
}
