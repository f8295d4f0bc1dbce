// The consumer's side of the count-classified dispatch (`AdaptivePass::dispatch_classified`,
// `AdaptivePass::CLASSIFIED_WGSL`): a sampling pass recorded once per class of tiles
// decodes the pixel of each invocation here. Group 1 is the component's: binding 0 the
// class's list (its header, then its tiles, `x | y << 16` in tile units), binding 1 the
// pixel order of every tile (16 words per tile, row-major over the frame's tiles, byte k
// the index in the tile of the pixel taken k-th). The grid is 2-D when a class holds more
// tiles than a dispatch dimension allows; the workgroups past its end get z = 1.

struct AdaptiveClassList {
    // Tiles in the list.
    count: u32,
    // Tiles per row of the frame (the order's row length).
    tiles_x: u32,
    pad0: u32,
    pad1: u32,
    tiles: array<u32>,
}

@group(1) @binding(0) var<storage, read> adaptive_class_list: AdaptiveClassList;
@group(1) @binding(1) var<storage, read> adaptive_class_order: array<u32>;

// The pixel that invocation `index` (`local_invocation_index` of an 8 x 8 workgroup) of
// workgroup `wg` on the grid `groups` samples, in z = 0; z = 1 past the list's end. The
// pixels of a tile are taken in the order of their counts' classes, so the invocations of one
// SIMD group run similar counts; each pixel is taken exactly once. A pixel of a partial
// tile may lie outside the frame: check it as an 8 x 8 dispatch does.
fn adaptive_class_pixel(wg: vec3<u32>, groups: vec3<u32>, index: u32) -> vec3<u32> {
    let k = wg.y * groups.x + wg.x;
    if (k >= adaptive_class_list.count) {
        return vec3<u32>(0u, 0u, 1u);
    }
    let t = adaptive_class_list.tiles[k];
    let tx = t & 0xffffu;
    let ty = t >> 16u;
    let word = adaptive_class_order[(ty * adaptive_class_list.tiles_x + tx) * 16u + index / 4u];
    let o = (word >> (8u * (index % 4u))) & 63u;
    return vec3<u32>(tx * 8u + o % 8u, ty * 8u + o / 8u, 0u);
}
