// spvg::dilation: count dilation, each pixel spends the largest count of its
// neighbourhood (docs/algorithms.md §2.5). Depends on nothing.
// Rust twins: `spvg::dilation::{KEEP, dilated_count, dilated_count_with_prior, TILE,
// tile_region}` and `spvg::controller::young::spatial_window`, the same windows and the
// same rules.
//
// The counts are the caller's (a texture or buffer of the estimate's counts), so the
// window is folded by the caller, one count at a time:
//
//   var d = spvg_dilation_window(own, pixel, size, radius);
//   for (var y = d.lo.y; y <= d.hi.y; y++) {
//       for (var x = d.lo.x; x <= d.hi.x; x++) {
//           d.count = spvg_dilation_take(d.count, counts_at(x, y));
//       }
//   }
//   // d.count is dilated_count(counts, size, pixel, radius)

// Marks a count as one the pixel keeps (a pixel without history, disoccluded: it takes
// its first-observation count, not its neighbours'); cleared in the output, ignored in a
// neighbour's window (spvg::dilation::KEEP).
const spvg_DILATION_KEEP: u32 = 0x80000000u;

// The window of a pixel and the count folded so far.
struct spvg_Dilation {
    count: u32,
    lo: vec2<u32>,
    hi: vec2<u32>,
}

// The start of dilated_count for the pixel whose own (estimate) count is `own`: where
// `own` is 0 or marked spvg_DILATION_KEEP, the count is `own` without the mark and the
// window is empty (lo > hi); a pixel outside the `size` frame has count 0 and an empty
// window; otherwise the window of `radius` around `pixel` clipped to the frame, inclusive
// bounds, with count 0.
fn spvg_dilation_window(own: u32, pixel: vec2<u32>, size: vec2<u32>, radius: u32) -> spvg_Dilation {
    let empty = vec2<u32>(1u, 1u);
    if (pixel.x >= size.x || pixel.y >= size.y) {
        return spvg_Dilation(0u, empty, vec2<u32>(0u));
    }
    if (own == 0u || (own & spvg_DILATION_KEEP) != 0u) {
        return spvg_Dilation(own & ~spvg_DILATION_KEEP, empty, vec2<u32>(0u));
    }
    // saturating_sub and min(saturating_add, size - 1), without overflow.
    let lo = pixel - min(pixel, vec2<u32>(radius));
    let hi = pixel + min(vec2<u32>(radius), size - 1u - pixel);
    return spvg_Dilation(0u, lo, hi);
}

// One count of the window folded in: the maximum, the neighbour's mark cleared.
fn spvg_dilation_take(count: u32, neighbour: u32) -> u32 {
    return max(count, neighbour & ~spvg_DILATION_KEEP);
}

// ---- the depth-aware neighbour prior (spvg::dilation::dilated_count_with_prior) ----
// A pixel without history (marked spvg_DILATION_KEEP) takes the mean, rounded (halves
// up), of the counts of the pixels that have history (not marked, not 0) on its surface
// within max(radius, spvg_DILATION_PRIOR_RADIUS), at least its own count; the others
// dilate as above. Folded the same way, then finished:
//
//   var d = spvg_dilation_prior_window(own, pixel, size, radius);
//   for (var y = d.lo.y; y <= d.hi.y; y++) {
//       for (var x = d.lo.x; x <= d.hi.x; x++) {
//           d = spvg_dilation_prior_take(d, own, counts_at(x, y), same_surface(x, y));
//       }
//   }
//   let count = spvg_dilation_prior_count(d, own);
//
// The sum is a u32: equal to the core for windows whose counts sum below 2^32 (every
// count below 2^23 in the largest window; the budget's maximum is at most 1024).

// The prior's window radius at least (spvg::dilation::PRIOR_RADIUS).
const spvg_DILATION_PRIOR_RADIUS: u32 = 4u;

// The window of a pixel, the maximum folded so far (a pixel with history) or the sum and
// number of the same-surface counts with history (a pixel without).
struct spvg_DilationPrior {
    count: u32,
    sum: u32,
    n: u32,
    lo: vec2<u32>,
    hi: vec2<u32>,
}

