// Route 2 of docs/integrating.md: a renderer's own adaptive pass that runs the spvg rules
// itself, from the spvg-shaders library (prepended: spvg_shaders::WGSL), with the
// component's default rules (spvg_wgpu::adaptive::AdaptiveSettings::default(): border
// prior, footprint search, neighbour prior, the spatial variance of young histories).
// Four dispatches per frame, in this order:
//   route2_estimate  locate the history (spvg_reproject_locate_start / _locate), estimate
//                    its count (spvg_estimate_texel), the border prior's entering count
//                    (spvg_reproject_entering_count), and with a dilation radius the
//                    spvg_DILATION_KEEP mark on a pixel without history; stores the count
//                    and the decision (the link);
//   route2_dilate    (radius > 0 only) the neighbour prior and the count dilation
//                    (spvg_dilation_prior_window / _take / _count) over the estimate's
//                    counts;
//   route2_sample    the renderer's own Monte Carlo loop, `count` samples;
//   route2_update    spvg_update_young_texel on the linked history, with the spatial
//                    moments of the same-surface values this frame in the pixel's
//                    spvg_spatial_window (3x3 clipped to its 8 x 8 tile).
// The split is what the default rules need: the dilation reads its neighbours' counts,
// the update its neighbours' values, and neither exists before the step that writes it.
// Counts, links and histories equal spvg_wgpu::adaptive::AdaptivePass's, bit for bit
// (spvg-wgpu/tests/route2.rs).

// The renderer's per-frame uniform block (Rust twin: `FrameUniforms` in pass.rs).
struct FrameUniforms {
    width: u32,
    height: u32,
    frame: u32,
    // Count dilation radius; 0 = off (route2_dilate is not dispatched).
    dilation: u32,
    // The reprojection rule (Rust: spvg_shaders::ReprojectionRule); last, as a struct
    // member of a uniform block is 16-byte aligned (the block is 32 bytes).
    rule: spvg_Reprojection,
}

@group(0) @binding(0) var<uniform> controller: spvg_Params;
@group(0) @binding(1) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var motion: texture_2d<f32>;
// This frame's linear depth: the reprojection's depth test (this scene has no reprojected
// depth, see docs/integrating.md) and every same-surface test of this frame.
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var prev_depth: texture_2d<f32>;
// The scene: the radiance's mean and noise amplitude at each pixel.
@group(0) @binding(5) var radiance: texture_2d<f32>;
@group(0) @binding(6) var hist_in: texture_2d<f32>;
@group(0) @binding(7) var hist_out: texture_storage_2d<rgba16float, write>;
// The counts a step reads: the estimate's (route2_dilate), the final ones (sampling,
// update).
@group(0) @binding(8) var count_in: texture_2d<u32>;
// The counts a step writes: the estimate's (with a radius, into the texture the dilation
// reads; without, the final ones), the dilated ones.
@group(0) @binding(9) var count_out: texture_storage_2d<r32uint, write>;
// The estimate's decision for the update: 1 + the previous frame's texel index where the
// pixel continues a history (spvg_SOURCE_HISTORY), else 0.
@group(0) @binding(10) var link_in: texture_2d<u32>;
@group(0) @binding(11) var link_out: texture_storage_2d<r32uint, write>;
// The monitored value: the mean of the pixel's samples.
@group(0) @binding(12) var value_in: texture_2d<f32>;
@group(0) @binding(13) var value_out: texture_storage_2d<r32float, write>;

fn frame_size() -> vec2<u32> {
    return vec2<u32>(frame.width, frame.height);
}

fn in_frame(p: vec2<u32>) -> bool {
    return p.x < frame.width && p.y < frame.height;
}

// Whether the pixels `q` and `p` lie on one surface: the reprojection's depth test of
// q's depth against p's, both this frame's (the neighbour prior and the spatial moments).
fn same_surface(q: vec2<u32>, p: vec2<u32>) -> bool {
    return spvg_reproject_depth_agrees(textureLoad(depth, q, 0).x, textureLoad(depth, p, 0).x, frame.rule.depth_tolerance);
}

@compute @workgroup_size(8, 8, 1)
fn route2_estimate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.xy;
    if (!in_frame(p)) {
        return;
    }
    let size = frame_size();
    let v = textureLoad(motion, p, 0).xy;
    // The depth the reprojection compares: the reprojected depth where a renderer has it,
    // else this frame's.
    let d = textureLoad(depth, p, 0).x;
    var l = spvg_reproject_locate_start(frame.rule, p, v, size, size);
    while (l.source == spvg_SOURCE_PENDING) {
        // This renderer has no pass mask: every texel is covered.
        let previous = spvg_PreviousTexel(
            true,
            textureLoad(prev_depth, l.texel, 0).x,
            spvg_history_written(textureLoad(hist_in, l.texel, 0)),
        );
        l = spvg_reproject_locate(frame.rule, p, v, size, d, l, previous);
    }
    var h = vec4<f32>(0.0);
    if (l.source != spvg_SOURCE_DISOCCLUDED) {
        h = textureLoad(hist_in, l.texel, 0);
    }
    var n = spvg_estimate_texel(controller, h, 1.0);
    if (l.source == spvg_SOURCE_BORDER_PRIOR) {
        n = spvg_reproject_entering_count(frame.rule, n, controller.max_samples);
    }
    // Only a disoccluded pixel is marked: one entering under the border prior has a count
    // from the border texel's history and dilates like a pixel with history.
    if (frame.dilation != 0u && l.source == spvg_SOURCE_DISOCCLUDED) {
        n = n | spvg_DILATION_KEEP;
    }
    var link = 0u;
    if (l.source == spvg_SOURCE_HISTORY) {
        link = 1u + l.texel.y * frame.width + l.texel.x;
    }
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
    textureStore(link_out, p, vec4<u32>(link, 0u, 0u, 0u));
}

