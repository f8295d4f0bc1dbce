//! Run-time CPU dispatch of the frame loops (`std` builds on x86-64), and the chunk
//! primitives each variant runs.
//!
//! The portable build (x86-64 baseline, SSE2) compiles the frame loops three times: as
//! they are, inside a function marked `#[target_feature(enable = "avx2,fma,f16c")]`
//! (x86-64-v3; the inlined lane code vectorises 8 wide), and inside one marked
//! `#[target_feature(enable = "avx512f,avx512bw,avx512vl,avx2,fma,f16c")]` (x86-64-v4's
//! AVX-512 subsets the loops can use). The first frame call picks the highest variant
//! the CPU has ([`LoopVariant`], [`selected_loop_variant`]; `is_x86_feature_detected!`,
//! cached by `std`) and every call after takes it. The variants compute the same IEEE
//! operations in the same order (Rust never fuses a multiply and an add into an FMA on
//! its own, in any of them), so their results are bit-identical; `tests/texel_batch.rs`
//! ties the dispatched loop to the per-pixel controller and this module's tests tie
//! every variant the CPU has to the others and to [`Portable`].
//!
//! The loops are generic over [`Isa`], the chunk primitives (`f16 <-> f32` conversion
//! and the texel transposes). The AVX2 and AVX-512 variants are both handed an [`Avx2`]
//! token, whose primitives are F16C and AVX instructions inlined into the loop (8 values
//! per instruction): calling a library's conversion from there is a call per chunk into
//! code compiled for the baseline, which cost a quarter of the f16 frame update.
//! [`BASELINE`], the loop as compiled, uses the same instructions where F16C is
//! compiled in, and otherwise [`Portable`]'s branch-free code.
//!
//! # The AVX-512 variant: width pending measurement
//!
//! The AVX-512 variant is the AVX2 variant's loop compiled with AVX-512 F/BW/VL enabled,
//! nothing written for it by hand. LLVM widens part of the lane code to 16 lanes in
//! 512-bit registers (the x86-64 baseline's tuning, which the portable build's functions
//! keep, prefers 512-bit vectors once AVX-512 is enabled, so part of the variant's
//! instructions are on `zmm` registers; BENCHMARKS.md gives the share), and the 256-bit code it keeps
//! gains AVX-512VL's 32 vector registers and mask registers. The primitives stay 8-wide
//! F16C/AVX (`Avx2`): 16-wide conversions (`vcvtph2ps zmm`) and transposes could pay
//! only if 16-wide lanes pay, which BENCHMARKS.md reports where it was measured. LLVM's tuning for Intel's AVX-512 server parts (what `-C target-cpu=native`
//! gets there) prefers 256-bit vectors, so this variant may run slower there than 8-wide
//! code would. To measure it, a build with `RUSTFLAGS="-C
//! target-feature=+prefer-256-bit"` keeps every function 256 wide, and
//! `SPVG_MAX_LOOP_VARIANT=avx2` runs the AVX2 variant in the same binary (the commands
//! are in BENCHMARKS.md, "AVX-512"). `avx512fp16` conversions (`vcvtph2psx`,
//! `vcvtps2phx`) were not added: between `f16` and `f32` they compute what F16C computes,
//! and the 16-wide forms of F16C's own instructions are already in AVX-512F; FP16 adds
//! `f16` arithmetic, which these loops do not do (they compute in `f32`), and exists only
//! on Sapphire Rapids and later.
//!
//! Where the features are compiled in already (`-C target-cpu=native` on such a CPU),
//! on other architectures (aarch64 keeps its baseline NEON loop) and in `no_std` builds
//! there is nothing to dispatch: [`dispatched`] returns `false` and the caller runs its
//! loop as compiled.
//!
//! # Unsafe code
//!
//! This is the crate's only module with `unsafe`. Calling a `#[target_feature]`
//! function, or an F16C/AVX intrinsic, is `unsafe` because it would be undefined
//! behaviour on a CPU without the features: each such call either sits right after the
//! check that the features are present ([`run_on`]), or behind an [`Avx2`] token,
//! which only that check makes (or [`BASELINE`], compiled only where the features are
//! compiled in).
//! The intrinsics' loads and stores read and write whole fixed-size arrays (8 values or 8
//! texels at a time, the lengths checked at compile time). The module stays small so that
//! it can be read at a glance.
#![allow(
    unsafe_code,
    reason = "#[target_feature] functions and F16C/AVX intrinsics after run-time detection; see the module docs"
)]

use super::chunk::{CHUNK, Wide};

