// spvg::sequence: pcg3d16 seeds, the fixed-point R2 sequence and the per-channel hash of
// stochastic rounding, all in u32 arithmetic so CPU and GPU agree bit for bit
// (docs/algorithms.md §6). Depends on nothing.
// Rust twins: `spvg::sequence::{pcg3d16, pixel_seed, r2_offset_from_seed, r2_point,
// to_unit_f32, dither_threshold}`, `spvg::texel::channel_bits`.

// spvg::sequence::R2_STEP: round(2^32 / phi2), round(2^32 / phi2^2).
const spvg_R2_STEP: vec2<u32> = vec2<u32>(3242174889u, 2447445414u);

// pcg3d16 (Jarzynski & Olano 2020): 16 random bits per lane.
fn spvg_pcg3d16(p: vec3<u32>) -> vec3<u32> {
    var v = p * 12829u + vec3<u32>(47989u);
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v >> vec3<u32>(16u);
}

// pixel_seed: pcg3d16 of (px, py, frame).
fn spvg_pixel_seed(px: u32, py: u32, frame: u32) -> vec3<u32> {
    return spvg_pcg3d16(vec3<u32>(px, py, frame));
}

// r2_offset_from_seed: the first two 16-bit lanes as the top halves of the offset.
fn spvg_r2_offset_from_seed(seed: vec3<u32>) -> vec2<u32> {
    return vec2<u32>(seed.x << 16u, seed.y << 16u);
}

// r2_point: point `index` of the sequence started at `offset` (wrapping).
fn spvg_r2_point(offset: vec2<u32>, index: u32) -> vec2<u32> {
    return offset + index * spvg_R2_STEP;
}

// to_unit_f32: the top 24 bits as a float in [0, 1), exact in f32, never 1.
fn spvg_to_unit_f32(u: u32) -> f32 {
    return f32(u >> 8u) * (1.0 / 16777216.0);
}

// dither_threshold: the threshold of dithered count rounding (docs/algorithms.md §8.6),
// the R2 lattice over the pixel grid rotated by the golden ratio per frame, in fixed
// point: px * R2_STEP.x + py * R2_STEP.y + frame * round(2^32 / phi) (wrapping).
fn spvg_dither_threshold(px: u32, py: u32, frame: u32) -> u32 {
    return px * spvg_R2_STEP.x + py * spvg_R2_STEP.y + frame * 0x9E3779B9u;
}

// channel_bits: the random word for channel `channel` of a stochastically rounded texel.
fn spvg_channel_bits(random: u32, channel: u32) -> u32 {
    var x = random + channel * 0x9e3779b9u;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    return x ^ (x >> 16u);
}
