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
