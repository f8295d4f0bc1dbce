// The one-pass form of the component (`spvg_wgpu::adaptive::AdaptivePass::one_pass_wgsl`):
// the estimate and the update inside the renderer's own compute dispatch, as the seeds ran
// them. The renderer's entry point is `@workgroup_size(8, 8, 1)`, dispatched over the
// frame's 8 x 8 tiles (`spvg_wgpu::util::dispatch_8x8`), and calls, at its top level (in
// uniform control flow: every invocation, those outside the frame included, since both
// functions hold a workgroup barrier):
//
//   let s = spvg_one_pass_begin(gid, lid);     // s.count: this pixel's samples
//   ... take s.count samples at s.pixel (none where s.count is 0) ...
//   spvg_one_pass_end(s, value, control);       // the new history
//
// with `value` the monitored value (`fbar`) and `control` the control value `G` (CCV and
// OCV; any value for AS); `spvg_one_pass_end_guided` also takes the renderer's TAA guide,
// and `spvg_one_pass_end_moment` the guide and the samples' second moment.
// Nothing goes to memory between the two calls: the count, the link, the real count and
// the continued H texel stay in the returned value, the neighbourhoods in workgroup
// memory. With the count order (AdaptivePass::set_one_pass_order, on by default) an
// invocation takes the pixel of its tile whose rank of count is its own index: take the
// pixel from the returned `.pixel`, never from the invocation's id. The counts go to the
// component's count texture only where the renderer asks
// (`AdaptivePass::set_one_pass_counts`).
//
// Workgroup memory holds, over the tile grown by a halo (spvg_ad_halo: the dilation
// radius r, or max(r, 4) where the neighbour prior acts), each pixel's estimated count
// and this frame's depth: the halo's estimates are recomputed here (one history read
// each), so the count dilation and the neighbour prior read their neighbours from
// workgroup memory. The spatial moments' window stops at the tile
// (spvg::controller::young::spatial_window): both forms of the component and the twin
// clip it the same way, so the one-pass and two-pass forms give the same counts and
// histories, bit for bit.
// Rust twin: `spvg_wgpu::adaptive::AdaptiveTwin` (`estimate` then `update`).

// The largest tile and halo a workgroup holds: (8 + 2 spvg::dilation::MAX_RADIUS)^2.
const spvg_AD_HALO_TEXELS: u32 = 576u;
const spvg_AD_TILE_TEXELS: u32 = 64u;

// Over the tile and its halo (row-major, side 8 + 2r): the estimate's count (marked
// spvg_DILATION_KEEP where the pixel has no history), and this frame's depth where the
// neighbourhood rules need it; 0 outside the frame.
var<workgroup> spvg_ad_tile_count: array<u32, spvg_AD_HALO_TEXELS>;
var<workgroup> spvg_ad_tile_depth: array<f32, spvg_AD_HALO_TEXELS>;
// Over the tile (row-major, side 8): this frame's count, value and control.
var<workgroup> spvg_ad_tile_sampled: array<u32, spvg_AD_TILE_TEXELS>;
var<workgroup> spvg_ad_tile_value: array<f32, spvg_AD_TILE_TEXELS>;
var<workgroup> spvg_ad_tile_control: array<f32, spvg_AD_TILE_TEXELS>;
// The count order (spvg_AD_FLAG_COUNT_ORDER): by rank, the tile index of the pixel the
// invocation of that index takes, and that pixel's link, real count and H texel.
var<workgroup> spvg_ad_order_local: array<u32, spvg_AD_TILE_TEXELS>;
var<workgroup> spvg_ad_order_link: array<u32, spvg_AD_TILE_TEXELS>;
var<workgroup> spvg_ad_order_real: array<f32, spvg_AD_TILE_TEXELS>;
var<workgroup> spvg_ad_order_history: array<vec4<f32>, spvg_AD_TILE_TEXELS>;

// One pixel's decision, from spvg_one_pass_begin to spvg_one_pass_end.
struct spvg_OnePass {
    // The pixel of this invocation.
    pixel: vec2<u32>,
    // Its samples this frame: 0 outside the frame, outside the mask, under the
    // zero-sample rule and where a fractional count skips the frame.
    count: u32,
    // Whether the pixel lies in the frame (a partial tile at the frame's edge has
    // invocations outside it).
    inside: bool,
    // The rest is the component's: the pixel's index in the tile, its link (1 + the
    // previous texel's index, 0 without history), its real count (-1: the integer rule)
    // and the H texel it continues.
    local: u32,
    link: u32,
    real: f32,
    history: vec4<f32>,
}