// The neighbour prior (a marked pixel takes the mean count of its same-surface
// neighbours with history within max(radius, spvg_DILATION_PRIOR_RADIUS)) and the count
// dilation (any other pixel with a count the largest within the radius), in one fold.
@compute @workgroup_size(8, 8, 1)
fn route2_dilate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.xy;
    if (!in_frame(p)) {
        return;
    }
    let own = textureLoad(count_in, p, 0).x;
    var m = spvg_dilation_prior_window(own, p, frame_size(), frame.dilation);
    for (var y = m.lo.y; y <= m.hi.y; y++) {
        for (var x = m.lo.x; x <= m.hi.x; x++) {
            let q = vec2<u32>(x, y);
            m = spvg_dilation_prior_take(m, own, textureLoad(count_in, q, 0).x, same_surface(q, p));
        }
    }
    textureStore(count_out, p, vec4<u32>(spvg_dilation_prior_count(m, own), 0u, 0u, 0u));
}

// A uniform number in [0, 1) from a pixel, a frame and a sample index.
fn noise(p: vec2<u32>, t: u32, i: u32) -> f32 {
    var h = p.x * 0x9e3779b1u ^ p.y * 0x85ebca77u ^ t * 0xc2b2ae3du ^ i * 0x27d4eb2fu;
    h = (h ^ (h >> 15u)) * 0x2c1b3c6du;
    h = (h ^ (h >> 12u)) * 0x297a2d39u;
    h = h ^ (h >> 15u);
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// The renderer's sampling: `count` samples of a noisy radiance, averaged.
@compute @workgroup_size(8, 8, 1)
fn route2_sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.xy;
    if (!in_frame(p)) {
        return;
    }
    let n = textureLoad(count_in, p, 0).x;
    let r = textureLoad(radiance, p, 0).xy;
    var sum = 0.0;
    for (var i = 0u; i < n; i++) {
        sum += r.x + r.y * (noise(p, frame.frame, i) - 0.5);
    }
    let value = select(0.0, sum / f32(n), n != 0u);
    textureStore(value_out, p, vec4<f32>(value, 0.0, 0.0, 0.0));
}

// The spatial moments of pixel `p` with the monitored value `centre`: the pixels of its
// spatial window (its 3x3 neighbours clipped to its 8 x 8 tile and the frame), itself
// included, row-major, that took samples this frame and lie on its surface. Gathered only for a history that is young after this frame: the update
// uses the moments for no other, so skipping the gather changes nothing and saves the
// reads on steady pixels.
fn spatial_moments(p: vec2<u32>, h: vec4<f32>, centre: f32) -> spvg_SpatialMoments {
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    var next = 1u;
    if (spvg_history_written(h)) {
        next = min(spvg_read_age(h.w) + 1u, spvg_AGE_CAP);
    }
    if (next > (controller.young & spvg_YOUNG_SPATIAL_MASK)) {
        return m;
    }
    let w = spvg_spatial_window(p, frame_size());
    for (var y = w.lo.y; y <= w.hi.y; y++) {
        for (var x = w.lo.x; x <= w.hi.x; x++) {
            let q = vec2<u32>(x, y);
            if (textureLoad(count_in, q, 0).x != 0u && same_surface(q, p)) {
                m = spvg_spatial_push(m, centre, textureLoad(value_in, q, 0).x);
            }
        }
    }
    return m;
}

@compute @workgroup_size(8, 8, 1)
fn route2_update(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.xy;
    if (!in_frame(p)) {
        return;
    }
    let n = textureLoad(count_in, p, 0).x;
    if (n == 0u) {
        textureStore(hist_out, p, vec4<f32>(0.0));
        return;
    }
    // The history the estimate decided to continue; zeros (a seed) for a disocclusion
    // and for a pixel that entered under the border prior.
    let link = textureLoad(link_in, p, 0).x;
    var h = vec4<f32>(0.0);
    if (link != 0u) {
        let k = link - 1u;
        h = textureLoad(hist_in, vec2<u32>(k % frame.width, k / frame.width), 0);
    }
    let value = textureLoad(value_in, p, 0).x;
    let m = spatial_moments(p, h, value);
    textureStore(hist_out, p, spvg_update_young_texel(controller, h, value, n, m, 0u));
}
