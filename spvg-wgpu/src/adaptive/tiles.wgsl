// The component's steps restricted to a list of 8 x 8 tiles (`spvg_wgpu::adaptive::AdaptiveTiles`):
// one workgroup per listed tile, each invocation one pixel of it, running the same body as
// the whole-frame entry point (`adaptive_estimate_at`, `adaptive_update_at` of
// adaptive.wgsl), so a listed pixel gets exactly what the whole-frame dispatch gives it and
// an unlisted pixel is not touched.
// The list is group 1 (the steps' group 0 is unchanged): one u32 per tile, the tile's x in
// the low 16 bits and its y in the high 16. The grid is 2-D when the list is longer than a
// dispatch dimension allows; the workgroups past its end return.

@group(1) @binding(0) var<storage, read> adaptive_tiles: array<u32>;

// The pixel of invocation `lid` in the tile of workgroup `wg` (grid `groups`), or false
// past the list's end.
struct AdaptiveTilePixel {
    gid: vec3<u32>,
    listed: bool,
}

fn adaptive_tile_pixel(wg: vec3<u32>, groups: vec3<u32>, lid: vec3<u32>) -> AdaptiveTilePixel {
    let k = wg.y * groups.x + wg.x;
    if (k >= arrayLength(&adaptive_tiles)) {
        return AdaptiveTilePixel(vec3<u32>(0u), false);
    }
    let t = adaptive_tiles[k];
    let gid = vec3<u32>((t & 0xffffu) * 8u + lid.x, (t >> 16u) * 8u + lid.y, 0u);
    return AdaptiveTilePixel(gid, true);
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_estimate_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let t = adaptive_tile_pixel(wg, groups, lid);
    if (t.listed) {
        adaptive_estimate_at(t.gid);
    }
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let t = adaptive_tile_pixel(wg, groups, lid);
    if (t.listed) {
        adaptive_update_at(t.gid);
    }
}
