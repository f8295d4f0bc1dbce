// What both forms of the component run (`spvg_wgpu::adaptive::AdaptivePass`): its
// bindings, the controller behind one wrapper per call, the per-pixel estimate (the
// reprojection, the validity, the count) and the per-pixel update of the histories.
// - The two-pass form (adaptive.wgsl) records the estimate and the update as the
//   component's own dispatches around the renderer's sampling pass, and exchanges the
//   count, the link and the real count through textures.
// - The one-pass form (one_pass.wgsl) runs both inside the renderer's own dispatch and
//   keeps them in registers and workgroup memory.
// Every name here starts with `spvg_ad_` (or `spvg_AD_`, `spvg_Ad`), so that the text joins
// a renderer's shader without clashes. The bindings sit at group SPVG_AD_GROUP, which the
// component replaces with the group number (0 for its own dispatches, the renderer's
// choice for the one-pass module). `spvg_AD_OCV` and the control-variate history's two
// helpers (`spvg_ad_load_cv`, `spvg_ad_store_cv`) come from component_cv.wgsl for OCV and
// from component_no_cv.wgsl otherwise, so that a model without that history binds none.
// Rust twin: `spvg_wgpu::adaptive::AdaptiveTwin` (`estimate`, `update`), through the
// functions of `controller.rs`, one per `spvg_ad_ctl_*` wrapper.