// The halo the workgroup holds around its tile: the dilation radius, or the neighbour
// prior's max(radius, spvg_DILATION_PRIOR_RADIUS) where the prior acts (its window is
// whole, as in the two-pass form), 0 without a dilation.
fn spvg_ad_halo() -> u32 {
    let r = spvg_ad_params.dilation;
    if (r != 0u && (spvg_ad_params.flags & spvg_AD_FLAG_NEIGHBOUR_PRIOR) != 0u) {
        return max(r, spvg_DILATION_PRIOR_RADIUS);
    }
    return r;
}

// The index in the tile-and-halo arrays of frame pixel `q` of the tile at `origin`.
fn spvg_ad_halo_index(q: vec2<u32>, origin: vec2<u32>) -> u32 {
    let r = spvg_ad_halo();
    let o = q + vec2<u32>(r) - origin;
    return o.y * (spvg_TILE + 2u * r) + o.x;
}

// Position `j` of the halo ring (in the tile-and-halo grid of side 8 + 2r, from its low
// corner): the r rows above, the r rows below, then the r columns left and right of the
// tile's 8 rows.
fn spvg_ad_ring(j: u32, r: u32) -> vec2<u32> {
    let side = spvg_TILE + 2u * r;
    let band = r * side;
    if (j < band) {
        return vec2<u32>(j % side, j / side);
    }
    if (j < 2u * band) {
        let k = j - band;
        return vec2<u32>(k % side, r + spvg_TILE + k / side);
    }
    let k = j - 2u * band;
    if (k < spvg_TILE * r) {
        return vec2<u32>(k % r, r + k / r);
    }
    let m = k - spvg_TILE * r;
    return vec2<u32>(r + spvg_TILE + m % r, r + m / r);
}

// This frame's depth at pixel `q` where the neighbourhood rules need it, else 0.
fn spvg_ad_kept_depth(q: vec2<u32>) -> f32 {
    if (spvg_ad_keeps_depth()) {
        return textureLoad(spvg_ad_depth, vec2<i32>(q), 0).x;
    }
    return 0.0;
}

// The count of the pixel at `st` after the count dilation (and the neighbour prior), from
// the estimates of its tile and halo; its own estimate `own` without a dilation radius.
fn spvg_ad_dilated(st: spvg_OnePass, own: u32, origin: vec2<u32>) -> u32 {
    let radius = spvg_ad_params.dilation;
    if (radius == 0u) {
        return own;
    }
    let size = spvg_ad_size();
    if ((spvg_ad_params.flags & spvg_AD_FLAG_NEIGHBOUR_PRIOR) != 0u) {
        var m = spvg_dilation_prior_window(own, st.pixel, size, radius);
        let d = spvg_ad_tile_depth[spvg_ad_halo_index(st.pixel, origin)];
        for (var y = m.lo.y; y <= m.hi.y; y++) {
            for (var x = m.lo.x; x <= m.hi.x; x++) {
                let k = spvg_ad_halo_index(vec2<u32>(x, y), origin);
                let same = spvg_reproject_depth_agrees(spvg_ad_tile_depth[k], d, spvg_ad_params.depth_tolerance);
                m = spvg_dilation_prior_take(m, own, spvg_ad_tile_count[k], same);
            }
        }
        return spvg_dilation_prior_count(m, own);
    }
    var m = spvg_dilation_window(own, st.pixel, size, radius);
    for (var y = m.lo.y; y <= m.hi.y; y++) {
        for (var x = m.lo.x; x <= m.hi.x; x++) {
            m.count = spvg_dilation_take(m.count, spvg_ad_tile_count[spvg_ad_halo_index(vec2<u32>(x, y), origin)]);
        }
    }
    return m.count;
}

