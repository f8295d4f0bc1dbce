// Separable subsurface scattering (docs/algorithms.md §5.1): the pre-integrated rank-1
// kernel of the separable profile fitted to the material's Burley profile, applied along x
// (sep_horizontal) then along y (sep_vertical). The kernel (offsets in mm, per-channel
// weights normalised to 1) is built on the host by `spvg::burley::SeparableProfile`; the
// passes only gather.
// - A tap sits `offset / (depth * w_px)` pixels from the centre (the kernel is in mm on the
//   surface, the texel `depth * w_px` mm wide), read with linear interpolation between the
//   two nearest texels; a texel off the image or off the material reads the centre's value
//   instead (the filter does not bleed across the silhouette). The taps ascend, so the
//   passes load each texel of a pixel's span once (the texel walk below), not two per tap.
// - In a hybrid frame (`hybrid = 1`, Fig. 5.9 of the dissertation) the pixels tagged AFIS
//   (`technique = 1`) hold the Monte Carlo result: sep_horizontal reads its taps there from
//   that result instead of the lighting, so the separable pixels next to an AFIS region see
//   light of the same brightness (no dark border); both passes pass the AFIS result through
//   unfiltered at the tagged pixels (an early out: the tagged area costs a copy).
//   The first pass's input is composed before it: sep_compose writes the AFIS result into
//   the lighting texture at the tagged pixels, over the tagged tiles only (the tile list of
//   the hybrid pass's first step), so the taps read one texture and no technique id (the
//   twin picks the source per tap: the same values). It also writes the first pass's
//   output there, and the second pass writes into the AFIS result's own texture (the
//   tagged pixels hold their final value already: P4 is free), so the hybrid frame runs
//   the passes (sep_horizontal_tiles, sep_vertical_tiles) only over the tiles that hold
//   an untagged pixel: a wholly tagged tile costs neither pass, not even the early out.
// CPU twins: `spvg_effects::sss::twin::{sep_horizontal, sep_vertical}`.
// Rust twin of the block: `spvg_effects::sss::SeparableParams` (same field order and types).

const SEP_MAX_SAMPLES: u32 = 33u;

// The flag of a listed tile of the separable passes that holds a tagged pixel too (the
// others read no technique id); the tile's coordinates are the low 15 bits of each half.
const SEP_TILE_MIXED: u32 = 0x8000u;

struct SeparableParams {
    width: u32,
    height: u32,
    samples: u32,
    hybrid: u32,
    w_px: f32,
    h_px: f32,
    reserved0: u32,
    reserved1: u32,
    // (offset mm, weight R, weight G, weight B) per tap.
    kernel: array<vec4<f32>, 33>,
}

@group(0) @binding(0) var<uniform> sep: SeparableParams;
@group(0) @binding(1) var lighting: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<u32>;
@group(0) @binding(4) var technique: texture_2d<u32>;
@group(0) @binding(5) var afis_in: texture_2d<f32>;
// sep_horizontal (and sep_compose)
@group(0) @binding(6) var blurred_out: texture_storage_2d<rgba32float, write>;
// sep_vertical (in a hybrid frame the output is the AFIS result's texture)
@group(0) @binding(7) var blurred_in: texture_2d<f32>;
@group(0) @binding(8) var result_out: texture_storage_2d<rgba16float, write>;
// sep_compose: the lighting texture it writes the AFIS result into (mip 0 of the
// subsurface pass's, which the hybrid frame's first pass then reads as `lighting`).
@group(0) @binding(9) var source_out: texture_storage_2d<rgba16float, write>;
// The tile list of the *_tiles entry points and sep_compose (`x | y << 16` per tile, as
// spvg_wgpu::adaptive::AdaptiveTiles lists them).
@group(1) @binding(0) var<storage, read> sep_tiles: array<u32>;

fn sep_tagged(q: vec2<i32>) -> bool {
    return sep.hybrid != 0u && textureLoad(technique, q, 0).x == 1u;
}

// The first pass's input at q: the AFIS result where tagged (composed into the lighting
// texture by sep_compose), else the lighting.
fn sep_source(q: vec2<i32>) -> vec3<f32> {
    return textureLoad(lighting, q, 0).xyz;
}

