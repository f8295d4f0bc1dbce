// The demand reduction of the frame budget governor (docs/algorithms.md §8.2): run right
// after a frame's update pass over the history the next frame reads and the counts the
// frame used, it writes one partial sum per 8x8 workgroup; the host sums the partials in
// f64 and feeds `spvg::budget::Governor::{observe, plan}` before the next frame.
// CPU twin: `spvg_wgpu::twin::reduce_demand` (same per-pixel terms, same tree order).
// Every per-pixel rule is the WGSL library's: `spvg_decode_history`, `spvg_frame_demand`
// (twin `spvg::budget::FrameDemand::pixel`), `spvg_saturate`; the distant ratio is the
// pass's `pixel_gamma_s` (shared/estimator.wgsl); this file keeps the bindings and the
// order of the sums.

@group(0) @binding(0) var<uniform> params: PassParams;
// Named by shared/estimator.wgsl; this entry point does not read it (not bound).
@group(0) @binding(1) var lighting: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<u32>;
@group(0) @binding(4) var count_in: texture_2d<u32>;
@group(0) @binding(5) var hist_in: texture_2d<f32>;
@group(0) @binding(6) var<storage, read_write> partials: array<DemandPartial>;

// Rust twin: `spvg_wgpu::DemandPartial` (16 bytes, same field order).
struct DemandPartial {
    scaled: f32,
    offset: f32,
    fixed: f32,
    count: u32,
}

var<workgroup> demand_sums: array<vec3<f32>, 64>;
var<workgroup> count_sums: array<u32, 64>;

// FrameDemand's `+`: each field saturates at the largest finite f32.
fn add_demand(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(spvg_saturate(a.x + b.x), spvg_saturate(a.y + b.y), spvg_saturate(a.z + b.z));
}

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
    var d = vec3<f32>(0.0);
    var n = 0u;
    if (gid.x < params.width && gid.y < params.height) {
        let p = vec2<i32>(gid.xy);
        n = textureLoad(count_in, p, 0).x;
        // A pixel outside the mask takes no samples next frame (static camera: the
        // component reprojects each pixel onto its own texel).
        if (textureLoad(mask, p, 0).x != 0u) {
            let h = textureLoad(hist_in, p, 0);
            let t = spvg_frame_demand(params.spvg, spvg_decode_history(params.spvg, h), pixel_gamma_s(p), h.w >= 0.5);
            d = vec3<f32>(t.scaled, t.offset, t.fixed);
        }
    }
    demand_sums[li] = d;
    count_sums[li] = n;
    // Tree over the 64 invocations: at stride s, slot i < s adds slot i + s.
    for (var s = 32u; s > 0u; s = s >> 1u) {
        workgroupBarrier();
        if (li < s) {
            demand_sums[li] = add_demand(demand_sums[li], demand_sums[li + s]);
            count_sums[li] = add_count(count_sums[li], count_sums[li + s]);
        }
    }
    if (li == 0u) {
        let t = demand_sums[0];
        partials[wid.y * groups.x + wid.x] = DemandPartial(t.x, t.y, t.z, count_sums[0]);
    }
}