/// The chunk primitives of a frame loop, by the instruction set it is compiled for:
/// [`Portable`], or [`Avx2`] (the run-time dispatched variant); [`BASELINE`] is one of
/// the two. All variants give the same bits: the conversions are those of
/// `half::f16::{to_f32, from_f32}` on their domain, and the transposes move values. A
/// `pub` trait in a private module because `Chunked`'s methods are generic over it.
#[allow(
    unreachable_pub,
    reason = "named by the methods of the sealed `Chunked`, so public in a private module"
)]
pub trait Isa: Copy {
    /// `dst[i] = f16::from_bits(src[i]).to_f32()`, exactly. `N` is a multiple of 8.
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]);
    /// `dst[i] = f16::from_f32(src[i]).to_bits()` (round to nearest, ties to even) for
    /// `src[i]` in `[-65504, 65504]`, not NaN. `N` is a multiple of 8.
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]);
    /// Texels to channels: `out[c][i] = texels[i][c]`. `N` is a multiple of 8.
    fn deinterleave<const N: usize>(self, texels: &[[f32; 4]; N], out: &mut [[f32; N]; 4]);
    /// Channels to texels: `texels[i][c] = values[c][i]`. `N` is a multiple of 8.
    fn interleave<const N: usize>(self, values: &[[f32; N]; 4], texels: &mut [[f32; 4]; N]);

    /// `f16` texels to channels, [`widen`](Self::widen) then
    /// [`deinterleave`](Self::deinterleave): `out[c][i] = f16::from_bits(texels[i][c])
    /// .to_f32()`, exactly. `wide` is scratch (its contents are left unspecified).
    #[inline(always)]
    fn widen_deinterleave(
        self,
        texels: &[[u16; 4]; CHUNK],
        wide: &mut Wide,
        out: &mut [[f32; CHUNK]; 4],
    ) {
        let flat: &mut [f32; 4 * CHUNK] = bytemuck::cast_mut(wide);
        self.widen(bytemuck::cast_ref(texels), flat);
        self.deinterleave(wide, out);
    }

    /// Channels to `f16` texels, [`interleave`](Self::interleave) then
    /// [`narrow`](Self::narrow): `texels[i][c] = f16::from_f32(values[c][i]).to_bits()`
    /// for values in `[-65504, 65504]`, not NaN. `wide` is scratch.
    #[inline(always)]
    fn interleave_narrow(
        self,
        values: &[[f32; CHUNK]; 4],
        wide: &mut Wide,
        texels: &mut [[u16; 4]; CHUNK],
    ) {
        self.interleave(values, wide);
        let flat: &[f32; 4 * CHUNK] = bytemuck::cast_ref(wide);
        self.narrow(flat, bytemuck::cast_mut(texels));
    }
}

/// Code for any target: the branch-free conversions of `rounding.rs` and transposes
/// written as loops, which the compiler vectorises (SSE2, NEON). What [`BASELINE`] is
/// where no F16C or AVX is compiled in or detected; tests run it anywhere.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(
    all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "f16c"
    ),
    allow(
        dead_code,
        reason = "F16C (and so AVX) compiled in: only the tests run it"
    )
)]
pub(super) struct Portable;

impl Isa for Portable {
    #[inline(always)]
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]) {
        for (d, &s) in dst.iter_mut().zip(src) {
            *d = super::rounding::widen_bits(s);
        }
    }

    #[inline(always)]
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]) {
        for (d, &s) in dst.iter_mut().zip(src) {
            *d = super::rounding::narrow_bits(s);
        }
    }

    #[inline(always)]
    fn deinterleave<const N: usize>(self, texels: &[[f32; 4]; N], out: &mut [[f32; N]; 4]) {
        for (i, t) in texels.iter().enumerate() {
            for (o, &v) in out.iter_mut().zip(t) {
                o[i] = v;
            }
        }
    }

    #[inline(always)]
    fn interleave<const N: usize>(self, values: &[[f32; N]; 4], texels: &mut [[f32; 4]; N]) {
        for (i, t) in texels.iter_mut().enumerate() {
            for (d, v) in t.iter_mut().zip(values) {
                *d = v[i];
            }
        }
    }
}

/// The primitives of the loop as compiled: [`Avx2`]'s F16C and AVX instructions where
/// F16C (and so AVX) is compiled in (`-C target-feature=+f16c`, `target-cpu=native`),
/// [`Portable`]'s code otherwise.
// SAFETY: every CPU this binary runs on has F16C and AVX (compiled in).
#[cfg(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
))]
pub(super) const BASELINE: Avx2 = Avx2 { _detected: () };

/// The primitives of the loop as compiled: [`Avx2`]'s F16C and AVX instructions where
/// F16C (and so AVX) is compiled in (`-C target-feature=+f16c`, `target-cpu=native`),
/// [`Portable`]'s code otherwise.
#[cfg(not(all(
    any(target_arch = "x86", target_arch = "x86_64"),
    target_feature = "f16c"
)))]
pub(super) const BASELINE: Portable = Portable;