// Rust twin: `spvg_wgpu::adaptive::AdaptiveParams`; same field order and types.
struct spvg_AdaptiveParams {
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
    // neighbour prior (spvg_dilation_prior_*), this frame's depth kept. Bit 8: the
    // update's TAA guide is bound; the variance follows value - guide
    // (spvg_update_young_texel_guided). Bit 9: the one-pass form stores the counts. Bit
    // 10: the one-pass form's count order (its invocations take the tile's pixels by rank
    // of their counts).
    flags: u32,
    // Radius of the count dilation; 0 = off.
    dilation: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

const spvg_AD_FLAG_MASKS: u32 = 1u;
const spvg_AD_FLAG_GAMMA: u32 = 2u;
const spvg_AD_FLAG_CONTROL: u32 = 4u;
const spvg_AD_FLAG_REPROJECTED_DEPTH: u32 = 64u;
const spvg_AD_FLAG_NEIGHBOUR_PRIOR: u32 = 128u;
const spvg_AD_FLAG_GUIDE: u32 = 256u;
const spvg_AD_FLAG_STORE_COUNTS: u32 = 512u;
const spvg_AD_FLAG_COUNT_ORDER: u32 = 1024u;
const spvg_AD_FLAG_MOMENT: u32 = 2048u;
// Where spvg_Reprojection.flags sit in spvg_AdaptiveParams.flags (bits 3 to 5).
const spvg_AD_REPROJECT_SHIFT: u32 = 3u;
// Bits 3 to 5 only: the library's spvg_Reprojection.flags.
const spvg_AD_REPROJECT_MASK: u32 = 7u;

@group(SPVG_AD_GROUP) @binding(0) var<uniform> spvg_ad_controller: spvg_Params;
@group(SPVG_AD_GROUP) @binding(1) var<uniform> spvg_ad_params: spvg_AdaptiveParams;
@group(SPVG_AD_GROUP) @binding(2) var spvg_ad_hist_in: texture_2d<f32>;
// estimate
@group(SPVG_AD_GROUP) @binding(3) var spvg_ad_motion: texture_2d<f32>;
@group(SPVG_AD_GROUP) @binding(4) var spvg_ad_depth: texture_2d<f32>;
@group(SPVG_AD_GROUP) @binding(5) var spvg_ad_prev_depth: texture_2d<f32>;
@group(SPVG_AD_GROUP) @binding(6) var spvg_ad_mask: texture_2d<u32>;
@group(SPVG_AD_GROUP) @binding(7) var spvg_ad_prev_mask: texture_2d<u32>;
@group(SPVG_AD_GROUP) @binding(8) var spvg_ad_gamma_in: texture_2d<f32>;
// The counts: the two-pass estimate and dilation write them, the one-pass form where
// asked (spvg_AD_FLAG_STORE_COUNTS).
@group(SPVG_AD_GROUP) @binding(9) var spvg_ad_count_out: texture_storage_2d<r32uint, write>;
// update
@group(SPVG_AD_GROUP) @binding(15) var spvg_ad_hist_out: texture_storage_2d<rgba16float, write>;
// estimate: this pixel's surface point's depth as the previous camera saw it
@group(SPVG_AD_GROUP) @binding(18) var spvg_ad_reprojected_depth: texture_2d<f32>;
// Fractional counts (controller.fractional != 0, docs/algorithms.md §8.6): the frame index
// of the dither threshold (x; the number of frames the component has updated).
@group(SPVG_AD_GROUP) @binding(22) var<uniform> spvg_ad_frame_index: vec4<u32>;
// estimate: the renderer's resolve weight per pixel for the resolved-image rule
// (docs/algorithms.md §8.7), or a 1x1 texel of zero ("none") where it gave none.
@group(SPVG_AD_GROUP) @binding(25) var spvg_ad_resolve_in: texture_2d<f32>;

// ---- the controller (spvg_shaders::WGSL), behind one wrapper per call ----
// The H texel is the library's history encoding in r, g, b and the history's age in the
// spare channel (spvg_update_young_texel; age >= 1 is the written mark that
// spvg_history_written reads); an invalid history arrives here as all zeros (age 0).

// Count from the reprojected H texel.
fn spvg_ad_ctl_estimate(h: vec4<f32>, gamma: f32) -> u32 {
    return spvg_estimate_texel(spvg_ad_controller, h, gamma);
}

// Whether fractional counts are on.
fn spvg_ad_ctl_fractional() -> bool {
    return spvg_ad_controller.fractional != 0u;
}

// Count and real count from a continued H texel under fractional counts, with the dither
// threshold of pixel `q` in this frame.
fn spvg_ad_ctl_estimate_fractional(h: vec4<f32>, gamma: f32, q: vec2<u32>) -> spvg_FrameCount {
    let xi = spvg_dither_threshold(q.x, q.y, spvg_ad_frame_index.x);
    return spvg_estimate_texel_resolved(spvg_ad_controller, h, gamma, xi, spvg_ad_resolve_at(q));
}

// The renderer's resolve weight at pixel `q`: the load is clamped to the texture, so the
// 1x1 texel of zero bound where the renderer gave none reads "none" at every pixel.
fn spvg_ad_resolve_at(q: vec2<u32>) -> f32 {
    let last = textureDimensions(spvg_ad_resolve_in) - vec2<u32>(1u);
    return textureLoad(spvg_ad_resolve_in, vec2<i32>(min(q, last)), 0).x;
}

// New H texel, ready for the rgba16float store, with the young-history rules the block
// switches on (`m`: the spatial moments of the pixel's neighbourhood); a refused frame
// keeps a valid texel and clears an invalid one. With `guided`, the variance follows
// s - guide (a non-finite guide falls back to the unguided update inside the library).
// Under fractional counts the frame's real count `real` (-1 where the integer rule
// decided) selects the fractional update: a skipped frame (n = 0) keeps the statistics
// and moves the mean count.
// `frame_var` is the frame's spvg_per_sample_variance where the renderer handed its second
// moment (docs/algorithms.md §8.8), -1 otherwise: the update then follows it
// (spvg_update_moment_texel).
fn spvg_ad_ctl_update(h: vec4<f32>, s: f32, n: u32, real: f32, m: spvg_SpatialMoments, guided: bool, guide: f32, frame_var: f32) -> vec4<f32> {
    if (frame_var >= 0.0) {
        var r = -1.0;
        if (spvg_ad_ctl_fractional()) {
            r = real;
        }
        return spvg_update_moment_texel_centred(spvg_ad_controller, h, s, guide, guided, frame_var, n, r, m, 0u);
    }
    if (spvg_ad_ctl_fractional()) {
        return spvg_update_fractional_texel_centred(spvg_ad_controller, h, s, guide, guided, n, real, m, 0u);
    }
    if (guided) {
        return spvg_update_young_texel_guided(spvg_ad_controller, h, s, guide, n, m, 0u);
    }
    return spvg_update_young_texel(spvg_ad_controller, h, s, n, m, 0u);
}

// Whether a pixel skipped this frame under a fractional count: no sample, a continued
// history and a real count.
fn spvg_ad_ctl_skipped(n: u32, link: u32, real: f32) -> bool {
    return n == 0u && link != 0u && spvg_is_real(real);
}

// Whether the spatial variance of young histories is on.
fn spvg_ad_ctl_spatial() -> bool {
    return (spvg_ad_controller.young & spvg_YOUNG_SPATIAL_MASK) != 0u;
}

// The control-variate coefficient: AS 0, CCV 1, OCV from the reprojected J texel (the
// cold state when invalid).
fn spvg_ad_ctl_alpha(j: vec4<f32>, valid: bool, f: f32, g: f32) -> f32 {
    var js = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid) {
        js = spvg_decode_cv(spvg_ad_controller, j);
    }
    return spvg_cv_coefficient(spvg_ad_controller, js, f, g);
}

