// Route 2: a renderer's own single compute pass that runs the spvg rules itself, from the
// spvg-shaders library (prepended: spvg_shaders::WGSL). Per pixel, in this order:
//   1. locate the history: spvg_reproject_locate_start, then spvg_reproject_locate once
//      per texel it asks for (the previous frame's mask, depth and history texel there);
//   2. estimate the count: spvg_estimate_texel on the located texel (zeros where none);
//      under the border prior spvg_reproject_entering_count; with count dilation, mark a
//      pixel without history with spvg_DILATION_KEEP;
//   3. dilate (radius > 0): spvg_dilation_window / spvg_dilation_take over the window.
//      A single pass has no neighbour's count to read, so it recomputes steps 1 and 2 for
//      each pixel of the window (a renderer with a separate estimate pass reads them);
//   4. sample: the renderer's own Monte Carlo loop, `count` samples;
//   5. update: spvg_update_young_texel on the texel of a continued history (zeros for
//      the border prior and a disocclusion), stored with the history's age in the spare
//      channel (age >= 1 is the written mark); a pixel that took no samples stores zeros.
//      This pass passes no neighbourhood (empty spatial moments): with the spatial
//      variance of young histories on, a pass gathers its same-surface neighbours'
//      values after sampling, as the component's update does.
// The counts equal spvg_wgpu::adaptive::AdaptivePass's, pixel for pixel
// (spvg-wgpu/tests/route2.rs).

// The renderer's per-frame uniform block (Rust twin: `FrameUniforms` in mod.rs).
struct FrameUniforms {
    width: u32,
    height: u32,
    frame: u32,
    // Count dilation radius; 0 = off.
    dilation: u32,
    // The reprojection rule (spvg_Reprojection); last, as a struct member of a uniform
    // block is 16-byte aligned and followed by 16 bytes (the block is 32 bytes).
    rule: spvg_Reprojection,
}

@group(0) @binding(0) var<uniform> controller: spvg_Params;
@group(0) @binding(1) var<uniform> frame: FrameUniforms;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var prev_depth: texture_2d<f32>;
// The scene: the radiance's mean and noise amplitude at each pixel.
@group(0) @binding(5) var radiance: texture_2d<f32>;
@group(0) @binding(6) var hist_in: texture_2d<f32>;
@group(0) @binding(7) var hist_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var count_out: texture_storage_2d<r32uint, write>;
@group(0) @binding(9) var value_out: texture_storage_2d<r32float, write>;

// Steps 1 and 2 for pixel `p`: the count (marked for dilation where there is no history)
// and the history texel the update continues.
struct Estimate {
    count: u32,
    continued: vec4<f32>,
}

fn estimate(p: vec2<u32>) -> Estimate {
    let size = vec2<u32>(frame.width, frame.height);
    let v = textureLoad(motion, p, 0).xy;
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
    var e = Estimate(spvg_estimate_texel(controller, h, 1.0), vec4<f32>(0.0));
    if (l.source == spvg_SOURCE_HISTORY) {
        e.continued = h;
    }
    if (l.source == spvg_SOURCE_BORDER_PRIOR) {
        e.count = spvg_reproject_entering_count(frame.rule, e.count, controller.max_samples);
    }
    if (frame.dilation != 0u && l.source == spvg_SOURCE_DISOCCLUDED) {
        e.count = e.count | spvg_DILATION_KEEP;
    }
    return e;
}

// A uniform number in [0, 1) from a pixel, a frame and a sample index.
fn noise(p: vec2<u32>, t: u32, i: u32) -> f32 {
    var h = p.x * 0x9e3779b1u ^ p.y * 0x85ebca77u ^ t * 0xc2b2ae3du ^ i * 0x27d4eb2fu;
    h = (h ^ (h >> 15u)) * 0x2c1b3c6du;
    h = (h ^ (h >> 12u)) * 0x297a2d39u;
    h = h ^ (h >> 15u);
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

@compute @workgroup_size(8, 8, 1)
fn route2(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.xy;
    if (p.x >= frame.width || p.y >= frame.height) {
        return;
    }
    let own = estimate(p);
    var n = own.count;
    if (frame.dilation != 0u) {
        let size = vec2<u32>(frame.width, frame.height);
        var w = spvg_dilation_window(own.count, p, size, frame.dilation);
        for (var y = w.lo.y; y <= w.hi.y; y++) {
            for (var x = w.lo.x; x <= w.hi.x; x++) {
                var c = own.count;
                if (x != p.x || y != p.y) {
                    c = estimate(vec2<u32>(x, y)).count;
                }
                w.count = spvg_dilation_take(w.count, c);
            }
        }
        n = w.count;
    }
    // The renderer's sampling: n samples of a noisy radiance, averaged.
    let r = textureLoad(radiance, p, 0).xy;
    var sum = 0.0;
    for (var i = 0u; i < n; i++) {
        sum += r.x + r.y * (noise(p, frame.frame, i) - 0.5);
    }
    let value = select(0.0, sum / f32(n), n != 0u);
    var h = vec4<f32>(0.0);
    if (n != 0u) {
        let no_neighbours = spvg_SpatialMoments(0u, 0.0, 0.0);
        h = spvg_update_young_texel(controller, own.continued, value, n, no_neighbours, 0u);
    }
    textureStore(hist_out, p, h);
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
    textureStore(value_out, p, vec4<f32>(value, 0.0, 0.0, 0.0));
}