/// Proof that the CPU has F16C and AVX: made by [`run_on`] after it detects the AVX2 or the
/// AVX-512 variant's features (each a superset of AVX and F16C), and handed to the loop
/// it compiles for those features, or as [`BASELINE`]
/// where F16C is compiled in. Its primitives are F16C and AVX instructions inlined into
/// the loop.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(
    not(any(
        all(feature = "std", target_arch = "x86_64"),
        all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "f16c"
        )
    )),
    allow(dead_code, reason = "made only by run_on or where F16C is compiled in")
)]
pub(super) struct Avx2 {
    _detected: (),
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
impl Isa for Avx2 {
    #[inline(always)]
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::widen(src, dst) }
    }

    #[inline(always)]
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::narrow(src, dst) }
    }

    #[inline(always)]
    fn deinterleave<const N: usize>(self, texels: &[[f32; 4]; N], out: &mut [[f32; N]; 4]) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::deinterleave(texels, out) }
    }

    #[inline(always)]
    fn interleave<const N: usize>(self, values: &[[f32; N]; 4], texels: &mut [[f32; 4]; N]) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::interleave(values, texels) }
    }

    /// In registers: no pass through `wide`.
    #[inline(always)]
    fn widen_deinterleave(
        self,
        texels: &[[u16; 4]; CHUNK],
        _wide: &mut Wide,
        out: &mut [[f32; CHUNK]; 4],
    ) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::widen_deinterleave(texels, out) }
    }

    /// In registers: no pass through `wide`.
    #[inline(always)]
    fn interleave_narrow(
        self,
        values: &[[f32; CHUNK]; 4],
        _wide: &mut Wide,
        texels: &mut [[u16; 4]; CHUNK],
    ) {
        // SAFETY: `self` is an `Avx2` token, which exists only on a CPU with AVX and F16C.
        unsafe { x86::interleave_narrow(values, texels) }
    }
}

/// Elsewhere an `Avx2` is never made; the portable code keeps the crate compiling.
#[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
impl Isa for Avx2 {
    #[inline(always)]
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]) {
        Portable.widen(src, dst);
    }

    #[inline(always)]
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]) {
        Portable.narrow(src, dst);
    }

    #[inline(always)]
    fn deinterleave<const N: usize>(self, texels: &[[f32; 4]; N], out: &mut [[f32; N]; 4]) {
        Portable.deinterleave(texels, out);
    }

    #[inline(always)]
    fn interleave<const N: usize>(self, values: &[[f32; N]; 4], texels: &mut [[f32; 4]; N]) {
        Portable.interleave(values, texels);
    }
}

