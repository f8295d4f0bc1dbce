// spvg::reproject: the history of a pixel under motion (docs/algorithms.md §2.3a).
// Depends on float.wgsl (spvg_is_finite).
// Rust twins: `spvg::reproject::{previous_texel, border_texel, footprint_texel,
// Reprojection::depth_agrees}`, same operation order (only correctly rounded add, subtract,
// multiply and floor, so the GPU and the core agree bit for bit).
//
// Motion-vector convention: `v` is this frame's position minus the previous frame's, in
// pixels, +x right, +y down (texel rows). The centre of pixel p was at (p + 0.5) - v, and
// its history is the texel containing that point (nearest texel, never filtered).

// The previous frame's texel holding the history of `pixel`; `.z` is 1 when it lies inside
// a `size` frame (NaN or infinite motion never does), 0 otherwise (then `.xy` is 0).
fn spvg_reproject_texel(pixel: vec2<u32>, v: vec2<f32>, size: vec2<u32>) -> vec3<u32> {
    let q = floor((vec2<f32>(pixel) + 0.5) - v);
    // Written so that NaN fails the comparisons.
    let inside = q.x >= 0.0 && q.y >= 0.0 && q.x < f32(size.x) && q.y < f32(size.y);
    if (!inside) {
        return vec3<u32>(0u);
    }
    return vec3<u32>(u32(q.x), u32(q.y), 1u);
}

// One axis of spvg_reproject_border_texel: the floor position `q` where it lies inside
// [0, n); past an edge, ceil(|v|) texels in from that edge (at most n - 1). The inset and
// the clamp are in u32, so that no rounding of n - 1 in f32 names a texel past the last.
// `q` is finite and within the motion bound, so `v` is finite.
fn spvg_reproject_border_axis(q: f32, v: f32, n: u32) -> u32 {
    let last = n - 1u;
    let a = ceil(abs(v));
    // f32(u32::MAX) is 2^32: below it the conversion is exact.
    var inset = 0xffffffffu;
    if (a < 4294967296.0) {
        inset = u32(a);
    }
    inset = min(inset, last);
    if (q < 0.0) {
        return inset;
    }
    if (q >= f32(n)) {
        return last - inset;
    }
    return min(u32(q), last);
}

// Whether the floor position `q` lies within the motion bound of an `n`-texel axis: at
// most n texels past either edge (q >= -n and q < 2n; NaN fails).
fn spvg_reproject_within_bound(q: f32, n: u32) -> bool {
    let nf = f32(n);
    return q >= -nf && q < nf + nf;
}

// The texel of a `size` frame whose history the border prior reads for `pixel` (where
// spvg_reproject_texel finds none): per axis the reprojected texel when inside, else the
// texel ceil(|v|) in from the edge it lies past (under steady motion the texels nearer the
// edge entered the previous frame themselves and hold only a seed). `.z` is 0 when the
// position is not finite, the frame is empty, or the position lies beyond the motion
// bound (more than the frame size past an edge: absurd motion is a disocclusion, not a
// pan).
fn spvg_reproject_border_texel(pixel: vec2<u32>, v: vec2<f32>, size: vec2<u32>) -> vec3<u32> {
    let q = floor((vec2<f32>(pixel) + 0.5) - v);
    if (!spvg_is_finite(q.x) || !spvg_is_finite(q.y) || size.x == 0u || size.y == 0u) {
        return vec3<u32>(0u);
    }
    if (!spvg_reproject_within_bound(q.x, size.x) || !spvg_reproject_within_bound(q.y, size.y)) {
        return vec3<u32>(0u);
    }
    return vec3<u32>(
        spvg_reproject_border_axis(q.x, v.x, size.x),
        spvg_reproject_border_axis(q.y, v.y, size.y),
        1u,
    );
}

// The relative depth test |d_prev - d| <= tol * d, with d positive and finite; NaN or
// infinite depths on either side fail, even where tol * d overflows.
fn spvg_reproject_depth_agrees(previous: f32, depth: f32, tolerance: f32) -> bool {
    return depth > 0.0 && spvg_is_finite(depth) && spvg_is_finite(previous)
        && abs(previous - depth) <= tolerance * depth;
}