// The decision of the invocation at global id `gid` and local id `lid` of an 8 x 8
// workgroup: its pixel's estimate (reprojection, validity, count), the estimates of the
// tile's halo shared out among the workgroup, a barrier, then the dilated count. Call it
// in uniform control flow, from every invocation of the workgroup.
fn spvg_one_pass_begin(gid: vec3<u32>, lid: vec3<u32>) -> spvg_OnePass {
    let origin = gid.xy - lid.xy;
    var st = spvg_OnePass(gid.xy, 0u, spvg_ad_in_frame(gid.xy), lid.y * spvg_TILE + lid.x, 0u, -1.0, vec4<f32>(0.0));
    var own = 0u;
    var depth = 0.0;
    if (st.inside) {
        let e = spvg_ad_estimate_pixel(gid.xy);
        own = e.count;
        st.link = e.link;
        st.real = e.real;
        st.history = e.history;
        depth = spvg_ad_kept_depth(gid.xy);
    }
    let at = spvg_ad_halo_index(gid.xy, origin);
    spvg_ad_tile_count[at] = own;
    spvg_ad_tile_depth[at] = depth;
    // The halo ring, shared out: 4 r (8 + r) estimates over the 64 invocations.
    let r = spvg_ad_halo();
    let ring = 4u * r * (spvg_TILE + r);
    let rounds = (ring + spvg_AD_TILE_TEXELS - 1u) / spvg_AD_TILE_TEXELS;
    for (var k = 0u; k < rounds; k++) {
        let j = st.local + k * spvg_AD_TILE_TEXELS;
        if (j < ring) {
            let o = spvg_ad_ring(j, r);
            var n = 0u;
            var d = 0.0;
            // The ring's texel in the frame: origin + o - r, where that is not negative.
            if (origin.x + o.x >= r && origin.y + o.y >= r) {
                let q = origin + o - vec2<u32>(r);
                if (spvg_ad_in_frame(q)) {
                    n = spvg_ad_estimate_pixel(q).count;
                    d = spvg_ad_kept_depth(q);
                }
            }
            let i = o.y * (spvg_TILE + 2u * r) + o.x;
            spvg_ad_tile_count[i] = n;
            spvg_ad_tile_depth[i] = d;
        }
    }
    workgroupBarrier();
    if (st.inside) {
        st.count = spvg_ad_dilated(st, own, origin);
        if ((spvg_ad_params.flags & spvg_AD_FLAG_STORE_COUNTS) != 0u) {
            textureStore(spvg_ad_count_out, vec2<i32>(gid.xy), vec4<u32>(st.count, 0u, 0u, 0u));
        }
    }
    if ((spvg_ad_params.flags & spvg_AD_FLAG_COUNT_ORDER) != 0u) {
        st = spvg_ad_count_order(st, origin);
    }
    return st;
}

// The count order: the invocations of the tile take its pixels by rank of their counts
// (ties in pixel order), so that the invocations a SIMD group runs together, consecutive
// in their local index, take similar counts, and the group's sampling loop runs about as
// long as its pixels need rather than as long as the largest count among them. The
// decision travels with the pixel (its state moves through workgroup memory), so the
// counts, the samples of each pixel and the histories are those without the order; the
// renderer takes its pixel from `s.pixel`, never from its own invocation id.
fn spvg_ad_count_order(st: spvg_OnePass, origin: vec2<u32>) -> spvg_OnePass {
    spvg_ad_tile_sampled[st.local] = st.count;
    workgroupBarrier();
    var rank = 0u;
    for (var k = 0u; k < spvg_AD_TILE_TEXELS; k++) {
        let c = spvg_ad_tile_sampled[k];
        if (c < st.count || (c == st.count && k < st.local)) {
            rank += 1u;
        }
    }
    spvg_ad_order_local[rank] = st.local;
    spvg_ad_order_link[rank] = st.link;
    spvg_ad_order_real[rank] = st.real;
    spvg_ad_order_history[rank] = st.history;
    workgroupBarrier();
    // This invocation's index is its pixel's before the order (st.local).
    let me = st.local;
    let l = spvg_ad_order_local[me];
    let pixel = origin + vec2<u32>(l % spvg_TILE, l / spvg_TILE);
    return spvg_OnePass(
        pixel,
        spvg_ad_tile_sampled[l],
        spvg_ad_in_frame(pixel),
        l,
        spvg_ad_order_link[me],
        spvg_ad_order_real[me],
        spvg_ad_order_history[me],
    );
}