// New J texel, ready for the rgba16float store.
fn spvg_ad_ctl_update_cv(j: vec4<f32>, valid: bool, f: f32, g: f32) -> vec4<f32> {
    var js = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid) {
        js = spvg_decode_cv(spvg_ad_controller, j);
    }
    let u = spvg_update_cv(spvg_ad_controller, js, f, g, valid);
    if (!u.accepted && valid) {
        return j;
    }
    return spvg_encode_cv(spvg_ad_controller, u.cv, 0u);
}

// ---- the estimate ----

fn spvg_ad_in_frame(p: vec2<u32>) -> bool {
    return p.x < spvg_ad_params.width && p.y < spvg_ad_params.height;
}

fn spvg_ad_size() -> vec2<u32> {
    return vec2<u32>(spvg_ad_params.width, spvg_ad_params.height);
}

fn spvg_ad_covered(m: texture_2d<u32>, p: vec2<i32>) -> bool {
    if ((spvg_ad_params.flags & spvg_AD_FLAG_MASKS) == 0u) {
        return true;
    }
    return textureLoad(m, p, 0).x != 0u;
}

// Whether this frame's depth is kept for the neighbourhood rules (the spatial variance of
// young histories, the neighbour prior).
fn spvg_ad_keeps_depth() -> bool {
    return spvg_ad_ctl_spatial() || (spvg_ad_params.flags & spvg_AD_FLAG_NEIGHBOUR_PRIOR) != 0u;
}

// What the previous frame holds at texel `q`: its mask, its depth and its history texel.
fn spvg_ad_previous_at(q: vec2<u32>) -> spvg_PreviousTexel {
    let qi = vec2<i32>(q);
    return spvg_PreviousTexel(
        spvg_ad_covered(spvg_ad_prev_mask, qi),
        textureLoad(spvg_ad_prev_depth, qi, 0).x,
        spvg_history_written(textureLoad(spvg_ad_hist_in, qi, 0)),
    );
}

// The link: 0 where the history is invalid, else 1 + the previous frame's texel index.
fn spvg_ad_link_texel(link: u32) -> vec2<i32> {
    let k = link - 1u;
    return vec2<i32>(i32(k % spvg_ad_params.width), i32(k / spvg_ad_params.width));
}

// One pixel's estimate: its count (marked spvg_DILATION_KEEP where it has no history and
// the dilation is on), the link to the history its update continues (0: none), the real
// count of a fractional decision (-1: the integer rule) and the H texel the update
// continues (zeros without a link).
struct spvg_AdEstimate {
    count: u32,
    link: u32,
    real: f32,
    history: vec4<f32>,
}

// The estimate of pixel `q` of the frame: the reprojection (the library's whole decision,
// spvg_reproject_locate, reading the previous frame only where it needs to), the validity
// and the controller's count. Both forms call it for every pixel they estimate, the
// one-pass form also for the pixels of its tile's halo.
fn spvg_ad_estimate_pixel(q: vec2<u32>) -> spvg_AdEstimate {
    var e = spvg_AdEstimate(0u, 0u, -1.0, vec4<f32>(0.0));
    let p = vec2<i32>(q);
    if (!spvg_ad_covered(spvg_ad_mask, p)) {
        return e;
    }
    let size = spvg_ad_size();
    let v = textureLoad(spvg_ad_motion, p, 0).xy;
    // The depth the test compares with the previous frame's: the reprojected depth where
    // the renderer gives it (the surface point as the previous camera saw it, so a dolly's
    // own depth change is no disocclusion), else this frame's.
    var d = textureLoad(spvg_ad_depth, p, 0).x;
    if ((spvg_ad_params.flags & spvg_AD_FLAG_REPROJECTED_DEPTH) != 0u) {
        d = textureLoad(spvg_ad_reprojected_depth, p, 0).x;
    }
    let rule = spvg_Reprojection(
        spvg_ad_params.depth_tolerance,
        (spvg_ad_params.flags >> spvg_AD_REPROJECT_SHIFT) & spvg_AD_REPROJECT_MASK,
    );
    var l = spvg_reproject_locate_start(rule, q, v, size, size);
    while (l.source == spvg_SOURCE_PENDING) {
        l = spvg_reproject_locate(rule, q, v, size, d, l, spvg_ad_previous_at(l.texel));
    }
    let history = l.source != spvg_SOURCE_DISOCCLUDED;
    var h = vec4<f32>(0.0);
    if (history) {
        h = textureLoad(spvg_ad_hist_in, vec2<i32>(l.texel), 0);
    }
    if (l.source == spvg_SOURCE_HISTORY) {
        e.link = 1u + l.texel.y * spvg_ad_params.width + l.texel.x;
        e.history = h;
    }
    var gamma = 1.0;
    if ((spvg_ad_params.flags & spvg_AD_FLAG_GAMMA) != 0u) {
        gamma = textureLoad(spvg_ad_gamma_in, p, 0).x;
    }
    if (spvg_ad_ctl_fractional() && e.link != 0u) {
        // A continued history under fractional counts: its real count, realised with
        // this pixel's and frame's dither threshold.
        let f = spvg_ad_ctl_estimate_fractional(h, gamma, q);
        e.count = f.count;
        e.real = f.real;
    } else {
        e.count = spvg_ad_ctl_estimate(h, gamma);
    }
    // Entered the frame under the border prior (Reprojection::entering_count).
    if (l.source == spvg_SOURCE_BORDER_PRIOR) {
        e.count = spvg_reproject_entering_count(rule, e.count, spvg_ad_controller.max_samples);
    }
    // A pixel without history keeps its first-observation count under dilation.
    if (spvg_ad_params.dilation != 0u && !history) {
        e.count = e.count | spvg_DILATION_KEEP;
    }
    return e;
}