/// The x86 primitives: F16C conversions, 8 values per instruction (`vcvtph2ps`, and
/// `vcvtps2ph` with round-to-nearest-even: the instructions `half` itself uses when it
/// detects F16C), and 8-texel transposes in AVX registers. `#[inline(always)]` without
/// `#[target_feature]`: inlined into a loop compiled with the features (the `avx2`
/// and `avx512` functions below, or a build with them compiled in), the intrinsics
/// inline too.
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
mod x86 {
    #[cfg(target_arch = "x86")]
    use core::arch::x86::{
        __m256, _MM_FROUND_TO_NEAREST_INT, _mm_loadu_si128, _mm_storeu_si128, _mm256_castpd_ps,
        _mm256_castps_pd, _mm256_cvtph_ps, _mm256_cvtps_ph, _mm256_loadu_ps, _mm256_loadu2_m128,
        _mm256_permute2f128_ps, _mm256_storeu_ps, _mm256_storeu2_m128, _mm256_unpackhi_pd,
        _mm256_unpackhi_ps, _mm256_unpacklo_pd, _mm256_unpacklo_ps,
    };
    #[cfg(target_arch = "x86_64")]
    use core::arch::x86_64::{
        __m256, _MM_FROUND_TO_NEAREST_INT, _mm_loadu_si128, _mm_storeu_si128, _mm256_castpd_ps,
        _mm256_castps_pd, _mm256_cvtph_ps, _mm256_cvtps_ph, _mm256_loadu_ps, _mm256_loadu2_m128,
        _mm256_permute2f128_ps, _mm256_storeu_ps, _mm256_storeu2_m128, _mm256_unpackhi_pd,
        _mm256_unpackhi_ps, _mm256_unpacklo_pd, _mm256_unpacklo_ps,
    };

    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn widen<const N: usize>(src: &[u16; N], dst: &mut [f32; N]) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 values") };
        for (d, s) in dst.chunks_exact_mut(8).zip(src.chunks_exact(8)) {
            // SAFETY: `s` holds 8 `u16` (16 bytes) and `d` 8 `f32` (32 bytes); unaligned
            // loads and stores; the caller guarantees the features.
            unsafe {
                let h = _mm_loadu_si128(s.as_ptr().cast());
                _mm256_storeu_ps(d.as_mut_ptr(), _mm256_cvtph_ps(h));
            }
        }
    }

    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn narrow<const N: usize>(src: &[f32; N], dst: &mut [u16; N]) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 values") };
        for (d, s) in dst.chunks_exact_mut(8).zip(src.chunks_exact(8)) {
            // SAFETY: as in `widen`.
            unsafe {
                let v = _mm256_loadu_ps(s.as_ptr());
                let h = _mm256_cvtps_ph::<_MM_FROUND_TO_NEAREST_INT>(v);
                _mm_storeu_si128(d.as_mut_ptr().cast(), h);
            }
        }
    }

    /// The 4x4 transpose in each 128-bit half of four registers: rows `a, b, c, d` in,
    /// columns out.
    ///
    /// # Safety
    ///
    /// The CPU has AVX.
    #[inline(always)]
    unsafe fn transpose(a: __m256, b: __m256, c: __m256, d: __m256) -> [__m256; 4] {
        // SAFETY: register shuffles; the caller guarantees AVX.
        unsafe {
            let ab_lo = _mm256_castps_pd(_mm256_unpacklo_ps(a, b));
            let ab_hi = _mm256_castps_pd(_mm256_unpackhi_ps(a, b));
            let cd_lo = _mm256_castps_pd(_mm256_unpacklo_ps(c, d));
            let cd_hi = _mm256_castps_pd(_mm256_unpackhi_ps(c, d));
            [
                _mm256_castpd_ps(_mm256_unpacklo_pd(ab_lo, cd_lo)),
                _mm256_castpd_ps(_mm256_unpackhi_pd(ab_lo, cd_lo)),
                _mm256_castpd_ps(_mm256_unpacklo_pd(ab_hi, cd_hi)),
                _mm256_castpd_ps(_mm256_unpackhi_pd(ab_hi, cd_hi)),
            ]
        }
    }

    /// Texels `j..j + 8` go in as four registers `[texel j + k | texel j + 4 + k]`; the
    /// transpose leaves channel `c` of texels `j..j + 4 | j + 4..j + 8` in register `c`.
    ///
    /// # Safety
    ///
    /// The CPU has AVX.
    #[inline(always)]
    pub(super) unsafe fn deinterleave<const N: usize>(
        texels: &[[f32; 4]; N],
        out: &mut [[f32; N]; 4],
    ) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 texels") };
        for (j, t) in texels.chunks_exact(8).enumerate() {
            let j = 8 * j;
            // SAFETY: `t` holds 8 texels of 4 `f32`: each `t[k]` is 16 bytes; `out[c]`
            // has `N >= j + 8` values; unaligned loads and stores; the caller
            // guarantees AVX.
            unsafe {
                let row = |k: usize| _mm256_loadu2_m128(t[k + 4].as_ptr(), t[k].as_ptr());
                let cols = transpose(row(0), row(1), row(2), row(3));
                for (o, v) in out.iter_mut().zip(cols) {
                    _mm256_storeu_ps(o[j..j + 8].as_mut_ptr(), v);
                }
            }
        }
    }

    /// The inverse of [`deinterleave`].
    ///
    /// # Safety
    ///
    /// The CPU has AVX.
    #[inline(always)]
    pub(super) unsafe fn interleave<const N: usize>(
        values: &[[f32; N]; 4],
        texels: &mut [[f32; 4]; N],
    ) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 texels") };
        for (j, t) in texels.chunks_exact_mut(8).enumerate() {
            let j = 8 * j;
            // SAFETY: as in `deinterleave`.
            unsafe {
                let col = |c: usize| _mm256_loadu_ps(values[c][j..j + 8].as_ptr());
                let rows = transpose(col(0), col(1), col(2), col(3));
                let (lo, hi) = t.split_at_mut(4);
                for ((l, h), v) in lo.iter_mut().zip(hi).zip(rows) {
                    _mm256_storeu2_m128(h.as_mut_ptr(), l.as_mut_ptr(), v);
                }
            }
        }
    }

    /// [`widen`] and [`deinterleave`] in registers: each conversion widens two texels
    /// `[texel 2k | texel 2k + 1]`, lane permutes make the transpose's rows
    /// `[texel k | texel k + 4]`.
    ///
    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn widen_deinterleave<const N: usize>(
        texels: &[[u16; 4]; N],
        out: &mut [[f32; N]; 4],
    ) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 texels") };
        for (j, t) in texels.chunks_exact(8).enumerate() {
            let j = 8 * j;
            // SAFETY: `t` holds 8 texels of 4 `u16`: `t[2 k..]` has at least the 16 bytes
            // of texels 2k and 2k + 1 for k < 4; `out[c]` has `N >= j + 8` values;
            // unaligned loads and stores; the caller guarantees the features.
            unsafe {
                let pair = |k: usize| _mm256_cvtph_ps(_mm_loadu_si128(t[2 * k..].as_ptr().cast()));
                let (p01, p23, p45, p67) = (pair(0), pair(1), pair(2), pair(3));
                let cols = transpose(
                    _mm256_permute2f128_ps::<0x20>(p01, p45),
                    _mm256_permute2f128_ps::<0x31>(p01, p45),
                    _mm256_permute2f128_ps::<0x20>(p23, p67),
                    _mm256_permute2f128_ps::<0x31>(p23, p67),
                );
                for (o, v) in out.iter_mut().zip(cols) {
                    _mm256_storeu_ps(o[j..j + 8].as_mut_ptr(), v);
                }
            }
        }
    }

    /// The inverse of [`widen_deinterleave`]: [`interleave`] and [`narrow`] in
    /// registers.
    ///
    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn interleave_narrow<const N: usize>(
        values: &[[f32; N]; 4],
        texels: &mut [[u16; 4]; N],
    ) {
        const { assert!(N.is_multiple_of(8), "whole groups of 8 texels") };
        for (j, t) in texels.chunks_exact_mut(8).enumerate() {
            let j = 8 * j;
            // SAFETY: as in `widen_deinterleave`.
            unsafe {
                let col = |c: usize| _mm256_loadu_ps(values[c][j..j + 8].as_ptr());
                let [r04, r15, r26, r37] = transpose(col(0), col(1), col(2), col(3));
                let pairs = [
                    _mm256_permute2f128_ps::<0x20>(r04, r15),
                    _mm256_permute2f128_ps::<0x20>(r26, r37),
                    _mm256_permute2f128_ps::<0x31>(r04, r15),
                    _mm256_permute2f128_ps::<0x31>(r26, r37),
                ];
                for (k, p) in pairs.into_iter().enumerate() {
                    let h = _mm256_cvtps_ph::<_MM_FROUND_TO_NEAREST_INT>(p);
                    _mm_storeu_si128(t[2 * k..].as_mut_ptr().cast(), h);
                }
            }
        }
    }
}