// One axis of spvg_reproject_footprint_texel: the neighbour of texel `q` on the side the
// position `f` lies towards; `.y` is 0 at the texel's centre (fraction exactly 0.5) and
// outside [0, n).
fn spvg_reproject_footprint_axis(f: f32, q: u32, n: u32) -> vec2<u32> {
    let d = f - floor(f);
    if (d < 0.5) {
        if (q == 0u) {
            return vec2<u32>(0u);
        }
        return vec2<u32>(q - 1u, 1u);
    }
    if (d > 0.5 && q + 1u < n) {
        return vec2<u32>(q + 1u, 1u);
    }
    return vec2<u32>(0u);
}

// The `k`-th other texel (k = 1, 2, 3) of the 2x2 footprint around the previous position
// of `pixel`, which the footprint search tries when the texel containing it fails the mask
// or depth test: 1 the horizontal neighbour on the side the position lies towards, 2 the
// vertical one, 3 the diagonal one. `.z` is 0 where spvg_reproject_texel finds no texel,
// on an axis where the position is at the texel's centre, outside the frame, and for any
// other `k`.
fn spvg_reproject_footprint_texel(pixel: vec2<u32>, v: vec2<f32>, size: vec2<u32>, k: u32) -> vec3<u32> {
    let q = spvg_reproject_texel(pixel, v, size);
    if (q.z == 0u) {
        return vec3<u32>(0u);
    }
    let f = (vec2<f32>(pixel) + 0.5) - v;
    let x = spvg_reproject_footprint_axis(f.x, q.x, size.x);
    let y = spvg_reproject_footprint_axis(f.y, q.y, size.y);
    if (k == 1u && x.y != 0u) {
        return vec3<u32>(x.x, q.y, 1u);
    }
    if (k == 2u && y.y != 0u) {
        return vec3<u32>(q.x, y.x, 1u);
    }
    if (k == 3u && x.y != 0u && y.y != 0u) {
        return vec3<u32>(x.x, y.x, 1u);
    }
    return vec3<u32>(0u);
}

// ---- The whole decision: spvg::reproject::Reprojection::locate ----
//
// WGSL has no closures, so the search reads the previous frame through the caller, one
// texel at a time and only where the rule needs it (at most four texels, all inside the
// previous frame), as the core's `previous` callback does:
//
//   var l = spvg_reproject_locate_start(rule, pixel, v, size, previous_size);
//   while (l.source == spvg_SOURCE_PENDING) {
//       // read the previous frame's mask, depth and history texel at l.texel
//       l = spvg_reproject_locate(rule, pixel, v, previous_size, depth, l,
//                                 spvg_PreviousTexel(mask, prev_depth, spvg_history_written(h)));
//   }
//   // l.source: spvg_SOURCE_HISTORY or spvg_SOURCE_BORDER_PRIOR at l.texel, or
//   // spvg_SOURCE_DISOCCLUDED.

// spvg::reproject::Reprojection as plain values: the relative depth tolerance and the
// spvg_REPROJECT_* switches (u32 fields, so that it can live in a uniform block).
struct spvg_Reprojection {
    depth_tolerance: f32,
    flags: u32,
}

// The border prior (Reprojection::with_border_prior).
const spvg_REPROJECT_BORDER_PRIOR: u32 = 1u;
// The footprint search (Reprojection::with_footprint_search).
const spvg_REPROJECT_FOOTPRINT: u32 = 2u;
// Pixels entering under the border prior take beta_max (BorderCount::Maximum; without
// the bit, BorderCount::Texel).
const spvg_REPROJECT_BORDER_MAXIMUM: u32 = 4u;
// Reprojection::default(): 2% depth tolerance, every switch on.
const spvg_REPROJECT_DEFAULT_FLAGS: u32 = 7u;

// What the previous frame holds at a texel the search reads: its mask (the pass's
// coverage), its depth, and whether the previous frame wrote its history texel (the
// spare channel, spvg_history_written).
struct spvg_PreviousTexel {
    mask: bool,
    depth: f32,
    written: bool,
}

