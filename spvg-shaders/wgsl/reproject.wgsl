// spvg::reproject: the history of a pixel under motion (docs/algorithms.md §2.3a).
// Depends on float.wgsl (spvg_is_finite).
// Rust twins: `spvg::reproject::{previous_texel, border_texel,
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

// One axis of spvg_reproject_border_texel: the floor position clamped into [0, n - 1].
fn spvg_reproject_border_axis(q: f32, n: u32) -> u32 {
    if (q < 0.0) {
        return 0u;
    }
    if (q >= f32(n)) {
        return n - 1u;
    }
    return u32(q);
}

// The texel of a `size` frame nearest to the reprojected position of `pixel` (the border
// prior's texel where spvg_reproject_texel finds none): the floor position clamped into
// the frame per axis. `.z` is 0 when the position is not finite or the frame is empty.
fn spvg_reproject_border_texel(pixel: vec2<u32>, v: vec2<f32>, size: vec2<u32>) -> vec3<u32> {
    let q = floor((vec2<f32>(pixel) + 0.5) - v);
    if (!spvg_is_finite(q.x) || !spvg_is_finite(q.y) || size.x == 0u || size.y == 0u) {
        return vec3<u32>(0u);
    }
    return vec3<u32>(
        spvg_reproject_border_axis(q.x, size.x),
        spvg_reproject_border_axis(q.y, size.y),
        1u,
    );
}

// The relative depth test |d_prev - d| <= tol * d, with d positive and finite; NaN or
// infinite depths fail.
fn spvg_reproject_depth_agrees(previous: f32, depth: f32, tolerance: f32) -> bool {
    return depth > 0.0 && spvg_is_finite(depth)
        && abs(previous - depth) <= tolerance * depth;
}