/// Which compilation of the frame loops runs ([`selected_loop_variant`]), from the
/// least to the most capable. All give the same bits.
///
/// In the portable build on x86-64 (with `std`) the loops are compiled for the baseline
/// and, dispatched at run time, for AVX2 and for AVX-512; elsewhere, in `no_std` builds
/// and where a variant's features are compiled in already (`-C target-cpu=native` on
/// such a CPU), the loop as compiled is the one that runs. The `Display` form is the
/// name [`selected_loop_variant`]'s environment variable takes (`as-compiled`, `avx2`,
/// `avx512`), followed for `AsCompiled` by the instruction-set level compiled in, for
/// example `as-compiled (x86-64-v3)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum LoopVariant {
    /// The loop as compiled, with whatever the build's target features are (the x86-64
    /// baseline, SSE2, in a plain `cargo build`); no run-time dispatch.
    AsCompiled,
    /// Dispatched at run time: the loops compiled for AVX2, FMA and F16C (x86-64-v3),
    /// 8 lanes in 256-bit registers.
    Avx2,
    /// Dispatched at run time: the loops compiled for AVX-512 F, BW and VL with AVX2,
    /// FMA and F16C (x86-64-v4's subsets these loops can use); whether LLVM runs them 16
    /// wide is its choice, see `BENCHMARKS.md`.
    Avx512,
}

impl LoopVariant {
    /// Every variant, from the least to the most capable.
    pub const ALL: [Self; 3] = [Self::AsCompiled, Self::Avx2, Self::Avx512];

    /// The name [`selected_loop_variant`]'s environment variable takes.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::AsCompiled => "as-compiled",
            Self::Avx2 => "avx2",
            Self::Avx512 => "avx512",
        }
    }

    /// Whether this variant can run here: `AsCompiled` always; a dispatched variant
    /// where this build compiles it (`std`, x86-64, its features not all compiled in)
    /// and this CPU has its features.
    #[must_use]
    pub fn is_available(self) -> bool {
        match self {
            Self::AsCompiled => true,
            Self::Avx2 => avx2_available(),
            Self::Avx512 => avx512_available(),
        }
    }
}

impl core::fmt::Display for LoopVariant {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())?;
        if *self == Self::AsCompiled {
            write!(f, " ({})", compiled_level())?;
        }
        Ok(())
    }
}

