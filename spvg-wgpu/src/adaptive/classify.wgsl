// Count-classified dispatch (`AdaptiveSettings::classified_dispatch`): after the estimate
// (and the dilation), two passes sort the frame's 8 x 8 tiles into classes by their
// largest count and write, per class, a compacted tile list and the indirect dispatch
// arguments a consumer's sampling pass is recorded with
// (`AdaptivePass::dispatch_classified`), and per tile the order its pixels are taken in
// (by the class of their counts, so that a SIMD group of a tile runs similar counts).
// - adaptive_classify: one invocation per tile: the tile's largest count, its class, the
//   pixel order (stable, by the class of each count), and the count of the tile row's
//   tiles per class.
// - adaptive_class_scatter: one workgroup per tile row: each tile's slot in its class's
//   list, in row-major order (a prefix over the rows before and the tiles before in the
//   row: deterministic, no atomic decides a position), the lists' headers and the
//   dispatch arguments.
// Rust twin: `classify.rs` (`classify`, what `AdaptiveTwin::estimate` runs).
// `ADAPTIVE_CLASS_BOUNDS` and `ADAPTIVE_CLASSES` are prepended from the Rust constants.

// The lists: class c's region starts at word c * adaptive_class_stride(): a header
// (tile count, tiles per row, 0, 0) then the tiles, `x | y << 16` in tile units.
@group(0) @binding(32) var<storage, read_write> class_tile: array<u32>;
@group(0) @binding(33) var<storage, read_write> class_row_counts: array<atomic<u32>>;
@group(0) @binding(34) var<storage, read_write> class_order: array<u32>;
@group(0) @binding(35) var<storage, read> class_tile_in: array<u32>;
@group(0) @binding(36) var<storage, read> class_row_counts_in: array<u32>;
@group(0) @binding(37) var<storage, read_write> class_lists: array<u32>;
@group(0) @binding(38) var<storage, read_write> class_args: array<u32>;

// Most workgroups along one dispatch dimension (wgpu's default limit), as `tiles.rs`'s
// grid: a longer list runs on a 2-D grid.
const CLASS_MAX_GROUPS: u32 = 65535u;

fn class_tiles_x() -> u32 {
    return (spvg_ad_params.width + 7u) / 8u;
}

fn class_tiles_y() -> u32 {
    return (spvg_ad_params.height + 7u) / 8u;
}

// Words per class region: the header and room for every tile, rounded up to 64 words so
// that each region starts at a 256-byte offset (a storage binding's offset alignment).
fn adaptive_class_stride() -> u32 {
    return ((4u + class_tiles_x() * class_tiles_y() + 63u) / 64u) * 64u;
}

// The class of a tile whose largest count is `m`: the number of bounds below it.
fn adaptive_class_of(m: u32) -> u32 {
    var c = 0u;
    for (var k = 0u; k < ADAPTIVE_CLASSES - 1u; k++) {
        if (m > ADAPTIVE_CLASS_BOUNDS[k]) {
            c = k + 1u;
        }
    }
    return c;
}

