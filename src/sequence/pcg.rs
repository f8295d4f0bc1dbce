//! The pcg3d16 hash (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020)
//! and the per-pixel, per-frame seed built on it.

/// The LCG multiplier of pcg3d16 (a 16-bit constant, so the hash needs only 32-bit
/// products).
pub const PCG3D16_MULTIPLIER: u32 = 12829;

/// The LCG increment of pcg3d16.
pub const PCG3D16_INCREMENT: u32 = 47989;

/// The pcg3d16 hash of three `u32` lanes; each output lane holds 16 random bits (the
/// upper 16 bits are 0).
///
/// The exact arithmetic, all `u32` with wrapping (modulo `2^32`) multiply and add, each
/// line using the values updated by the lines before it:
///
/// ```text
/// x = x * 12829 + 47989;  y = y * 12829 + 47989;  z = z * 12829 + 47989;
/// x += y * z;  y += z * x;  z += x * y;   // round 1
/// x += y * z;  y += z * x;  z += x * y;   // round 2, identical
/// x >>= 16;    y >>= 16;    z >>= 16;
/// ```
///
/// WGSL twin: `fn pcg3d16(v: vec3<u32>) -> vec3<u32>` with the same lines (WGSL `u32`
/// arithmetic wraps).
///
/// # Examples
///
/// ```
/// use spvg::sequence::pcg3d16;
/// let h = pcg3d16([1, 2, 3]);
/// assert!(h.iter().all(|&lane| lane < 1 << 16));
/// assert_ne!(h, pcg3d16([1, 2, 4]));
/// ```
#[inline]
#[must_use]
pub const fn pcg3d16(v: [u32; 3]) -> [u32; 3] {
    let [mut x, mut y, mut z] = v;
    x = x
        .wrapping_mul(PCG3D16_MULTIPLIER)
        .wrapping_add(PCG3D16_INCREMENT);
    y = y
        .wrapping_mul(PCG3D16_MULTIPLIER)
        .wrapping_add(PCG3D16_INCREMENT);
    z = z
        .wrapping_mul(PCG3D16_MULTIPLIER)
        .wrapping_add(PCG3D16_INCREMENT);
    // Two identical rounds; written out (not a loop) to mirror the WGSL line for line.
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    [x >> 16, y >> 16, z >> 16]
}

/// The seed of pixel `(px, py)` in frame `frame`: `pcg3d16([px, py, frame])` (docs/algorithms.md §6).
///
/// Three lanes of 16 bits; [`r2_offset_from_seed`](super::r2_offset_from_seed) turns the
/// first two into the R2 offset, the third is free for the caller.
///
/// # Examples
///
/// ```
/// use spvg::sequence::{pcg3d16, pixel_seed};
/// assert_eq!(pixel_seed(3, 4, 5), pcg3d16([3, 4, 5]));
/// assert_ne!(pixel_seed(3, 4, 5), pixel_seed(3, 4, 6));
/// ```
#[inline]
#[must_use]
pub const fn pixel_seed(px: u32, py: u32, frame: u32) -> [u32; 3] {
    pcg3d16([px, py, frame])
}