/// The x86-64 micro-architecture level whose features are all compiled in
/// (`x86-64-v1` to `x86-64-v4`), or the target architecture elsewhere.
fn compiled_level() -> &'static str {
    if cfg!(target_arch = "aarch64") {
        return "aarch64";
    }
    if cfg!(not(target_arch = "x86_64")) {
        return "not x86-64";
    }
    if cfg!(all(
        target_feature = "avx512f",
        target_feature = "avx512bw",
        target_feature = "avx512cd",
        target_feature = "avx512dq",
        target_feature = "avx512vl"
    )) {
        "x86-64-v4"
    } else if cfg!(all(
        target_feature = "avx2",
        target_feature = "bmi1",
        target_feature = "bmi2",
        target_feature = "f16c",
        target_feature = "fma",
        target_feature = "lzcnt",
        target_feature = "movbe"
    )) {
        "x86-64-v3"
    } else if cfg!(all(
        target_feature = "sse4.2",
        target_feature = "popcnt",
        target_feature = "ssse3"
    )) {
        "x86-64-v2"
    } else {
        "x86-64-v1"
    }
}

/// The frame-loop variant this process runs: the most capable one that is
/// [available](LoopVariant::is_available), at most the one named by the environment
/// variable `SPVG_MAX_LOOP_VARIANT` (`as-compiled`, `avx2` or `avx512`; unset or any
/// other value: no limit). Chosen at the first call and kept for the process.
///
/// The variable exists to compare variants on one machine (timings, and the bits, which
/// are equal); it never selects a variant the CPU lacks. Without `std` nothing is
/// dispatched and this is always [`LoopVariant::AsCompiled`].
///
/// ```
/// let variant = spvg::texel::selected_loop_variant();
/// assert!(variant.is_available());
/// println!("frame loops: {variant}");
/// ```
#[must_use]
pub fn selected_loop_variant() -> LoopVariant {
    #[cfg(feature = "std")]
    {
        static SELECTED: std::sync::OnceLock<LoopVariant> = std::sync::OnceLock::new();
        *SELECTED.get_or_init(|| {
            let limit = std::env::var("SPVG_MAX_LOOP_VARIANT").ok();
            let limit = LoopVariant::ALL
                .into_iter()
                .find(|v| limit.as_deref() == Some(v.name()))
                .unwrap_or(LoopVariant::Avx512);
            LoopVariant::ALL
                .into_iter()
                .rev()
                .find(|v| *v <= limit && v.is_available())
                .unwrap_or(LoopVariant::AsCompiled)
        })
    }
    #[cfg(not(feature = "std"))]
    LoopVariant::AsCompiled
}

/// Whether the AVX2 variant is compiled into this build (`std`, x86-64, AVX2/FMA/F16C
/// not all compiled in) and the CPU has AVX2, FMA and F16C.
fn avx2_available() -> bool {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    ))]
    {
        // `std` caches each detection.
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("f16c")
    }
    #[cfg(not(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    )))]
    false
}

/// Whether the AVX-512 variant is compiled into this build (`std`, x86-64, its features
/// not all compiled in) and the CPU has AVX-512 F/BW/VL, AVX2, FMA and F16C (`std`'s
/// detection also checks that the OS saves the AVX-512 registers).
fn avx512_available() -> bool {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx512f",
            target_feature = "avx512bw",
            target_feature = "avx512vl",
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    ))]
    {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("f16c")
    }
    #[cfg(not(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx512f",
            target_feature = "avx512bw",
            target_feature = "avx512vl",
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    )))]
    false
}

/// Runs `run` in the [selected](selected_loop_variant) variant and returns `true` when
/// that is a dispatched one; returns `false` (without running it) when it is
/// [`LoopVariant::AsCompiled`]: the caller then runs its loop with [`BASELINE`]. `run`
/// must be an `#[inline(always)]` closure over `#[inline(always)]` code (the frame
/// loops' `run_lanes`), so that it is compiled inside each `#[target_feature]` function.
#[inline(always)]
pub(super) fn dispatched(run: impl FnOnce(Avx2)) -> bool {
    run_on(selected_loop_variant(), run)
}