// The spatial moments of the pixel at `st` (its spatial window: 3x3 clipped to the tile)
// with the monitored value `centre` and coefficient `alpha`, from this frame's counts,
// values and controls of the tile: the twin of adaptive.wgsl's `adaptive_spatial_moments`.
fn spvg_ad_tile_moments(st: spvg_OnePass, centre: f32, alpha: f32) -> spvg_SpatialMoments {
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    let origin = st.pixel - vec2<u32>(st.local % spvg_TILE, st.local / spvg_TILE);
    let d = spvg_ad_tile_depth[spvg_ad_halo_index(st.pixel, origin)];
    let w = spvg_spatial_window(st.pixel, spvg_ad_size());
    for (var y = w.lo.y; y <= w.hi.y; y++) {
        for (var x = w.lo.x; x <= w.hi.x; x++) {
            let q = vec2<u32>(x, y);
            let k = (y - origin.y) * spvg_TILE + (x - origin.x);
            let same = spvg_reproject_depth_agrees(spvg_ad_tile_depth[spvg_ad_halo_index(q, origin)], d, spvg_ad_params.depth_tolerance);
            if (spvg_ad_tile_sampled[k] != 0u && same) {
                m = spvg_spatial_push(m, centre, spvg_ad_monitored(spvg_ad_tile_value[k], spvg_ad_tile_control[k], alpha));
            }
        }
    }
    return m;
}

// The update of the pixel at `st` with this frame's value `f` and control `g`: shares
// them with the tile, a barrier, then the new H texel (and J texel for OCV).
// `moment` is the mean of the squares of the samples whose mean is `f` where `has_moment`
// (docs/algorithms.md §8.8).
fn spvg_ad_finish(st: spvg_OnePass, f: f32, g: f32, guided: bool, guide: f32, has_moment: bool, moment: f32) {
    spvg_ad_tile_sampled[st.local] = st.count;
    spvg_ad_tile_value[st.local] = f;
    spvg_ad_tile_control[st.local] = g;
    workgroupBarrier();
    if (!st.inside) {
        return;
    }
    let j = spvg_ad_load_cv(st.link);
    var s = 0.0;
    var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    if (st.count != 0u) {
        let alpha = spvg_ad_alpha(j, st.link, f, g);
        s = spvg_ad_monitored(f, g, alpha);
        if (spvg_ad_young(st.history)) {
            m = spvg_ad_tile_moments(st, s, alpha);
        }
    }
    var frame_var = -1.0;
    if (has_moment && !spvg_ad_controlled()) {
        frame_var = spvg_per_sample_variance(s, moment, st.count);
    }
    let t = spvg_ad_update_texels(st.count, st.link, st.real, st.history, j, f, g, s, m, guided, guide, frame_var);
    let p = vec2<i32>(st.pixel);
    textureStore(spvg_ad_hist_out, p, t.h);
    if (spvg_AD_OCV) {
        spvg_ad_store_cv(p, t.j);
    }
}

// The end of the pixel's frame: its monitored value `value` (fbar) and control value
// `control` (G, for CCV and OCV; any value for AS) update its history. Call it in uniform
// control flow, from every invocation of the workgroup, after spvg_one_pass_begin.
fn spvg_one_pass_end(st: spvg_OnePass, value: f32, control: f32) {
    spvg_ad_finish(st, value, control, false, 0.0, false, 0.0);
}

// spvg_one_pass_end with the renderer's TAA guide `guide` (its resolved history C_t at the
// pixel, in the monitored value's space): the variance follows value - guide
// (docs/algorithms.md §8.5); a non-finite guide gives the unguided update.
fn spvg_one_pass_end_guided(st: spvg_OnePass, value: f32, control: f32, guide: f32) {
    spvg_ad_finish(st, value, control, true, guide, false, 0.0);
}

// spvg_one_pass_end_guided with the frame's second moment `moment`, the mean of the squares
// of the samples whose mean is `value` (sum(x * x) / n beside sum(x) / n): where the pixel
// took at least 2 samples, the variance follows the in-frame variance of its mean instead
// of its deviation (docs/algorithms.md §8.8), so variance its samples cannot remove buys
// none. AS only (with CCV and OCV the monitored value is not the samples' mean, and the
// moment is ignored). A NaN guide is the unguided update; a NaN moment is
// spvg_one_pass_end_guided.
fn spvg_one_pass_end_moment(st: spvg_OnePass, value: f32, control: f32, guide: f32, moment: f32) {
    spvg_ad_finish(st, value, control, true, guide, true, moment);
}
