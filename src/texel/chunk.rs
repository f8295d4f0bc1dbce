//! Chunk loads and stores of texels for the frame functions: 64 texels widened to `f32`
//! and transposed to one array per channel, and back.

use half::f16;

use super::dispatch::Isa;
use super::rounding::{Rounding, channel_bits, stochastic_bits};

/// Width of the chunks that the frame functions process at once.
pub(crate) const CHUNK: usize = 64;

/// Scratch for one chunk of texels as interleaved `f32` channels. The frame functions own
/// one per texture and reuse it for every chunk: a fresh zeroed array per chunk cost 5-8%
/// of the f16 update (a 1 KiB memset per load and store). Its contents between calls are
/// stale and never read before being written (lanes past a partial chunk's end are
/// computed on but never stored).
pub(crate) type Wide = [[f32; 4]; CHUNK];

/// A channel storage type (`f16`, `f32`) whose texels the frame functions load and store
/// a chunk at a time, converting `f16` with the conversions of the loop's instruction set
/// ([`Isa`]).
#[allow(
    unreachable_pub,
    reason = "a sealed supertrait of the public `Element`: public so it may bound it, unnameable outside"
)]
pub trait Chunked: Sized {
    /// Widens the channels of up to `CHUNK` texels (`4 * CHUNK` values) to `f32` without
    /// sanitising, channel-major: `out[c][i]` is channel `c` of texel `i`.
    fn load_chunk<I: Isa>(isa: I, texels: &[Self], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]);

    /// Stores channel-major values already clamped to the type's finite range (not NaN);
    /// `f16` rounds them, pixel `i` of the chunk with the word `channel_bits(seed, first +
    /// i)` under `Rounding::Stochastic(seed)`.
    fn store_chunk<I: Isa>(
        isa: I,
        values: &[[f32; CHUNK]; 4],
        wide: &mut Wide,
        texels: &mut [Self],
        rounding: Rounding,
        first: u32,
    );
}

impl Chunked for f16 {
    /// Widened in place of a full chunk's texels (a copy to a padded array for the
    /// frame's last, partial chunk), then transposed.
    #[inline(always)]
    fn load_chunk<I: Isa>(isa: I, texels: &[f16], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]) {
        if let Ok(full) = <&[f16; 4 * CHUNK]>::try_from(texels) {
            isa.widen_deinterleave(bytemuck::cast_ref(full), wide, out);
        } else {
            let mut bits = [0_u16; 4 * CHUNK];
            for (d, s) in bits.iter_mut().zip(texels) {
                *d = s.to_bits();
            }
            isa.widen_deinterleave(bytemuck::cast_ref(&bits), wide, out);
        }
    }

    #[inline(always)]
    fn store_chunk<I: Isa>(
        isa: I,
        values: &[[f32; CHUNK]; 4],
        wide: &mut Wide,
        texels: &mut [f16],
        rounding: Rounding,
        first: u32,
    ) {
        match rounding {
            Rounding::Nearest => {
                if let Ok(full) = <&mut [f16; 4 * CHUNK]>::try_from(&mut *texels) {
                    isa.interleave_narrow(values, wide, bytemuck::cast_mut(full));
                } else {
                    let mut bits = [0_u16; 4 * CHUNK];
                    isa.interleave_narrow(values, wide, bytemuck::cast_mut(&mut bits));
                    for (d, s) in texels.iter_mut().zip(&bits) {
                        *d = f16::from_bits(*s);
                    }
                }
            }
            Rounding::Stochastic(seed) => {
                // Channel-major, every lane of the chunk (a fixed trip count that
                // vectorises: the hashes and `stochastic_bits` are branch-free integer
                // code), then interleaved into the texels that exist.
                let mut bits = [[0_u16; CHUNK]; 4];
                for i in 0..CHUNK {
                    let word = channel_bits(seed, first.wrapping_add(i as u32));
                    for (c, (b, v)) in bits.iter_mut().zip(values).enumerate() {
                        b[i] = stochastic_bits(v[i], channel_bits(word, c as u32));
                    }
                }
                for (i, dst) in texels.chunks_exact_mut(4).enumerate() {
                    for (d, b) in dst.iter_mut().zip(&bits) {
                        *d = f16::from_bits(b[i]);
                    }
                }
            }
        }
    }
}

impl Chunked for f32 {
    #[inline(always)]
    fn load_chunk<I: Isa>(isa: I, texels: &[f32], wide: &mut Wide, out: &mut [[f32; CHUNK]; 4]) {
        // A full chunk is transposed straight from the texels; only the frame's last,
        // partial chunk goes through a padded copy.
        if let Ok(full) = <&[f32; 4 * CHUNK]>::try_from(texels) {
            isa.deinterleave(bytemuck::cast_ref(full), out);
            return;
        }
        for (d, s) in wide.as_flattened_mut().iter_mut().zip(texels) {
            *d = *s;
        }
        isa.deinterleave(wide, out);
    }

    /// `f32` texels store the values exactly: the rounding mode does not apply.
    #[inline(always)]
    fn store_chunk<I: Isa>(
        isa: I,
        values: &[[f32; CHUNK]; 4],
        wide: &mut Wide,
        texels: &mut [f32],
        _rounding: Rounding,
        _first: u32,
    ) {
        if let Ok(full) = <&mut [f32; 4 * CHUNK]>::try_from(&mut *texels) {
            isa.interleave(values, bytemuck::cast_mut(full));
            return;
        }
        isa.interleave(values, wide);
        for (d, s) in texels.iter_mut().zip(wide.as_flattened()) {
            *d = *s;
        }
    }
}
