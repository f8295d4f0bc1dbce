// History reprojection along motion vectors (docs/algorithms.md §2.3a): no globals, no
// bindings, every name prefixed `spvg_reproject_`, so a host shader can include it as is.
// Rust twin: `spvg::reproject::{previous_texel, Reprojection::depth_agrees}`, same
// operation order (only correctly rounded add, subtract, multiply and floor, so the GPU and
// the core agree bit for bit).
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

// Exponent all ones means inf or NaN; tested on the bits so no fast-math can fold it.
fn spvg_reproject_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// The relative depth test |d_prev - d| <= tol * d, with d positive and finite; NaN or
// infinite depths fail.
fn spvg_reproject_depth_agrees(previous: f32, depth: f32, tolerance: f32) -> bool {
    return depth > 0.0 && spvg_reproject_is_finite(depth)
        && abs(previous - depth) <= tolerance * depth;
}