// ---- the update ----

// Whether the spatial moments of a pixel whose continued H texel is `h` are gathered: the
// rule is on and the history is young after this frame (spvg_update_young_texel uses the
// moments only for a new age of at most the spatial limit), so a steady pixel skips its
// neighbourhood and the rule costs where histories are young and nowhere else.
fn spvg_ad_young(h: vec4<f32>) -> bool {
    if (!spvg_ad_ctl_spatial()) {
        return false;
    }
    var next = 1u;
    if (spvg_history_written(h)) {
        next = min(spvg_read_age(h.w) + 1u, spvg_AGE_CAP);
    }
    return next <= (spvg_ad_controller.young & spvg_YOUNG_SPATIAL_MASK);
}

// The new H and J texels of one pixel (J: OCV only, zeros otherwise).
struct spvg_AdTexels {
    h: vec4<f32>,
    j: vec4<f32>,
}

// The update of one pixel: count `n`, link `link`, real count `real`, the continued H
// texel `h` and J texel `j` (zeros without a link), this frame's value `f` and control
// `g`, the monitored value `s` and the spatial moments `m` its caller gathered, the TAA
// guide where `guided`, the in-frame variance `frame_var` (-1: none). A pixel that took no sample clears both texels, unless it skipped
// this frame under a fractional count: that carries both (the H texel's mean count
// updated).
fn spvg_ad_update_texels(n: u32, link: u32, real: f32, h: vec4<f32>, j: vec4<f32>, f: f32, g: f32, s: f32, m: spvg_SpatialMoments, guided: bool, guide: f32, frame_var: f32) -> spvg_AdTexels {
    var out = spvg_AdTexels(vec4<f32>(0.0), vec4<f32>(0.0));
    if (n == 0u) {
        if (spvg_ad_ctl_skipped(n, link, real)) {
            out.h = spvg_ad_ctl_update(h, 0.0, 0u, real, spvg_SpatialMoments(0u, 0.0, 0.0), false, 0.0, -1.0);
            out.j = j;
        }
        return out;
    }
    out.h = spvg_ad_ctl_update(h, s, n, real, m, guided, guide, frame_var);
    if (spvg_AD_OCV) {
        out.j = spvg_ad_ctl_update_cv(j, link != 0u, f, g);
    }
    return out;
}

// The coefficient of a pixel that took samples: OCV from its continued J texel, else 0
// (CCV's constant coefficient enters through spvg_ad_monitored).
fn spvg_ad_alpha(j: vec4<f32>, link: u32, f: f32, g: f32) -> f32 {
    if (spvg_AD_OCV) {
        return spvg_ad_ctl_alpha(j, link != 0u, f, g);
    }
    return 0.0;
}

// Whether the model reads a control value (CCV, OCV).
fn spvg_ad_reads_control() -> bool {
    return spvg_AD_OCV || (spvg_ad_params.flags & spvg_AD_FLAG_CONTROL) != 0u;
}

// The monitored value of a pixel with value `f` and control `g` in a neighbourhood whose
// centre uses the coefficient `alpha`: AS f, CCV the pixel's own constant coefficient,
// OCV the centre's.
// Whether the monitored value is a control-variate residual fbar - alpha G (CCV, OCV)
// rather than the samples' mean: the second moment of docs/algorithms.md §8.8 does not
// apply there.
fn spvg_ad_controlled() -> bool {
    return spvg_AD_OCV || (spvg_ad_params.flags & spvg_AD_FLAG_CONTROL) != 0u;
}

fn spvg_ad_monitored(f: f32, g: f32, alpha: f32) -> f32 {
    if ((spvg_ad_params.flags & spvg_AD_FLAG_CONTROL) != 0u) {
        return f - spvg_ad_ctl_alpha(vec4<f32>(0.0), false, f, g) * g;
    }
    if (spvg_AD_OCV) {
        return f - alpha * g;
    }
    return f;
}
