// The demand reduction of the frame budget governor (docs/algorithms.md §8.2): run right
// after a frame's update pass over the history the next frame reads and the counts the
// frame used, it writes one partial per 8x8 workgroup: the frame's count and, at each of
// the 16 candidate targets, the counts the next frame's pixels would take there (the
// clamped demand curve); the host sums the partials and feeds
// `spvg::budget::Governor::{observe, plan_curve}` before the next frame.
// CPU twin: `spvg_effects::sss::twin::reduce_demand` (same per-pixel terms, same tree order).
// Every per-pixel rule is the WGSL library's: `spvg_decode_history`, `spvg_count_at`
// (twin `spvg::budget::count_at`); the distant ratio is the
// pass's `pixel_gamma_s` (estimator.wgsl); this file keeps the bindings and the
// order of the sums.

@group(0) @binding(0) var<uniform> params: PassParams;
// Named by estimator.wgsl; this entry point does not read it (not bound).
@group(0) @binding(1) var lighting: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<u32>;
@group(0) @binding(4) var count_in: texture_2d<u32>;
@group(0) @binding(5) var hist_in: texture_2d<f32>;
@group(0) @binding(6) var<storage, read_write> partials: array<DemandPartial>;
// The candidate targets of the demand curve, four per vec4 (uniform arrays need a 16-byte
// stride). Rust twin: the `[f32; CURVE_POINTS]` that `ReducePass::encode` writes.
@group(0) @binding(7) var<uniform> candidates: array<vec4<f32>, 4>;

// spvg::budget::CURVE_POINTS.
const CURVE_POINTS: u32 = 16u;

// Rust twin: `spvg_wgpu::DemandPartial` (68 bytes, same field order).
struct DemandPartial {
    curve: array<u32, 16>,
    count: u32,
}

// Per invocation: the curve's counts (slots 0..15) and the frame's count (slot 16).
var<workgroup> sums: array<array<u32, 17>, 64>;

fn add_count(a: u32, b: u32) -> u32 {
    let s = a + b;
    return select(s, 0xffffffffu, s < a);
}

@compute @workgroup_size(8, 8, 1)
fn reduce_demand(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    var terms: array<u32, 17>;
    if (gid.x < params.width && gid.y < params.height) {
        let p = vec2<i32>(gid.xy);
        terms[CURVE_POINTS] = textureLoad(count_in, p, 0).x;
        // A pixel outside the mask takes no samples next frame (static camera: the
        // component reprojects each pixel onto its own texel).
        if (textureLoad(mask, p, 0).x != 0u) {
            let h = textureLoad(hist_in, p, 0);
            let hist = spvg_decode_history(params.spvg, h);
            let gamma = pixel_gamma_s(p);
            for (var j = 0u; j < CURVE_POINTS; j++) {
                terms[j] = spvg_count_at(params.spvg, candidates[j / 4u][j % 4u], hist, gamma, h.w >= 0.5);
            }
        }
    }
    sums[li] = terms;
    // Tree over the 64 invocations: at stride s, slot i < s adds slot i + s.
    for (var s = 32u; s > 0u; s = s >> 1u) {
        workgroupBarrier();
        if (li < s) {
            for (var k = 0u; k <= CURVE_POINTS; k++) {
                sums[li][k] = add_count(sums[li][k], sums[li + s][k]);
            }
        }
    }
    if (li == 0u) {
        var out: DemandPartial;
        for (var k = 0u; k < CURVE_POINTS; k++) {
            out.curve[k] = sums[0][k];
        }
        out.count = sums[0][CURVE_POINTS];
        partials[wid.y * groups.x + wid.x] = out;
    }
}