// Whether q is on the image and on the material.
fn sep_on_surface(q: vec2<i32>) -> bool {
    if (q.x < 0 || q.y < 0 || q.x >= i32(sep.width) || q.y >= i32(sep.height)) {
        return false;
    }
    return textureLoad(mask, q, 0).x != 0u;
}

// The two texels around tap `k` of pixel p along x (vertical = false) or y, and the
// linear interpolation weight of the second.
struct SepTap {
    q0: vec2<i32>,
    q1: vec2<i32>,
    t: f32,
}

fn sep_tap(p: vec2<i32>, vertical: bool, offset_mm: f32, inv_mm: f32) -> SepTap {
    // Continuous coordinate of the tap along the axis, texel centres at integers.
    var u = f32(p.x) + offset_mm * inv_mm;
    if (vertical) {
        u = f32(p.y) + offset_mm * inv_mm;
    }
    let u0 = floor(u);
    let i0 = i32(u0);
    var tap = SepTap(vec2<i32>(i0, p.y), vec2<i32>(i0 + 1, p.y), u - u0);
    if (vertical) {
        tap.q0 = vec2<i32>(p.x, i0);
        tap.q1 = vec2<i32>(p.x, i0 + 1);
    }
    return tap;
}

// 1 / (millimetres per texel) along the axis at p, or 0 where the depth gives no scale
// (then the filter keeps the centre).
fn sep_inv_mm(p: vec2<i32>, vertical: bool) -> f32 {
    let z = textureLoad(depth, p, 0).x;
    var mm = z * sep.w_px;
    if (vertical) {
        mm = z * sep.h_px;
    }
    if (!(mm > 0.0)) {
        return 0.0;
    }
    return 1.0 / mm;
}

// A pass's texel at q: its input `src` there (the first pass's: the lighting, with the AFIS
// result composed in at the tagged pixels; the second's: the first's output), or the
// centre's off the surface.
fn sep_texel(src: texture_2d<f32>, q: vec2<i32>, centre: vec3<f32>) -> vec3<f32> {
    if (!sep_on_surface(q)) {
        return centre;
    }
    return textureLoad(src, q, 0).xyz;
}

// Texel reuse. The host's kernels (SeparableProfile::fill_kernel) have ascending offsets,
// dense near the centre: at a texel about as wide as the kernel's millimetre, 17 taps fall
// between 5 or so texels, each read by several taps. So the filter walks the texels
// instead of loading two per tap: from the first tap's first texel to the last tap's
// second, one texel (mask and value) loaded per step, and at each step it adds the taps
// whose first texel is the step's, in kernel order. A tap sees the same two texel values
// as a load of its own would give (a texel's value depends only on its position and the
// pixel's centre, fixed per pixel) and the sum runs in the same order with the same
// operations: the result is the same to the bit, and the CPU twin stays the per-tap loop.
// The loads are not conditional per tap: reuse behind a branch per tap measured no faster
// on lavapipe (likely because its SIMD lanes run a divergent branch's body, loads
// included, under a mask); the walk's length is the texel span (the longest of a SIMD
// group's pixels).
// The walk applies when the span is at most SEP_WALK_SPAN_PER_TAP texels per tap (beyond
// that the per-tap loads are fewer); taps it leaves (offsets out of order, or a span the
// walk does not take) are added after it one by one with two loads each, in order, so
// every kernel gives the per-tap loop's result.
const SEP_WALK_SPAN_PER_TAP: i32 = 2;

// The texel `i` along the axis through p.
fn sep_axis_texel(p: vec2<i32>, vertical: bool, i: i32) -> vec2<i32> {
    if (vertical) {
        return vec2<i32>(p.x, i);
    }
    return vec2<i32>(i, p.y);
}

// A tap's first texel's coordinate along the axis (sep_tap's i0).
fn sep_tap_i0(tap: SepTap, vertical: bool) -> i32 {
    if (vertical) {
        return tap.q0.y;
    }
    return tap.q0.x;
}