/// Runs `run` compiled for `variant`'s features, with the [`Avx2`] token, when `variant`
/// is a dispatched one and [available](LoopVariant::is_available), and returns `true`;
/// returns `false` (without running it) otherwise. See [`dispatched`] for what `run`
/// must be.
#[inline(always)]
pub(super) fn run_on(variant: LoopVariant, run: impl FnOnce(Avx2)) -> bool {
    match variant {
        LoopVariant::AsCompiled => {}
        LoopVariant::Avx2 => {
            #[cfg(all(
                feature = "std",
                target_arch = "x86_64",
                not(all(
                    target_feature = "avx2",
                    target_feature = "fma",
                    target_feature = "f16c"
                ))
            ))]
            {
                #[target_feature(enable = "avx2,fma,f16c")]
                fn avx2(run: impl FnOnce(Avx2)) {
                    run(Avx2 { _detected: () });
                }
                if avx2_available() {
                    // SAFETY: the CPU has AVX2, FMA and F16C (checked just above).
                    unsafe { avx2(run) };
                    return true;
                }
            }
        }
        LoopVariant::Avx512 => {
            #[cfg(all(
                feature = "std",
                target_arch = "x86_64",
                not(all(
                    target_feature = "avx512f",
                    target_feature = "avx512bw",
                    target_feature = "avx512vl",
                    target_feature = "avx2",
                    target_feature = "fma",
                    target_feature = "f16c"
                ))
            ))]
            {
                #[target_feature(enable = "avx512f,avx512bw,avx512vl,avx2,fma,f16c")]
                fn avx512(run: impl FnOnce(Avx2)) {
                    run(Avx2 { _detected: () });
                }
                if avx512_available() {
                    // SAFETY: the CPU has AVX-512 F/BW/VL, AVX2, FMA and F16C (checked
                    // just above), a superset of what the `Avx2` token stands for.
                    unsafe { avx512(run) };
                    return true;
                }
            }
        }
    }
    let _ = run;
    false
}

// The tests build frames with `FrameInputsBuf` (feature `std`).
#[cfg(all(test, feature = "std"))]
mod tests {
    use super::super::batch::{ConstantUpdate, Estimate, OcvUpdate};
    use super::super::{
        CvTexel16, CvTexel32, FrameInputs, FrameInputsBuf, Rounding, SpvgTexel16, SpvgTexel32,
        TexelEncoding, estimate_frame,
    };
    use super::LoopVariant;
    use crate::SpvgConfig;
    use crate::cv::{Ccv, Ocv, PixelController, PixelFrame};
    use std::io::Write;