// One invocation per tile, 64 tiles of a tile row per workgroup: no workgroup memory
// and no barrier (a barrier per tile cost more than the sort on a software rasterizer),
// each invocation reading its tile's 64 counts. The pixel order is a counting sort by the
// class of each pixel's count (the tiles' bins): stable, so ties keep the pixel order,
// and the lanes of a SIMD group run counts within one bin of each other.
@compute @workgroup_size(64, 1, 1)
fn adaptive_classify(@builtin(global_invocation_id) gid: vec3<u32>) {
    let tiles_x = class_tiles_x();
    if (gid.x >= tiles_x || gid.y >= class_tiles_y()) {
        return;
    }
    // Per pixel the class of its count, 4 bits each; per class its pixels; the largest count.
    var keys: array<u32, 8>;
    var per_class: array<u32, ADAPTIVE_CLASSES>;
    var m = 0u;
    for (var k = 0u; k < 64u; k++) {
        let p = gid.xy * 8u + vec2<u32>(k % 8u, k / 8u);
        // A pixel outside the frame (a partial tile) counts 0.
        var n = 0u;
        if (p.x < spvg_ad_params.width && p.y < spvg_ad_params.height) {
            n = textureLoad(spvg_ad_count_in, vec2<i32>(p), 0).x;
        }
        m = max(m, n);
        let c = adaptive_class_of(n);
        keys[k / 8u] |= c << (4u * (k % 8u));
        per_class[c] += 1u;
    }
    // Each class's first slot, then the pixels in pixel order into their class's slots.
    var next: array<u32, ADAPTIVE_CLASSES>;
    var first = 0u;
    for (var c = 0u; c < ADAPTIVE_CLASSES; c++) {
        next[c] = first;
        first += per_class[c];
    }
    var order: array<u32, 16>;
    for (var k = 0u; k < 64u; k++) {
        let c = (keys[k / 8u] >> (4u * (k % 8u))) & 15u;
        let slot = next[c];
        next[c] = slot + 1u;
        order[slot / 4u] |= k << (8u * (slot % 4u));
    }
    let tile = gid.y * tiles_x + gid.x;
    for (var w = 0u; w < 16u; w++) {
        class_order[tile * 16u + w] = order[w];
    }
    let c = adaptive_class_of(m);
    class_tile[tile] = c;
    atomicAdd(&class_row_counts[gid.y * ADAPTIVE_CLASSES + c], 1u);
}

var<workgroup> scatter_base: array<atomic<u32>, ADAPTIVE_CLASSES>;
var<workgroup> scatter_next: array<u32, ADAPTIVE_CLASSES>;
var<workgroup> scatter_chunk: array<u32, 64>;

@compute @workgroup_size(64, 1, 1)
fn adaptive_class_scatter(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let row = wg.x;
    let tiles_x = class_tiles_x();
    let stride = adaptive_class_stride();
    // The tiles of each class in the rows above, summed over the workgroup (a sum is the
    // same in any order).
    for (var r = li; r < row; r += 64u) {
        for (var c = 0u; c < ADAPTIVE_CLASSES; c++) {
            let k = class_row_counts_in[r * ADAPTIVE_CLASSES + c];
            if (k != 0u) {
                atomicAdd(&scatter_base[c], k);
            }
        }
    }
    workgroupBarrier();
    if (li < ADAPTIVE_CLASSES) {
        scatter_next[li] = atomicLoad(&scatter_base[li]);
    }
    workgroupBarrier();
    // The row in chunks of 64 tiles: a tile's slot is the next free one of its class plus
    // the tiles of its class before it in the chunk.
    for (var x0 = 0u; x0 < tiles_x; x0 += 64u) {
        let x = x0 + li;
        var c = ADAPTIVE_CLASSES;
        if (x < tiles_x) {
            c = class_tile_in[row * tiles_x + x];
        }
        scatter_chunk[li] = c;
        workgroupBarrier();
        if (c < ADAPTIVE_CLASSES) {
            var before = 0u;
            for (var j = 0u; j < li; j++) {
                if (scatter_chunk[j] == c) {
                    before += 1u;
                }
            }
            class_lists[c * stride + 4u + scatter_next[c] + before] = x | (row << 16u);
        }
        workgroupBarrier();
        if (li < ADAPTIVE_CLASSES) {
            var k = 0u;
            for (var j = 0u; j < 64u; j++) {
                if (scatter_chunk[j] == li) {
                    k += 1u;
                }
            }
            scatter_next[li] += k;
        }
        workgroupBarrier();
    }
    // The last row knows every total: the headers and the dispatch arguments.
    if (row + 1u == class_tiles_y() && li < ADAPTIVE_CLASSES) {
        let total = scatter_next[li];
        let h = li * stride;
        class_lists[h] = total;
        class_lists[h + 1u] = tiles_x;
        class_lists[h + 2u] = 0u;
        class_lists[h + 3u] = 0u;
        var groups = vec2<u32>(total, 1u);
        if (total > CLASS_MAX_GROUPS) {
            groups = vec2<u32>(CLASS_MAX_GROUPS, (total + CLASS_MAX_GROUPS - 1u) / CLASS_MAX_GROUPS);
        }
        class_args[3u * li] = groups.x;
        class_args[3u * li + 1u] = groups.y;
        class_args[3u * li + 2u] = 1u;
    }
}