// spvg_Locate.source: no history (HistorySource::Disoccluded).
const spvg_SOURCE_DISOCCLUDED: u32 = 0u;
// A reprojected history at .texel: estimate from it and update it (HistorySource::History).
const spvg_SOURCE_HISTORY: u32 = 1u;
// The border prior at .texel: estimate from it, update as a disocclusion
// (HistorySource::BorderPrior).
const spvg_SOURCE_BORDER_PRIOR: u32 = 2u;
// Undecided: read the previous frame at .texel and call spvg_reproject_locate.
const spvg_SOURCE_PENDING: u32 = 3u;

// The state of the search: the outcome (or PENDING and the texel to read next) and which
// candidate .texel is (0 the texel containing the position, 1 to 3 the footprint
// texels, 4 the border texel).
struct spvg_Locate {
    source: u32,
    texel: vec2<u32>,
    candidate: u32,
}

// The first texel the rule reads for `pixel`: the texel containing its previous position
// (spvg_reproject_texel) or, where that lies outside the previous frame and the border
// prior is on, the border texel. DISOCCLUDED without any read when the frame was resized
// (`size` != `previous_size`), the motion is not finite or there is no such texel.
fn spvg_reproject_locate_start(rule: spvg_Reprojection, pixel: vec2<u32>, v: vec2<f32>, size: vec2<u32>, previous_size: vec2<u32>) -> spvg_Locate {
    let none = spvg_Locate(spvg_SOURCE_DISOCCLUDED, vec2<u32>(0u), 0u);
    if (any(size != previous_size)) {
        return none;
    }
    let q = spvg_reproject_texel(pixel, v, previous_size);
    if (q.z != 0u) {
        return spvg_Locate(spvg_SOURCE_PENDING, q.xy, 0u);
    }
    if ((rule.flags & spvg_REPROJECT_BORDER_PRIOR) != 0u) {
        let e = spvg_reproject_border_texel(pixel, v, previous_size);
        if (e.z != 0u) {
            return spvg_Locate(spvg_SOURCE_PENDING, e.xy, 4u);
        }
    }
    return none;
}

// One step of the search (Reprojection::locate, then the written check of the history
// store): `previous` is what the previous frame holds at `l.texel`, `depth` this pixel's
// depth. Where the texel passes the mask and depth tests (Reprojection::accepts) the
// search ends there: HISTORY (or BORDER_PRIOR for the border texel) when the previous
// frame wrote that texel, DISOCCLUDED when it did not (the search does not go on). Where
// it fails, the next footprint texel (the footprint search, after the texel containing
// the position only) is PENDING, else DISOCCLUDED. A decided `l` is returned unchanged.
fn spvg_reproject_locate(rule: spvg_Reprojection, pixel: vec2<u32>, v: vec2<f32>, previous_size: vec2<u32>, depth: f32, l: spvg_Locate, previous: spvg_PreviousTexel) -> spvg_Locate {
    if (l.source != spvg_SOURCE_PENDING) {
        return l;
    }
    let none = spvg_Locate(spvg_SOURCE_DISOCCLUDED, vec2<u32>(0u), l.candidate);
    if (previous.mask && spvg_reproject_depth_agrees(previous.depth, depth, rule.depth_tolerance)) {
        if (!previous.written) {
            return none;
        }
        let source = select(spvg_SOURCE_HISTORY, spvg_SOURCE_BORDER_PRIOR, l.candidate == 4u);
        return spvg_Locate(source, l.texel, l.candidate);
    }
    if (l.candidate < 3u && (rule.flags & spvg_REPROJECT_FOOTPRINT) != 0u) {
        for (var k = l.candidate + 1u; k <= 3u; k++) {
            let t = spvg_reproject_footprint_texel(pixel, v, previous_size, k);
            if (t.z != 0u) {
                return spvg_Locate(spvg_SOURCE_PENDING, t.xy, k);
            }
        }
    }
    return none;
}

// Reprojection::entering_count: the count of a pixel whose source is BORDER_PRIOR, from
// `estimate` (the controller's count from the border texel's history): `max_samples`
// under spvg_REPROJECT_BORDER_MAXIMUM unless `estimate` is 0 (the zero-sample rule),
// else `estimate`.
fn spvg_reproject_entering_count(rule: spvg_Reprojection, estimate: u32, max_samples: u32) -> u32 {
    if ((rule.flags & spvg_REPROJECT_BORDER_MAXIMUM) != 0u && estimate != 0u) {
        return max_samples;
    }
    return estimate;
}