// spvg_dilation_window, except that a pixel marked spvg_DILATION_KEEP gets the window of
// max(radius, spvg_DILATION_PRIOR_RADIUS) around it and its own count (the mark cleared).
fn spvg_dilation_prior_window(own: u32, pixel: vec2<u32>, size: vec2<u32>, radius: u32) -> spvg_DilationPrior {
    if ((own & spvg_DILATION_KEEP) == 0u || pixel.x >= size.x || pixel.y >= size.y) {
        let d = spvg_dilation_window(own, pixel, size, radius);
        return spvg_DilationPrior(d.count, 0u, 0u, d.lo, d.hi);
    }
    let r = max(radius, spvg_DILATION_PRIOR_RADIUS);
    let lo = pixel - min(pixel, vec2<u32>(r));
    let hi = pixel + min(vec2<u32>(r), size - 1u - pixel);
    return spvg_DilationPrior(own & ~spvg_DILATION_KEEP, 0u, 0u, lo, hi);
}

// One count of the window folded in: for a pixel whose own count `own` is marked, the
// neighbour's count where it has history (not marked, not 0) and `same_surface`;
// otherwise spvg_dilation_take.
fn spvg_dilation_prior_take(d: spvg_DilationPrior, own: u32, neighbour: u32, same_surface: bool) -> spvg_DilationPrior {
    var out = d;
    if ((own & spvg_DILATION_KEEP) == 0u) {
        out.count = spvg_dilation_take(d.count, neighbour);
    } else if ((neighbour & spvg_DILATION_KEEP) == 0u && neighbour != 0u && same_surface) {
        out.sum = d.sum + neighbour;
        out.n = d.n + 1u;
    }
    return out;
}

// The count after the fold: the rounded mean, at least the pixel's own count, for a
// marked pixel with same-surface neighbours; its own count for one without; the dilated
// count for any other.
fn spvg_dilation_prior_count(d: spvg_DilationPrior, own: u32) -> u32 {
    if ((own & spvg_DILATION_KEEP) == 0u || d.n == 0u) {
        return d.count;
    }
    return max((d.sum + d.n / 2u) / d.n, d.count);
}

// ---- the tile of a one-pass dispatch (spvg::dilation::{TILE, tile_region}) ----
// A workgroup of spvg_TILE x spvg_TILE invocations holds its tile (and the estimates of a
// halo around it) in workgroup memory: the spatial moments' window (spvg_spatial_window)
// stops at the tile; the dilation and the prior above read a halo of their radius, which
// the workgroup recomputes.

// The side of a one-pass dispatch's tile (spvg::dilation::TILE): @workgroup_size(8, 8).
const spvg_TILE: u32 = 8u;

// A rectangle of texels, both corners inclusive.
struct spvg_Region {
    lo: vec2<u32>,
    hi: vec2<u32>,
}

// The tile holding `pixel`, grown by `halo` on every side, clipped to the `size` frame
// (spvg::dilation::tile_region): saturating arithmetic as the core's.
fn spvg_tile_region(pixel: vec2<u32>, size: vec2<u32>, halo: u32) -> spvg_Region {
    let t = pixel / spvg_TILE * spvg_TILE;
    let lo = t - min(t, vec2<u32>(halo));
    let far = t + vec2<u32>(spvg_TILE - 1u);
    let grown = far + min(vec2<u32>(halo), vec2<u32>(0xffffffffu) - far);
    return spvg_Region(lo, min(grown, size - min(size, vec2<u32>(1u))));
}

// The window of the spatial moments of `pixel` (spvg::controller::young::spatial_window):
// its 3x3 neighbourhood clipped to its tile and the frame.
fn spvg_spatial_window(pixel: vec2<u32>, size: vec2<u32>) -> spvg_Region {
    let t = spvg_tile_region(pixel, size, 0u);
    let lo = max(pixel - min(pixel, vec2<u32>(1u)), t.lo);
    let hi = min(pixel + min(vec2<u32>(1u), vec2<u32>(0xffffffffu) - pixel), t.hi);
    return spvg_Region(lo, hi);
}
