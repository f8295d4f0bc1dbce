//! Chunk loads and stores of texels for the frame functions: 64 texels widened to `f32`
//! and transposed to one array per channel, and back.

use half::f16;

use super::rounding::{Rounding, channel_bits, stochastic_bits};

/// Width of the chunks that the frame functions process at once.
pub(crate) const CHUNK: usize = 64;

/// Scratch for one chunk of texels as interleaved `f32` channels. The frame functions own
/// one per texture and reuse it for every chunk: a fresh zeroed array per chunk cost 5-8%
/// of the f16 update (a 1 KiB memset per load and store). Its contents between calls are
/// stale and never read before being written (lanes past a partial chunk's end are
/// computed on but never stored).
pub(crate) type Wide = [f32; 4 * CHUNK];

#[cfg(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
))]
pub(super) fn load_chunk16(texels: &[f16], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]) {
    let n = texels.len().min(4 * CHUNK);
    if let (Some(dst), Some(src)) = (wide.get_mut(..n), texels.get(..n)) {
        super::rounding::widen_slice(src, dst);
    }
    deinterleave(wide, out);
}

/// Without F16C: widen and transpose in one pass with the branch-free conversion.
#[cfg(not(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
)))]
#[allow(
    clippy::needless_range_loop,
    reason = "fixed-size transposes vectorise as written"
)]
#[cfg_attr(
    not(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))),
    allow(unused_variables, reason = "the scratch serves the run-time F16C path")
)]
pub(super) fn load_chunk16(texels: &[f16], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]) {
    #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
    if runtime_f16c() {
        let n = texels.len().min(4 * CHUNK);
        if let (Some(dst), Some(src)) = (wide.get_mut(..n), texels.get(..n)) {
            half::slice::HalfFloatSliceExt::convert_to_f32_slice(src, dst);
        }
        deinterleave(wide, out);
        return;
    }
    let mut bits = [0_u16; 4 * CHUNK];
    for (d, s) in bits.iter_mut().zip(texels) {
        *d = s.to_bits();
    }
    for i in 0..CHUNK {
        for c in 0..4 {
            out[c][i] = super::rounding::widen_bits(bits[4 * i + c]);
        }
    }
}

/// Round-to-nearest store of a chunk: narrow and transpose in one pass without F16C.
#[cfg(not(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
)))]
#[allow(
    clippy::needless_range_loop,
    reason = "fixed-size transposes vectorise as written"
)]
#[cfg_attr(
    not(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64"))),
    allow(unused_variables, reason = "the scratch serves the run-time F16C path")
)]
fn store_nearest16(values: &[[f32; CHUNK]; 4], wide: &mut Wide, texels: &mut [f16]) {
    #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
    if runtime_f16c() {
        let n = texels.len().min(4 * CHUNK);
        interleave(values, wide);
        if let (Some(dst), Some(src)) = (texels.get_mut(..n), wide.get(..n)) {
            half::slice::HalfFloatSliceExt::convert_from_f32_slice(dst, src);
        }
        return;
    }
    let mut bits = [0_u16; 4 * CHUNK];
    for i in 0..CHUNK {
        for c in 0..4 {
            bits[4 * i + c] = super::rounding::narrow_bits(values[c][i]);
        }
    }
    for (d, s) in texels.iter_mut().zip(&bits) {
        *d = f16::from_bits(*s);
    }
}

#[cfg(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
))]
fn store_nearest16(values: &[[f32; CHUNK]; 4], wide: &mut Wide, texels: &mut [f16]) {
    let n = texels.len().min(4 * CHUNK);
    interleave(values, wide);
    if let (Some(dst), Some(src)) = (texels.get_mut(..n), wide.get(..n)) {
        super::rounding::narrow_slice(src, dst);
    }
}

/// Whether the CPU has F16C, detected at run time (cached by `std`): then `half`'s slice
/// conversion uses it, several times faster than the branch-free SSE2 conversion.
#[cfg(all(
    feature = "std",
    any(target_arch = "x86", target_arch = "x86_64"),
    not(target_feature = "f16c")
))]
#[inline(always)]
fn runtime_f16c() -> bool {
    std::arch::is_x86_feature_detected!("f16c")
}

pub(super) fn load_chunk32(texels: &[f32], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]) {
    // A full chunk is transposed straight from the texels; only the frame's last,
    // partial chunk goes through a padded copy.
    if let Ok(full) = <&[f32; 4 * CHUNK]>::try_from(texels) {
        deinterleave(full, out);
        return;
    }
    for (d, s) in wide.iter_mut().zip(texels) {
        *d = *s;
    }
    deinterleave(wide, out);
}

// Fixed trip counts over arrays: every index is in bounds by construction, and the
// loops vectorise (lanes past the chunk's end carry stale values that are never stored).
// LLVM turns the stride-4 loops into wide loads and shuffles (interleaved access); a
// 4x4-block formulation was tried and came out as one scalar move per value.
#[allow(
    clippy::needless_range_loop,
    reason = "fixed-size transposes vectorise as written"
)]
#[inline(always)]
fn deinterleave(wide: &[f32; 4 * CHUNK], out: &mut [[f32; CHUNK]; 4]) {
    for i in 0..CHUNK {
        for c in 0..4 {
            out[c][i] = wide[4 * i + c];
        }
    }
}

#[allow(
    clippy::needless_range_loop,
    reason = "fixed-size transposes vectorise as written"
)]
#[inline(always)]
fn interleave(values: &[[f32; CHUNK]; 4], wide: &mut [f32; 4 * CHUNK]) {
    for i in 0..CHUNK {
        for c in 0..4 {
            wide[4 * i + c] = values[c][i];
        }
    }
}

pub(super) fn store_chunk32(values: &[[f32; CHUNK]; 4], wide: &mut Wide, texels: &mut [f32]) {
    if let Ok(full) = <&mut [f32; 4 * CHUNK]>::try_from(&mut *texels) {
        interleave(values, full);
        return;
    }
    interleave(values, wide);
    for (d, s) in texels.iter_mut().zip(wide.iter()) {
        *d = *s;
    }
}

pub(super) fn store_chunk16(
    values: &[[f32; CHUNK]; 4],
    wide: &mut Wide,
    texels: &mut [f16],
    rounding: Rounding,
    first: u32,
) {
    match rounding {
        Rounding::Nearest => store_nearest16(values, wide, texels),
        Rounding::Stochastic(seed) => {
            interleave(values, wide);
            for (i, (dst, src)) in texels
                .chunks_exact_mut(4)
                .zip(wide.chunks_exact(4))
                .enumerate()
            {
                let word = channel_bits(seed, first.wrapping_add(i as u32));
                for (c, (d, &v)) in dst.iter_mut().zip(src).enumerate() {
                    *d = f16::from_bits(stochastic_bits(v, channel_bits(word, c as u32)));
                }
            }
        }
    }
}