// How many steps the texel walk takes over `n` taps (n > 0) from `first` to `last` (their
// first texels along the axis), or -1 where it does not apply (taps out of order at the
// ends, or a span longer than SEP_WALK_SPAN_PER_TAP per tap).
fn sep_walk_steps(first: i32, last: i32, n: u32) -> i32 {
    // Compared without subtracting (the difference of two far-apart i0 would wrap); where
    // `first + cap` wraps, the test refuses the walk, which is then merely not taken.
    if (last < first || last >= first + SEP_WALK_SPAN_PER_TAP * i32(n)) {
        return -1;
    }
    return last - first + 1;
}

// The kernel along the axis (x, or y where `vertical`) at p over the pass's input `src`;
// `centre` is p's own value in it. (The texture is an argument, not a flag: each pass
// binds only the texture it reads.)
fn sep_filter(src: texture_2d<f32>, p: vec2<i32>, vertical: bool, centre: vec3<f32>) -> vec3<f32> {
    let inv_mm = sep_inv_mm(p, vertical);
    if (inv_mm == 0.0) {
        return centre;
    }
    let n = min(sep.samples, SEP_MAX_SAMPLES);
    var sum = vec3<f32>(0.0);
    if (n == 0u) {
        return sum;
    }
    var i = 0u;
    // The walk, where sep_walk_steps takes it. `tap` is kernel[i]'s tap, computed once:
    // the walk tests it at each step until its first texel comes up.
    var tap = sep_tap(p, vertical, sep.kernel[0].x, inv_mm);
    let first = sep_tap_i0(tap, vertical);
    let last = sep_tap_i0(sep_tap(p, vertical, sep.kernel[n - 1u].x, inv_mm), vertical);
    let steps = sep_walk_steps(first, last, n);
    if (steps > 0) {
        // `b` holds the texel after `j` (the walk's current first texel).
        var j = first;
        var b = sep_texel(src, sep_axis_texel(p, vertical, j), centre);
        j -= 1;
        for (var s = 0; s < steps; s++) {
            j += 1;
            let a = b;
            b = sep_texel(src, sep_axis_texel(p, vertical, j + 1), centre);
            loop {
                if (i >= n || sep_tap_i0(tap, vertical) != j) {
                    break;
                }
                sum += sep.kernel[i].yzw * (a * (1.0 - tap.t) + b * tap.t);
                i += 1u;
                if (i < n) {
                    tap = sep_tap(p, vertical, sep.kernel[i].x, inv_mm);
                }
            }
        }
    }
    for (; i < n; i++) {
        let k = sep.kernel[i];
        let tap = sep_tap(p, vertical, k.x, inv_mm);
        let a = sep_texel(src, tap.q0, centre);
        let b = sep_texel(src, tap.q1, centre);
        sum += k.yzw * (a * (1.0 - tap.t) + b * tap.t);
    }
    return sum;
}

fn sep_result_texel(v: vec3<f32>) -> vec4<f32> {
    let r = spvg_ROUNDING_NEAREST;
    return vec4<f32>(spvg_to_f16(v.x, r, 0u), spvg_to_f16(v.y, r, 0u), spvg_to_f16(v.z, r, 0u), 1.0);
}

// sep_horizontal at p (on the image); `mixed`: p's tile may hold tagged pixels (false
// only for a listed tile the list marks as wholly untagged: no technique read then).
fn sep_horizontal_at(p: vec2<i32>, mixed: bool) {
    if (textureLoad(mask, p, 0).x == 0u) {
        textureStore(blurred_out, p, vec4<f32>(0.0));
        return;
    }
    let c = sep_source(p);
    if (mixed && sep_tagged(p)) {
        // The AFIS result passes through unfiltered: the second pass reads it as it is.
        textureStore(blurred_out, p, vec4<f32>(c, 0.0));
        return;
    }
    textureStore(blurred_out, p, vec4<f32>(sep_filter(lighting, p, false, c), 0.0));
}