    /// Inputs with every kind of pixel: ordinary, disoccluded, refused, non-finite.
    fn inputs(n: usize) -> FrameInputsBuf {
        let mut x = 0x9e37_79b9_u32;
        let mut u = move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            f64::from(x) as f32 / 4.294_967e9
        };
        let mut f = FrameInputsBuf::with_capacity(n);
        for i in 0..n {
            let b = 3.0 * u();
            let radiance = if i % 97 == 0 {
                f32::NAN
            } else {
                b * (0.5 + u())
            };
            let pixel = PixelFrame {
                radiance,
                preintegrated: b,
                gamma: u(),
            };
            let count = if i % 41 == 0 {
                0
            } else {
                8 + (u() * 56.0) as u32
            };
            f.push(pixel, count, u() > 0.05);
        }
        f
    }

    /// Which loop [`three_frames`] runs.
    #[derive(Clone, Copy, Debug)]
    enum Loop {
        /// The frame functions' own dispatch (the selected variant).
        Dispatched,
        /// `run_lanes` compiled for a dispatched variant (the CPU has it).
        Variant(LoopVariant),
        /// `run_lanes` with the given `Isa`, compiled for the build's baseline.
        Lanes,
    }

    /// The texels after three frames (first pixel 0, 3 and 64) of CCV with f16 texels,
    /// OCV with f32 and f16 texels, and OCV with f16 and f32 texels, and the counts
    /// estimated from the f16 and the f32 histories after them, through `how` (`isa` is
    /// the primitives of `Loop::Lanes`).
    #[allow(clippy::type_complexity, reason = "the four layouts a test compares")]
    fn three_frames<I: super::Isa>(
        isa: I,
        how: Loop,
        frame: &FrameInputs<'_>,
        rounding: Rounding,
    ) -> (
        Vec<SpvgTexel16>,
        (Vec<SpvgTexel32>, Vec<CvTexel16>),
        (Vec<SpvgTexel16>, Vec<CvTexel32>),
        (Vec<u32>, Vec<u32>),
    ) {
        let n = frame.radiance.len();
        let config = SpvgConfig::<f32>::published();
        let enc = TexelEncoding::new(config.target_variance()).expect("valid target");
        let update = ConstantUpdate::new(&PixelController::new(config, Ccv), &enc, rounding);
        let ocv = Ocv::with_weight(0.05)
            .expect("valid weight")
            .with_f16_inputs(true);
        let ocv_update = OcvUpdate::new(&PixelController::new(config, ocv), &enc, rounding);
        let mut h = vec![SpvgTexel16::default(); n];
        let (mut k, mut j) = (
            vec![SpvgTexel32::default(); n],
            vec![CvTexel16::default(); n],
        );
        let (mut t, mut m) = (
            vec![SpvgTexel16::default(); n],
            vec![CvTexel32::default(); n],
        );
        for first in [0, 3, 64] {
            match how {
                Loop::Dispatched => {
                    update.run(frame, &mut h, first);
                    ocv_update.run(frame, &mut k, &mut j, first);
                    ocv_update.run(frame, &mut t, &mut m, first);
                }
                Loop::Variant(variant) => {
                    let ran = super::run_on(
                        variant,
                        #[inline(always)]
                        |isa| {
                            update.run_lanes(isa, frame, &mut h, first);
                            ocv_update.run_lanes(isa, frame, &mut k, &mut j, first);
                            ocv_update.run_lanes(isa, frame, &mut t, &mut m, first);
                        },
                    );
                    assert!(ran, "{variant} is available, so run_on runs it");
                }
                Loop::Lanes => {
                    update.run_lanes(isa, frame, &mut h, first);
                    ocv_update.run_lanes(isa, frame, &mut k, &mut j, first);
                    ocv_update.run_lanes(isa, frame, &mut t, &mut m, first);
                }
            }
        }
        let estimate = Estimate::new(&config, &enc);
        let (mut from_h, mut from_k) = (vec![0_u32; n], vec![0_u32; n]);
        let (gamma, valid) = (frame.gamma, frame.valid);
        match how {
            Loop::Dispatched => {
                estimate_frame(&config, &enc, &h, gamma, valid, &mut from_h)
                    .expect("equal lengths");
                estimate_frame(&config, &enc, &k, gamma, valid, &mut from_k)
                    .expect("equal lengths");
            }
            Loop::Variant(variant) => {
                let ran = super::run_on(
                    variant,
                    #[inline(always)]
                    |isa| {
                        estimate.run_lanes(isa, &h, gamma, valid, &mut from_h);
                        estimate.run_lanes(isa, &k, gamma, valid, &mut from_k);
                    },
                );
                assert!(ran, "{variant} is available, so run_on runs it");
            }
            Loop::Lanes => {
                estimate.run_lanes(isa, &h, gamma, valid, &mut from_h);
                estimate.run_lanes(isa, &k, gamma, valid, &mut from_k);
            }
        }
        (h, (k, j), (t, m), (from_h, from_k))
    }

    /// The dispatched loop (the selected variant), every dispatched variant this CPU has,
    /// the loop as compiled (`BASELINE`) and the portable loop (branch-free conversions,
    /// loop transposes) give the same bits, frame after frame, with a partial last
    /// chunk, and the same estimated counts. A variant the CPU lacks is skipped, and the test says so.
    #[test]
    fn every_variant_baseline_and_portable_loops_agree() {
        let buf = inputs(1000);
        let frame = buf.inputs();
        let variants: Vec<LoopVariant> = [LoopVariant::Avx2, LoopVariant::Avx512]
            .into_iter()
            .filter(|v| v.is_available())
            .collect();
        let skipped: Vec<LoopVariant> = [LoopVariant::Avx2, LoopVariant::Avx512]
            .into_iter()
            .filter(|v| !v.is_available())
            .collect();
        // Written to stderr directly, not with `eprintln!`, which the test harness
        // captures: a skipped variant must show in every run.
        let _ = writeln!(
            std::io::stderr(),
            "variant equality: selected {}; compared {variants:?} with BASELINE and \
             Portable; skipped {skipped:?} (this CPU lacks their features, the build \
             compiles them in and BASELINE is that loop, or it is not x86-64)",
            super::selected_loop_variant()
        );
        for rounding in [Rounding::Nearest, Rounding::Stochastic(5)] {
            let portable = three_frames(super::Portable, Loop::Lanes, &frame, rounding);
            let baseline = three_frames(super::BASELINE, Loop::Lanes, &frame, rounding);
            let dispatched = three_frames(super::BASELINE, Loop::Dispatched, &frame, rounding);
            assert!(
                baseline == portable,
                "baseline against portable, {rounding:?}"
            );
            assert!(
                dispatched == portable,
                "dispatched against portable, {rounding:?}"
            );
            for &variant in &variants {
                let got = three_frames(super::BASELINE, Loop::Variant(variant), &frame, rounding);
                assert!(got == portable, "{variant} against portable, {rounding:?}");
            }
        }
    }

    /// The selection is available, at least the as-compiled loop, and the highest
    /// available variant unless `SPVG_MAX_LOOP_VARIANT` limits it.
    #[test]
    fn the_selected_variant_is_the_best_available() {
        let selected = super::selected_loop_variant();
        assert!(selected.is_available(), "{selected} must be available");
        let best = LoopVariant::ALL
            .into_iter()
            .rev()
            .find(|v| v.is_available())
            .expect("as-compiled is always available");
        if std::env::var_os("SPVG_MAX_LOOP_VARIANT").is_none() {
            assert_eq!(selected, best, "no limit: the most capable variant runs");
        } else {
            assert!(selected <= best, "a limit never raises the variant");
        }
    }
}