// sep_vertical at p (on the image); `mixed` as for sep_horizontal_at.
fn sep_vertical_at(p: vec2<i32>, mixed: bool) {
    if (textureLoad(mask, p, 0).x == 0u) {
        textureStore(result_out, p, vec4<f32>(0.0));
        return;
    }
    if (mixed && sep_tagged(p)) {
        // The first pass wrote the AFIS result through (f16 values: exact in rgba32float).
        textureStore(result_out, p, sep_result_texel(textureLoad(blurred_in, p, 0).xyz));
        return;
    }
    let c = textureLoad(blurred_in, p, 0).xyz;
    textureStore(result_out, p, sep_result_texel(sep_filter(blurred_in, p, true, c)));
}

@compute @workgroup_size(8, 8, 1)
fn sep_horizontal(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= sep.width || gid.y >= sep.height) {
        return;
    }
    sep_horizontal_at(vec2<i32>(gid.xy), true);
}

@compute @workgroup_size(8, 8, 1)
fn sep_vertical(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= sep.width || gid.y >= sep.height) {
        return;
    }
    sep_vertical_at(vec2<i32>(gid.xy), true);
}

// The pixel of this invocation in the listed tile of its workgroup (the workgroups in
// rows; tile units, `x | y << 16`), at -1 past the list's end or the image's edge, and
// the tile's SEP_TILE_MIXED flag. One decoding serves both lists: sep_compose's (the
// component's, as its tiles.wgsl writes it, whose x never reaches bit 15: a tile x of
// 0x8000 would be a frame 262144 px wide) and the separable passes' (flag in bit 15).
struct SepListed {
    pixel: vec2<i32>,
    mixed: bool,
}

fn sep_listed(wg: vec3<u32>, groups: vec3<u32>, lid: vec3<u32>) -> SepListed {
    let k = wg.y * groups.x + wg.x;
    if (k >= arrayLength(&sep_tiles)) {
        return SepListed(vec2<i32>(-1), false);
    }
    let t = sep_tiles[k];
    let q = vec2<u32>((t & 0x7fffu) * 8u + lid.x, ((t >> 16u) & 0x7fffu) * 8u + lid.y);
    if (q.x >= sep.width || q.y >= sep.height) {
        return SepListed(vec2<i32>(-1), false);
    }
    return SepListed(vec2<i32>(q), (t & SEP_TILE_MIXED) != 0u);
}

// The hybrid frame's passes over the tiles that hold an untagged pixel (the list's
// workgroups in rows; SEP_TILE_MIXED on those holding a tagged pixel too). A tile whose
// pixels are all tagged needs neither: sep_compose has written the first pass's values
// there (the AFIS result, which the vertical taps of an untagged pixel reaching into the
// tile read), and result_out is then the AFIS result's texture, which holds the second's.
// (The bounds checks return at the top, as in the whole-frame entry points.)
@compute @workgroup_size(8, 8, 1)
fn sep_horizontal_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let l = sep_listed(wg, groups, lid);
    if (l.pixel.x < 0) {
        return;
    }
    sep_horizontal_at(l.pixel, l.mixed);
}

@compute @workgroup_size(8, 8, 1)
fn sep_vertical_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let l = sep_listed(wg, groups, lid);
    if (l.pixel.x < 0) {
        return;
    }
    sep_vertical_at(l.pixel, l.mixed);
}

// The AFIS result at the tagged pixels of the listed tiles (those holding a tagged
// pixel): into the first pass's input (its taps read it), and, as sep_horizontal would
// write it there, into the first pass's output (the vertical taps of an untagged pixel
// read it, also in a wholly tagged tile that the passes skip). The result needs nothing:
// in a hybrid frame sep_vertical writes into the AFIS result's own texture, which holds
// the AFIS result at the tagged pixels already.
@compute @workgroup_size(8, 8, 1)
fn sep_compose(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let p = sep_listed(wg, groups, lid).pixel;
    if (p.x < 0 || !sep_tagged(p)) {
        return;
    }
    let a = textureLoad(afis_in, p, 0);
    textureStore(source_out, p, a);
    // Read back only on the surface (the taps check the mask), so no mask test here.
    textureStore(blurred_out, p, vec4<f32>(a.xyz, 0.0));
}
